//! The μ(I) rheology (Jop, Forterre & Pouliquen 2006, Nature 441:727; GDR MiDi 2004):
//! the friction coefficient μ = √J2/p grows with the inertial number
//! I = γ̇ d/√(p/ρ_s) from μ_s to μ_2:
//!
//! μ(I) = μ_s + (μ_2 − μ_s)/(1 + I_0/I).
//!
//! γ̇ = √(2 ė:ė), ė the deviatoric strain rate (|γ̇| = √(½ γ̇_ij γ̇_ij) with
//! γ̇_ij = 2 ė_ij, Jop et al.; γ̇ in simple shear). The law is written
//! μ = μ_s + (μ_2 − μ_s) γ̇ d/(I_0 √(p/ρ_s) + γ̇ d), which is bounded everywhere and so
//! needs no regularisation: at p → 0 (and in tension, p ≤ 0) I → ∞ and μ → μ_2; at
//! γ̇ → 0 μ → μ_s, the rate-independent cone; at p = γ̇ = 0 μ = μ_s.

use crate::numerics::math::Real;
use crate::scene::MuISpec;

/// μ(I)'s constants.
#[derive(Clone, Copy, Debug, PartialEq, serde::Serialize, serde::Deserialize)]
pub struct MuI {
    pub mu_s: Real,
    pub mu_2: Real,
    pub i_0: Real,
    pub grain_diameter: Real,
    pub grain_density: Real,
}

impl MuI {
    pub fn from_spec(m: &MuISpec) -> Self {
        MuI {
            mu_s: m.mu_s,
            mu_2: m.mu_2,
            i_0: m.i_0,
            grain_diameter: m.grain_diameter,
            grain_density: m.grain_density,
        }
    }

    /// μ at shear rate γ̇ and pressure p (positive in compression).
    #[inline]
    pub fn mu(&self, shear_rate: Real, p: Real) -> Real {
        let gd = shear_rate * self.grain_diameter;
        let ref_rate = self.i_0 * (p.max(0.0) / self.grain_density).sqrt();
        let den = ref_rate + gd;
        if den > 0.0 {
            self.mu_s + (self.mu_2 - self.mu_s) * gd / den
        } else {
            self.mu_s
        }
    }
}

impl MuI {
    /// μ at the inertial number `i` (≥ 0; infinite gives μ_2): the law as Jop et al.
    /// write it, for a number taken elsewhere ([`Dilatancy`]'s blend).
    ///
    /// [`Dilatancy`]: super::dilatancy::Dilatancy
    #[inline]
    pub fn mu_of_i(&self, i: Real) -> Real {
        if i.is_infinite() {
            return self.mu_2;
        }
        self.mu_s + (self.mu_2 - self.mu_s) * i / (self.i_0 + i)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Glass beads (Jop et al. 2006): μ_s = 0.383, μ_2 = 0.643, I_0 = 0.279. At I = I_0 μ
    /// lies half-way; the written form equals μ_s + (μ_2 − μ_s)/(1 + I_0/I); the limits.
    #[test]
    fn mu_of_i_follows_jop_et_al() {
        let m = MuI {
            mu_s: 0.383,
            mu_2: 0.643,
            i_0: 0.279,
            grain_diameter: 0.5e-3,
            grain_density: 2500.0,
        };
        let p: Real = 800.0;
        for i in [1e-4, 0.01, 0.279, 1.0, 30.0] {
            // the shear rate whose I = γ̇ d/√(p/ρ_s) is i
            let rate = i * (p / 2500.0).sqrt() / 0.5e-3;
            let want = 0.383 + (0.643 - 0.383) / (1.0 + 0.279 / i);
            assert!((m.mu(rate, p) - want).abs() < 1e-14, "I = {i}");
        }
        let half = 0.279 * (p / 2500.0).sqrt() / 0.5e-3;
        assert!((m.mu(half, p) - 0.513).abs() < 1e-14);
        assert_eq!(m.mu(0.0, p), 0.383);
        assert_eq!(m.mu(0.0, 0.0), 0.383);
        assert_eq!(m.mu(1.0, 0.0), 0.643);
        assert_eq!(m.mu(1.0, -5.0), 0.643);
    }
}
