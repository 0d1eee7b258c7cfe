//! Momentum sweep of the fine grains, Eqs. (16), (20), (27) and (55).
//!
//! For each fine particle i:
//!   dv_i/dt = 2/ρ_i Σ_j (σ̄ˢ_ij − P* I + f_ijⁿ R̄_ij)·∇_i W_ij V_j + g + (interactions)
//! and v_{n+1} = v_n + Δt dv/dt (Eq. 55). The terms of walls and coarse grains are
//! interactions ([`interactions`](crate::interactions)); this module holds the
//! fine–fine terms and the update.
//!
//! The pair law is written once, on lanes ([`lanes`](super::lanes)): it evaluates each
//! fine–fine pair once and adds its terms to both particles' [`MomentumSums`]: σ̄ˢ_ij,
//! P* and the hourglass weight are symmetric in the pair and e_ji = −e_ij, so j
//! receives the negated traction weighted by V_i. The same pass takes the continuity
//! sweep's terms without velocity ([`JumpDiffusion`](super::continuity::JumpDiffusion),
//! [`pair_sums`](super::pair_sums)). The particle pass
//! ([`interactions::momentum_pass`](crate::interactions::momentum_pass)) turns the sums
//! into an acceleration ([`pair_acceleration`]), adds the interactions and
//! [`integrate`]s.

use super::material::FineMaterial;
use super::pair_sums::MomentumSums;
use super::state::FineParticles;
use crate::numerics::kernel::WendlandC2;
use crate::numerics::math::{Real, Vect};
use crate::numerics::periodic::Wrap;
use crate::numerics::riemann::Riemann;
use nalgebra::SVector;

/// Artificial-stress settings (cohesive materials only).
#[derive(Clone, Copy, Debug)]
pub struct ArtificialStress {
    /// Exponent n of Eq. (27).
    pub exponent: Real,
    /// W(dp, h).
    pub w_dp: Real,
}

/// Inputs of the momentum sweep that are not particle arrays.
pub struct MomentumParams<'a, const D: usize> {
    pub kernel: WendlandC2,
    pub riemann: Riemann,
    pub gravity: Vect<D>,
    pub dt: Real,
    pub artificial: Option<ArtificialStress>,
    /// Per material: ξ G of the hourglass penalty (empty: off).
    pub hourglass: &'a [Real],
    /// Per material: share of the stored penalty kept over the step, exp(−Δt c0/(N h)).
    pub hourglass_leak: &'a [f32],
    /// The fine materials (sound speed of a pair of different soils).
    pub materials: &'a [FineMaterial],
    /// All materials share one impedance and sound speed
    /// ([`uniform_acoustics`](super::material::uniform_acoustics)).
    pub uniform: bool,
    /// The periodic axis, if any: pairs across it take the minimum image.
    pub wrap: Wrap,
    /// MUSCL reconstruction of the Riemann jump (`numerics.muscl`).
    pub muscl: bool,
}

/// The acceleration of particle i from its fine–fine pair sums: (2/ρ_i) times the sum
/// of Eq. (16).
#[inline(always)]
pub fn pair_acceleration<const D: usize>(sum: &MomentumSums<D>, rho: Real) -> Vect<D> {
    sum.acc * (2.0 / rho)
}

/// Eq. (55) for particle i: v_{n+1} = v_n + Δt (a + a_hg + g), with `acc` the
/// acceleration of its pair sums and interactions, and the hourglass acceleration
/// `hg` advanced in place from the pair sums' increment `sum_hourglass`:
/// Δa_i = Δt/ρ_i Σ_j ..., accumulated on the share of the old one kept through
/// plastic flow (e_i) and over the step's relaxation.
#[inline(always)]
pub fn integrate<const D: usize>(
    p: &FineParticles<D>,
    prm: &MomentumParams<'_, D>,
    i: usize,
    acc: Vect<D>,
    sum_hourglass: &Vect<D>,
    hg: &mut SVector<f32, D>,
) -> Vect<D> {
    let mat = p.material[i] as usize;
    // hourglass penalty: ξ G_i while some of it is kept (0: off, or released by
    // plastic flow)
    let kept_i = p.hourglass_kept[i];
    let gi = if kept_i > 0.0 {
        prm.hourglass.get(mat).copied().unwrap_or(0.0)
    } else {
        0.0
    };
    *hg = if gi > 0.0 {
        *hg * (kept_i * prm.hourglass_leak[mat])
            + (sum_hourglass * (prm.dt / p.rho[i])).cast::<f32>()
    } else {
        SVector::zeros()
    };
    let acc = acc + hg.cast::<Real>();
    p.vel[i] + (acc + prm.gravity) * prm.dt
}
