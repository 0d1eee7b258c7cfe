//! The water's pair laws against what they must give: the lattice sums of the kernel,
//! exact gradients of linear fields, hydrostatic balance, no Riemann dissipation for a
//! linear velocity field under MUSCL, no density change at hydrostatic rest, the
//! conservation of momentum, and the invariance of a periodic seam; on both
//! instruction sets, which agree bitwise.

// the checks loop over particles of several arrays at once
#![allow(clippy::needless_range_loop)]

use super::correction::Corr;
use super::lanes::WaterLanes;
use super::momentum::{WaterParams, WaterSums};
use super::source::WaterSource;
use super::state::WaterParticles;
use crate::numerics::kernel::WendlandC2;
use crate::numerics::math::{Real, Vect};
use crate::numerics::neighbors::{Binned, CellGrid, NeighborLists};
use crate::numerics::pairs::clusters::ClusterPairs;
use crate::numerics::pairs::quad::Lanes;
use crate::numerics::periodic::{Period, Wrap};
use crate::numerics::rng::Rng;
use crate::water::correction::{invert, share};

const DP: Real = 0.01;
const RHO: Real = 1000.0;
const G: Real = 9.81;

/// A block of water `side` spacings wide, on the lattice (`jitter` 0) or displaced
/// by up to ±`jitter` dp, sorted by cell, with its lists, clusters and parameters.
struct Tank<const D: usize> {
    w: WaterParticles<D>,
    cp: ClusterPairs,
    prm: WaterParams<D>,
    side: [usize; 3],
}

impl<const D: usize> Tank<D> {
    fn new(side: [usize; 3], jitter: Real, wrap: Wrap) -> Self {
        let mut rng = Rng(7);
        let mut w = WaterParticles::<D>::default();
        let mut u = || rng.uniform() - 0.5;
        for a in 0..side[0] {
            for b in 0..side[1] {
                for c in 0..side[2] {
                    let ijk = [a, b, c];
                    let x =
                        Vect::<D>::from_fn(|d, _| (ijk[d] as Real + 0.5 + 2.0 * jitter * u()) * DP);
                    w.push(x, Vect::<D>::zeros(), RHO, RHO * DP.powi(D as i32));
                }
            }
        }
        let kernel = WendlandC2::new(1.3 * DP, D);
        let radius = kernel.cutoff + 0.3 * DP;
        let lo = Vect::<D>::from_element(-0.05);
        let hi = Vect::<D>::from_fn(|d, _| side[d] as Real * DP + 0.05);
        let mut g = CellGrid::periodic(&lo, &hi, radius, wrap);
        g.bin(&w.pos);
        let order = g.order().to_vec();
        w.permute(&order, &mut Default::default());
        g.bin(&w.pos);
        let none = CellGrid::periodic(&lo, &hi, radius, wrap);
        let nb = |grid| Binned { pos: &[], grid };
        let mut lists = NeighborLists::default();
        lists.build(&w.pos, &g, nb(&none), nb(&none), radius, &wrap);
        let cp = lists.clusters.clone();
        let mut gravity = Vect::<D>::zeros();
        gravity[D - 1] = -G;
        let prm = WaterParams {
            kernel,
            gravity,
            hydrostatic: gravity,
            wrap,
            dt: 1e-5,
            z: RHO * 30.0,
            inv_c: 1.0 / 30.0,
            eta: Real::INFINITY,
            mu: 0.0,
            keep: 1.0,
            push_only: true,
        };
        Tank { w, cp, prm, side }
    }

    /// The particles at least `margin` spacings inside the block on every
    /// non-periodic axis.
    fn inner(&self, margin: Real) -> Vec<usize> {
        let wrap = self.prm.wrap.map(|p| p.axis);
        (0..self.w.len())
            .filter(|&i| {
                (0..D).all(|d| {
                    let x = self.w.pos[i][d] / DP;
                    Some(d) == wrap || (x > margin && x < self.side[d] as Real - margin)
                })
            })
            .collect()
    }

    /// The records with pressure `p(x)`.
    fn sources(&self, p: impl Fn(&Vect<D>) -> Real) -> Vec<WaterSource> {
        let w = &self.w;
        (0..w.len())
            .map(|i| WaterSource {
                p: p(&w.pos[i]),
                vol: w.mass[i] / w.rho[i],
                rho: w.rho[i],
            })
            .collect()
    }

    /// M and B of every particle from its water neighbours.
    fn correction(&self, lanes: Lanes, src: &[WaterSource]) -> (Vec<Corr<D>>, Vec<Corr<D>>) {
        let mut buf = WaterLanes::<D>::default();
        buf.pack(&self.cp, &self.w, src);
        let mut m = vec![Corr::<D>::zeros(); self.w.len()];
        buf.correction(&self.cp, &self.prm, lanes, &mut m);
        let b = m.iter().map(invert).collect();
        (m, b)
    }

    /// ∇v = L B of every particle.
    fn gradient(&self, lanes: Lanes, src: &[WaterSource], b: &[Corr<D>]) -> Vec<Corr<D>> {
        let mut buf = WaterLanes::<D>::default();
        buf.pack(&self.cp, &self.w, src);
        let mut ml = vec![[Corr::<D>::zeros(); 2]; self.w.len()];
        buf.moment_and_gradient(&self.cp, &self.prm, lanes, &mut ml);
        ml.iter().zip(b).map(|([_, l], b)| l * b).collect()
    }

    /// M and ∇v = L B of every particle from one walk over the pairs
    /// ([`WaterLanes::moment_and_gradient`]).
    fn fused(&self, lanes: Lanes, src: &[WaterSource]) -> (Vec<Corr<D>>, Vec<Corr<D>>) {
        let mut buf = WaterLanes::<D>::default();
        buf.pack(&self.cp, &self.w, src);
        let mut ml = vec![[Corr::<D>::zeros(); 2]; self.w.len()];
        buf.moment_and_gradient(&self.cp, &self.prm, lanes, &mut ml);
        ml.iter().map(|[m, l]| (*m, l * invert(m))).unzip()
    }

    /// The pair sums of the momentum (with ∇v `grad` if MUSCL) and continuity
    /// passes, the seepage acceleration `body` in the latter.
    fn sums(
        &self,
        lanes: Lanes,
        (src, b, grad): (&[WaterSource], &[Corr<D>], Option<&[Corr<D>]>),
        body: &[Vect<D>],
    ) -> Vec<WaterSums<D>> {
        let (cp, prm) = (&self.cp, &self.prm);
        let mut buf = WaterLanes::<D>::default();
        buf.pack(cp, &self.w, src);
        buf.pack_corr(cp, b);
        if let Some(g) = grad {
            buf.pack_grad(cp, g);
        }
        let mut s = vec![WaterSums::<D>::zero(); self.w.len()];
        buf.momentum(cp, (prm, grad.is_some()), lanes, &mut s);
        buf.repack_velocity(cp, &self.w.vel, (&prm.hydrostatic, body));
        buf.continuity(cp, prm, lanes, &mut s);
        s
    }
}

fn levels() -> [Lanes; 2] {
    [Lanes::portable(), Lanes::best()]
}

fn bits<const D: usize>(s: &[WaterSums<D>]) -> Vec<u64> {
    s.iter()
        .flat_map(|x| x.acc.iter().copied().chain([x.drho]))
        .map(f64::to_bits)
        .collect()
}

/// M of a full lattice neighbourhood is the lattice sum of −r ∂W/∂r V e⊗e
/// (κ I, κ = 0.9739 in 2D at h = 1.3 dp).
fn moment_is_the_lattice_sum<const D: usize>(side: [usize; 3]) {
    let blk = Tank::<D>::new(side, 0.0, None);
    let k = blk.prm.kernel;
    let mut want = Corr::<D>::zeros();
    let n = if D == 3 { 4 } else { 0 };
    for a in -4i32..=4 {
        for b in -4i32..=4 {
            for c in -n..=n {
                let o = [a, b, c];
                let x = Vect::<D>::from_fn(|d, _| o[d] as Real * DP);
                let r = x.norm();
                if r > 0.0 && r < k.cutoff {
                    want += share(&(x / r), r, k.dw(r), DP.powi(D as i32));
                }
            }
        }
    }
    let src = blk.sources(|_| 0.0);
    for lanes in levels() {
        let (m, _) = blk.correction(lanes, &src);
        for i in blk.inner(3.0) {
            let d = (m[i] - want).norm() / want.norm();
            assert!(d < 1e-12, "{} particle {i}: {d:e}", lanes.name());
        }
    }
    if D == 2 {
        assert!((want[(0, 0)] - 0.973921).abs() < 1e-5, "{want}");
    }
}

#[test]
fn moment_is_the_lattice_sum_2d() {
    moment_is_the_lattice_sum::<2>([16, 16, 1]);
}

#[test]
fn moment_is_the_lattice_sum_3d() {
    moment_is_the_lattice_sum::<3>([9, 9, 9]);
}

/// A linear velocity field v = A x, on a disordered block: the corrected gradient
/// L B is A wherever B is the inverse of M; with the jump reconstructed by it
/// (MUSCL) the Riemann term leaves no force at all, while the raw jump of the same
/// field is dissipated. The walk over the pairs that gives M and L together gives M
/// bitwise as the correction's own pass does.
fn linear_field_has_exact_gradient_and_no_dissipation<const D: usize>(side: [usize; 3]) {
    let mut blk = Tank::<D>::new(side, 0.1, None);
    let a = Corr::<D>::from_fn(|r, c| [[0.3, -0.7, 0.2], [0.5, -0.1, 0.4], [-0.6, 0.2, 0.1]][r][c]);
    for i in 0..blk.w.len() {
        blk.w.vel[i] = a * blk.w.pos[i];
    }
    let src = blk.sources(|_| 0.0);
    let inner = blk.inner(2.0 * 2.6 + 0.5);
    assert!(!inner.is_empty());
    let mut runs = Vec::new();
    for lanes in levels() {
        let (m, b) = blk.correction(lanes, &src);
        let grad = blk.gradient(lanes, &src, &b);
        // M from the walk that takes L too: bitwise the correction pass's, and so ∇v
        let (mf, gf) = blk.fused(lanes, &src);
        let corr_bits = |v: &[Corr<D>]| -> Vec<u64> {
            v.iter()
                .flat_map(|x| x.iter().map(|e| e.to_bits()))
                .collect()
        };
        assert_eq!(
            corr_bits(&m),
            corr_bits(&mf),
            "{}: the fused M differs",
            lanes.name()
        );
        assert_eq!(
            corr_bits(&grad),
            corr_bits(&gf),
            "{}: the fused ∇v differs",
            lanes.name()
        );
        for &i in &inner {
            let inv = (b[i] * m[i] - Corr::<D>::identity()).norm();
            assert!(
                inv < 1e-12,
                "{} particle {i}: B is not M⁻¹ ({inv:e})",
                lanes.name()
            );
            let d = (grad[i] - a).norm() / a.norm();
            assert!(d < 1e-12, "{} particle {i}: ∇v off by {d:e}", lanes.name());
        }
        let raw = blk.sums(lanes, (&src, &b, None), &[]);
        let rec = blk.sums(lanes, (&src, &b, Some(&grad)), &[]);
        let scale = inner
            .iter()
            .map(|&i| raw[i].acc.norm())
            .fold(0.0, Real::max);
        assert!(
            scale > 0.0,
            "the raw jump of a compressing field dissipates"
        );
        for &i in &inner {
            let left = rec[i].acc.norm() / scale;
            assert!(
                left < 1e-9,
                "{} particle {i}: MUSCL leaves {left:e}",
                lanes.name()
            );
        }
        runs.push((bits(&raw), bits(&rec)));
    }
    assert_eq!(runs[0], runs[1], "the two instruction sets differ");
}

#[test]
fn linear_field_has_exact_gradient_and_no_dissipation_2d() {
    linear_field_has_exact_gradient_and_no_dissipation::<2>([30, 30, 1]);
}

#[test]
fn linear_field_has_exact_gradient_and_no_dissipation_3d() {
    linear_field_has_exact_gradient_and_no_dissipation::<3>([16, 16, 16]);
}

/// Hydrostatic rest, p = ρ g (H − z): the corrected pressure force of a full
/// lattice neighbourhood balances gravity, (2/ρ) Σ = −g, and the continuity's
/// jump, taken relative to the hydrostatic state, leaves the density unchanged on a
/// disordered block too (where the plain jump would not).
fn hydrostatic_rest<const D: usize>(side: [usize; 3]) {
    let h = side[D - 1] as Real * DP;
    let p = |x: &Vect<D>| RHO * G * (h - x[D - 1]);
    for jitter in [0.0, 0.1] {
        let blk = Tank::<D>::new(side, jitter, None);
        let src = blk.sources(p);
        for lanes in levels() {
            let (_, b) = blk.correction(lanes, &src);
            let s = blk.sums(lanes, (&src, &b, None), &[]);
            let inner = blk.inner(3.0);
            if jitter == 0.0 {
                // B̄ = B_i = B_j = M⁻¹ of the full lattice for every pair of i
                for i in blk.inner(2.0 * 2.6 + 0.5) {
                    let a = s[i].acc * (2.0 / RHO) + blk.prm.gravity;
                    assert!(a.norm() < 1e-10 * G, "{} particle {i}: {a}", lanes.name());
                }
            }
            let mut plain = blk.prm;
            plain.hydrostatic = Vect::<D>::zeros();
            let mut buf = WaterLanes::<D>::default();
            buf.pack(&blk.cp, &blk.w, &src);
            let mut t = vec![WaterSums::<D>::zero(); blk.w.len()];
            buf.repack_velocity(&blk.cp, &blk.w.vel, (&plain.hydrostatic, &[]));
            buf.continuity(&blk.cp, &plain, lanes, &mut t);
            // the plain jump's largest rate: at the floor and the free surface
            let scale = t.iter().map(|t| t.drho.abs()).fold(0.0, Real::max);
            assert!(scale > 0.0);
            for &i in &inner {
                let d = s[i].drho.abs() / scale;
                assert!(d < 1e-10, "{} particle {i}: dρ {d:e}", lanes.name());
            }
        }
    }
}

#[test]
fn hydrostatic_rest_2d() {
    hydrostatic_rest::<2>([16, 16, 1]);
}

#[test]
fn hydrostatic_rest_3d() {
    hydrostatic_rest::<3>([14, 14, 14]);
}

/// A steady seepage, ∇p = ρ (g + a), is rest too: the jump is taken relative to
/// the seepage acceleration `a` with gravity (soil_water's pore water).
#[test]
fn steady_seepage_leaves_the_density_unchanged() {
    let blk = Tank::<2>::new([16, 16, 1], 0.1, None);
    let a = Vect::<2>::new(2.0, -3.0);
    let total = blk.prm.hydrostatic + a;
    let src = blk.sources(|x| 1e4 + RHO * total.dot(x));
    let body = vec![a; blk.w.len()];
    let b = vec![Corr::<2>::identity(); blk.w.len()];
    let s = blk.sums(Lanes::best(), (&src, &b, None), &body);
    let t = blk.sums(Lanes::best(), (&src, &b, None), &[]);
    let scale = t.iter().map(|t| t.drho.abs()).fold(0.0, Real::max);
    for i in 0..blk.w.len() {
        assert!(s[i].drho.abs() < 1e-10 * scale, "particle {i}");
    }
}

/// A uniform compression v = −ε x raises the density at ε tr(M) per unit density
/// (the kernel's own divergence of the field), on a disordered block.
#[test]
fn uniform_compression_raises_the_density_by_the_divergence() {
    let mut blk = Tank::<3>::new([10, 10, 10], 0.1, None);
    // no hydrostatic state to take the jump relative to
    blk.prm.hydrostatic = Vect::<3>::zeros();
    let eps = 0.7;
    for i in 0..blk.w.len() {
        blk.w.vel[i] = blk.w.pos[i] * -eps;
    }
    let src = blk.sources(|_| 0.0);
    let (m, b) = blk.correction(Lanes::best(), &src);
    let s = blk.sums(Lanes::best(), (&src, &b, None), &[]);
    for i in blk.inner(3.0) {
        let want = eps * m[i].trace();
        assert!((s[i].drho - want).abs() < 1e-12 * want, "particle {i}");
    }
}

/// Each pair's force is equal and opposite: Σ_i V_i Σ_j(...) = 0 on a disordered
/// block with every term on (pressure, limiter, viscosity, MUSCL, a different B per
/// particle), and both instruction sets agree bitwise.
fn momentum_is_conserved<const D: usize>(side: [usize; 3]) {
    let mut blk = Tank::<D>::new(side, 0.3, None);
    blk.prm.eta = 3.0;
    blk.prm.mu = 1e-3;
    let mut rng = Rng(3);
    for i in 0..blk.w.len() {
        blk.w.vel[i] = Vect::<D>::from_fn(|_, _| 0.4 * (rng.uniform() - 0.5));
    }
    let src = blk.sources(|x| 2000.0 * (1.0 + (37.0 * x[0]).sin()));
    let mut runs = Vec::new();
    for lanes in levels() {
        let (_, b) = blk.correction(lanes, &src);
        let grad = blk.gradient(lanes, &src, &b);
        let s = blk.sums(lanes, (&src, &b, Some(&grad)), &[]);
        let mut total = Vect::<D>::zeros();
        let mut scale = 0.0;
        for (i, s) in s.iter().enumerate() {
            total += s.acc * src[i].vol;
            scale += s.acc.norm() * src[i].vol;
        }
        assert!(
            total.norm() < 1e-13 * scale,
            "{}: {:e}",
            lanes.name(),
            total.norm() / scale
        );
        runs.push(bits(&s));
    }
    assert_eq!(runs[0], runs[1], "the two instruction sets differ");
}

#[test]
fn momentum_is_conserved_2d() {
    momentum_is_conserved::<2>([24, 17, 1]);
}

#[test]
fn momentum_is_conserved_3d() {
    momentum_is_conserved::<3>([12, 8, 10]);
}

/// Across a periodic seam the lattice continues: with fields that vary across the
/// seam's axis only, every particle of a row has the sums of the row's middle.
fn seam_is_invisible<const D: usize>(side: [usize; 3]) {
    let seam = Period {
        axis: 0,
        lo: 0.0,
        len: side[0] as Real * DP,
    };
    let mut blk = Tank::<D>::new(side, 0.0, Some(seam));
    blk.prm.eta = 3.0;
    blk.prm.mu = 1e-3;
    for i in 0..blk.w.len() {
        let z = blk.w.pos[i][D - 1];
        blk.w.vel[i][0] = 3.0 * z * z;
    }
    let h = side[D - 1] as Real * DP;
    let src = blk.sources(|x| RHO * G * (h - x[D - 1]) + 50.0 * (60.0 * x[D - 1]).sin());
    for lanes in levels() {
        let (_, b) = blk.correction(lanes, &src);
        let grad = blk.gradient(lanes, &src, &b);
        let s = blk.sums(lanes, (&src, &b, Some(&grad)), &[]);
        let scale = s.iter().map(|s| s.acc.norm()).fold(0.0, Real::max);
        let dscale = s.iter().map(|s| s.drho.abs()).fold(0.0, Real::max);
        let row = |i: usize| -> Vec<Real> { (1..D).map(|d| blk.w.pos[i][d]).collect() };
        let mid = |i: usize| {
            (0..blk.w.len())
                .find(|&k| {
                    row(k) == row(i) && ((blk.w.pos[k][0] / DP) - side[0] as Real / 2.0).abs() < 0.6
                })
                .unwrap()
        };
        for i in 0..blk.w.len() {
            let k = mid(i);
            let da = (s[i].acc - s[k].acc).norm() / scale;
            let dd = (s[i].drho - s[k].drho).abs() / dscale;
            assert!(
                da < 1e-11 && dd < 1e-11,
                "{} particle {i}: {da:e} {dd:e}",
                lanes.name()
            );
        }
    }
}

#[test]
fn seam_is_invisible_2d() {
    seam_is_invisible::<2>([20, 14, 1]);
}

#[test]
fn seam_is_invisible_3d() {
    seam_is_invisible::<3>([10, 6, 8]);
}
