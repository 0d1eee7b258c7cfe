//! The low-dissipation Riemann solver of seed 000, Eqs. (17)–(23). Shared: the fine
//! sweeps use it between fine particles and at walls (Eqs. 32–35), the fine–coarse
//! coupling at boulder surfaces (Eqs. 48–50), so it belongs to no particle family.
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

use crate::numerics::math::Real;
use crate::numerics::pairs::quad::Quad;

/// The jump `du` = U_L − U_R of a pair limited against `rec`, the same jump between
/// the two velocities reconstructed to the pair's midpoint by the particles' gradients
/// (MUSCL, van Leer 1979, as Vila (1999) brings it to SPH), on [`Quad`] lanes: minmod,
/// so zero for a linear velocity field (rec = 0), the raw jump where the
/// reconstruction would exceed it, and zero where the two disagree in sign.
#[inline(always)]
pub fn minmod_jump<Q: Quad>(q: Q, du: Q::V, rec: Q::V) -> Q::V {
    let zero = q.splat(0.0);
    // of the same sign: the smaller in magnitude, the minimum of two positive jumps
    // and the maximum of two negative ones
    let same = q.lt(zero, q.mul(du, rec));
    let small = q.select(q.lt(zero, du), q.min(du, rec), q.max(du, rec));
    q.select(same, small, zero)
}

/// Parameters of the solver for one pair of materials.
#[derive(Clone, Copy, Debug)]
pub struct Riemann {
    /// Limiter coefficient η (default 20·d).
    pub eta: Real,
}

impl Riemann {
    /// Limiter β of Eq. (23), dimensionless form; `inv_c` = 1/c̄.
    #[inline(always)]
    pub fn limiter(&self, du: Real, inv_c: Real) -> Real {
        (self.eta * (-du).max(0.0) * inv_c).min(1.0)
    }

    /// Interface pressure P* of Eq. (20); `inv_zsum` = 1/(Z_L + Z_R), `inv_c` = 1/c̄.
    #[inline(always)]
    pub fn p_star(&self, l: Side, r: Side, inv_zsum: Real, inv_c: Real) -> Real {
        let du = l.u - r.u;
        let beta = self.limiter(du, inv_c);
        (l.z * r.p + r.z * l.p + beta * l.z * r.z * du) * inv_zsum
    }

    /// P* of Eq. (20) when both sides share one impedance Z (`half_z` = Z/2):
    /// ½ (P_L + P_R) + ½ β Z (U_L − U_R), with β from [`limiter`](Self::limiter).
    #[inline(always)]
    pub fn p_star_uniform(pl: Real, pr: Real, beta: Real, half_z: Real, du: Real) -> Real {
        0.5 * (pl + pr) + beta * half_z * du
    }

    /// U* of Eq. (19) when both sides share one impedance Z (`half_inv_z` = 1/(2Z)):
    /// ½ (U_L + U_R) + (P_L − P_R)/(2Z).
    #[inline(always)]
    pub fn u_star_uniform(ul: Real, ur: Real, pl: Real, pr: Real, half_inv_z: Real) -> Real {
        0.5 * (ul + ur) + (pl - pr) * half_inv_z
    }

    /// Interface velocity U* of Eq. (19) (along −e_ij); `inv_zsum` = 1/(Z_L + Z_R).
    #[inline(always)]
    pub fn u_star(l: Side, r: Side, inv_zsum: Real) -> Real {
        (l.z * l.u + r.z * r.u + l.p - r.p) * inv_zsum
    }
}

/// 1/(Z_i + Z_j) and 1/c̄ for a pair, without a division when both particles share a
/// material (the common case): `half_inv_z` = 1/(2Z_i), `inv_c` = 1/c_i.
#[inline(always)]
pub fn pair_reciprocals(
    zi: Real,
    zj: Real,
    ci: Real,
    cj: Real,
    half_inv_z: Real,
    inv_c: Real,
) -> (Real, Real) {
    if zi == zj && ci == cj {
        (half_inv_z, inv_c)
    } else {
        (1.0 / (zi + zj), 2.0 / (ci + cj))
    }
}

/// One side of the inter-particle Riemann problem, Eq. (21).
#[derive(Clone, Copy, Debug)]
pub struct Side {
    /// Acoustic impedance ρ0 c0 (reference density, as in SPHinXsys; the current
    /// density differs by well under 1 % in granular flows).
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
    use crate::numerics::pairs::quad::Lanes;

    /// minmod on the lanes: the smaller jump of the same sign, nothing across signs or
    /// for a linear field, on both instruction sets.
    #[test]
    fn minmod_takes_the_smaller_jump_of_one_sign() {
        struct Cases;
        impl crate::numerics::pairs::quad::QuadTask for Cases {
            type Output = [f64; 4 * 2];
            #[inline(always)]
            fn run<Q: Quad>(self, q: Q) -> Self::Output {
                let du = [[1.0, 1.0, 1.0, -1.0], [-1.0, -1.0, 0.0, 2.0]];
                let rec = [[0.5, 2.0, -1.0, -0.5], [-3.0, 0.0, 1.0, 2.0]];
                let mut out = [0.0; 8];
                for k in 0..2 {
                    let m = minmod_jump(q, q.load(&du[k]), q.load(&rec[k]));
                    let mut a = [0.0; 4];
                    q.store(&mut a, m);
                    out[4 * k..4 * k + 4].copy_from_slice(&a);
                }
                out
            }
        }
        for lanes in [Lanes::portable(), Lanes::best()] {
            assert_eq!(
                lanes.run(Cases),
                [0.5, 1.0, 0.0, -0.5, -1.0, 0.0, 0.0, 2.0],
                "{}",
                lanes.name()
            );
        }
    }

    #[test]
    fn symmetric_states_give_average() {
        let r = Riemann { eta: 40.0 };
        // equal impedance, no velocity jump → P* is the mean pressure
        assert!(
            (r.p_star(Side::new(1.0, 0.3, 2.0), Side::new(1.0, 0.3, 4.0), 0.5, 0.1) - 3.0).abs()
                < 1e-14
        );
        // compression (U_L > U_R) is not dissipated
        assert!(
            (r.p_star(
                Side::new(1.0, 1.0, 2.0),
                Side::new(1.0, -1.0, 2.0),
                0.5,
                0.1
            ) - 2.0)
                .abs()
                < 1e-14
        );
        // separation lowers the interface pressure by β·Z·|ΔU|/2, β capped at 1
        let p = r.p_star(
            Side::new(5.0, -1.0, 0.0),
            Side::new(5.0, 1.0, 0.0),
            0.1,
            0.1,
        );
        assert!((p + 5.0).abs() < 1e-12, "{p}");
        // small jumps: β = η ΔU / c̄
        let p = r.p_star(
            Side::new(5.0, -0.01, 0.0),
            Side::new(5.0, 0.01, 0.0),
            0.1,
            0.1,
        );
        assert!(
            (p + 0.5 * 40.0 * 0.02 / 10.0 * 5.0 * 0.02).abs() < 1e-12,
            "{p}"
        );
        // acoustic interface velocity moves away from the high pressure side
        assert!(Riemann::u_star(Side::new(1.0, 0.0, 2.0), Side::new(1.0, 0.0, 0.0), 0.5) > 0.0);
    }

    /// The one-impedance forms are Eqs. (19)–(20) with Z_L = Z_R.
    #[test]
    fn uniform_forms_match_the_general_ones() {
        let r = Riemann { eta: 40.0 };
        let (z, c) = (2.0e5, 60.0);
        for (ul, ur, pl, pr) in [
            (0.3, -0.2, 1.5e3, 2.5e3),
            (-0.4, 0.1, 800.0, -20.0),
            (0.0, 0.0, 10.0, 10.0),
        ] {
            let (l, rr) = (Side::new(z, ul, pl), Side::new(z, ur, pr));
            let general = r.p_star(l, rr, 0.5 / z, 1.0 / c);
            let beta = r.limiter(ul - ur, 1.0 / c);
            let uniform = Riemann::p_star_uniform(pl, pr, beta, 0.5 * z, ul - ur);
            assert!((general - uniform).abs() <= 1e-12 * general.abs().max(1.0));
            let general = Riemann::u_star(l, rr, 0.5 / z);
            let uniform = Riemann::u_star_uniform(ul, ur, pl, pr, 0.5 / z);
            assert!((general - uniform).abs() <= 1e-12 * general.abs().max(1.0));
        }
    }
}
