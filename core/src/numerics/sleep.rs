//! Resting particles sleep (`numerics.sleep`, docs/method.md §Sleep): a particle whose
//! motion and strain rate stay below the rule's thresholds for `steps` steps falls
//! asleep; its state is frozen (v = 0, dρ/dt = 0, its stress kept) and not
//! integrated, and the lane passes leave out the pairs of two sleeping particles
//! ([`mark_runs`]).
//!
//! Waking is causal. A particle that failed the rule's test in a step (*restless*)
//! wakes every particle within its kernel support at the step's end ([`wake`]): the
//! support 2h is more than the distance CFL·h the elastic signal travels in a step, so
//! a wake front is never outrun. A
//! particle a family holds awake (a coarse grain, a barrier or a moving wall within
//! its reach) has its count reset without waking its neighbours: if it moves, it is
//! restless at the step's end and wakes them then.
//!
//! A particle's count of quiet steps is part of its state (it moves with the particle
//! through re-sorting and is saved with a restored state); the flags of a step are
//! scratch, written in full by the step's passes before they are read.

use crate::numerics::math::{Real, Vect};
use crate::numerics::pairs::clusters::{ClusterPairs, Take};
use crate::numerics::pairs::slabs::two_phase_in;
use rayon::prelude::*;

/// Flag of a particle whose motion or strain rate exceeded a threshold in the step:
/// it wakes its neighbours.
pub const RESTLESS: u8 = 1;
/// Flag of a particle held awake by something outside its family (a coarse grain, a
/// barrier or a moving wall within its reach).
pub const HELD: u8 = 2;
/// Flag of a particle woken by a restless neighbour.
const WOKEN: u8 = 4;

/// The thresholds of one family's sleep (`numerics.sleep_speed`, `sleep_steps`).
#[derive(Clone, Copy, Debug, PartialEq, serde::Serialize, serde::Deserialize)]
pub struct SleepRule {
    /// |v| below which a particle may rest (m/s).
    pub speed: Real,
    /// Consecutive quiet steps before it falls asleep.
    pub steps: u16,
    /// |dv/dt| below which it may rest (m/s²).
    pub accel: Real,
    /// |L| (Frobenius) below which it may rest: the speed across a smoothing length,
    /// `speed / h` (1/s).
    pub strain_rate: Real,
}

impl SleepRule {
    /// The rule of `speed`, `accel` and `steps` at smoothing length `h`.
    pub fn new(speed: Real, accel: Real, steps: u16, h: Real) -> Self {
        SleepRule {
            speed,
            steps,
            accel,
            strain_rate: speed / h,
        }
    }

    /// Whether a particle of `quiet` steps sleeps.
    #[inline(always)]
    pub fn asleep(&self, quiet: u16) -> bool {
        quiet >= self.steps
    }

    /// Whether a step of `dt` that took a particle from `v0` to `v1` is restless: |v1|
    /// at or above the speed, or |v1 − v0| / dt at or above the acceleration.
    #[inline(always)]
    pub fn restless_motion<const D: usize>(&self, v0: &Vect<D>, v1: &Vect<D>, dt: Real) -> bool {
        let dv = self.accel * dt;
        v1.norm_squared() >= self.speed * self.speed || (v1 - v0).norm_squared() >= dv * dv
    }

    /// Whether a velocity gradient of squared Frobenius norm `l2` is restless.
    #[inline(always)]
    pub fn restless_strain(&self, l2: Real) -> bool {
        l2 >= self.strain_rate * self.strain_rate
    }

    /// The flags of a step of `dt` that took a particle from `v0` to `v1`, `held`
    /// awake or not ([`RESTLESS`] by [`restless_motion`](Self::restless_motion),
    /// [`HELD`]).
    #[inline(always)]
    pub fn motion_flags<const D: usize>(
        &self,
        (v0, v1): (&Vect<D>, &Vect<D>),
        dt: Real,
        held: bool,
    ) -> u8 {
        let restless = if self.restless_motion(v0, v1, dt) {
            RESTLESS
        } else {
            0
        };
        restless | if held { HELD } else { 0 }
    }
}

/// Which particles sleep in a step: the rule (None: none does) and each particle's
/// count of quiet steps.
#[derive(Clone, Copy)]
pub struct Asleep<'a> {
    pub rule: Option<&'a SleepRule>,
    pub quiet: &'a [u16],
}

impl Asleep<'_> {
    /// Whether particle `i` sleeps.
    #[inline(always)]
    pub fn at(&self, i: usize) -> bool {
        self.rule.is_some_and(|r| r.asleep(self.quiet[i]))
    }
}

/// One family's sleep scratch: each particle's flags of the step, and the clusters
/// each cluster's list reaches (built once per list build, so that a step's scans
/// read one entry per neighbouring cluster rather than one per partner).
#[derive(Clone, Debug, Default)]
pub struct SleepFlags {
    /// [`RESTLESS`] | [`HELD`] of each particle, written by the step's passes.
    pub flags: Vec<u8>,
    /// `reach[off[c]..off[c + 1]]`: the clusters other than c holding a partner of c,
    /// ascending.
    off: Vec<u32>,
    reach: Vec<u32>,
    /// The list build the reach was made from.
    built: Option<usize>,
    /// Per cluster: a member restless (wake) or awake (runs).
    any: Vec<bool>,
}

impl SleepFlags {
    /// Flags for `n` particles, all clear.
    pub fn reset(&mut self, n: usize) {
        self.flags.clear();
        self.flags.resize(n, 0);
    }

    pub fn bytes(&self) -> usize {
        self.flags.capacity() + 4 * (self.off.capacity() + self.reach.capacity())
    }

    /// The reach of `cp`'s clusters, rebuilt if `build` (the lists' build count) is
    /// not the one it was made from.
    pub fn refresh_reach(&mut self, cp: &ClusterPairs, build: usize) {
        if self.built == Some(build) && self.off.len() == cp.len() + 1 {
            return;
        }
        let rows: Vec<Vec<u32>> = (0..cp.len())
            .into_par_iter()
            .map(|c| {
                let mut row: Vec<u32> = Vec::new();
                for &j in cp.of(c) {
                    let k = cp.of[j as usize];
                    if k as usize != c && row.last() != Some(&k) {
                        row.push(k);
                    }
                }
                row.sort_unstable();
                row.dedup();
                row
            })
            .collect();
        self.off.clear();
        self.reach.clear();
        self.off.push(0);
        for r in rows {
            self.reach.extend_from_slice(&r);
            self.off.push(self.reach.len() as u32);
        }
        self.built = Some(build);
    }

    /// The clusters other than `c` holding a partner of `c`.
    #[inline(always)]
    fn reach(&self, c: usize) -> &[u32] {
        &self.reach[self.off[c] as usize..self.off[c + 1] as usize]
    }

    /// Per cluster of `cp`, whether `f` holds for some member, into `self.any`; then
    /// per cluster whether it or a cluster of its reach does.
    fn spread(&mut self, cp: &ClusterPairs, f: impl Fn(usize) -> bool + Sync) -> Vec<bool> {
        self.any.clear();
        self.any
            .par_extend((0..cp.len()).into_par_iter().map(|c| cp.members(c).any(&f)));
        let any = &self.any;
        (0..cp.len())
            .into_par_iter()
            .map(|c| any[c] || self.reach(c).iter().any(|&k| any[k as usize]))
            .collect()
    }
}

/// Wake, at a step's end, every particle within the kernel support of a restless one
/// (`flags`; `near(i, j)`: particles i and j lie within it), from the pairs of `cp`'s
/// clusters that hold a restless particle, then advance each particle's count of quiet
/// steps (`quiet`): back to zero if it was restless, held or woken (or `hold_all`,
/// e.g. while gravity ramps up), otherwise one more, up to the rule's `steps`.
/// Returns the particles that fall asleep in this step (whose state the family then
/// freezes).
pub fn wake(
    cp: &ClusterPairs,
    rule: &SleepRule,
    sf: &mut SleepFlags,
    quiet: &mut [u16],
    hold_all: bool,
    near: impl Fn(usize, usize) -> bool + Sync,
) -> Vec<u32> {
    let n = quiet.len();
    debug_assert_eq!(sf.flags.len(), n);
    if cp.particles() == n && n > 0 {
        let restless: Vec<bool> = sf.flags.par_iter().map(|&f| f & RESTLESS != 0).collect();
        let near_restless = sf.spread(cp, |i| restless[i]);
        let task = |slab: usize, win: &mut [u8], base: usize| {
            let clusters = cp.slabs[slab] as usize..cp.slabs[slab + 1] as usize;
            for c in clusters.filter(|&c| near_restless[c]) {
                let (members, partners) = (cp.members(c), cp.of(c));
                for i in members {
                    let ri = restless[i];
                    for &j in partners {
                        let j = j as usize;
                        // each pair once, under its lower index; a pair of two restless
                        // particles, or whose quiet side is already woken, has nothing
                        // to wake
                        let rj = restless[j];
                        let quiet = if ri == rj {
                            continue;
                        } else if ri {
                            j
                        } else {
                            i
                        };
                        if j <= i || win[quiet - base] & WOKEN != 0 || !near(i, j) {
                            continue;
                        }
                        win[quiet - base] |= WOKEN;
                    }
                }
            }
        };
        two_phase_in(&cp.particle_slabs, &mut sf.flags, 512, &task);
    }
    let steps = rule.steps;
    quiet
        .par_iter_mut()
        .zip(sf.flags.par_iter())
        .enumerate()
        .filter_map(|(i, (q, &f))| {
            let was = *q >= steps;
            *q = if f != 0 || hold_all {
                0
            } else {
                (*q + 1).min(steps)
            };
            (!was && *q >= steps).then_some(i as u32)
        })
        .collect()
}

/// How the lane passes take each cluster of `cp` ([`ClusterPairs::runs`], with each
/// particle's [`ClusterPairs::awake`]): whole if a member is awake (`quiet` below the
/// rule's steps), its awake partners only if a cluster of its reach (`sf`'s, made from
/// `cp`'s build, [`SleepFlags::refresh_reach`]) has one, otherwise not at all.
pub fn mark_runs(cp: &mut ClusterPairs, rule: &SleepRule, quiet: &[u16], sf: &mut SleepFlags) {
    let mut awake = std::mem::take(&mut cp.awake);
    awake.clear();
    awake.par_extend(quiet.par_iter().map(|&q| !rule.asleep(q)));
    let near = sf.spread(cp, |i| awake[i]);
    let any = &sf.any;
    let mut runs = std::mem::take(&mut cp.runs);
    runs.clear();
    runs.par_extend((0..cp.len()).into_par_iter().map(|c| {
        if any[c] {
            Take::All
        } else if near[c] {
            Take::AwakePartners
        } else {
            Take::Skip
        }
    }));
    cp.runs = runs;
    cp.awake = awake;
}

/// The share of `quiet`'s particles awake under `rule` (1 for an empty family).
pub fn awake_share(rule: &SleepRule, quiet: &[u16]) -> Real {
    if quiet.is_empty() {
        return 1.0;
    }
    let asleep = quiet.par_iter().filter(|&&q| rule.asleep(q)).count();
    1.0 - asleep as Real / quiet.len() as Real
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Within the kernel support of the chain: the next two particles.
    fn near(i: usize, j: usize) -> bool {
        i.abs_diff(j) <= 2
    }

    /// A chain of 16 particles, each pairing with the next two: clusters of four in
    /// one slab.
    fn chain() -> ClusterPairs {
        let mut cp = ClusterPairs::default();
        cp.build(&[0, 16], 16, |i, out| {
            out.extend((i + 1..(i + 3).min(16)).map(|j| j as u32))
        });
        cp
    }

    #[test]
    fn quiet_particles_fall_asleep_after_the_window_and_a_restless_one_wakes_its_reach() {
        let cp = chain();
        let rule = SleepRule::new(1e-3, 10.0, 3, 0.01);
        let mut quiet = vec![0u16; 16];
        let mut sf = SleepFlags::default();
        sf.reset(16);
        sf.refresh_reach(&cp, 1);
        for step in 0..3 {
            sf.flags.iter_mut().for_each(|f| *f = 0);
            let fell = wake(&cp, &rule, &mut sf, &mut quiet, false, near);
            assert_eq!(fell.len(), if step == 2 { 16 } else { 0 });
        }
        assert_eq!(awake_share(&rule, &quiet), 0.0);
        // particle 9 restless: its neighbours 7, 8 (the clusters whose list holds 9)
        // and 10, 11 (its own list) wake; the rest sleep on
        sf.flags.iter_mut().for_each(|f| *f = 0);
        sf.flags[9] = RESTLESS;
        wake(&cp, &rule, &mut sf, &mut quiet, false, near);
        let awake: Vec<usize> = (0..16).filter(|&i| !rule.asleep(quiet[i])).collect();
        assert_eq!(awake, (7..12).collect::<Vec<_>>());
        let mut cp = cp;
        mark_runs(&mut cp, &rule, &quiet, &mut sf);
        // cluster 3 sleeps with its partners; cluster 0 reaches the awake cluster 1
        use Take::*;
        assert_eq!(cp.runs, [AwakePartners, All, All, Skip]);
        // a held particle is reset but wakes nobody
        sf.flags.iter_mut().for_each(|f| *f = 0);
        let mut quiet = vec![3u16; 16];
        sf.flags[0] = HELD;
        wake(&cp, &rule, &mut sf, &mut quiet, false, near);
        assert_eq!(quiet[0], 0);
        assert!(quiet[1..].iter().all(|&q| q == 3));
        mark_runs(&mut cp, &rule, &quiet, &mut sf);
        assert_eq!(cp.runs, [All, Skip, Skip, Skip]);
    }

    #[test]
    fn a_ramp_holds_everything_awake() {
        let cp = chain();
        let rule = SleepRule::new(1e-3, 10.0, 2, 0.01);
        let mut quiet = vec![2u16; 16];
        let mut sf = SleepFlags::default();
        sf.reset(16);
        sf.refresh_reach(&cp, 1);
        wake(&cp, &rule, &mut sf, &mut quiet, true, near);
        assert!(quiet.iter().all(|&q| q == 0));
    }

    #[test]
    fn motion_and_strain_thresholds() {
        let rule = SleepRule::new(1e-3, 10.0, 100, 0.005);
        let v = |x: Real| Vect::<2>::new(x, 0.0);
        let dt = 1e-5;
        assert!(!rule.restless_motion(&v(5e-4), &v(5.9e-4), dt));
        assert!(rule.restless_motion(&v(5e-4), &v(6.1e-4), dt));
        assert!(rule.restless_motion(&v(1e-3), &v(1e-3), dt));
        assert!(!rule.restless_strain(0.19 * 0.19));
        assert!(rule.restless_strain(0.2 * 0.2));
    }
}
