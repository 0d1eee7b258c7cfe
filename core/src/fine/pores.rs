//! The soil's pores: porosity and intrinsic permeability, for the seepage and
//! pore-pressure forces of seed 001 Eqs. (8)–(10) (applied in
//! [`interactions::soil_water`](crate::interactions::soil_water)).

use crate::numerics::math::Real;
use crate::scene::{MaterialSpec, PHI_MAX};

/// Porosity and permeability of one soil material.
#[derive(Clone, Copy, Debug, PartialEq, serde::Serialize, serde::Deserialize)]
pub struct Pores {
    /// Porosity n: the pore fraction of the volume. The soil particle carries the
    /// grains' mass only, ρ_d = (1 − n) ρ_grain (the material's `density`).
    pub porosity: Real,
    /// Intrinsic permeability k (m²), given or from Kozeny–Carman.
    pub permeability: Real,
    /// The pores are filled with water at start-up.
    pub saturated: bool,
}

/// Kozeny–Carman: k = n³ d² / (180 (1 − n)²) for porosity n and grain diameter d
/// (seed 001 §1.5, `SeepageType` 1).
pub fn kozeny_carman(porosity: Real, grain_size: Real) -> Real {
    let n = porosity;
    n * n * n * grain_size * grain_size / (180.0 * (1.0 - n) * (1.0 - n))
}

impl Pores {
    /// The pores of a validated material: `None` when it has no permeability (water
    /// passes it freely).
    pub fn of(m: &MaterialSpec) -> Option<Self> {
        let n = m.porosity?;
        let k = m
            .permeability
            .or_else(|| m.grain_size.map(|d| kozeny_carman(n, d)))?;
        Some(Pores {
            porosity: n,
            permeability: k,
            saturated: m.saturated,
        })
    }

    /// Porosity of a particle of density `rho` of a soil of dry density `rho0`: the
    /// grains keep their volume, so the solid fraction follows the density,
    /// 1 − n = (1 − n0) ρ/ρ0 (issue 44 item 1). Held within [n_min, 0.99], n_min the
    /// porosity of the densest packing of spheres (or n0 where that is lower).
    #[inline]
    pub fn porosity_at(&self, rho: Real, rho0: Real) -> Real {
        let least = self.porosity.min(1.0 - PHI_MAX);
        (1.0 - (1.0 - self.porosity) * rho / rho0).clamp(least, 0.99)
    }

    /// The permeability at porosity `n`: the material's k scaled by Kozeny–Carman,
    /// k n³ (1 − n0)² / (n0³ (1 − n)²) (seed 001 §1.5).
    #[inline]
    pub fn permeability_at(&self, n: Real) -> Real {
        if n == self.porosity {
            return self.permeability;
        }
        let n0 = self.porosity;
        let r = n / n0;
        let s = (1.0 - n0) / (1.0 - n);
        self.permeability * r * r * r * s * s
    }

    /// Hydraulic conductivity k_h = k ρ_w g / μ (m/s).
    pub fn conductivity(&self, rho_w: Real, g: Real, mu: Real) -> Real {
        self.permeability * rho_w * g / mu
    }

    /// The largest Δt at which the soil's side of the seepage drag may stay explicit,
    /// ½ ρ_d k / μ, for a soil of dry density `rho_d` in water of viscosity `mu`: a
    /// longer step closes the drag implicitly on both sides
    /// ([`seepage_implicit`](crate::interactions::seepage_implicit)).
    pub fn seepage_dt(&self, rho_d: Real, mu: Real) -> Real {
        0.5 * rho_d * self.permeability / mu
    }

    /// Submerged density ρ' = ρ_sat − ρ_w = ρ_d − (1 − n) ρ_w of a soil of dry density
    /// `rho_d`: the weight its skeleton carries below the water table.
    pub fn submerged_density(&self, rho_d: Real, rho_w: Real) -> Real {
        rho_d - (1.0 - self.porosity) * rho_w
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Kozeny–Carman for Toyoura sand (seed 001 §4: n = 0.435, d = 0.25 mm):
    /// k = 0.435³ · (2.5e-4)² / (180 · 0.565²) = 8.9532e-11 m².
    #[test]
    fn kozeny_carman_of_toyoura_sand() {
        let k = kozeny_carman(0.435, 2.5e-4);
        let expect = 0.435_f64.powi(3) * 6.25e-8 / (180.0 * 0.565 * 0.565);
        assert!((k - expect).abs() < 1e-25);
        assert!((k - 8.9532e-11).abs() / 8.9532e-11 < 1e-4, "{k:e}");
    }

    /// A particle's porosity follows its density (1 − n = (1 − n0) ρ/ρ0) and its
    /// permeability follows Kozeny–Carman at that porosity.
    #[test]
    fn porosity_and_permeability_follow_the_density() {
        let d = 2.25e-4;
        let p = Pores {
            porosity: 0.4,
            permeability: kozeny_carman(0.4, d),
            saturated: true,
        };
        assert_eq!(p.porosity_at(1500.0, 1500.0), 0.4);
        // 5 % looser: φ = 0.6 × 0.95 = 0.57
        let n = p.porosity_at(1425.0, 1500.0);
        assert!((n - 0.43).abs() < 1e-12, "{n}");
        let k = p.permeability_at(n);
        assert!((k / kozeny_carman(0.43, d) - 1.0).abs() < 1e-12);
        // never denser than the densest packing
        assert!((p.porosity_at(3000.0, 1500.0) - (1.0 - PHI_MAX)).abs() < 1e-12);
    }
}
