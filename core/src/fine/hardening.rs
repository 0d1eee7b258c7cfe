//! Friction hardening and softening on the accumulated equivalent plastic strain ε_p,
//! seed 004 Eq. (43):
//!
//! φ = φ_e                                        ε_p = 0
//! φ = a ε_p³ + b ε_p² + c ε_p + d               0 < ε_p ≤ ε_p^peak
//! φ = φ_r + (φ_p − φ_r) exp(−H (ε_p − ε_p^peak))  ε_p > ε_p^peak
//!
//! with φ in radians. ε_p accumulates √(2/3 Δe_p:Δe_p) of the deviatoric plastic strain
//! increments (seed 004 leaves it open; `plasticity::update_stress`).

use crate::numerics::math::Real;
use crate::scene::HardeningSpec;

/// Eq. (43)'s constants, angles in radians.
#[derive(Clone, Copy, Debug, PartialEq, serde::Serialize, serde::Deserialize)]
pub struct Hardening {
    /// φ_e, the angle at ε_p = 0 (the material's friction angle).
    pub initial: Real,
    pub peak_strain: Real,
    pub cubic: [Real; 4],
    pub peak: Real,
    pub residual: Real,
    pub softening: Real,
}

impl Hardening {
    /// From the scene's block, with φ_e = `initial_deg` (the material's friction angle).
    pub fn from_spec(h: &HardeningSpec, initial_deg: Real) -> Self {
        Hardening {
            initial: initial_deg.to_radians(),
            peak_strain: h.peak_strain,
            cubic: h.cubic,
            peak: h.peak_angle.to_radians(),
            residual: h.residual_angle.to_radians(),
            softening: h.softening,
        }
    }

    /// φ(ε_p) in radians, Eq. (43).
    #[inline]
    pub fn angle(&self, eps_p: Real) -> Real {
        if eps_p <= 0.0 {
            self.initial
        } else if eps_p <= self.peak_strain {
            let [a, b, c, d] = self.cubic;
            ((a * eps_p + b) * eps_p + c) * eps_p + d
        } else {
            self.residual
                + (self.peak - self.residual) * (-self.softening * (eps_p - self.peak_strain)).exp()
        }
    }
}
