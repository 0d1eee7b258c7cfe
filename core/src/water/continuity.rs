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
//!
//! The law is written once, on [`Quad`] lanes, and run by the cluster-pair executor
//! ([`WaterLanes::continuity`](super::lanes::WaterLanes::continuity)).

// the terms loop over components of several lane arrays at once (x, v, g)
#![allow(clippy::needless_range_loop)]

use super::lanes::{Block, WaterLanes};
use super::momentum::{WaterParams, WaterSums};
use crate::numerics::pairs::cluster_pass::run_pass;
use crate::numerics::pairs::cluster_pass::{
    at, each_lane, gather, geometry, lane_indices, separation, ClusterPass, Geometry, Window,
};
use crate::numerics::pairs::clusters::ClusterPairs;
use crate::numerics::pairs::quad::Lanes;
use crate::numerics::pairs::quad::Quad;

/// The lanes of a cluster as its continuity terms read them.
struct ContinuityLanes<Q: Quad, const D: usize> {
    idx: Q::V,
    x: [Q::V; D],
    v: [Q::V; D],
    g: [Q::V; D],
    p: Q::V,
    vol: Q::V,
    rho: Q::V,
}

/// The continuity term of the four lanes against particle `j`: what the lanes gain
/// (times V_j) and what j gains from each (times V_i, to be summed over the lanes);
/// none if no lane pairs with j.
#[inline(always)]
fn continuity_term<Q: Quad, const D: usize>(
    q: Q,
    prm: &WaterParams<D>,
    i: &ContinuityLanes<Q, D>,
    (bj, l, j): (&Block<D>, usize, usize),
) -> Option<(Q::V, Q::V)> {
    let zero = q.splat(0.0);
    let half = q.splat(0.5);
    let rij = separation(q, &prm.wrap, &i.x, &bj[l].x);
    let Geometry { m, inv_r, dw, .. } = geometry(q, &prm.kernel, &rij, (i.idx, j));
    if !q.any(m) {
        return None;
    }
    // u = v_ij·x_ij / r; the jump relative to ρ̄ ḡ·x_ij
    let (mut vx, mut gx) = (zero, zero);
    for d in 0..D {
        let vij = q.sub(i.v[d], q.splat(bj[l].v[d]));
        vx = q.add(vx, q.mul(vij, rij[d]));
        let g = q.mul(half, q.add(i.g[d], q.splat(bj[l].g[d])));
        gx = q.add(gx, q.mul(g, rij[d]));
    }
    let u = q.mul(vx, inv_r);
    let rho = q.mul(half, q.add(i.rho, q.splat(bj[l].rho)));
    let dp = q.sub(i.p, q.splat(bj[l].p));
    let jump = q.mul(q.sub(dp, q.mul(rho, gx)), q.splat(1.0 / prm.z));
    let dw = q.select(m, dw, zero);
    let own = q.mul(q.mul(q.add(u, jump), dw), q.splat(bj[l].vol));
    let tj = q.mul(q.mul(q.sub(u, jump), dw), i.vol);
    Some((own, tj))
}

/// The continuity pass.
pub(super) struct Continuity<'a, const D: usize>(pub(super) &'a WaterParams<D>);

impl<const D: usize> ClusterPass for Continuity<'_, D> {
    type Block = Block<D>;
    type Sums = WaterSums<D>;

    #[inline(always)]
    fn cluster<Q: Quad>(
        &self,
        q: Q,
        (blocks, cp): (&[Block<D>], &ClusterPairs),
        ci: usize,
        win: &mut Window<'_, WaterSums<D>>,
    ) {
        let prm = self.0;
        let zero = q.splat(0.0);
        let bi = &blocks[ci];
        let mut lanes = ContinuityLanes::<Q, D> {
            idx: lane_indices(q, cp, ci),
            x: [zero; D],
            v: [zero; D],
            g: [zero; D],
            p: gather(q, bi, |r| r.p),
            vol: gather(q, bi, |r| r.vol),
            rho: gather(q, bi, |r| r.rho),
        };
        for d in 0..D {
            lanes.x[d] = gather(q, bi, |r| r.x[d]);
            lanes.v[d] = gather(q, bi, |r| r.v[d]);
            lanes.g[d] = gather(q, bi, |r| r.g[d]);
        }
        let mut own = zero;
        // the neighbours' terms, four at a time into one lane sum
        let (mut t, mut to, mut k) = ([zero; 4], [0; 4], 0);
        for &j in cp.of(ci) {
            let (c, l, j) = at(cp, j);
            let Some((o, tj)) = continuity_term(q, prm, &lanes, (&blocks[c], l, j)) else {
                continue;
            };
            own = q.add(own, o);
            (t[k], to[k]) = (tj, j);
            k += 1;
            if k == 4 {
                for (j, s) in to.into_iter().zip(q.sums(&t)) {
                    win.at(j).drho += s;
                }
                k = 0;
            }
        }
        for n in 0..k {
            win.at(to[n]).drho += q.sum(t[n]);
        }
        each_lane(q, win.cluster(cp, ci), own, |s, t| s.drho += t);
    }
}

impl<const D: usize> WaterLanes<D> {
    /// The continuity pass's water–water sums into `sums[..].drho` (added), on
    /// `lanes`, after [`repack_velocity`](Self::repack_velocity).
    pub fn continuity(
        &mut self,
        cp: &ClusterPairs,
        prm: &WaterParams<D>,
        lanes: Lanes,
        sums: &mut [WaterSums<D>],
    ) {
        run_pass(&Continuity(prm), (&self.blocks, cp), lanes, sums);
    }
}
