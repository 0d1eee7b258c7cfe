//! The low-dissipation Riemann solver of seed 000, Eqs. (17)–(23).
//!
//! Sign convention: e_ij points from j to i and the left/right states are the
//! velocities *along −e_ij* (towards the partner), U_L = −v_i·e_ij, U_R = −v_j·e_ij, so
//! that U_L − U_R > 0 when the particles approach. With this convention Eq. (19) moves
//! the interface away from the higher pressure and Eq. (20) raises the interface
//! pressure under compression, as in Zhang et al. (2017), seed 000 ref. [53].
//!
//! The limiter of Eq. (23) is used in its dimensionless form, β = min(η·max(Δ, 0)/c̄, 1),
//! with Δ = (v_i − v_j)·e_ij, the jump of Eq. (21) as printed (U = v·e_ij there): the
//! limiter opens when particles separate and stays shut under compression. This is
//! also what SPHinXsys (the seed's implementation) computes for plastic continua
//! (`u_jump = (v_i − v_j)·e_ij`, `limiter(max(u_jump, 0))`, η = 20·d). With the
//! compression-opened variant of ref. [53] the 3D collapse of VALIDATION.md §2 does not
//! come to rest (kinetic energy grows again after 0.7 s at dp = r0/10), so granmix
//! follows the seed. Under separation P* drops below the mean pressure, which resists
//! the separation: the term dissipates.

use crate::math::Real;

/// Parameters of the solver for one pair of materials.
#[derive(Clone, Copy, Debug)]
pub struct Riemann {
    /// Limiter coefficient η (default 20·d).
    pub eta: Real,
}

impl Riemann {
    /// Limiter β of Eq. (23), dimensionless form.
    #[inline(always)]
    pub fn limiter(&self, du: Real, c_mean: Real) -> Real {
        (self.eta * (-du).max(0.0) / c_mean).min(1.0)
    }

    /// Interface pressure P* of Eq. (20).
    #[inline(always)]
    pub fn p_star(&self, l: Side, r: Side, c_mean: Real) -> Real {
        let du = l.u - r.u;
        let beta = self.limiter(du, c_mean);
        (l.z * r.p + r.z * l.p + beta * l.z * r.z * du) / (l.z + r.z)
    }

    /// Interface velocity U* of Eq. (19) (along −e_ij).
    #[inline(always)]
    pub fn u_star(l: Side, r: Side) -> Real {
        (l.z * l.u + r.z * r.u + l.p - r.p) / (l.z + r.z)
    }
}

/// One side of the inter-particle Riemann problem, Eq. (21).
#[derive(Clone, Copy, Debug)]
pub struct Side {
    /// Acoustic impedance ρ c.
    pub z: Real,
    /// Velocity along −e_ij.
    pub u: Real,
    /// Pressure −tr(σ)/3.
    pub p: Real,
}

impl Side {
    #[inline(always)]
    pub fn new(z: Real, u: Real, p: Real) -> Self {
        Side { z, u, p }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn symmetric_states_give_average() {
        let r = Riemann { eta: 40.0 };
        // equal impedance, no velocity jump → P* is the mean pressure
        assert!(
            (r.p_star(Side::new(1.0, 0.3, 2.0), Side::new(1.0, 0.3, 4.0), 10.0) - 3.0).abs()
                < 1e-14
        );
        // compression (U_L > U_R) is not dissipated
        assert!(
            (r.p_star(Side::new(1.0, 1.0, 2.0), Side::new(1.0, -1.0, 2.0), 10.0) - 2.0).abs()
                < 1e-14
        );
        // separation lowers the interface pressure by β·Z·|ΔU|/2, β capped at 1
        let p = r.p_star(Side::new(5.0, -1.0, 0.0), Side::new(5.0, 1.0, 0.0), 10.0);
        assert!((p + 5.0).abs() < 1e-12, "{p}");
        // small jumps: β = η ΔU / c̄
        let p = r.p_star(Side::new(5.0, -0.01, 0.0), Side::new(5.0, 0.01, 0.0), 10.0);
        assert!(
            (p + 0.5 * 40.0 * 0.02 / 10.0 * 5.0 * 0.02).abs() < 1e-12,
            "{p}"
        );
        // acoustic interface velocity moves away from the high pressure side
        assert!(Riemann::u_star(Side::new(1.0, 0.0, 2.0), Side::new(1.0, 0.0, 0.0)) > 0.0);
    }
}
