//! The water's velocity gradient, corrected (Bonet & Lok 1999):
//!
//!   L_i = −Σ_j v_ij ⊗ ∇_i W_ij V_j,   ∇v_i = L_i B_i
//!
//! with B_i the pressure force's correction ([`correction`](super::correction)):
//! exact for a linear velocity field wherever B is (a full neighbourhood). With
//! `water.muscl` the momentum sweep reconstructs each pair's velocities to its midpoint
//! with it, so that the Riemann dissipation acts only on what a linear field does not
//! explain ([`momentum`](super::momentum)).

//!
//! The water–water sum of L is written once, on [`Quad`] lanes ([`Gradient`]), and
//! run by the cluster-pair executor
//! ([`WaterLanes::gradient`](super::lanes::WaterLanes::gradient)).

// the terms loop over the rows and columns of L
#![allow(clippy::needless_range_loop)]

use super::correction::Corr;
use super::lanes::{rows, Block, WaterLanes};
use super::momentum::WaterParams;
use crate::numerics::pairs::cluster_pass::{
    at, each_lane, gather, geometry, lane_indices, separation, ClusterPass, Geometry, Window,
};
use crate::numerics::pairs::cluster_pass::{repack, run_pass};
use crate::numerics::pairs::clusters::ClusterPairs;
use crate::numerics::pairs::quad::Lanes;
use crate::numerics::pairs::quad::Quad;

/// The velocity gradient's pass: L_i = −Σ_j v_ij ⊗ e_ij ∂W/∂r V_j; for j, −v_ji ⊗
/// ∇_j W is the same tensor, times V_i.
pub(super) struct Gradient<'a, const D: usize>(pub(super) &'a WaterParams<D>);

impl<const D: usize> ClusterPass for Gradient<'_, D> {
    type Block = Block<D>;
    type Sums = Corr<D>;

    #[inline(always)]
    fn cluster<Q: Quad>(
        &self,
        q: Q,
        (blocks, cp): (&[Block<D>], &ClusterPairs),
        ci: usize,
        win: &mut Window<'_, Corr<D>>,
    ) {
        let prm = self.0;
        let zero = q.splat(0.0);
        let bi = &blocks[ci];
        let idx = lane_indices(q, cp, ci);
        let (mut xi, mut vi) = ([zero; D], [zero; D]);
        for d in 0..D {
            xi[d] = gather(q, bi, |r| r.x[d]);
            vi[d] = gather(q, bi, |r| r.v[d]);
        }
        let voli = gather(q, bi, |r| r.vol);
        let mut own = [[zero; D]; D];
        for &j in cp.of(ci) {
            let (c, l, j) = at(cp, j);
            let bj = &blocks[c];
            let rij = separation(q, &prm.wrap, &xi, &bj[l].x);
            let Geometry { m, inv_r, dw, .. } = geometry(q, &prm.kernel, &rij, (idx, j));
            if !q.any(m) {
                continue;
            }
            let f = q.select(m, q.sub(zero, dw), zero);
            let volj = q.splat(bj[l].vol);
            // −v_ij ⊗ e ∂W/∂r, row by row into one array for the lane sums
            let mut tj = [zero; 9];
            for a in 0..D {
                let g = q.mul(q.sub(vi[a], q.splat(bj[l].v[a])), f);
                for b in 0..D {
                    let t = q.mul(g, q.mul(rij[b], inv_r));
                    own[a][b] = q.add(own[a][b], q.mul(t, volj));
                    tj[a * D + b] = q.mul(t, voli);
                }
            }
            let s = if D == 2 {
                let s = q.sums(&[tj[0], tj[1], tj[2], tj[3]]);
                let mut out = [0.0; 9];
                out[..4].copy_from_slice(&s);
                out
            } else {
                q.sums(&tj)
            };
            let out = win.at(j);
            for a in 0..D {
                for b in 0..D {
                    out[(a, b)] += s[a * D + b];
                }
            }
        }
        let out = win.cluster(cp, ci);
        for a in 0..D {
            for b in 0..D {
                each_lane(q, out, own[a][b], |m, t| m[(a, b)] += t);
            }
        }
    }
}

impl<const D: usize> WaterLanes<D> {
    /// Pack each particle's corrected velocity gradient ∇v (`water.muscl`), after
    /// [`pack`](Self::pack).
    pub fn pack_grad(&mut self, cp: &ClusterPairs, grad: &[Corr<D>]) {
        repack(&mut self.blocks, cp, |r, i| r.gv = rows(&grad[i]));
    }

    /// The velocity gradient's water–water sums of L into `l` (added), on `lanes`,
    /// after [`pack`](Self::pack).
    pub fn gradient(
        &mut self,
        cp: &ClusterPairs,
        prm: &WaterParams<D>,
        lanes: Lanes,
        l: &mut [Corr<D>],
    ) {
        run_pass(&Gradient(prm), (&self.blocks, cp), lanes, l);
    }
}
