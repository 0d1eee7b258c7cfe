//! The water–water pair terms of the momentum and continuity passes on cluster pairs
//! ([`clusters`](crate::clusters)), four neighbours at a time on [`Quad`] lanes (issue
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
//! cluster slabs in the two-phase schedule ([`slabs`](crate::slabs)), so they do not
//! depend on the thread count; the two instruction sets agree bitwise ([`quad`]).
//! The order of summation differs from the one-pair passes, so the two agree to
//! round-off (tested below).
//!
//! [`quad`]: crate::quad

use super::correction::Corr;
use super::momentum::{WaterParams, WaterSums};
use super::source::WaterSource;
use super::state::WaterParticles;
use crate::clusters::ClusterPairs;
use crate::math::{Real, Vect};
use crate::quad::{Lanes, Quad, QuadTask, WIDTH};
use crate::slabs::two_phase;
use rayon::prelude::*;

/// Where the lanes of a cluster with fewer than four particles sit: so far that no
/// pair with them is within the cut-off.
const FAR: Real = 1e30;

/// Lanes of one component.
type L = [Real; WIDTH];

/// The state the pair terms read, for the four particles of a cluster.
#[derive(Clone, Copy, Debug)]
pub struct Block<const D: usize> {
    x: [L; D],
    v: [L; D],
    p: L,
    vol: L,
    rho: L,
    /// The correction B, by row and column.
    b: [[L; D]; D],
    /// The gravity the continuity's jump is taken relative to, with the seepage
    /// acceleration.
    g: [L; D],
}

impl<const D: usize> Default for Block<D> {
    fn default() -> Self {
        Block {
            x: [[FAR; WIDTH]; D],
            v: [[0.0; WIDTH]; D],
            p: [0.0; WIDTH],
            vol: [0.0; WIDTH],
            rho: [0.0; WIDTH],
            b: [[[0.0; WIDTH]; D]; D],
            g: [[0.0; WIDTH]; D],
        }
    }
}

/// The pair sums of the four particles of a cluster.
#[derive(Clone, Copy, Debug)]
pub struct LaneSums<const D: usize> {
    acc: [L; D],
    drho: L,
}

impl<const D: usize> Default for LaneSums<D> {
    fn default() -> Self {
        LaneSums {
            acc: [[0.0; WIDTH]; D],
            drho: [0.0; WIDTH],
        }
    }
}

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

    /// Pack positions, velocities, pressure, volume, density and B of every cluster.
    pub fn pack(
        &mut self,
        cp: &ClusterPairs,
        w: &WaterParticles<D>,
        src: &[WaterSource],
        corr: &[Corr<D>],
    ) {
        self.blocks.resize(cp.len(), Block::default());
        self.blocks.par_iter_mut().enumerate().for_each(|(c, b)| {
            *b = Block::default();
            for (l, i) in cp.members(c).enumerate() {
                for d in 0..D {
                    b.x[d][l] = w.pos[i][d];
                    b.v[d][l] = w.vel[i][d];
                    for e in 0..D {
                        b.b[d][e][l] = corr[i][(d, e)];
                    }
                }
                b.p[l] = src[i].p;
                b.vol[l] = src[i].vol;
                b.rho[l] = src[i].rho;
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
                    b.v[d][l] = vel[i][d];
                    b.g[d][l] = hyd[d] + body.get(i).map_or(0.0, |a| a[d]);
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
        self.run(cp, |blocks, cp, s, win, base| {
            lanes.run(Momentum {
                blocks,
                cp,
                prm,
                slab: s,
                win,
                base,
            })
        });
        self.unpack(cp, sums, |o, s, l| {
            for d in 0..D {
                o.acc[d] += s.acc[d][l];
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
        self.run(cp, |blocks, cp, s, win, base| {
            lanes.run(Continuity {
                blocks,
                cp,
                prm,
                slab: s,
                win,
                base,
            })
        });
        self.unpack(cp, sums, |o, s, l| o.drho += s.drho[l]);
    }

    /// Zero the lane sums and run `task` on every cluster slab, two-phase.
    fn run<F>(&mut self, cp: &ClusterPairs, task: F)
    where
        F: Fn(&[Block<D>], &ClusterPairs, usize, &mut [LaneSums<D>], usize) + Sync,
    {
        self.sums.clear();
        self.sums.resize(cp.len(), LaneSums::default());
        let blocks = &self.blocks;
        two_phase(&cp.slabs, &mut self.sums, &|s, win: &mut [LaneSums<D>], base| {
            task(blocks, cp, s, win, base)
        });
    }

    /// Add each particle's lane sums to its entry of `sums` with `add`.
    fn unpack<F>(&self, cp: &ClusterPairs, sums: &mut [WaterSums<D>], add: F)
    where
        F: Fn(&mut WaterSums<D>, &LaneSums<D>, usize) + Sync,
    {
        let lane_sums = &self.sums;
        let start = &cp.start;
        sums.par_chunks_mut(1024)
            .enumerate()
            .for_each(|(k, out)| {
                let first = k * 1024;
                // the cluster of the chunk's first particle
                let mut c = start.partition_point(|&b| b as usize <= first) - 1;
                for (m, o) in out.iter_mut().enumerate() {
                    let i = first + m;
                    while start[c + 1] as usize <= i {
                        c += 1;
                    }
                    add(o, &lane_sums[c], i - start[c] as usize);
                }
            });
    }
}

/// Lane `l` of `v`, broadcast.
#[inline(always)]
fn bc<Q: Quad>(q: Q, v: &L, l: usize) -> Q::V {
    q.splat(v[l])
}

/// x_i − x_j of one particle against four, minimum images across a periodic seam.
#[inline(always)]
fn separation<Q: Quad, const D: usize>(
    q: Q,
    prm: &WaterParams<D>,
    (bi, k): (&Block<D>, usize),
    xj: &[Q::V; D],
) -> [Q::V; D] {
    let mut r = [q.splat(0.0); D];
    for d in 0..D {
        r[d] = q.sub(bc(q, &bi.x[d], k), xj[d]);
    }
    if let Some(p) = prm.wrap {
        let a = p.axis;
        let (half, len, zero) = (q.splat(0.5 * p.len), q.splat(p.len), q.splat(0.0));
        let up = q.select(q.lt(half, r[a]), len, zero);
        let down = q.select(q.lt(r[a], q.sub(zero, half)), len, zero);
        r[a] = q.add(q.sub(r[a], up), down);
    }
    r
}

/// The lanes of the diagonal cluster pair a particle in lane `k` pairs with (l > k).
#[inline(always)]
fn above<Q: Quad>(q: Q, k: usize) -> Q::M {
    let lane = q.load(&[0.0, 1.0, 2.0, 3.0]);
    q.lt(q.splat(k as Real), lane)
}

/// The lanes within the cut-off (and above `k` on the diagonal); r², r, 1/r and
/// ∂W/∂r there (r² = 1 elsewhere, to keep the arithmetic finite).
#[inline(always)]
fn geometry<Q: Quad, const D: usize>(
    q: Q,
    prm: &WaterParams<D>,
    rij: &[Q::V; D],
    diagonal: Option<usize>,
) -> (Q::M, Q::V, Q::V, Q::V) {
    let mut r2 = q.mul(rij[0], rij[0]);
    for x in rij.iter().skip(1) {
        r2 = q.add(r2, q.mul(*x, *x));
    }
    let cut = prm.kernel.cutoff;
    let mut m = q.lt(r2, q.splat(cut * cut));
    if let Some(k) = diagonal {
        m = q.and(m, above(q, k));
    }
    let one = q.splat(1.0);
    let r = q.sqrt(q.select(m, r2, one));
    let inv_r = q.div(one, r);
    // ∂W/∂r of the Wendland C2 kernel (WendlandC2::dw_within)
    let (inv_h, coef) = prm.kernel.dw_factors();
    let s = q.mul(r, q.splat(inv_h));
    let t = q.sub(one, q.mul(q.splat(0.5), s));
    let dw = q.mul(q.mul(q.mul(q.mul(q.splat(coef), s), t), t), t);
    (m, r, inv_r, dw)
}

/// One slab of the momentum pass.
struct Momentum<'a, const D: usize> {
    blocks: &'a [Block<D>],
    cp: &'a ClusterPairs,
    prm: &'a WaterParams<D>,
    slab: usize,
    win: &'a mut [LaneSums<D>],
    base: usize,
}

impl<const D: usize> QuadTask for Momentum<'_, D> {
    type Output = ();

    #[inline(always)]
    fn run<Q: Quad>(self, q: Q) {
        let Momentum {
            blocks,
            cp,
            prm,
            slab,
            win,
            base,
        } = self;
        let zero = q.splat(0.0);
        let (half, one) = (q.splat(0.5), q.splat(1.0));
        let (eta_c, z, mu) = (q.splat(prm.eta * prm.inv_c), q.splat(prm.z), q.splat(prm.mu));
        for ci in cp.slabs[slab] as usize..cp.slabs[slab + 1] as usize {
            let bi = &blocks[ci];
            let ni = cp.members(ci).len();
            let mut own = [[zero; D]; WIDTH];
            for &cj in cp.of(ci) {
                let cj = cj as usize;
                let bj = &blocks[cj];
                let mut xj = [zero; D];
                let mut vj = [zero; D];
                let mut bjm = [[zero; D]; D];
                for d in 0..D {
                    xj[d] = q.load(&bj.x[d]);
                    vj[d] = q.load(&bj.v[d]);
                    for e in 0..D {
                        bjm[d][e] = q.load(&bj.b[d][e]);
                    }
                }
                let (pj, volj) = (q.load(&bj.p), q.load(&bj.vol));
                let mut accj = [zero; D];
                for (k, own) in own.iter_mut().enumerate().take(ni) {
                    let rij = separation(q, prm, (bi, k), &xj);
                    let (m, _r, inv_r, dw) = geometry(q, prm, &rij, (cj == ci).then_some(k));
                    let mut e = [zero; D];
                    let mut vij = [zero; D];
                    // U_L − U_R = −v_ij·e
                    let mut vie = zero;
                    for d in 0..D {
                        e[d] = q.mul(rij[d], inv_r);
                        vij[d] = q.sub(bc(q, &bi.v[d], k), vj[d]);
                        vie = q.add(vie, q.mul(vij[d], e[d]));
                    }
                    let du = q.sub(zero, vie);
                    // β = min(η du/c0, 1) under compression, 0 in expansion (p_star)
                    let beta = q.select(q.lt(zero, du), q.min(q.mul(eta_c, du), one), zero);
                    let mean = q.mul(half, q.add(bc(q, &bi.p, k), pj));
                    let ps = q.add(mean, q.mul(q.mul(q.mul(half, beta), z), du));
                    // B̄e = ½ (B_i + B_j) e
                    let mut be = [zero; D];
                    let mut ebe = zero;
                    for d in 0..D {
                        let mut s = zero;
                        for c in 0..D {
                            let bsum = q.add(bc(q, &bi.b[d][c], k), bjm[d][c]);
                            s = q.add(s, q.mul(bsum, q.mul(e[c], half)));
                        }
                        be[d] = s;
                        ebe = q.add(ebe, q.mul(e[d], s));
                    }
                    // Morris' term with the corrected gradient: μ ∂W/∂r e·B̄e / r
                    let visc = q.mul(q.mul(q.mul(mu, dw), inv_r), ebe);
                    let pd = q.mul(q.sub(zero, ps), dw);
                    let voli = bc(q, &bi.vol, k);
                    for d in 0..D {
                        let t = q.add(q.mul(be[d], pd), q.mul(vij[d], visc));
                        let t = q.select(m, t, zero);
                        own[d] = q.add(own[d], q.mul(t, volj));
                        accj[d] = q.sub(accj[d], q.mul(t, voli));
                    }
                }
                let out = &mut win[cj - base].acc;
                for d in 0..D {
                    let s = q.add(q.load(&out[d]), accj[d]);
                    q.store(&mut out[d], s);
                }
            }
            let out = &mut win[ci - base].acc;
            for (k, own) in own.iter().enumerate().take(ni) {
                for d in 0..D {
                    out[d][k] += q.sum(own[d]);
                }
            }
        }
    }
}

/// One slab of the continuity pass.
struct Continuity<'a, const D: usize> {
    blocks: &'a [Block<D>],
    cp: &'a ClusterPairs,
    prm: &'a WaterParams<D>,
    slab: usize,
    win: &'a mut [LaneSums<D>],
    base: usize,
}

impl<const D: usize> QuadTask for Continuity<'_, D> {
    type Output = ();

    #[inline(always)]
    fn run<Q: Quad>(self, q: Q) {
        let Continuity {
            blocks,
            cp,
            prm,
            slab,
            win,
            base,
        } = self;
        let zero = q.splat(0.0);
        let (half, inv_z) = (q.splat(0.5), q.splat(1.0 / prm.z));
        for ci in cp.slabs[slab] as usize..cp.slabs[slab + 1] as usize {
            let bi = &blocks[ci];
            let ni = cp.members(ci).len();
            let mut own = [zero; WIDTH];
            for &cj in cp.of(ci) {
                let cj = cj as usize;
                let bj = &blocks[cj];
                let mut xj = [zero; D];
                let mut vj = [zero; D];
                let mut gj = [zero; D];
                for d in 0..D {
                    xj[d] = q.load(&bj.x[d]);
                    vj[d] = q.load(&bj.v[d]);
                    gj[d] = q.load(&bj.g[d]);
                }
                let (pj, volj, rhoj) = (q.load(&bj.p), q.load(&bj.vol), q.load(&bj.rho));
                let mut accj = zero;
                for (k, own) in own.iter_mut().enumerate().take(ni) {
                    let rij = separation(q, prm, (bi, k), &xj);
                    let (m, _r, inv_r, dw) = geometry(q, prm, &rij, (cj == ci).then_some(k));
                    // u = v_ij·x_ij / r; the jump relative to ρ̄ ḡ·x_ij
                    let (mut vx, mut gx) = (zero, zero);
                    for d in 0..D {
                        let vij = q.sub(bc(q, &bi.v[d], k), vj[d]);
                        vx = q.add(vx, q.mul(vij, rij[d]));
                        let g = q.mul(half, q.add(bc(q, &bi.g[d], k), gj[d]));
                        gx = q.add(gx, q.mul(g, rij[d]));
                    }
                    let u = q.mul(vx, inv_r);
                    let rho = q.mul(half, q.add(bc(q, &bi.rho, k), rhoj));
                    let dp = q.sub(bc(q, &bi.p, k), pj);
                    let jump = q.mul(q.sub(dp, q.mul(rho, gx)), inv_z);
                    let dw = q.select(m, dw, zero);
                    *own = q.add(*own, q.mul(q.mul(q.add(u, jump), dw), volj));
                    let voli = bc(q, &bi.vol, k);
                    accj = q.add(accj, q.mul(q.mul(q.sub(u, jump), dw), voli));
                }
                let out = &mut win[cj - base].drho;
                let s = q.add(q.load(out), accj);
                q.store(out, s);
            }
            let out = &mut win[ci - base].drho;
            for (k, own) in own.iter().enumerate().take(ni) {
                out[k] += q.sum(*own);
            }
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::kernel::WendlandC2;
    use crate::neighbors::{Binned, CellGrid, NeighborLists};
    use crate::periodic::{Period, Wrap};
    use crate::rng::Rng;
    use crate::water::{continuity, momentum};

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
                    w.push(x, v, 1000.0 * (1.0 + 0.01 * u()), 1000.0 * dp.powi(D as i32));
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
        let mut order = g.order().to_vec();
        if std::env::var("PROBE_SORT").is_ok() {
            let mut sl = Vec::new();
            g.slab_starts(&mut sl);
            let fast = if D == 2 { 1 } else { 1 };
            for s in 0..sl.len() - 1 {
                let (a, b) = (sl[s] as usize, sl[s + 1] as usize);
                let p = &w.pos;
                order[a..b].sort_by(|&i, &j| p[i as usize][fast].total_cmp(&p[j as usize][fast]));
            }
        }
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
        let mut cp = ClusterPairs::default();
        cp.update(&lists, n);
        let mut runs = Vec::new();
        for lanes in [Lanes::portable(), Lanes::best()] {
            let mut buf = WaterLanes::<D>::default();
            let mut got = vec![WaterSums::<D>::zero(); n];
            buf.pack(&cp, &w, &src, &corr);
            buf.momentum(&cp, &prm, lanes, &mut got);
            buf.repack_velocity(&cp, &w.vel, (&prm.hydrostatic, &body));
            buf.continuity(&cp, &prm, lanes, &mut got);
            let scale_a = want.iter().map(|s| s.acc.norm()).fold(0.0, Real::max);
            let scale_d = want.iter().map(|s| s.drho.abs()).fold(0.0, Real::max);
            for i in 0..n {
                let da = (got[i].acc - want[i].acc).norm() / scale_a;
                let dd = (got[i].drho - want[i].drho).abs() / scale_d;
                assert!(da < 1e-12 && dd < 1e-12, "{} particle {i}: {da:e} {dd:e}", lanes.name());
            }
            runs.push(got);
        }
        let bits = |s: &[WaterSums<D>]| -> Vec<u64> {
            s.iter()
                .flat_map(|x| x.acc.iter().copied().chain([x.drho]))
                .map(f64::to_bits)
                .collect()
        };
        assert_eq!(bits(&runs[0]), bits(&runs[1]), "the two instruction sets differ");
    }

    #[test]
    fn usage_probe() {
        let (w, _src, _corr, _body, lists, prm) = cloud::<2>(None, 11);
        let n = w.len();
        let mut cp = ClusterPairs::default();
        cp.update(&lists, n);
        let cut2 = prm.kernel.cutoff * prm.kernel.cutoff;
        let mut within = 0;
        let mut listed = 0;
        for i in 0..n {
            for &j in lists.inner_of(i) {
                listed += 1;
                if (w.pos[i] - w.pos[j as usize]).norm_squared() < cut2 {
                    within += 1;
                }
            }
        }
        let mut lanes = 0;
        for c in 0..cp.len() {
            for &cj in cp.of(c) {
                lanes += cp.members(c).len() * WIDTH;
                let _ = cj;
            }
        }
        let mut l41 = 0;
        for c in 0..cp.len() {
            let mut u: Vec<u32> = cp.members(c).flat_map(|i| lists.inner_of(i).iter().copied()).collect();
            u.extend(cp.members(c).map(|i| i as u32));
            u.sort_unstable();
            u.dedup();
            l41 += u.len() * WIDTH;
        }
        eprintln!("4x1 lanes {l41} useful {:.3}", within as f64 / l41 as f64);
        eprintln!("n {n} listed {listed} within {within} cluster pairs {} lanes {lanes} useful {:.3}", cp.pairs(), within as f64 / lanes as f64);
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
