//! Four f64 lanes for the cluster-pair passes (issue 45), on the instruction set chosen
//! at run time.
//!
//! A cluster-pair pass ([`clusters`](crate::clusters)) takes one particle against the
//! four of a neighbour cluster at a time: its terms are written once, generic over
//! [`Quad`], and [`Lanes::run`] compiles them twice:
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

    /// min(a, b) as a < b ? a : b in each lane.
    #[inline(always)]
    fn min(self, a: Self::V, b: Self::V) -> Self::V {
        self.select(self.lt(a, b), a, b)
    }

    /// The four lanes' sum, ((l0 + l1) + (l2 + l3)).
    #[inline(always)]
    fn sum(self, v: Self::V) -> f64 {
        let mut a = [0.0; WIDTH];
        self.store(&mut a, v);
        (a[0] + a[1]) + (a[2] + a[3])
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
}

/// A [`pulp::Simd`] of four f64 lanes (x86-64-v3's `f64x4`).
#[derive(Clone, Copy, Debug)]
struct Wide<S>(S);

impl<S: pulp::Simd> Quad for Wide<S> {
    type V = S::f64s;
    type M = S::m64s;
    #[inline(always)]
    fn splat(self, x: f64) -> Self::V {
        self.0.splat_f64s(x)
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
        self.0.add_f64s(a, b)
    }
    #[inline(always)]
    fn sub(self, a: Self::V, b: Self::V) -> Self::V {
        self.0.sub_f64s(a, b)
    }
    #[inline(always)]
    fn mul(self, a: Self::V, b: Self::V) -> Self::V {
        self.0.mul_f64s(a, b)
    }
    #[inline(always)]
    fn div(self, a: Self::V, b: Self::V) -> Self::V {
        self.0.div_f64s(a, b)
    }
    #[inline(always)]
    fn sqrt(self, a: Self::V) -> Self::V {
        self.0.sqrt_f64s(a)
    }
    #[inline(always)]
    fn lt(self, a: Self::V, b: Self::V) -> Self::M {
        self.0.less_than_f64s(a, b)
    }
    #[inline(always)]
    fn and(self, a: Self::M, b: Self::M) -> Self::M {
        self.0.and_m64s(a, b)
    }
    #[inline(always)]
    fn select(self, m: Self::M, a: Self::V, b: Self::V) -> Self::V {
        self.0.select_f64s(m, a, b)
    }
}

/// Work written once over [`Quad`]; [`Lanes::run`] picks the lanes.
pub trait QuadTask {
    type Output;
    /// Must be `#[inline(always)]`: only then is it compiled into the AVX2 entry point
    /// rather than called from it.
    fn run<Q: Quad>(self, q: Q) -> Self::Output;
}

/// The AVX2 entry point of a [`QuadTask`].
struct OnWide<K>(K);

impl<K: QuadTask> pulp::WithSimd for OnWide<K> {
    type Output = K::Output;
    #[inline(always)]
    fn with_simd<S: pulp::Simd>(self, s: S) -> K::Output {
        self.0.run(Wide(s))
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

    /// The name of the instruction set, as the bench and the run summary print it.
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
            Level::Avx2(v3) => pulp::Simd::vectorize(v3, OnWide(task)),
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
                    out[0] = q.sum(q.load(&out));
                    out
                })
                .collect()
        }
    }

    /// Both levels take the same terms, min, masks and the lane sum to the same bits,
    /// and those of one value at a time.
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
                o[0] = (o[0] + o[1]) + (o[2] + o[3]);
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
}
