//! The soil's pores: porosity and intrinsic permeability, for the seepage and
//! pore-pressure forces of seed 001 Eqs. (8)–(10) (applied in
//! [`interactions::soil_water`](crate::interactions::soil_water)).

use crate::math::Real;
use crate::scene::MaterialSpec;

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
}
