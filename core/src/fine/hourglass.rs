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
//! return mapping (Eqs. 11–12) drops its accumulated penalty, and a pair with one
//! yielded particle counts at half weight (s_ij = ½(e_i + e_j), e = 1 when elastic).
//! Between two elastic particles each increment is antisymmetric (m_i Δa_ij =
//! −m_j Δa_ji with V = m/ρ), an internal force; a dropped penalty is not returned.

use crate::math::{Real, Vect};
use nalgebra::SMatrix;

/// Non-affine relative velocity ṽ_ij = v_ij − ½ (L_i + L_j) r_ij.
#[inline(always)]
pub fn non_affine<const D: usize>(
    vij: &Vect<D>,
    rij: &Vect<D>,
    li: &SMatrix<f32, D, D>,
    lj: &SMatrix<f32, D, D>,
) -> Vect<D> {
    let l = (li + lj).cast::<Real>();
    vij - l * rij * 0.5
}

/// Pair weight s_ij = ½(e_i + e_j) from the elastic flags of the pair.
#[inline(always)]
pub fn pair_weight(elastic_i: bool, elastic_j: bool) -> Real {
    0.5 * (elastic_i as u8 + elastic_j as u8) as Real
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
        assert_eq!(pair_weight(true, true), 1.0);
        assert_eq!(pair_weight(true, false), 0.5);
        assert_eq!(pair_weight(false, false), 0.0);
    }
}
