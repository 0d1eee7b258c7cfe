//! The water–water pair terms of the momentum and continuity passes on cluster pairs
//! ([`clusters`](crate::pairs::clusters)), four neighbours at a time on [`Quad`] lanes (issue
//! 45, docs/method.md §Throughput).
//!
//! The terms are those of [`momentum::pair_pass`](super::momentum::pair_pass) (Zhang,
//! Hu & Adams 2017, Eqs. 7, 16–19, with Morris' viscosity and the corrected gradient)
//! and [`continuity::pair_pass`](super::continuity::pair_pass) (Eq. 15 with the
//! pressure jump relative to the hydrostatic state). The state they read is packed per
//! cluster, one array of four lanes per component ([`Block`]), so that a neighbour
//! cluster comes in whole vectors; one particle of the cluster is taken at a time
//! against them (its values broadcast), the pairs beyond the cut-off are masked out,
//! and the neighbour cluster's four sums go back with one vector add per component.
//! Each pair is evaluated once, as in the one-pair passes, and the sums run over the
//! cluster slabs in the two-phase schedule ([`slabs`](crate::pairs::slabs)), so they do not
//! depend on the thread count; the two instruction sets agree bitwise ([`quad`]).
//! The order of summation differs from the one-pair passes, so the two agree to
//! round-off (tested below).
//!
//! [`quad`]: crate::pairs::quad

// the terms loop over components of several lane arrays at once (x, v, B, their sums)
#![allow(clippy::needless_range_loop)]

use super::correction::Corr;
use super::momentum::{WaterParams, WaterSums};
use super::source::WaterSource;
use super::state::WaterParticles;
use crate::math::{Real, Vect};
use crate::pairs::cluster_pass::{
    at, each_lane, gather, geometry, lane_indices, run_pass, separation, unpack, ClusterPass,
    Geometry, Window, FAR,
};
use crate::pairs::clusters::ClusterPairs;
use crate::pairs::quad::{Lanes, Quad, WIDTH};
use rayon::prelude::*;

/// The state the pair terms read, for one particle of a cluster.
#[derive(Clone, Copy, Debug)]
pub struct Rec<const D: usize> {
    x: [Real; D],
    v: [Real; D],
    p: Real,
    vol: Real,
    rho: Real,
    /// The correction B, by row and column.
    b: [[Real; D]; D],
    /// The gravity the continuity's jump is taken relative to, with the seepage
    /// acceleration.
    g: [Real; D],
}

impl<const D: usize> Default for Rec<D> {
    fn default() -> Self {
        Rec {
            x: [FAR; D],
            v: [0.0; D],
            p: 0.0,
            vol: 0.0,
            rho: 0.0,
            b: [[0.0; D]; D],
            g: [0.0; D],
        }
    }
}

/// The state of the four particles of a cluster, one record each.
pub type Block<const D: usize> = [Rec<D>; WIDTH];

/// The pair sums of one particle of a cluster.
#[derive(Clone, Copy, Debug)]
pub struct Sums<const D: usize> {
    acc: [Real; D],
    drho: Real,
    /// M of the correction, upper triangle (row ≤ column).
    m: [[Real; D]; D],
}

impl<const D: usize> Default for Sums<D> {
    fn default() -> Self {
        Sums {
            acc: [0.0; D],
            drho: 0.0,
            m: [[0.0; D]; D],
        }
    }
}

/// The pair sums of the four particles of a cluster.
pub type LaneSums<const D: usize> = [Sums<D>; WIDTH];

/// The cluster-pair passes' buffers: the packed state and the sums.
#[derive(Clone, Debug, Default)]
pub struct WaterLanes<const D: usize> {
    blocks: Vec<Block<D>>,
    sums: Vec<LaneSums<D>>,
}

impl<const D: usize> WaterLanes<D> {
    /// Bytes held.
    pub fn bytes(&self) -> usize {
        self.blocks.capacity() * std::mem::size_of::<Block<D>>()
            + self.sums.capacity() * std::mem::size_of::<LaneSums<D>>()
    }

    /// Pack positions, velocities, pressure, volume and density of every cluster.
    pub fn pack(&mut self, cp: &ClusterPairs, w: &WaterParticles<D>, src: &[WaterSource]) {
        self.blocks.resize(cp.len(), Block::default());
        self.blocks.par_iter_mut().enumerate().for_each(|(c, b)| {
            *b = Block::default();
            for (l, i) in cp.members(c).enumerate() {
                for d in 0..D {
                    b[l].x[d] = w.pos[i][d];
                    b[l].v[d] = w.vel[i][d];
                }
                b[l].p = src[i].p;
                b[l].vol = src[i].vol;
                b[l].rho = src[i].rho;
            }
        });
    }

    /// Pack each particle's correction B, after [`pack`](Self::pack).
    pub fn pack_corr(&mut self, cp: &ClusterPairs, corr: &[Corr<D>]) {
        self.blocks.par_iter_mut().enumerate().for_each(|(c, b)| {
            for (l, i) in cp.members(c).enumerate() {
                for d in 0..D {
                    for e in 0..D {
                        b[l].b[d][e] = corr[i][(d, e)];
                    }
                }
            }
        });
    }

    /// The correction's water–water sums of M into `m` (added), on `lanes`, after
    /// [`pack`](Self::pack).
    pub fn correction(
        &mut self,
        cp: &ClusterPairs,
        prm: &WaterParams<D>,
        lanes: Lanes,
        m: &mut [Corr<D>],
    ) {
        run_pass(&Moment(prm), (&self.blocks, cp), lanes, &mut self.sums);
        unpack(cp, &self.sums, m, |o, s, l| {
            for d in 0..D {
                for e in d..D {
                    o[(d, e)] += s[l].m[d][e];
                    if e != d {
                        o[(e, d)] += s[l].m[d][e];
                    }
                }
            }
        });
    }

    /// Replace the velocities by `vel` and set the continuity's gravity: `hyd`, plus
    /// each particle's seepage acceleration `body` (empty: none).
    pub fn repack_velocity(
        &mut self,
        cp: &ClusterPairs,
        vel: &[Vect<D>],
        (hyd, body): (&Vect<D>, &[Vect<D>]),
    ) {
        self.blocks.par_iter_mut().enumerate().for_each(|(c, b)| {
            for (l, i) in cp.members(c).enumerate() {
                for d in 0..D {
                    b[l].v[d] = vel[i][d];
                    b[l].g[d] = hyd[d] + body.get(i).map_or(0.0, |a| a[d]);
                }
            }
        });
    }

    /// The momentum pass's water–water sums into `sums[..].acc` (added), on `lanes`.
    pub fn momentum(
        &mut self,
        cp: &ClusterPairs,
        prm: &WaterParams<D>,
        lanes: Lanes,
        sums: &mut [WaterSums<D>],
    ) {
        run_pass(&Momentum(prm), (&self.blocks, cp), lanes, &mut self.sums);
        self.unpack(cp, sums, |o, s, l| {
            for d in 0..D {
                o.acc[d] += s[l].acc[d];
            }
        });
    }

    /// The continuity pass's water–water sums into `sums[..].drho` (added), on
    /// `lanes`, after [`repack_velocity`](Self::repack_velocity).
    pub fn continuity(
        &mut self,
        cp: &ClusterPairs,
        prm: &WaterParams<D>,
        lanes: Lanes,
        sums: &mut [WaterSums<D>],
    ) {
        run_pass(&Continuity(prm), (&self.blocks, cp), lanes, &mut self.sums);
        self.unpack(cp, sums, |o, s, l| o.drho += s[l].drho);
    }

    /// Add each particle's lane sums to its entry of `sums` with `add`.
    fn unpack<F>(&self, cp: &ClusterPairs, sums: &mut [WaterSums<D>], add: F)
    where
        F: Fn(&mut WaterSums<D>, &LaneSums<D>, usize) + Sync,
    {
        unpack(cp, &self.sums, sums, add);
    }
}

/// The correction's pass: M_i = −Σ_j r ∂W/∂r e⊗e V_j
/// ([`correction`](super::correction)), its upper triangle.
struct Moment<'a, const D: usize>(&'a WaterParams<D>);

impl<const D: usize> ClusterPass for Moment<'_, D> {
    type Block = Block<D>;
    type Sums = LaneSums<D>;

    #[inline(always)]
    fn cluster<Q: Quad>(
        &self,
        q: Q,
        (blocks, cp): (&[Block<D>], &ClusterPairs),
        ci: usize,
        win: &mut Window<'_, LaneSums<D>>,
    ) {
        let prm = self.0;
        let zero = q.splat(0.0);
        let bi = &blocks[ci];
        let idx = lane_indices(q, cp, ci);
        let mut xi = [zero; D];
        for d in 0..D {
            xi[d] = gather(q, bi, |r| r.x[d]);
        }
        let voli = gather(q, bi, |r| r.vol);
        let mut own = [[zero; D]; D];
        for &j in cp.of(ci) {
            let j = j as usize;
            let cj = cp.of[j] as usize;
            let (bj, l) = (&blocks[cj], j - cp.start[cj] as usize);
            let rij = separation(q, &prm.wrap, &xi, &bj[l].x);
            let Geometry {
                m, r, inv_r, dw, ..
            } = geometry(q, &prm.kernel, &rij, (idx, j));
            if !q.any(m) {
                // beyond the cut-off of every lane (the lists' skin)
                continue;
            }
            let f = q.select(m, q.sub(zero, q.mul(r, dw)), zero);
            let volj = q.splat(bj[l].vol);
            let mut e = [zero; D];
            for d in 0..D {
                e[d] = q.mul(rij[d], inv_r);
            }
            // the upper triangle, row by row, into one array for the lane sums
            let mut tj = [zero; 6];
            let mut k = 0;
            for d in 0..D {
                for c in d..D {
                    let t = q.mul(q.mul(e[d], e[c]), f);
                    own[d][c] = q.add(own[d][c], q.mul(t, volj));
                    tj[k] = q.mul(t, voli);
                    k += 1;
                }
            }
            let sums = if D == 2 {
                let s = q.sums(&[tj[0], tj[1], tj[2]]);
                [s[0], s[1], s[2], 0.0, 0.0, 0.0]
            } else {
                q.sums(&tj)
            };
            let out = &mut win.at(cj)[l].m;
            let mut k = 0;
            for d in 0..D {
                for c in d..D {
                    out[d][c] += sums[k];
                    k += 1;
                }
            }
        }
        let out = win.at(ci);
        for d in 0..D {
            for c in d..D {
                each_lane(q, out, own[d][c], |s, t| s.m[d][c] += t);
            }
        }
    }
}

/// What the four lanes gain from a neighbour (times V_j) and what it gains from each
/// of them (times V_i), per component.
type OwnAndPartner<Q, const D: usize> = ([<Q as Quad>::V; D], [<Q as Quad>::V; D]);

/// The lanes of a cluster as its momentum terms read them.
struct MomentumLanes<Q: Quad, const D: usize> {
    idx: Q::V,
    x: [Q::V; D],
    v: [Q::V; D],
    b: [[Q::V; D]; D],
    p: Q::V,
    vol: Q::V,
}

/// The momentum term of the four lanes of a cluster against particle `j` (lane `l` of
/// block `bj`): what the lanes gain (times V_j) and what j gains from each (times
/// V_i, to be summed over the lanes and subtracted); zero outside the cut-off, and
/// none if no lane pairs with j.
#[inline(always)]
fn momentum_term<Q: Quad, const D: usize>(
    q: Q,
    prm: &WaterParams<D>,
    i: &MomentumLanes<Q, D>,
    (bj, l, j): (&Block<D>, usize, usize),
) -> Option<OwnAndPartner<Q, D>> {
    let zero = q.splat(0.0);
    let (half, one) = (q.splat(0.5), q.splat(1.0));
    let rij = separation(q, &prm.wrap, &i.x, &bj[l].x);
    let Geometry { m, inv_r, dw, .. } = geometry(q, &prm.kernel, &rij, (i.idx, j));
    if !q.any(m) {
        return None;
    }
    let mut e = [zero; D];
    let mut vij = [zero; D];
    // U_L − U_R = −v_ij·e
    let mut vie = zero;
    for d in 0..D {
        e[d] = q.mul(rij[d], inv_r);
        vij[d] = q.sub(i.v[d], q.splat(bj[l].v[d]));
        vie = q.add(vie, q.mul(vij[d], e[d]));
    }
    let du = q.sub(zero, vie);
    // β = min(η du/c0, 1) under compression, 0 in expansion (p_star)
    let eta_c = q.splat(prm.eta * prm.inv_c);
    let beta = q.select(q.lt(zero, du), q.min(q.mul(eta_c, du), one), zero);
    let mean = q.mul(half, q.add(i.p, q.splat(bj[l].p)));
    let ps = q.add(mean, q.mul(q.mul(q.mul(half, beta), q.splat(prm.z)), du));
    // B̄e = ½ (B_i + B_j) e
    let mut eh = [zero; D];
    for d in 0..D {
        eh[d] = q.mul(e[d], half);
    }
    let mut be = [zero; D];
    let mut ebe = zero;
    for d in 0..D {
        let mut s = zero;
        for c in 0..D {
            let bsum = q.add(i.b[d][c], q.splat(bj[l].b[d][c]));
            s = q.add(s, q.mul(bsum, eh[c]));
        }
        be[d] = s;
        ebe = q.add(ebe, q.mul(e[d], s));
    }
    // Morris' term with the corrected gradient: μ ∂W/∂r e·B̄e / r
    let visc = q.mul(q.mul(q.mul(q.splat(prm.mu), dw), inv_r), ebe);
    let pd = q.mul(q.sub(zero, ps), dw);
    let volj = q.splat(bj[l].vol);
    let (mut own, mut tj) = ([zero; D], [zero; D]);
    for d in 0..D {
        let t = q.add(q.mul(be[d], pd), q.mul(vij[d], visc));
        let t = q.select(m, t, zero);
        own[d] = q.mul(t, volj);
        tj[d] = q.mul(t, i.vol);
    }
    Some((own, tj))
}

/// The momentum pass.
struct Momentum<'a, const D: usize>(&'a WaterParams<D>);

impl<const D: usize> ClusterPass for Momentum<'_, D> {
    type Block = Block<D>;
    type Sums = LaneSums<D>;

    #[inline(always)]
    fn cluster<Q: Quad>(
        &self,
        q: Q,
        (blocks, cp): (&[Block<D>], &ClusterPairs),
        ci: usize,
        win: &mut Window<'_, LaneSums<D>>,
    ) {
        let prm = self.0;
        let zero = q.splat(0.0);
        let bi = &blocks[ci];
        let mut lanes = MomentumLanes::<Q, D> {
            idx: lane_indices(q, cp, ci),
            x: [zero; D],
            v: [zero; D],
            b: [[zero; D]; D],
            p: gather(q, bi, |r| r.p),
            vol: gather(q, bi, |r| r.vol),
        };
        for d in 0..D {
            lanes.x[d] = gather(q, bi, |r| r.x[d]);
            lanes.v[d] = gather(q, bi, |r| r.v[d]);
            for c in 0..D {
                lanes.b[d][c] = gather(q, bi, |r| r.b[d][c]);
            }
        }
        let mut own = [zero; D];
        for &j in cp.of(ci) {
            let (c, l, j) = at(cp, j);
            let Some((o, t)) = momentum_term(q, prm, &lanes, (&blocks[c], l, j)) else {
                continue;
            };
            for d in 0..D {
                own[d] = q.add(own[d], o[d]);
            }
            for (d, s) in q.sums(&t).into_iter().enumerate() {
                win.at(c)[l].acc[d] -= s;
            }
        }
        let out = win.at(ci);
        for d in 0..D {
            each_lane(q, out, own[d], |s, t| s.acc[d] += t);
        }
    }
}

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
struct Continuity<'a, const D: usize>(&'a WaterParams<D>);

impl<const D: usize> ClusterPass for Continuity<'_, D> {
    type Block = Block<D>;
    type Sums = LaneSums<D>;

    #[inline(always)]
    fn cluster<Q: Quad>(
        &self,
        q: Q,
        (blocks, cp): (&[Block<D>], &ClusterPairs),
        ci: usize,
        win: &mut Window<'_, LaneSums<D>>,
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
        let (mut t, mut to, mut k) = ([zero; 4], [(0, 0); 4], 0);
        for &j in cp.of(ci) {
            let (c, l, j) = at(cp, j);
            let Some((o, tj)) = continuity_term(q, prm, &lanes, (&blocks[c], l, j)) else {
                continue;
            };
            own = q.add(own, o);
            (t[k], to[k]) = (tj, (c, l));
            k += 1;
            if k == 4 {
                for ((c, l), s) in to.into_iter().zip(q.sums(&t)) {
                    win.at(c)[l].drho += s;
                }
                k = 0;
            }
        }
        for n in 0..k {
            let (c, l) = to[n];
            win.at(c)[l].drho += q.sum(t[n]);
        }
        each_lane(q, win.at(ci), own, |s, t| s.drho += t);
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::kernel::WendlandC2;
    use crate::math::Real;
    use crate::neighbors::{Binned, CellGrid, NeighborLists};
    use crate::periodic::{Period, Wrap};
    use crate::rng::Rng;
    use crate::water::{continuity, correction, momentum};

    /// A disordered block of water (spacing `dp`, ±30 % jitter), sorted by cell, its
    /// lists, and per-particle pressures, volumes, B and seepage accelerations that
    /// vary from particle to particle.
    #[allow(clippy::type_complexity)]
    fn cloud<const D: usize>(
        wrap: Wrap,
        seed: u64,
    ) -> (
        WaterParticles<D>,
        Vec<WaterSource>,
        Vec<Corr<D>>,
        Vec<Vect<D>>,
        NeighborLists,
        WaterParams<D>,
    ) {
        let dp = 0.01;
        let side = if D == 2 { [24, 17, 1] } else { [12, 8, 10] };
        let mut rng = Rng(seed);
        let mut w = WaterParticles::<D>::default();
        let mut u = || rng.uniform() - 0.5;
        for a in 0..side[0] {
            for b in 0..side[1] {
                for c in 0..side[2] {
                    let ijk = [a, b, c];
                    let x = Vect::<D>::from_fn(|d, _| (ijk[d] as Real + 0.6 * u()) * dp);
                    let v = Vect::<D>::from_fn(|_, _| 0.4 * u());
                    w.push(
                        x,
                        v,
                        1000.0 * (1.0 + 0.01 * u()),
                        1000.0 * dp.powi(D as i32),
                    );
                }
            }
        }
        if let Some(p) = wrap {
            w.pos.iter_mut().for_each(|x| p.wrap_point(x));
        }
        let kernel = WendlandC2::new(1.3 * dp, D);
        let radius = kernel.cutoff + 0.3 * dp;
        let lo = Vect::<D>::from_element(-0.05);
        let hi = Vect::<D>::from_fn(|d, _| side[d] as Real * dp + 0.05);
        let mut g = CellGrid::periodic(&lo, &hi, radius, wrap);
        g.bin(&w.pos);
        let order = g.order().to_vec();
        w.permute(&order, &mut Default::default());
        g.bin(&w.pos);
        let none = CellGrid::periodic(&lo, &hi, radius, wrap);
        let nb = |grid| Binned { pos: &[], grid };
        let mut lists = NeighborLists::default();
        lists.build(&w.pos, &g, nb(&none), nb(&none), radius, &wrap);
        let n = w.len();
        let src: Vec<WaterSource> = (0..n)
            .map(|i| WaterSource {
                p: 2000.0 * (1.0 + u()),
                vol: w.mass[i] / w.rho[i],
                rho: w.rho[i],
            })
            .collect();
        let corr: Vec<Corr<D>> = (0..n)
            .map(|_| Corr::<D>::identity() + Corr::<D>::from_fn(|_, _| 0.2 * u()))
            .collect();
        let body: Vec<Vect<D>> = (0..n).map(|_| Vect::<D>::from_fn(|_, _| u())).collect();
        let mut gravity = Vect::<D>::zeros();
        gravity[D - 1] = -9.81;
        let prm = WaterParams {
            kernel,
            gravity,
            hydrostatic: gravity,
            wrap,
            dt: 1e-5,
            z: 1000.0 * 30.0,
            inv_c: 1.0 / 30.0,
            eta: 3.0,
            mu: 1e-3,
            keep: 1.0,
            push_only: true,
        };
        (w, src, corr, body, lists, prm)
    }

    /// The cluster-pair sums equal the one-pair passes' to round-off (the order of
    /// summation differs), on both instruction sets, which agree bitwise; with and
    /// without a periodic seam, the limiter and a seepage acceleration, in 2D and 3D.
    fn lanes_match_one_pair<const D: usize>(wrap: Wrap, eta: Real, with_body: bool) {
        let (w, src, corr, body, lists, mut prm) = cloud::<D>(wrap, 11);
        prm.eta = eta;
        let body = if with_body { body } else { Vec::new() };
        let n = w.len();
        let mut want = vec![WaterSums::<D>::zero(); n];
        momentum::pair_pass(&w, &src, (&corr, &[]), &lists, &prm, &mut want);
        continuity::pair_pass(&w, &src, &lists, &prm, &body, &mut want);
        let mut want_m = vec![Corr::<D>::zeros(); n];
        let vol = |i: usize| src[i].vol;
        correction::pair_pass(&w, vol, &lists, (&prm.kernel, &prm.wrap), &mut want_m);
        let mut cp = ClusterPairs::default();
        cp.update(&lists, n);
        let mut runs = Vec::new();
        for lanes in [Lanes::portable(), Lanes::best()] {
            let mut buf = WaterLanes::<D>::default();
            let mut got = vec![WaterSums::<D>::zero(); n];
            buf.pack(&cp, &w, &src);
            let mut m = vec![Corr::<D>::zeros(); n];
            buf.correction(&cp, &prm, lanes, &mut m);
            let scale_m = want_m.iter().map(|m| m.norm()).fold(0.0, Real::max);
            for i in 0..n {
                let dm = (m[i] - want_m[i]).norm() / scale_m;
                assert!(dm < 1e-12, "{} particle {i}: M {dm:e}", lanes.name());
            }
            buf.pack_corr(&cp, &corr);
            buf.momentum(&cp, &prm, lanes, &mut got);
            buf.repack_velocity(&cp, &w.vel, (&prm.hydrostatic, &body));
            buf.continuity(&cp, &prm, lanes, &mut got);
            let scale_a = want.iter().map(|s| s.acc.norm()).fold(0.0, Real::max);
            let scale_d = want.iter().map(|s| s.drho.abs()).fold(0.0, Real::max);
            for i in 0..n {
                let da = (got[i].acc - want[i].acc).norm() / scale_a;
                let dd = (got[i].drho - want[i].drho).abs() / scale_d;
                assert!(
                    da < 1e-12 && dd < 1e-12,
                    "{} particle {i}: {da:e} {dd:e}",
                    lanes.name()
                );
            }
            runs.push((got, m));
        }
        let bits = |s: &[WaterSums<D>]| -> Vec<u64> {
            s.iter()
                .flat_map(|x| x.acc.iter().copied().chain([x.drho]))
                .map(f64::to_bits)
                .collect()
        };
        assert_eq!(
            bits(&runs[0].0),
            bits(&runs[1].0),
            "the two instruction sets differ"
        );
        let mbits = |m: &[Corr<D>]| -> Vec<u64> {
            m.iter()
                .flat_map(|x| x.iter().copied())
                .map(f64::to_bits)
                .collect()
        };
        assert_eq!(
            mbits(&runs[0].1),
            mbits(&runs[1].1),
            "M differs between the two"
        );
    }

    #[test]
    fn lanes_match_one_pair_2d() {
        lanes_match_one_pair::<2>(None, Real::INFINITY, false);
        lanes_match_one_pair::<2>(None, 3.0, true);
        let seam = Period {
            axis: 1,
            lo: 0.0,
            len: 0.17,
        };
        lanes_match_one_pair::<2>(Some(seam), 3.0, false);
    }

    #[test]
    fn lanes_match_one_pair_3d() {
        lanes_match_one_pair::<3>(None, Real::INFINITY, true);
        let seam = Period {
            axis: 2,
            lo: 0.0,
            len: 0.10,
        };
        lanes_match_one_pair::<3>(Some(seam), 3.0, false);
    }
}
