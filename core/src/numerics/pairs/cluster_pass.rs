//! What the cluster-pair passes of every family share (issue 45, docs/method.md
//! §Throughput): the pair geometry of a cluster's four particles against one
//! neighbour on [`Quad`] lanes, the two-phase schedule over cluster slabs, and the
//! return of the lane sums to the particles.
//!
//! A pass packs the state its terms read per cluster ([`clusters`](crate::numerics::pairs::clusters)),
//! one record per particle: a neighbour's values are read from its record, a few cache
//! lines, and broadcast ([`Quad::splat`]); a cluster's own four records are gathered
//! into the lanes once ([`gather`]). Its sums go straight into the family's sums, one
//! entry per particle: a neighbour's are added to its entry, a cluster's own lane by
//! lane ([`each_lane`]).
//! Pairs beyond the cut-off, or with j ≤ i, are masked out, so each pair is taken once,
//! as in the one-pair passes; the sums a neighbour gains from the four lanes are added
//! across the lanes in one fixed order ([`Quad::sums`]).

use crate::numerics::kernel::WendlandC2;
use crate::numerics::math::Real;
use crate::numerics::pairs::clusters::ClusterPairs;
use crate::numerics::pairs::quad::{Lanes, Quad, QuadTask, WIDTH};
use crate::numerics::pairs::slabs::two_phase_in;
use crate::numerics::periodic::Wrap;
use rayon::prelude::*;

/// Where the lanes of a cluster with fewer than four particles sit: so far that no
/// pair with them is within the cut-off.
pub const FAR: Real = 1e30;

/// x_i − x_j of the four particles of a cluster (`xi`) against particle j at `xj`,
/// minimum images across a periodic seam.
#[inline(always)]
pub fn separation<Q: Quad, const D: usize>(
    q: Q,
    wrap: &Wrap,
    xi: &[Q::V; D],
    xj: &[Real; D],
) -> [Q::V; D] {
    let mut r = *xi;
    for d in 0..D {
        r[d] = q.sub(xi[d], q.splat(xj[d]));
    }
    if let Some(p) = wrap {
        let a = p.axis;
        let (half, len, zero) = (q.splat(0.5 * p.len), q.splat(p.len), q.splat(0.0));
        let up = q.select(q.lt(half, r[a]), len, zero);
        let down = q.select(q.lt(r[a], q.sub(zero, half)), len, zero);
        r[a] = q.add(q.sub(r[a], up), down);
    }
    r
}

/// Field `f` of a cluster's four records (`recs`, one per particle) on the lanes.
#[inline(always)]
pub fn gather<Q: Quad, R>(q: Q, recs: &[R; WIDTH], f: impl Fn(&R) -> Real) -> Q::V {
    q.load(&[f(&recs[0]), f(&recs[1]), f(&recs[2]), f(&recs[3])])
}

/// Pack one record per particle, four to a cluster: `blocks` gets one entry per
/// cluster of `cp`, every record reset to its default (the lanes of a cluster with
/// fewer than four particles stay so: far away, [`FAR`]) and `fill(record, particle)`
/// called for each particle.
pub fn pack<R: Default + Send>(
    blocks: &mut Vec<[R; WIDTH]>,
    cp: &ClusterPairs,
    fill: impl Fn(&mut R, usize) + Sync,
) {
    blocks.resize_with(cp.len(), Default::default);
    blocks.par_iter_mut().enumerate().for_each(|(c, b)| {
        *b = Default::default();
        for (l, i) in cp.members(c).enumerate() {
            fill(&mut b[l], i);
        }
    });
}

/// `set(record, particle)` for every particle's record of `blocks`, packed by [`pack`].
pub fn repack<R: Send>(
    blocks: &mut [[R; WIDTH]],
    cp: &ClusterPairs,
    set: impl Fn(&mut R, usize) + Sync,
) {
    blocks.par_iter_mut().enumerate().for_each(|(c, b)| {
        for (l, i) in cp.members(c).enumerate() {
            set(&mut b[l], i);
        }
    });
}

/// `op(sums of lane l, lane l of v)` for the lanes of a cluster (`sums` holds its
/// particles' sums, at most four): how a cluster's own lane sums go back to its
/// particles (`|s, t| s.acc[d] += t`).
#[inline(always)]
pub fn each_lane<Q: Quad, S>(q: Q, sums: &mut [S], v: Q::V, op: impl Fn(&mut S, Real)) {
    let mut t = [0.0; WIDTH];
    q.store(&mut t, v);
    for (s, t) in sums.iter_mut().zip(t) {
        op(s, t);
    }
}

/// One lane pass's pair geometry: which lanes pair, and r², r, 1/r and ∂W/∂r there.
pub struct Geometry<Q: Quad> {
    /// Within the cut-off and i < j.
    pub m: Q::M,
    /// r² (1 outside `m`, to keep the arithmetic finite).
    pub r2: Q::V,
    pub r: Q::V,
    pub inv_r: Q::V,
    pub dw: Q::V,
}

/// The lanes that pair with particle `j`: within the cut-off and i < j (`idx` holds
/// the lanes' particle indices), with the kernel's ∂W/∂r.
#[inline(always)]
pub fn geometry<Q: Quad, const D: usize>(
    q: Q,
    kernel: &WendlandC2,
    rij: &[Q::V; D],
    (idx, j): (Q::V, usize),
) -> Geometry<Q> {
    let mut r2 = q.mul(rij[0], rij[0]);
    for x in rij.iter().skip(1) {
        r2 = q.add(r2, q.mul(*x, *x));
    }
    let cut = kernel.cutoff;
    let m = q.and(q.lt(r2, q.splat(cut * cut)), q.lt(idx, q.splat(j as Real)));
    let one = q.splat(1.0);
    let r2 = q.select(m, r2, one);
    let r = q.sqrt(r2);
    let inv_r = q.div(one, r);
    // ∂W/∂r of the Wendland C2 kernel (WendlandC2::dw_within)
    let (inv_h, coef) = kernel.dw_factors();
    let s = q.mul(r, q.splat(inv_h));
    let t = q.sub(one, q.mul(q.splat(0.5), s));
    let dw = q.mul(q.mul(q.mul(q.mul(q.splat(coef), s), t), t), t);
    Geometry {
        m,
        r2,
        r,
        inv_r,
        dw,
    }
}

/// The particle indices of cluster `c`'s lanes.
#[inline(always)]
pub fn lane_indices<Q: Quad>(q: Q, cp: &ClusterPairs, c: usize) -> Q::V {
    let first = cp.start[c] as Real;
    q.add(q.splat(first), q.load(&[0.0, 1.0, 2.0, 3.0]))
}

/// Particle `j`'s cluster, its lane there, and `j`.
#[inline(always)]
pub fn at(cp: &ClusterPairs, j: u32) -> (usize, usize, usize) {
    let j = j as usize;
    let c = cp.of[j] as usize;
    (c, j - cp.start[c] as usize, j)
}

/// The sums a slab's task may write, one per particle: those of its own particles and
/// of the next slab's ([`two_phase_in`]).
pub struct Window<'a, S> {
    sums: &'a mut [S],
    /// The particle of `sums[0]`.
    base: usize,
}

impl<S> Window<'_, S> {
    /// The sums of particle `j`.
    #[inline(always)]
    pub fn at(&mut self, j: usize) -> &mut S {
        &mut self.sums[j - self.base]
    }

    /// The sums of the particles of cluster `c`, in lane order.
    #[inline(always)]
    pub fn cluster(&mut self, cp: &ClusterPairs, c: usize) -> &mut [S] {
        let (a, b) = (cp.start[c] as usize, cp.start[c + 1] as usize);
        &mut self.sums[a - self.base..b - self.base]
    }
}

/// A cluster-pair pass: the state it reads per cluster ([`Block`](Self::Block)), the
/// sums it adds per particle ([`Sums`](Self::Sums)), and its terms for one cluster
/// against every particle of the cluster's list.
pub trait ClusterPass: Sync {
    type Block: Sync;
    type Sums: Send;
    /// The terms of cluster `ci`'s four lanes against its list, added into `out`. Must
    /// be `#[inline(always)]`, as [`QuadTask::run`] must.
    fn cluster<Q: Quad>(
        &self,
        q: Q,
        state: (&[Self::Block], &ClusterPairs),
        ci: usize,
        out: &mut Window<'_, Self::Sums>,
    );
}

/// One slab of a pass: its clusters in index order.
struct Slab<'a, P: ClusterPass> {
    pass: &'a P,
    blocks: &'a [P::Block],
    cp: &'a ClusterPairs,
    slab: usize,
    out: Window<'a, P::Sums>,
}

impl<P: ClusterPass> QuadTask for Slab<'_, P> {
    type Output = ();

    #[inline(always)]
    fn run<Q: Quad>(self, q: Q) {
        let Slab {
            pass,
            blocks,
            cp,
            slab,
            out: Window { sums, base },
        } = self;
        for ci in cp.slabs[slab] as usize..cp.slabs[slab + 1] as usize {
            // a window per cluster from the slice and base held here, so that the
            // terms' stores need not reload them
            let mut out = Window {
                sums: &mut *sums,
                base,
            };
            pass.cluster(q, (blocks, cp), ci, &mut out);
        }
    }
}

/// Run `pass` over the clusters of every slab on `lanes`, two-phase
/// ([`two_phase_in`]), its terms added into `sums` (one entry per particle).
pub fn run_pass<P: ClusterPass>(
    pass: &P,
    (blocks, cp): (&[P::Block], &ClusterPairs),
    lanes: Lanes,
    sums: &mut [P::Sums],
) {
    let task = |slab: usize, sums: &mut [P::Sums], base: usize| {
        let out = Window { sums, base };
        lanes.run(Slab {
            pass,
            blocks,
            cp,
            slab,
            out,
        })
    };
    two_phase_in(&cp.particle_slabs, &mut sums[..cp.particles()], 512, &task);
}
