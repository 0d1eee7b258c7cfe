//! The pair executor of the fine grains and the water (issue 45, docs/method.md
//! §Throughput): each pair law ([`PairLaw`]) is written once over [`Quad`] and gives
//! its terms for a cluster's four particles against one neighbour; [`run_pass`] does
//! everything else, for every law alike.
//!
//! A law's state is packed per cluster ([`pack`], [`repack`]), one record per
//! particle: a neighbour's values are read from its record, a few cache lines, and
//! broadcast ([`Quad::splat`]); a cluster's own four records are gathered into the
//! lanes once ([`gather`]). Pairs beyond the cut-off, or with j ≤ i, are masked out,
//! so each pair is taken once; the terms a neighbour gains from the four lanes are
//! added across the lanes in one fixed order ([`Quad::sums`]) and go straight into its
//! sums, a cluster's own lane by lane. The clusters run in the two-phase schedule over
//! slabs ([`two_phase_in`]), so the sums do not depend on the thread count.

use crate::numerics::kernel::WendlandC2;
use crate::numerics::math::Real;
use crate::numerics::pairs::clusters::{ClusterPairs, Take};
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
fn separation<Q: Quad, const D: usize>(
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
fn geometry<Q: Quad, const D: usize>(
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
fn lane_indices<Q: Quad>(q: Q, cp: &ClusterPairs, c: usize) -> Q::V {
    let first = cp.start[c] as Real;
    q.add(q.splat(first), q.load(&[0.0, 1.0, 2.0, 3.0]))
}

/// Particle `j`'s cluster, its lane there, and `j`.
#[inline(always)]
fn at(cp: &ClusterPairs, j: u32) -> (usize, usize, usize) {
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

/// One neighbour j of a cluster as a pair law sees it: the four lanes' separations
/// x_i − x_j, their pair geometry (only the lanes of `g.m` pair), j's record, and
/// where it sits (cluster `c`, lane `l`: a law's side records are read there).
pub struct Partner<'a, Q: Quad, R, const D: usize> {
    pub rij: [Q::V; D],
    pub g: Geometry<Q>,
    pub rec: &'a R,
    pub c: usize,
    pub l: usize,
}

/// A record that knows its particle's position.
pub trait Positioned<const D: usize> {
    fn x(&self) -> &[Real; D];
}

/// A pair law on [`Quad`] lanes: what it reads per particle ([`Rec`](Self::Rec),
/// packed four to a cluster by [`pack`]), what it adds per particle
/// ([`Sums`](Self::Sums)), and its `N` terms for the four lanes of a cluster against
/// one partner j: what the lanes gain and what j gains from each. The executor
/// ([`run_pass`]) owns the rest: the cluster's positions on the lanes, the
/// partners of its list, their separations across a periodic seam, the pair
/// geometry and the lanes it masks in, the lane sums of j's terms in one fixed order,
/// and their return to both particles' sums, in the two-phase slab schedule.
pub trait PairLaw<const D: usize, const N: usize>: Sync {
    type Rec: Sync + Positioned<D>;
    type Sums: Send;
    /// The cluster's own state on the lanes, as the terms read it.
    type Lanes<Q: Quad>;
    /// How many of the `N` terms the law fills (the others stay zero and are not
    /// summed; e.g. the 2D terms of a law sized for 3D).
    const USED: usize = N;
    /// The lanes of cluster `c`, whose records are `recs`.
    fn lanes<Q: Quad>(&self, q: Q, c: usize, recs: &[Self::Rec; WIDTH]) -> Self::Lanes<Q>;
    /// The terms of the lanes `i` against partner `j`: the lanes' own added into
    /// `own`, j's from each lane written into `tj` (to be summed over the lanes). Only
    /// called when some lane pairs with j. Must be `#[inline(always)]`, as
    /// [`QuadTask::run`] must.
    fn pair<Q: Quad>(
        &self,
        q: Q,
        i: &Self::Lanes<Q>,
        j: Partner<'_, Q, Self::Rec, D>,
        own: &mut [Q::V; N],
        tj: &mut [Q::V; N],
    );
    /// Add a lane's own terms `t` (summed over its partners) to its particle's sums.
    fn own(s: &mut Self::Sums, t: &[Real; N]);
    /// Add the lane sums `t` of a partner's terms to the partner's sums (by default
    /// as a lane's own: a law whose partner gains what it gives).
    #[inline(always)]
    fn partner(s: &mut Self::Sums, t: &[Real; N]) {
        Self::own(s, t)
    }
}

/// The lane sums of the first `used` entries of `t` ([`Quad::sums`] of that many; the
/// rest zero): `used` is a constant of the law, so one arm remains.
#[inline(always)]
fn lane_sums<Q: Quad, const N: usize>(q: Q, t: &[Q::V; N], used: usize) -> [Real; N] {
    #[inline(always)]
    fn first<Q: Quad, const K: usize, const N: usize>(q: Q, t: &[Q::V; N]) -> [Real; N] {
        let mut out = [0.0; N];
        if K <= N {
            let a: [Q::V; K] = std::array::from_fn(|k| t[k]);
            out[..K].copy_from_slice(&q.sums(&a));
        }
        out
    }
    match used {
        3 => first::<Q, 3, N>(q, t),
        4 => first::<Q, 4, N>(q, t),
        5 => first::<Q, 5, N>(q, t),
        7 => first::<Q, 7, N>(q, t),
        12 => first::<Q, 12, N>(q, t),
        _ => q.sums(t),
    }
}

/// Law `law` for cluster `ci` against every partner of its list (`only_awake`: those
/// awake, its members all sleeping), into `win`.
#[inline(always)]
fn cluster<Q: Quad, P: PairLaw<D, N>, const D: usize, const N: usize>(
    q: Q,
    (law, kernel, wrap): (&P, &WendlandC2, &Wrap),
    (blocks, cp): (&[[P::Rec; WIDTH]], &ClusterPairs),
    (ci, only_awake): (usize, bool),
    win: &mut Window<'_, P::Sums>,
) {
    let zero = q.splat(0.0);
    let bi = &blocks[ci];
    let idx = lane_indices(q, cp, ci);
    let xi: [Q::V; D] = std::array::from_fn(|d| gather(q, bi, |r| r.x()[d]));
    let lanes = law.lanes(q, ci, bi);
    let (mut own, mut tj) = ([zero; N], [zero; N]);
    // a law of one term sums four partners' at once
    let (mut t1, mut to, mut k) = ([zero; WIDTH], [0; WIDTH], 0);
    for &j in cp.of(ci) {
        if only_awake && !cp.awake[j as usize] {
            // a pair of two sleeping particles: its terms would be discarded
            continue;
        }
        let (c, l, j) = at(cp, j);
        let rec = &blocks[c][l];
        let rij = separation(q, wrap, &xi, rec.x());
        let g = geometry(q, kernel, &rij, (idx, j));
        if !q.any(g.m) {
            // beyond the cut-off of every lane (the lists' skin)
            continue;
        }
        law.pair(q, &lanes, Partner { rij, g, rec, c, l }, &mut own, &mut tj);
        if P::USED == 1 {
            (t1[k], to[k]) = (tj[0], j);
            k += 1;
            if k == WIDTH {
                for (j, s) in to.into_iter().zip(q.sums(&t1)) {
                    let mut t = [0.0; N];
                    t[0] = s;
                    P::partner(win.at(j), &t);
                }
                k = 0;
            }
        } else {
            P::partner(win.at(j), &lane_sums(q, &tj, P::USED));
        }
    }
    for n in 0..k {
        let mut t = [0.0; N];
        t[0] = q.sum(t1[n]);
        P::partner(win.at(to[n]), &t);
    }
    let mut by_lane = [[0.0; WIDTH]; N];
    for (t, o) in by_lane.iter_mut().zip(&own).take(P::USED) {
        q.store(t, *o);
    }
    for (l, s) in win.cluster(cp, ci).iter_mut().enumerate() {
        P::own(s, &std::array::from_fn(|k| by_lane[k][l]));
    }
}

/// One slab of a pass: its clusters in index order.
struct Slab<'a, P: PairLaw<D, N>, const D: usize, const N: usize> {
    law: (&'a P, &'a WendlandC2, &'a Wrap),
    blocks: &'a [[P::Rec; WIDTH]],
    cp: &'a ClusterPairs,
    slab: usize,
    out: Window<'a, P::Sums>,
}

impl<P: PairLaw<D, N>, const D: usize, const N: usize> QuadTask for Slab<'_, P, D, N> {
    type Output = ();

    #[inline(always)]
    fn run<Q: Quad>(self, q: Q) {
        let Slab {
            law,
            blocks,
            cp,
            slab,
            out: Window { sums, base },
        } = self;
        for ci in cp.slabs[slab] as usize..cp.slabs[slab + 1] as usize {
            let only_awake = match cp.take(ci) {
                Take::All => false,
                Take::AwakePartners => true,
                // its members and partners all sleep
                Take::Skip => continue,
            };
            // a window per cluster from the slice and base held here, so that the
            // terms' stores need not reload them
            let mut out = Window {
                sums: &mut *sums,
                base,
            };
            cluster(q, law, (blocks, cp), (ci, only_awake), &mut out);
        }
    }
}

/// Run `law` with `kernel` across the periodic seam `wrap` over the clusters of every
/// slab on `lanes`, two-phase ([`two_phase_in`]), its terms added into `sums` (one
/// entry per particle).
pub fn run_pass<P: PairLaw<D, N>, const D: usize, const N: usize>(
    law: (&P, &WendlandC2, &Wrap),
    (blocks, cp): (&[[P::Rec; WIDTH]], &ClusterPairs),
    lanes: Lanes,
    sums: &mut [P::Sums],
) {
    let task = |slab: usize, sums: &mut [P::Sums], base: usize| {
        let out = Window { sums, base };
        lanes.run(Slab {
            law,
            blocks,
            cp,
            slab,
            out,
        })
    };
    two_phase_in(&cp.particle_slabs, &mut sums[..cp.particles()], 512, &task);
}
