//! Momentum of the water, water–water terms (Zhang, Hu & Adams 2017, Eqs. 7, 16–19;
//! seed 001 Eq. 2 with the Riemann solver in place of Monaghan's viscosity):
//!
//!   dv_i/dt = (2/ρ_i) Σ_j ( −P*_ij ∇_i W_ij + μ v_ij (x_ij·∇_i W_ij)/(r² + 0.01h²) ) V_j + g
//!
//! P* = ½(P_i + P_j) + ½ β ρ_w c0 (U_L − U_R), U = −v·e_ij (the linearised Riemann
//! problem along the pair, seed 000 Eqs. 19–21): dissipation under compression only,
//! as in Zhang et al. (2017). Their limiter β = min(η max(U_L − U_R, 0)/c0, 1) (η = 3)
//! is optional (`water.limiter`); by default β = 1 under compression, which the resting
//! tank and the dam break of docs/method.md §Water measured as the better choice.
//! With `water.muscl` the jump U_L − U_R is taken between the velocities reconstructed
//! to the pair's midpoint ([`reconstructed_jump`]), so that the dissipation vanishes
//! for a linear velocity field: a standing wave's log decrement falls from 0.63 to 0.12
//! per period at h/50, and a resting tank still settles (docs/method.md §Water).
//! The viscous term is Morris et al. (1997) Eq. (8).
//! Each pair is evaluated once and added to both particles with opposite signs
//! (two-phase slab schedule, [`slabs`](crate::pairs::slabs)), so Σ m_i dv_i/dt of the pair
//! terms is zero to round-off.

use super::correction::Corr;
use super::source::WaterSource;
use super::state::WaterParticles;
use crate::kernel::WendlandC2;
use crate::math::{Real, Vect};
use crate::neighbors::NeighborLists;
use crate::pairs::block::{Pair, PairBlock, BLOCK};
use crate::pairs::slabs::two_phase;
use crate::periodic::Wrap;

/// Constants of the water sweeps for one step.
#[derive(Clone, Copy, Debug)]
pub struct WaterParams<const D: usize> {
    pub kernel: WendlandC2,
    pub gravity: Vect<D>,
    /// The gravity of the hydrostatic state: g without its component along a
    /// periodic axis, where no hydrostatic gradient can build (a body force there
    /// drives a flow, seed 001 §2.1).
    pub hydrostatic: Vect<D>,
    /// The periodic axis, if any: pairs across it take the minimum image.
    pub wrap: Wrap,
    pub dt: Real,
    /// Acoustic impedance ρ_w c0.
    pub z: Real,
    /// 1/c0.
    pub inv_c: Real,
    /// Limiter coefficient η (∞: none).
    pub eta: Real,
    /// Dynamic viscosity μ.
    pub mu: Real,
    /// Share of the velocity kept over the step: exp(−Δt/τ) while the settling
    /// damping is on, 1 otherwise.
    pub keep: Real,
    /// Walls and barriers push and never pull (P* ≥ 0 at them): free water has no
    /// tensile strength. False with a saturated soil, whose pore water keeps the
    /// suction it builds ([`WaterMaterial::walls_push_only`]), and for water without a
    /// free surface (a closed channel), whose pressure has no reference level: there
    /// the clamp would turn its fluctuations about zero into a net push.
    ///
    /// [`WaterMaterial::walls_push_only`]: super::material::WaterMaterial::walls_push_only
    pub push_only: bool,
}

/// Per-particle sums of the pair passes.
#[derive(Clone, Copy, Debug)]
pub struct WaterSums<const D: usize> {
    /// Σ (−P* e dW + μ v_ij r² dW/(r (r² + 0.01h²))) V_j; times 2/ρ_i is dv_i/dt.
    pub acc: Vect<D>,
    /// Σ (v_ij·e + ΔP/Z) dW V_j; times ρ_i is dρ_i/dt.
    pub drho: Real,
}

impl<const D: usize> WaterSums<D> {
    pub fn zero() -> Self {
        WaterSums {
            acc: Vect::<D>::zeros(),
            drho: 0.0,
        }
    }
}

/// P* of the pair (i, j) along e = e_ij: ½(P_i + P_j) + ½ β Z (U_L − U_R).
#[inline(always)]
pub fn p_star<const D: usize>(prm: &WaterParams<D>, pi: Real, pj: Real, du: Real) -> Real {
    // β = 0 in expansion; η = ∞ (no limiter) gives β = 1 in compression
    let beta = if du > 0.0 {
        (prm.eta * du * prm.inv_c).min(1.0)
    } else {
        0.0
    };
    0.5 * (pi + pj) + 0.5 * beta * prm.z * du
}

/// The jump U_L − U_R = `du` of a pair (i, j) at distance `r` along `e` with both
/// velocities reconstructed to the pair's midpoint by the particles' gradients
/// (v_i − ½ ∇v_i r e and v_j + ½ ∇v_j r e; MUSCL, van Leer 1979, as Vila (1999) brings
/// it to SPH), and limited by minmod against the jump itself: zero for a linear field,
/// the raw jump where the reconstruction would exceed it, zero where the two disagree
/// in sign.
#[inline(always)]
pub fn reconstructed_jump<const D: usize>(
    du: Real,
    r: Real,
    e: &Vect<D>,
    (gi, gj): (&Corr<D>, &Corr<D>),
) -> Real {
    let rec = du + 0.5 * r * e.dot(&((gi + gj) * e));
    crate::riemann::minmod_jump(du, rec)
}

/// Runs over the water–water relation (`NeighborLists::inner_of`).
///
/// The water–water momentum terms, each pair once, into `sums[..].acc`; `corr` holds
/// each particle's correction B ([`correction`](super::correction)), the pair's
/// pressure force taken along ½(B_i + B_j)·∇_i W; `grad` each particle's velocity
/// gradient ([`gradient`](super::gradient)) with `water.muscl`, empty without.
pub fn pair_pass<const D: usize>(
    w: &WaterParticles<D>,
    src: &[WaterSource],
    (corr, grad): (&[Corr<D>], &[Corr<D>]),
    lists: &NeighborLists,
    prm: &WaterParams<D>,
    sums: &mut [WaterSums<D>],
) {
    let muscl = !grad.is_empty();
    let cut2 = prm.kernel.cutoff * prm.kernel.cutoff;
    // Morris' 0.01h² guards 1/r² at r → 0; the Wendland kernel's ∂W/∂r/r stays finite
    // there, and the guard would cut the viscous stress by about 1 % at any resolution
    // (Poiseuille flow, docs/method.md §Water)
    let reg = 0.0;
    let n = w.len();
    let (pos, vel, src, corr) = (&w.pos[..n], &w.vel[..n], &src[..n], &corr[..n]);
    let slabs = &lists.slabs;
    two_phase(
        slabs,
        &mut sums[..n],
        &|s, win: &mut [WaterSums<D>], base| {
            let mut block = PairBlock::<D>::default();
            for i in slabs[s] as usize..slabs[s + 1] as usize {
                let (xi, vi, si) = (pos[i], vel[i], src[i]);
                let mut own = Vect::<D>::zeros();
                for js in lists.inner_of(i).chunks(BLOCK) {
                    block.fill((&xi, js, pos), cut2, reg, &prm.wrap);
                    for Pair {
                        j,
                        rij,
                        r,
                        inv_r,
                        inv,
                    } in block.pairs(reg)
                    {
                        let sj = src[j];
                        let e = rij * inv_r;
                        let dw = prm.kernel.dw_within(r);
                        let vij = vi - vel[j];
                        // U_L − U_R = −v_i·e + v_j·e
                        let mut du = -vij.dot(&e);
                        if muscl {
                            du = reconstructed_jump(du, r, &e, (&grad[i], &grad[j]));
                        }
                        let ps = p_star(prm, si.p, sj.p, du);
                        let be = (corr[i] + corr[j]) * (e * 0.5);
                        // Morris' x_ij·∇W with the corrected gradient: r ∂W/∂r e·B̄e
                        let visc = prm.mu * r * r * dw * inv * e.dot(&be);
                        let t = be * (-ps * dw) + vij * visc;
                        own += t * sj.vol;
                        win[j - base].acc -= t * si.vol;
                    }
                }
                win[i - base].acc += own;
            }
        },
    );
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A linear velocity field leaves no jump to dissipate; a jump the gradients do not
    /// explain keeps the part they do not, and the raw jump bounds it.
    #[test]
    fn reconstruction_removes_the_linear_part() {
        let g = Corr::<2>::new(0.3, -0.2, 0.5, 0.1);
        let (e, r) = (Vect::<2>::new(0.6, 0.8), 0.013);
        // v_i − v_j = G r_ij for a linear field: U_L − U_R = −(G r e)·e
        let du = -(g * e * r).dot(&e);
        assert!(reconstructed_jump(du, r, &e, (&g, &g)).abs() < 1e-18);
        // twice the linear jump: half of it is left
        let left = reconstructed_jump(2.0 * du, r, &e, (&g, &g));
        assert!((left - du).abs() < 1e-15, "{left} {du}");
        // no gradient: the raw jump
        let z = Corr::<2>::zeros();
        assert_eq!(reconstructed_jump(du, r, &e, (&z, &z)), du);
        // gradients that overshoot flip the sign: nothing
        assert_eq!(reconstructed_jump(du, r, &e, (&(g * 3.0), &(g * 3.0))), 0.0);
    }
}
