//! Continuity of the water, water–water terms (Zhang, Hu & Adams 2017, Eq. 15), with
//! the new velocities v_{n+1}:
//!
//!   dρ_i/dt = 2ρ_i Σ_j (v_i − v*)·∇_i W_ij V_j = ρ_i Σ_j (v_ij·e_ij + ΔP_ij/Z) ∂W/∂r V_j
//!
//! with U* = ½(U_L + U_R) + (P_L − P_R)/(2Z) along the pair. The pressure jump acts as
//! a density diffusion (the Riemann counterpart of seed 001 Eq. 1's δ-term). granmix
//! takes it relative to the hydrostatic state, ΔP_ij = P_i − P_j − ρ̄_ij g·x_ij, as
//! Fourtakas et al. (2019) do for δ-SPH and seed 000 Eq. (26) does for the stress:
//! with the plain jump the diffusion does not vanish at hydrostatic rest near the free
//! surface and the floor, and keeps a resting tank moving.

use super::momentum::{WaterParams, WaterSums};
use super::source::WaterSource;
use super::state::WaterParticles;
use crate::math::Vect;
use crate::neighbors::NeighborLists;
use crate::pairs::block::{Pair, PairBlock, BLOCK};
use crate::pairs::slabs::two_phase;

/// Runs over the water–water relation (`NeighborLists::inner_of`).
///
/// The water–water continuity terms, each pair once, into `sums[..].drho`. `body`
/// holds each particle's acceleration from a soil's seepage force (empty: none),
/// which the equilibrium pressure gradient carries besides gravity:
/// ∇p = ρ (g + a_seep) under steady seepage, so the jump is taken relative to it.
pub fn pair_pass<const D: usize>(
    w: &WaterParticles<D>,
    src: &[WaterSource],
    lists: &NeighborLists,
    prm: &WaterParams<D>,
    body: &[Vect<D>],
    sums: &mut [WaterSums<D>],
) {
    let cut2 = prm.kernel.cutoff * prm.kernel.cutoff;
    let n = w.len();
    let (pos, vel, src) = (&w.pos[..n], &w.vel[..n], &src[..n]);
    let inv_z = 1.0 / prm.z;
    // the hydrostatic gradient ρ̄ g is taken out of the jump
    let hyd: Vect<D> = prm.hydrostatic;
    let slabs = &lists.slabs;
    two_phase(
        slabs,
        &mut sums[..n],
        &|s, win: &mut [WaterSums<D>], base| {
            let mut block = PairBlock::<D>::default();
            for i in slabs[s] as usize..slabs[s + 1] as usize {
                let (xi, vi, si) = (pos[i], vel[i], src[i]);
                let mut own = 0.0;

                for js in lists.inner_of(i).chunks(BLOCK) {
                    block.fill((&xi, js, pos), cut2, 0.0, &prm.wrap);
                    for Pair {
                        j, rij, r, inv_r, ..
                    } in block.pairs(0.0)
                    {
                        let sj = src[j];
                        let dw = prm.kernel.dw_within(r);
                        let u = (vi - vel[j]).dot(&rij) * inv_r;
                        let g = if body.is_empty() {
                            hyd
                        } else {
                            hyd + (body[i] + body[j]) * 0.5
                        };
                        let jump = (si.p - sj.p - 0.5 * (si.rho + sj.rho) * g.dot(&rij)) * inv_z;
                        own += (u + jump) * dw * sj.vol;
                        win[j - base].drho += (u - jump) * dw * si.vol;
                    }
                }
                win[i - base].drho += own;
            }
        },
    );
}
