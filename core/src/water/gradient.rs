//! The water's velocity gradient, corrected (Bonet & Lok 1999):
//!
//!   L_i = −Σ_j v_ij ⊗ ∇_i W_ij V_j,   ∇v_i = L_i B_i
//!
//! with B_i the pressure force's correction ([`correction`](super::correction)):
//! exact for a linear velocity field wherever B is (a full neighbourhood). With
//! `water.muscl` the momentum sweep reconstructs each pair's velocities to its midpoint
//! with it, so that the Riemann dissipation acts only on what a linear field does not
//! explain ([`momentum`](super::momentum)).

use super::correction::Corr;
use super::state::WaterParticles;
use crate::kernel::WendlandC2;
use crate::math::Real;
use crate::neighbors::NeighborLists;
use crate::pairs::block::{Pair, PairBlock, BLOCK};
use crate::pairs::slabs::two_phase;
use crate::periodic::Wrap;

/// Runs over the water–water relation (`NeighborLists::inner_of`).
///
/// The water–water terms of L, each pair once, into `l` (zero on entry).
pub fn pair_pass<const D: usize>(
    w: &WaterParticles<D>,
    vol: impl Fn(usize) -> Real + Sync,
    lists: &NeighborLists,
    (kernel, wrap): (&WendlandC2, &Wrap),
    l: &mut [Corr<D>],
) {
    let cut2 = kernel.cutoff * kernel.cutoff;
    let n = w.len();
    let (pos, vel) = (&w.pos[..n], &w.vel[..n]);
    let slabs = &lists.slabs;
    two_phase(slabs, &mut l[..n], &|s, win: &mut [Corr<D>], base| {
        let mut block = PairBlock::<D>::default();
        for i in slabs[s] as usize..slabs[s + 1] as usize {
            let (xi, vi, voli) = (pos[i], vel[i], vol(i));
            let mut own = Corr::<D>::zeros();
            for js in lists.inner_of(i).chunks(BLOCK) {
                block.fill((&xi, js, pos), cut2, 0.0, wrap);
                for Pair {
                    j, rij, r, inv_r, ..
                } in block.pairs(0.0)
                {
                    // −v_ij ⊗ ∇_i W for i; for j, −v_ji ⊗ ∇_j W is the same tensor
                    let q = (vi - vel[j]) * (rij * inv_r).transpose() * (-kernel.dw_within(r));
                    own += q * vol(j);
                    win[j - base] += q * voli;
                }
            }
            win[i - base] += own;
        }
    });
}
