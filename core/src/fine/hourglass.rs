//! Hourglass control of the fine grains: an accumulated penalty on the non-affine part
//! of the relative motion of neighbours.
//!
//! The SPH velocity gradient of Eq. (24) is blind to modes in which neighbours move
//! against each other on a regular lattice (zero-energy or hourglass modes): for
//! alternate columns of particles sliding vertically, Σ_j v_ij ⊗ ∇_i W_ij V_j = 0, so
//! the stress of Eqs. (7)–(12) never resists them. In a resting deposit the stress
//! diffusion of Eqs. (25)–(26) feeds such a mode; without a penalty a level layer
//! started in its geostatic state gains kinetic energy a hundredfold in 0.25 s
//! (docs/method.md, *Hourglass control*).
//!
//! The penalty follows the accumulated hourglass acceleration of the SPHinXsys
//! continuum solver. Each fine step adds, for particle i,
//!
//!   Δa_i = Δt Σ_j ξ Ḡ_ij s_ij ṽ_ij (∂W/∂r)(r_ij) V_j / (ρ_i r_ij),
//!   ṽ_ij = v_ij − ½ (L_i + L_j) r_ij,
//!
//! with L the velocity gradient of Eq. (24) from the previous sweep, Ḡ_ij the mean
//! shear modulus of the pair and ξ the scene's `numerics.hourglass`. ṽ_ij vanishes to
//! second order for any smooth velocity field (the trapezoidal rule is exact for
//! quadratic fields), so only the non-affine motion is penalised, and the
//! accumulated a_i acts as an elastic spring of stiffness ξG on the accumulated
//! non-affine displacement: it stores energy instead of dissipating it.
//!
//! Plastic flow is left alone: a particle whose last stress update went through the
//! return mapping (Eqs. 11–12) keeps only the share e = ε_e/(ε_e + Δε_p) of its
//! accumulated penalty, with Δε_p the plastic strain of that update and ε_e the
//! elastic deviatoric strain of the stress it ended with. A particle that slipped by
//! more than its elastic strain in one step (e < ½) is flowing: it forgets the penalty
//! at once (e = 0) and adds none. A particle of a resting deposit that grazes the
//! yield surface (Δε_p of 1e-9 ε_e) keeps it; an all-or-nothing drop there released
//! the stored force in jumps, and a barrier saw its static load wander by ±6 % with
//! the deposit at rest. A pair counts at weight s_ij = ½(e_i + e_j), e = 1 when
//! elastic. Between two elastic particles each increment is antisymmetric
//! (m_i Δa_ij = −m_j Δa_ji with V = m/ρ), an internal force; a released penalty is
//! not returned.
//!
//! The stored penalty also relaxes: each step keeps exp(−Δt c0/(N h)) of it, with
//! N = `numerics.hourglass_memory` (default 100 acoustic times h/c0, about 13 ms at
//! dp = 5 mm). A hourglass mode oscillates within a few h/c0 and still meets the full
//! spring, while a deposit at rest ends up carrying its load by its stress alone, not
//! by a numerical spring that plastic flow releases at some later moment.

use crate::numerics::math::{Real, Sym, Vect};
use nalgebra::SMatrix;

/// Share e of the accumulated penalty kept through a stress update that ended at
/// `stress` with plastic strain increment `plastic` (1 when it stayed elastic):
/// e = ε_e/(ε_e + Δε_p), ε_e = √(⅔ s:s)/(2G), the measure in which Δε_p is taken;
/// 0 (flowing) when that is below ½.
#[inline]
pub fn penalty_kept(stress: &Sym, shear: Real, plastic: Real) -> f32 {
    if plastic <= 0.0 {
        return 1.0;
    }
    let s = stress.dev();
    let eps_e = (2.0 / 3.0 * s.ddot(&s)).sqrt() * (0.5 / shear);
    if plastic >= eps_e {
        return 0.0;
    }
    (eps_e / (eps_e + plastic)) as f32
}

/// Non-affine relative velocity ṽ_ij = v_ij − ½ (L_i + L_j) r_ij.
#[inline(always)]
pub fn non_affine<const D: usize>(
    vij: &Vect<D>,
    rij: &Vect<D>,
    li: &SMatrix<f32, D, D>,
    lj: &SMatrix<f32, D, D>,
) -> Vect<D> {
    // each gradient widened before the sum, as the cluster-pair pass takes it
    let l = li.cast::<Real>() + lj.cast::<Real>();
    vij - l * rij * 0.5
}

/// Pair weight s_ij = ½(e_i + e_j) from the kept shares of the pair.
#[inline(always)]
pub fn pair_weight(kept_i: f32, kept_j: f32) -> Real {
    0.5 * (kept_i as Real + kept_j as Real)
}

#[cfg(test)]
mod tests {
    use super::*;
    use nalgebra::{Matrix2, Vector2};

    #[test]
    fn affine_motion_is_not_penalised() {
        // v = A x, L = A at both particles: ṽ = A (x_i − x_j) − A r_ij = 0
        let a = Matrix2::new(0.3, -1.2, 0.7, 0.05);
        let (xi, xj) = (Vector2::new(0.01, 0.02), Vector2::new(0.013, 0.018));
        let (vi, vj) = (a * xi, a * xj);
        let l = a.cast::<f32>();
        let d = non_affine(&(vi - vj), &(xi - xj), &l, &l);
        assert!(d.norm() < 1e-6 * (vi - vj).norm(), "{d}"); // L is single precision
    }

    #[test]
    fn quadratic_motion_is_not_penalised() {
        // v = (0, x²): L = [[0, 0], [2x, 0]] at each particle, and the mean of the two
        // end-point gradients integrates a quadratic exactly
        let (xi, xj) = (Vector2::new(0.02, 0.0), Vector2::new(0.035, 0.01));
        let v = |x: &Vector2<Real>| Vector2::new(0.0, x[0] * x[0]);
        let l = |x: &Vector2<Real>| Matrix2::new(0.0, 0.0, 2.0 * x[0], 0.0).cast::<f32>();
        let d = non_affine(&(v(&xi) - v(&xj)), &(xi - xj), &l(&xi), &l(&xj));
        assert!(d.norm() < 1e-6 * (v(&xi) - v(&xj)).norm(), "{d}");
    }

    #[test]
    fn column_sliding_mode_is_penalised() {
        // neighbours in the next column move the other way; the SPH gradient of a
        // symmetric lattice sees nothing (L = 0), the penalty sees all of it
        let rij = Vector2::new(-0.01, 0.0);
        let vij = Vector2::new(0.0, 2e-3);
        let z = Matrix2::<f32>::zeros();
        assert_eq!(non_affine(&vij, &rij, &z, &z), vij);
    }

    #[test]
    fn pair_weights() {
        assert_eq!(pair_weight(1.0, 1.0), 1.0);
        assert_eq!(pair_weight(1.0, 0.0), 0.5);
        assert_eq!(pair_weight(0.0, 0.0), 0.0);
    }

    #[test]
    fn kept_share_of_the_penalty() {
        // G = 2 MPa, deviator with √(⅔ s:s) = 4 kPa: ε_e = 4e3 / 4e6 = 1e-3
        let g = 2e6;
        let s = Sym([-4e3, 0.0, 0.0, 0.0, 0.0, 0.0]);
        let dev = s.dev();
        let eps_e = (2.0 / 3.0 * dev.ddot(&dev)).sqrt() / (2.0 * g);
        assert_eq!(penalty_kept(&s, g, 0.0), 1.0);
        // grazing the yield surface keeps it, flowing forgets it
        assert!(penalty_kept(&s, g, 1e-9 * eps_e) > 0.999_999);
        assert!((penalty_kept(&s, g, 0.25 * eps_e) - 0.8).abs() < 1e-6);
        assert_eq!(penalty_kept(&s, g, eps_e), 0.0);
        assert_eq!(penalty_kept(&s, g, 1e3 * eps_e), 0.0);
        // at the apex (no deviator) any plastic strain releases it
        assert_eq!(penalty_kept(&Sym::iso(-1e3), g, 1e-12), 0.0);
    }
}
