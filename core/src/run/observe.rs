//! Observables: energies, run-out, probes, and barrier-load sampling.

use crate::fine::state::FineParticles;
use crate::numerics::kernel::WendlandC2;
use crate::numerics::math::{Real, Sym, Vect};
use crate::run::sample::{DensityRatio, ProbeValue, Sample};

/// How run-out is measured. Particle volumes are binned by horizontal distance from the
/// origin (bins of width dp); a bin is deposit where its thickness ΣV / bin-area is at
/// least half a particle spacing. The run-out is the outer edge of the farthest run of
/// consecutive deposit bins that holds at least [`DEPOSIT_SHARE`] of the binned volume
/// (of the fullest run when none does): stray particles beyond the first thinner bin do
/// not count, a pile that came to rest beyond a sparse stretch does, and so do bins the
/// flow has left behind only when nothing lies farther (a debris flow that leaves its
/// release area empties the bins at the origin, which ended the scan at 0 m before,
/// issue 39). Each bin's thickness is first replaced by
/// the median of its own and its two neighbours' (an edge-preserving filter: a sharp
/// front stays where it is). A bin of a
/// deposit one grain thick holds a handful of particles, and its thickness alone wanders
/// across the threshold with round-off: the coarse 3D collapse at a = 1.5 (dp = r0/10)
/// ended at 0.24 or 0.26 m when dp changed by 1e-8, by a single bin dipping below the
/// threshold in front of thicker ones; with the median, at 0.25 or 0.26 m.
#[derive(Clone, Debug, serde::Serialize, serde::Deserialize)]
pub struct RunoutSpec<const D: usize> {
    /// Horizontal origin (x in 2D; x, y in 3D). The vertical axis is the last one.
    pub origin: Vec<Real>,
    /// 2D: +1 or −1 along x.
    pub direction: Real,
}

/// Σ ½ m v²; +0 without particles (a float `sum` of nothing is −0).
pub fn kinetic_energy<const D: usize>(p: &FineParticles<D>) -> Real {
    p.vel
        .iter()
        .zip(&p.mass)
        .map(|(v, m)| 0.5 * m * v.norm_squared())
        .fold(0.0, |a, e| a + e)
}

/// −Σ m g·x (zero at the origin); +0 without particles.
pub fn potential_energy<const D: usize>(p: &FineParticles<D>, g: &Vect<D>) -> Real {
    p.pos
        .iter()
        .zip(&p.mass)
        .map(|(x, m)| -m * g.dot(x))
        .fold(0.0, |a, e| a + e)
}

/// ρ/ρ0 of every fine particle (`rho0` per material index), summarised; None without
/// particles. Percentiles are order statistics, ⌊q (n − 1)⌋ of the sorted ratios.
pub fn density_ratio<const D: usize>(p: &FineParticles<D>, rho0: &[Real]) -> Option<DensityRatio> {
    if p.is_empty() {
        return None;
    }
    let mut r: Vec<Real> = p
        .rho
        .iter()
        .zip(&p.material)
        .map(|(rho, m)| rho / rho0[*m as usize])
        .collect();
    let mut at = |q: Real| {
        let k = (q * (r.len() - 1) as Real).floor() as usize;
        *r.select_nth_unstable_by(k, Real::total_cmp).1
    };
    let (median, p10, min) = (at(0.5), at(0.1), at(0.0));
    Some(DensityRatio { median, p10, min })
}

/// Deposit run-out (see [`RunoutSpec`]): fine grains plus `coarse` (position, volume)
/// pairs, so that rocks inside a deposit count as deposit.
pub fn runout<const D: usize>(
    p: &FineParticles<D>,
    coarse: &[(Vect<D>, Real)],
    spec: &RunoutSpec<D>,
    dp: Real,
) -> Real {
    let dist = |x: &Vect<D>| -> Real {
        if D == 2 {
            (x[0] - spec.origin[0]) * spec.direction
        } else {
            ((x[0] - spec.origin[0]).powi(2) + (x[1] - spec.origin[1]).powi(2)).sqrt()
        }
    };
    // (bin, volume) of the fine grains, then the coarse ones
    let items: Vec<(usize, Real)> = p
        .pos
        .iter()
        .zip(p.mass.iter().zip(&p.rho))
        .map(|(x, (m, rho))| (dist(x), m / rho))
        // a NaN distance falls in bin 0, as the dense histogram had it
        .filter(|(r, _)| r.is_nan() || *r >= 0.0)
        .chain(
            coarse
                .iter()
                .map(|(x, v)| (dist(x), *v))
                .filter(|(r, _)| *r >= 0.0),
        )
        .map(|(r, v)| ((r / dp) as usize, v))
        .collect();
    let vol = occupied_bins(items);
    // the bins run from 0 to ⌈r_max / dp⌉, one past the farthest occupied one unless
    // r_max falls on a bin edge
    let rmax = p
        .pos
        .iter()
        .chain(coarse.iter().map(|(x, _)| x))
        .map(dist)
        .fold(0.0, Real::max);
    let runs = deposit_runs::<D>(&vol, (rmax / dp).ceil() as usize, dp);
    // the farthest run holding at least DEPOSIT_SHARE of the material, else the fullest
    let total: Real = vol.iter().map(|&(_, v)| v).sum();
    runs.iter()
        .rev()
        .find(|r| r.0 >= DEPOSIT_SHARE * total)
        .or_else(|| {
            runs.iter()
                .fold(None, |b: Option<&(Real, Real)>, r| match b {
                    Some(b) if b.0 >= r.0 => Some(b),
                    _ => Some(r),
                })
        })
        .map_or(0.0, |r| r.1)
}

/// `(bin, volume)` items as the occupied bins in bin order, each bin's volumes summed
/// in the items' order: a sparse histogram, so a particle far away costs one bin, not
/// a bin per dp up to it.
fn occupied_bins(mut items: Vec<(usize, Real)>) -> Vec<(usize, Real)> {
    items.sort_by_key(|&(k, _)| k);
    let mut vol: Vec<(usize, Real)> = Vec::new();
    for (k, v) in items {
        match vol.last_mut() {
            Some((b, sum)) if *b == k => *sum += v,
            _ => vol.push((k, v)),
        }
    }
    vol
}

/// The runs of deposit bins of the occupied bins `vol` (width `dp`, bins `0..=last`),
/// each (volume, outer edge): bins whose thickness, the median of their own and their
/// neighbours', is at least half a spacing.
fn deposit_runs<const D: usize>(vol: &[(usize, Real)], last: usize, dp: Real) -> Vec<(Real, Real)> {
    let volume = |k: usize| {
        vol.binary_search_by_key(&k, |&(b, _)| b)
            .map_or(0.0, |at| vol[at].1)
    };
    let thickness = |k: usize| -> Real {
        let (r0, r1) = (k as Real * dp, (k + 1) as Real * dp);
        let area = if D == 2 {
            dp
        } else {
            std::f64::consts::PI * (r1 * r1 - r0 * r0)
        };
        volume(k) / area
    };
    let next = |k: usize| k.saturating_add(1).min(last);
    // bins that may be deposit: the occupied ones and their neighbours (the median of
    // three of an empty bin between two occupied ones is not zero)
    let mut candidates: Vec<usize> = vol
        .iter()
        .flat_map(|&(k, _)| [k.saturating_sub(1), k, next(k)])
        .collect();
    candidates.sort_unstable();
    candidates.dedup();
    let mut runs: Vec<(Real, Real)> = Vec::new();
    let mut run: Option<Real> = None;
    let mut previous: Option<usize> = None;
    for k in candidates {
        if previous.is_some_and(|p| p.saturating_add(1) != k) {
            // the bins between were empty with empty neighbours: no deposit
            run = None;
        }
        previous = Some(k);
        // median of bins k − 1, k, k + 1 (the bin itself at either end)
        let (a, b) = (thickness(k.saturating_sub(1)), thickness(next(k)));
        let t = thickness(k);
        let median = t.min(a.max(b)).max(a.min(b));
        if median < 0.5 * dp {
            run = None;
            continue;
        }
        let edge = (k + 1) as Real * dp;
        match run {
            Some(v) => *runs.last_mut().expect("a run is open") = (v + volume(k), edge),
            None => runs.push((volume(k), edge)),
        }
        run = runs.last().map(|r| r.0);
    }
    runs
}

/// A run of deposit bins that holds at least this share of the binned volume counts as
/// deposit even when a sparse stretch separates it from the main body (issue 39: 73 of
/// the debris flow's 530 grains and a boulder came to rest 0.9 m beyond the rest).
pub const DEPOSIT_SHARE: Real = 0.05;

pub fn probe<const D: usize>(
    p: &FineParticles<D>,
    kernel: &WendlandC2,
    at: &Vect<D>,
) -> ProbeValue {
    let mut wsum = 0.0;
    let mut s = Sym::ZERO;
    let mut v = Vect::<D>::zeros();
    let mut n = 0;
    for i in 0..p.len() {
        let r = (p.pos[i] - at).norm();
        if r < kernel.cutoff {
            let w = kernel.w(r) * p.mass[i] / p.rho[i];
            wsum += w;
            s.axpy(w, &p.stress[i]);
            v += p.vel[i] * w;
            n += 1;
        }
    }
    if wsum > 0.0 {
        s = s.scale(1.0 / wsum);
        v /= wsum;
    }
    let mut vel = [0.0; 3];
    for k in 0..D {
        vel[k] = v[k];
    }
    ProbeValue {
        stress: s,
        velocity: vel,
        support: n,
        water_pressure: None,
        water_velocity: None,
    }
}

/// β of seed 000 Fig. 14: the angle (degrees, 0–90) between a 2D body's initially
/// vertical side and the x-axis, from its orientation quaternion (w, x, y, z).
pub fn side_angle_deg(q: &[Real; 4]) -> Real {
    let turn = 2.0 * q[3].atan2(q[0]);
    let a = (90.0 + turn.to_degrees()).rem_euclid(180.0);
    a.min(180.0 - a)
}

/// Events of the blocks case (seed 000 §5.3, VALIDATION §6) read off a run's samples.
#[derive(Clone, Debug, Default)]
pub struct BlockEvents {
    /// First time the fine grains load `hit` (the flow arrives at the blocks).
    pub arrival: Option<Real>,
    /// First time β of `watched` drops below 85° (it starts to topple).
    pub topple: Option<Real>,
    /// First time β of `watched` comes within 5° of 0 (it lands on its side).
    pub landing: Option<Real>,
    /// β of `watched` at the last sample, and its (time, β) history.
    pub final_beta: Real,
    pub beta: Vec<(Real, Real)>,
}

/// [`BlockEvents`] for the body named `watched`, with arrival taken on body `hit`.
pub fn block_events(samples: &[Sample], hit: &str, watched: &str) -> BlockEvents {
    let mut e = BlockEvents::default();
    for s in samples {
        if e.arrival.is_none() {
            if let Some(b) = s.bodies.iter().find(|b| b.name == hit) {
                if b.fine_force.iter().any(|f| *f != 0.0) {
                    e.arrival = Some(s.time);
                }
            }
        }
        if let Some(b) = s.bodies.iter().find(|b| b.name == watched) {
            let beta = side_angle_deg(&b.orientation);
            if e.topple.is_none() && beta < 85.0 {
                e.topple = Some(s.time);
            }
            if e.landing.is_none() && beta < 5.0 {
                e.landing = Some(s.time);
            }
            e.beta.push((s.time, beta));
            e.final_beta = beta;
        }
    }
    e
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A 2D deposit: `layers[k]` particles stacked in bin k (volume dp² each).
    fn deposit(layers: &[usize], dp: Real) -> FineParticles<2> {
        let mut p = FineParticles::<2>::default();
        for (k, &n) in layers.iter().enumerate() {
            for l in 0..n {
                let x = Vect::<2>::new((k as Real + 0.5) * dp, (l as Real + 0.5) * dp);
                p.push(
                    x,
                    Vect::<2>::zeros(),
                    1000.0,
                    1000.0 * dp * dp,
                    Sym::ZERO,
                    0,
                );
            }
        }
        p
    }

    fn front(layers: &[usize]) -> Real {
        let dp = 0.01;
        let spec = RunoutSpec {
            origin: vec![0.0],
            direction: 1.0,
        };
        runout(&deposit(layers, dp), &[], &spec, dp) / dp
    }

    #[test]
    fn runout_is_the_deposit_edge() {
        // a sharp front stays put: 20 bins three grains thick
        let mut d = vec![3; 20];
        assert_eq!(front(&d), 20.0);
        // stray grains beyond the front do not count
        d.extend([0, 0, 0, 1, 0, 0, 1]);
        assert_eq!(front(&d), 20.0);
        // a one-grain tail counts; a single empty bin inside it does not end it
        let mut t = vec![3; 20];
        t.extend([1, 1, 0, 1, 1, 0, 0, 1]);
        assert_eq!(front(&t), 25.0);
        // two empty bins do
        let mut u = vec![3; 20];
        u.extend([1, 1, 0, 0, 1, 1]);
        assert_eq!(front(&u), 22.0);
    }

    /// Issue 74: the bins are sparse, so a grain a petametre away (a restored state's
    /// forged position made the dense histogram ask for 10¹⁵ bytes) costs one bin and
    /// changes nothing of the deposit.
    #[test]
    fn a_far_grain_costs_one_bin() {
        let dp = 0.01;
        let spec = RunoutSpec {
            origin: vec![0.0],
            direction: 1.0,
        };
        let mut p = deposit(&[3; 20], dp);
        let near = runout(&p, &[], &spec, dp);
        p.push(
            Vect::<2>::new(1e15, 0.005),
            Vect::<2>::zeros(),
            1000.0,
            1000.0 * dp * dp,
            Sym::ZERO,
            0,
        );
        assert_eq!(runout(&p, &[], &spec, dp), near);
        assert_eq!(near, 20.0 * dp);
    }

    /// Issue 39: a flow that has left its release area empties the bins at the origin;
    /// the run-out is the deposit's edge, not 0 (it was 0 before).
    #[test]
    fn issue_39_runout_follows_a_deposit_that_left_the_origin() {
        let mut d = vec![0; 30];
        d.extend([2, 3, 3, 3, 2]);
        assert_eq!(front(&d), 35.0);
        // a thin film left behind upslope is not the deposit
        let mut f = vec![1; 6];
        f.extend([0; 10]);
        f.extend([3; 8]);
        assert_eq!(front(&f), 24.0);
    }

    /// Issue 39: a pile that came to rest beyond a sparse stretch is part of the
    /// deposit when it holds at least 5 % of the material (it was dropped before, and
    /// the run-out stopped at the main body's edge); a smaller one is not.
    #[test]
    fn issue_39_runout_reaches_a_detached_pile() {
        let mut d = vec![3; 20];
        d.extend([0, 0, 0, 0]);
        d.extend([3, 3, 3]); // 9 of 69 grains: 13 %
        assert_eq!(front(&d), 27.0);
        let mut e = vec![3; 40];
        e.extend([0, 0, 0, 0]);
        e.extend([2, 2]); // 4 of 124 grains: 3 %
        assert_eq!(front(&e), 40.0);
    }
}
