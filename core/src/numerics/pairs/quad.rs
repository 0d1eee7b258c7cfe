//! Four f64 lanes for pair passes over clusters of four particles (issue 45,
//! docs/method.md §Throughput), on the instruction set chosen at run time.
//!
//! Such a pass takes the four particles of a cluster, one per lane, against one
//! neighbour at a time: its terms are written once, generic over [`Quad`], and
//! [`Lanes::run`] compiles them twice:
//! - on AVX2 ([`pulp`]'s x86-64-v3 entry point, `f64x4`), when the processor has it;
//! - on `[f64; 4]` arrays with the baseline instruction set, on any x86-64 a master
//!   runs on, and wherever `GRANMIX_SIMD=scalar` asks for it.
//!
//! **The two agree bitwise.** Each lane takes the same IEEE operations in the same
//! order: no multiply and add is fused (Rust never fuses them), the minimum and the
//! maximum are written as a comparison and a selection (so no instruction's rule for
//! NaN or a signed zero enters), and the lanes are summed into one another only by
//! [`Quad::sum`], in one fixed order. `both_levels_compute_the_same_bits` tests it,
//! and each pass's own tests run both levels.

use std::sync::OnceLock;

/// Lanes per vector: the particles of a cluster.
pub const WIDTH: usize = 4;

/// Four f64 lanes and the operations the pair terms use.
pub trait Quad: Copy {
    type V: Copy;
    type M: Copy;
    fn splat(self, x: f64) -> Self::V;
    fn load(self, a: &[f64; WIDTH]) -> Self::V;
    fn store(self, a: &mut [f64; WIDTH], v: Self::V);
    fn add(self, a: Self::V, b: Self::V) -> Self::V;
    fn sub(self, a: Self::V, b: Self::V) -> Self::V;
    fn mul(self, a: Self::V, b: Self::V) -> Self::V;
    fn div(self, a: Self::V, b: Self::V) -> Self::V;
    fn sqrt(self, a: Self::V) -> Self::V;
    /// a < b in each lane.
    fn lt(self, a: Self::V, b: Self::V) -> Self::M;
    fn and(self, a: Self::M, b: Self::M) -> Self::M;
    /// `a` where the mask is set, `b` elsewhere.
    fn select(self, m: Self::M, a: Self::V, b: Self::V) -> Self::V;
    /// Some lane of the mask is set.
    fn any(self, m: Self::M) -> bool;

    /// min(a, b) as a < b ? a : b in each lane.
    #[inline(always)]
    fn min(self, a: Self::V, b: Self::V) -> Self::V {
        self.select(self.lt(a, b), a, b)
    }

    /// max(a, b) as b < a ? a : b in each lane.
    #[inline(always)]
    fn max(self, a: Self::V, b: Self::V) -> Self::V {
        self.select(self.lt(b, a), a, b)
    }

    /// The four lanes' sum, ((l0 + l1) + (l2 + l3)).
    #[inline(always)]
    fn sum(self, v: Self::V) -> f64 {
        let mut a = [0.0; WIDTH];
        self.store(&mut a, v);
        (a[0] + a[1]) + (a[2] + a[3])
    }

    /// [`sum`](Self::sum) of two vectors at once.
    #[inline(always)]
    fn sum2(self, a: Self::V, b: Self::V) -> [f64; 2] {
        [self.sum(a), self.sum(b)]
    }

    /// [`sum`](Self::sum) of four vectors at once.
    #[inline(always)]
    fn sum4(self, a: Self::V, b: Self::V, c: Self::V, d: Self::V) -> [f64; 4] {
        [self.sum(a), self.sum(b), self.sum(c), self.sum(d)]
    }

    /// [`sum`](Self::sum) of each of `N` vectors, four, two or one at a time.
    #[inline(always)]
    fn sums<const N: usize>(self, v: &[Self::V; N]) -> [f64; N] {
        let mut out = [0.0; N];
        let mut k = 0;
        while k + 4 <= N {
            let s = self.sum4(v[k], v[k + 1], v[k + 2], v[k + 3]);
            out[k..k + 4].copy_from_slice(&s);
            k += 4;
        }
        if k + 3 == N {
            // the fourth sum is a repeat of the third, dropped
            let s = self.sum4(v[k], v[k + 1], v[k + 2], v[k + 2]);
            out[k..].copy_from_slice(&s[..3]);
        } else if k + 2 == N {
            out[k..].copy_from_slice(&self.sum2(v[k], v[k + 1]));
        } else if k + 1 == N {
            out[k] = self.sum(v[k]);
        }
        out
    }
}

/// `[f64; 4]` with the baseline instruction set.
#[derive(Clone, Copy, Debug, Default)]
pub struct Portable;

impl Quad for Portable {
    type V = [f64; WIDTH];
    type M = [bool; WIDTH];
    #[inline(always)]
    fn splat(self, x: f64) -> Self::V {
        [x; WIDTH]
    }
    #[inline(always)]
    fn load(self, a: &[f64; WIDTH]) -> Self::V {
        *a
    }
    #[inline(always)]
    fn store(self, a: &mut [f64; WIDTH], v: Self::V) {
        *a = v;
    }
    #[inline(always)]
    fn add(self, a: Self::V, b: Self::V) -> Self::V {
        [a[0] + b[0], a[1] + b[1], a[2] + b[2], a[3] + b[3]]
    }
    #[inline(always)]
    fn sub(self, a: Self::V, b: Self::V) -> Self::V {
        [a[0] - b[0], a[1] - b[1], a[2] - b[2], a[3] - b[3]]
    }
    #[inline(always)]
    fn mul(self, a: Self::V, b: Self::V) -> Self::V {
        [a[0] * b[0], a[1] * b[1], a[2] * b[2], a[3] * b[3]]
    }
    #[inline(always)]
    fn div(self, a: Self::V, b: Self::V) -> Self::V {
        [a[0] / b[0], a[1] / b[1], a[2] / b[2], a[3] / b[3]]
    }
    #[inline(always)]
    fn sqrt(self, a: Self::V) -> Self::V {
        [a[0].sqrt(), a[1].sqrt(), a[2].sqrt(), a[3].sqrt()]
    }
    #[inline(always)]
    fn lt(self, a: Self::V, b: Self::V) -> Self::M {
        [a[0] < b[0], a[1] < b[1], a[2] < b[2], a[3] < b[3]]
    }
    #[inline(always)]
    fn and(self, a: Self::M, b: Self::M) -> Self::M {
        [a[0] & b[0], a[1] & b[1], a[2] & b[2], a[3] & b[3]]
    }
    #[inline(always)]
    fn select(self, m: Self::M, a: Self::V, b: Self::V) -> Self::V {
        let pick = |k: usize| if m[k] { a[k] } else { b[k] };
        [pick(0), pick(1), pick(2), pick(3)]
    }
    #[inline(always)]
    fn any(self, m: Self::M) -> bool {
        (m[0] | m[1]) | (m[2] | m[3])
    }
}

/// AVX2's four f64 lanes (pulp's x86-64-v3 token; its intrinsics are safe calls).
#[cfg(target_arch = "x86_64")]
#[derive(Clone, Copy, Debug)]
struct Avx2(pulp::x86::V3);

#[cfg(target_arch = "x86_64")]
impl Quad for Avx2 {
    type V = pulp::f64x4;
    type M = pulp::m64x4;
    #[inline(always)]
    fn splat(self, x: f64) -> Self::V {
        self.0.splat_f64x4(x)
    }
    #[inline(always)]
    fn load(self, a: &[f64; WIDTH]) -> Self::V {
        pulp::cast(*a)
    }
    #[inline(always)]
    fn store(self, a: &mut [f64; WIDTH], v: Self::V) {
        *a = pulp::cast(v);
    }
    #[inline(always)]
    fn add(self, a: Self::V, b: Self::V) -> Self::V {
        pulp::Simd::add_f64s(self.0, a, b)
    }
    #[inline(always)]
    fn sub(self, a: Self::V, b: Self::V) -> Self::V {
        pulp::Simd::sub_f64s(self.0, a, b)
    }
    #[inline(always)]
    fn mul(self, a: Self::V, b: Self::V) -> Self::V {
        pulp::Simd::mul_f64s(self.0, a, b)
    }
    #[inline(always)]
    fn div(self, a: Self::V, b: Self::V) -> Self::V {
        pulp::Simd::div_f64s(self.0, a, b)
    }
    #[inline(always)]
    fn sqrt(self, a: Self::V) -> Self::V {
        pulp::Simd::sqrt_f64s(self.0, a)
    }
    #[inline(always)]
    fn lt(self, a: Self::V, b: Self::V) -> Self::M {
        pulp::Simd::less_than_f64s(self.0, a, b)
    }
    #[inline(always)]
    fn and(self, a: Self::M, b: Self::M) -> Self::M {
        pulp::Simd::and_m64s(self.0, a, b)
    }
    #[inline(always)]
    fn select(self, m: Self::M, a: Self::V, b: Self::V) -> Self::V {
        pulp::Simd::select_f64s(self.0, m, a, b)
    }
    #[inline(always)]
    fn any(self, m: Self::M) -> bool {
        self.0.avx._mm256_movemask_pd(pulp::cast(m)) != 0
    }
    /// hadd gives (l0 + l1) and (l2 + l3) of both, the two halves' sum the rest.
    #[inline(always)]
    fn sum2(self, a: Self::V, b: Self::V) -> [f64; 2] {
        let avx = self.0.avx;
        let h = avx._mm256_hadd_pd(pulp::cast(a), pulp::cast(b));
        let s = self.0.sse2._mm_add_pd(
            avx._mm256_castpd256_pd128(h),
            avx._mm256_extractf128_pd::<1>(h),
        );
        pulp::cast(s)
    }
    /// Two hadds, then the low halves (l0 + l1) and high halves (l2 + l3) of all four
    /// gathered into one vector each, and added.
    #[inline(always)]
    fn sum4(self, a: Self::V, b: Self::V, c: Self::V, d: Self::V) -> [f64; 4] {
        let avx = self.0.avx;
        let ab = avx._mm256_hadd_pd(pulp::cast(a), pulp::cast(b));
        let cd = avx._mm256_hadd_pd(pulp::cast(c), pulp::cast(d));
        let lo = avx._mm256_permute2f128_pd::<0x20>(ab, cd);
        let hi = avx._mm256_permute2f128_pd::<0x31>(ab, cd);
        pulp::cast(avx._mm256_add_pd(lo, hi))
    }
}

/// Work written once over [`Quad`]; [`Lanes::run`] picks the lanes.
pub trait QuadTask {
    type Output;
    /// Must be `#[inline(always)]`: only then is it compiled into the AVX2 entry point
    /// rather than called from it.
    fn run<Q: Quad>(self, q: Q) -> Self::Output;
}

/// The AVX2 entry point of a [`QuadTask`]: run inside the function pulp compiles
/// with the x86-64-v3 features, on the token it was made with.
#[cfg(target_arch = "x86_64")]
struct OnAvx2<K>(K, pulp::x86::V3);

#[cfg(target_arch = "x86_64")]
impl<K: QuadTask> pulp::WithSimd for OnAvx2<K> {
    type Output = K::Output;
    #[inline(always)]
    fn with_simd<S: pulp::Simd>(self, _: S) -> K::Output {
        self.0.run(Avx2(self.1))
    }
}

/// The environment variable that forces the lanes: `scalar` (the baseline
/// instruction set) or `auto` (the best available, the default).
pub const ENV: &str = "GRANMIX_SIMD";

/// The instruction set a run's cluster-pair passes use.
#[derive(Clone, Copy, Debug)]
pub struct Lanes(Level);

#[derive(Clone, Copy, Debug)]
enum Level {
    Portable,
    #[cfg(target_arch = "x86_64")]
    Avx2(pulp::x86::V3),
}

impl Lanes {
    /// AVX2 where the processor has it, unless [`ENV`] says `scalar`. An unknown value
    /// of [`ENV`] is reported once on stderr and read as `auto`.
    pub fn detect() -> Self {
        static CHOSEN: OnceLock<Lanes> = OnceLock::new();
        *CHOSEN.get_or_init(|| match std::env::var(ENV).as_deref() {
            Ok("scalar") => Lanes::portable(),
            Ok("auto") | Ok("") | Err(_) => Lanes::best(),
            Ok(other) => {
                eprintln!(
                    "granmix: {ENV}={other:?} is not a setting granmix knows \
                     (`scalar` or `auto`); using the best available"
                );
                Lanes::best()
            }
        })
    }

    /// The baseline instruction set, whatever the processor has.
    pub fn portable() -> Self {
        Lanes(Level::Portable)
    }

    /// AVX2 if the processor has it, else the baseline.
    pub fn best() -> Self {
        #[cfg(target_arch = "x86_64")]
        if let Some(v3) = pulp::x86::V3::try_new() {
            return Lanes(Level::Avx2(v3));
        }
        Lanes::portable()
    }

    /// The name of the instruction set: `scalar` or `avx2`.
    pub fn name(&self) -> &'static str {
        match self.0 {
            Level::Portable => "scalar",
            #[cfg(target_arch = "x86_64")]
            Level::Avx2(_) => "avx2",
        }
    }

    /// Run `task` on these lanes.
    #[inline(always)]
    pub fn run<K: QuadTask>(self, task: K) -> K::Output {
        match self.0 {
            Level::Portable => task.run(Portable),
            #[cfg(target_arch = "x86_64")]
            Level::Avx2(v3) => pulp::Simd::vectorize(v3, OnAvx2(task, v3)),
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    struct Terms<'a>(&'a [[f64; WIDTH]]);

    impl QuadTask for Terms<'_> {
        type Output = Vec<[f64; WIDTH]>;
        #[inline(always)]
        fn run<Q: Quad>(self, q: Q) -> Self::Output {
            self.0
                .iter()
                .map(|x| {
                    let x = q.load(x);
                    let s = q.div(q.sqrt(q.mul(x, x)), q.add(x, q.splat(3.0)));
                    let v = q.add(q.mul(x, q.splat(1.7)), s);
                    let v = q.min(v, q.splat(1.2));
                    let keep = q.and(q.lt(q.splat(-0.5), x), q.lt(x, q.splat(0.9)));
                    let mut out = [0.0; WIDTH];
                    q.store(&mut out, q.select(keep, v, q.sub(q.splat(0.0), x)));
                    let v = q.load(&out);
                    let w = q.mul(v, q.splat(-0.3));
                    let [a, b] = q.sum2(v, w);
                    let [c, d, e, f] = q.sum4(w, v, v, w);
                    out[0] = q.sum(v);
                    out[1] = ((a - b) + (c - d)) + (e - f);
                    let [g, h, k] = q.sums(&[v, w, v]);
                    out[2] = (g - h) + k;
                    let s5 = q.sums(&[w, v, v, v, w]);
                    out[3] = s5.iter().sum::<f64>();
                    out
                })
                .collect()
        }
    }

    /// Both levels take the same terms, min, masks and the lane sums (one, two and four
    /// at a time) to the same bits, and those of one value at a time.
    #[test]
    fn both_levels_compute_the_same_bits() {
        let x: Vec<[f64; WIDTH]> = (0..37)
            .map(|k| std::array::from_fn(|l| 0.1 + ((4 * k + l) as f64).sin()))
            .collect();
        let one = |x: f64| {
            let v = (x * 1.7 + (x * x).sqrt() / (x + 3.0)).min(1.2);
            if -0.5 < x && x < 0.9 {
                v
            } else {
                0.0 - x
            }
        };
        let want: Vec<[f64; WIDTH]> = x
            .iter()
            .map(|x| {
                let mut o: [f64; WIDTH] = std::array::from_fn(|l| one(x[l]));
                let w: [f64; WIDTH] = std::array::from_fn(|l| o[l] * -0.3);
                let sum = |v: &[f64; WIDTH]| (v[0] + v[1]) + (v[2] + v[3]);
                let (sv, sw) = (sum(&o), sum(&w));
                o[0] = sv;
                o[1] = ((sv - sw) + (sw - sv)) + (sv - sw);
                o[2] = (sv - sw) + sv;
                o[3] = [sw, sv, sv, sv, sw].iter().sum::<f64>();
                o
            })
            .collect();
        for lanes in [Lanes::portable(), Lanes::best()] {
            let got = lanes.run(Terms(&x));
            let same = got
                .iter()
                .flatten()
                .zip(want.iter().flatten())
                .all(|(a, b)| a.to_bits() == b.to_bits());
            assert!(same, "{}", lanes.name());
        }
    }

    struct Any(f64);

    impl QuadTask for Any {
        type Output = Vec<bool>;
        #[inline(always)]
        fn run<Q: Quad>(self, q: Q) -> Self::Output {
            // each lane alone below the threshold, then none, then all
            let mut cases: Vec<[f64; WIDTH]> = (0..WIDTH)
                .map(|l| std::array::from_fn(|k| if k == l { -1.0 } else { 1.0 }))
                .collect();
            cases.push([1.0; WIDTH]);
            cases.push([-1.0; WIDTH]);
            cases
                .iter()
                .map(|x| q.any(q.lt(q.load(x), q.splat(self.0))))
                .collect()
        }
    }

    /// `any` sees each lane of a mask alone, and an empty mask as empty.
    #[test]
    fn any_sees_every_lane() {
        for lanes in [Lanes::portable(), Lanes::best()] {
            let got = lanes.run(Any(0.0));
            assert_eq!(
                got,
                [true, true, true, true, false, true],
                "{}",
                lanes.name()
            );
        }
    }
}
