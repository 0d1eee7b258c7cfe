//! The fine–fine pair sums of one particle, filled by the pair passes of both sweeps
//! and read (and zeroed) by their particle passes.
//!
//! The momentum sweep's pair pass also takes the continuity sweep's terms that need no
//! velocity (the pressure jump of Eq. (19) and the stress diffusion of Eqs. (25)–(26)):
//! positions and σ_n do not change between the two sweeps, and it has each pair's
//! distance and kernel gradient at hand. The continuity sweep's pair pass then adds
//! only the terms in v_{n+1}.

use crate::numerics::math::{Real, Sym, Vect};
use nalgebra::SMatrix;

/// Both sweeps' pair sums of one particle.
#[derive(Clone, Copy, Debug)]
pub struct PairSums<const D: usize> {
    pub momentum: MomentumSums<D>,
    pub continuity: ContinuitySums<D>,
}

impl<const D: usize> PairSums<D> {
    pub fn zero() -> Self {
        PairSums {
            momentum: MomentumSums::zero(),
            continuity: ContinuitySums::zero(),
        }
    }
}

/// The momentum sweep's fine–fine pair sums of one particle, added from both sides
/// of each pair.
#[derive(Clone, Copy, Debug)]
pub struct MomentumSums<const D: usize> {
    /// Σ_j (σ̄ˢ_ij − P* I + f_ijⁿ R̄_ij)·e_ij ∂W/∂r V_j of Eq. (16) (times 2/ρ_i gives
    /// the acceleration).
    pub acc: Vect<D>,
    /// Σ_j s_ij ξḠ_ij ṽ_ij ∂W/∂r V_j / r_ij, the hourglass increment (times Δt/ρ_i).
    pub hourglass: Vect<D>,
}

impl<const D: usize> MomentumSums<D> {
    pub fn zero() -> Self {
        MomentumSums {
            acc: Vect::<D>::zeros(),
            hourglass: Vect::<D>::zeros(),
        }
    }
}

/// The continuity sweep's fine–fine pair sums of one particle, added from both sides
/// of each pair.
#[derive(Clone, Copy, Debug)]
pub struct ContinuitySums<const D: usize> {
    /// Σ_j 2 (U* − U_L) ∂W/∂r V_j of Eq. (15) (times ρ_i gives dρ_i/dt) is
    /// `drho + drho_v`: its pressure part from the momentum sweep's pair pass
    /// ([`JumpDiffusion`](super::continuity::JumpDiffusion)), its velocity part from the
    /// continuity sweep's.
    pub drho: Real,
    pub drho_v: Real,
    /// Σ_j −v_ij ⊗ e_ij ∂W/∂r V_j, Eq. (24).
    pub grad: SMatrix<Real, D, D>,
    /// Σ w, Σ w (r_ij·up), Σ w P_j and Σ w σˢ_j of Eq. (26), with
    /// w = r_ij·∇_i W_ij V_j/(r² + 0.01h²).
    pub w: Real,
    pub wz: Real,
    pub wp: Real,
    pub wdev: Sym,
}

impl<const D: usize> ContinuitySums<D> {
    pub fn zero() -> Self {
        ContinuitySums {
            drho: 0.0,
            drho_v: 0.0,
            grad: SMatrix::zeros(),
            w: 0.0,
            wz: 0.0,
            wp: 0.0,
            wdev: Sym::ZERO,
        }
    }
}
