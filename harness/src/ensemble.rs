//! `granmix run SCENE --ensemble N`: the scene run N times, member m's start perturbed
//! by the scene's `simulation.perturbation` with seed `seed + m` (every soil and water
//! particle moved by ε dp), and the spread of every output over the members.
//!
//! A debris flow is chaotic and a boulder's impact a discrete event, so one run's peak
//! load is one draw of a random variable; the ensemble gives its mean, standard
//! deviation (N − 1), min, max and empirical 95th percentile (linear between order
//! statistics). Writes, under `--out`:
//! - `member_<m>/`: each member's own run (series.csv, summary.json, …);
//! - `ensemble.csv`: per series column and reduction (peak = max, min, final, and the
//!   time integral of loads: the impulse), the statistics over the finished members;
//! - `ensemble.json`: the same, with each member's seed, status and directory;
//! - `plots/ensemble.png`: each barrier's loads against time, every member and the
//!   mean ± sd band.
//!
//! Members run side by side when the machine has the cores (min(N, cores) at a time,
//! each on its own thread pool of cores / that many threads, at least one; `--threads`
//! sets the cores); the results do not depend on it.

use crate::plot::{self, Band};
use crate::run::{self, RunOptions, RunReport};
use anyhow::{bail, Context, Result};
use granmix_core::run::observables::{observables, Layout, Observable, Unit};
use granmix_core::run::simulation::Sample;
use granmix_core::scene::default_perturbation_amplitude;
use indicatif::{ProgressBar, ProgressStyle};
use serde_json::{json, Value};
use std::path::{Path, PathBuf};
use std::sync::atomic::{AtomicUsize, Ordering};
use std::sync::Mutex;

/// What the command line asks of an ensemble.
#[derive(Clone, Debug)]
pub struct Ensemble {
    pub members: usize,
    /// ε: each particle's displacement as a fraction of dp.
    pub epsilon: f64,
    /// Member m's seed is `seed + m`.
    pub seed: u64,
}

impl Default for Ensemble {
    fn default() -> Self {
        Ensemble {
            members: 8,
            epsilon: default_perturbation_amplitude(),
            seed: 0,
        }
    }
}

/// How a series column is reduced to one number per member.
#[derive(Clone, Copy, Debug, PartialEq)]
enum Reduction {
    Peak,
    Min,
    Final,
    /// ∫ dt by the trapezoidal rule: a load's impulse.
    Integral,
}

impl Reduction {
    fn name(self) -> &'static str {
        match self {
            Reduction::Peak => "peak",
            Reduction::Min => "min",
            Reduction::Final => "final",
            Reduction::Integral => "integral",
        }
    }
    fn of(self, t: &[f64], x: &[f64]) -> f64 {
        match self {
            Reduction::Peak => x.iter().copied().fold(f64::NEG_INFINITY, f64::max),
            Reduction::Min => x.iter().copied().fold(f64::INFINITY, f64::min),
            Reduction::Final => x.last().copied().unwrap_or(f64::NAN),
            Reduction::Integral => (1..x.len())
                .map(|k| 0.5 * (x[k] + x[k - 1]) * (t[k] - t[k - 1]))
                .sum(),
        }
    }
}

/// The statistics of one reduced column over the finished members.
#[derive(Clone, Debug, PartialEq)]
pub struct Spread {
    pub members: usize,
    pub mean: f64,
    /// The sample standard deviation (N − 1); NaN for one member.
    pub sd: f64,
    pub min: f64,
    pub max: f64,
    /// The empirical 95th percentile: linear between the order statistics at
    /// 0.95 (N − 1) (NumPy's default).
    pub p95: f64,
}

impl Spread {
    pub fn of(x: &[f64]) -> Spread {
        let n = x.len();
        if n == 0 {
            let nan = f64::NAN;
            return Spread {
                members: 0,
                mean: nan,
                sd: nan,
                min: nan,
                max: nan,
                p95: nan,
            };
        }
        let mean = x.iter().sum::<f64>() / n as f64;
        let sd = if n > 1 {
            (x.iter().map(|v| (v - mean).powi(2)).sum::<f64>() / (n - 1) as f64).sqrt()
        } else {
            f64::NAN
        };
        let mut o = x.to_vec();
        o.sort_by(f64::total_cmp);
        let at = 0.95 * (n - 1) as f64;
        let (k, f) = (at.floor() as usize, at - at.floor());
        let p95 = if k + 1 < n {
            o[k] + f * (o[k + 1] - o[k])
        } else {
            o[k]
        };
        Spread {
            members: n,
            mean,
            sd,
            min: o[0],
            max: o[n - 1],
            p95,
        }
    }
}

/// Each member's run options: the base run's, its own output directory, its seed, and
/// no progress bar of its own.
fn member_options(base: &RunOptions, e: &Ensemble, m: usize) -> RunOptions {
    let mut o = base.clone();
    o.out = member_dir(base, m);
    o.interactive = false;
    o.set.push(format!(
        "simulation.perturbation.seed={}",
        e.seed + m as u64
    ));
    o.set
        .push(format!("simulation.perturbation.amplitude={:?}", e.epsilon));
    o
}

/// Refuse what the ensemble itself sets.
fn check(base: &RunOptions, e: &Ensemble) -> Result<()> {
    if e.members < 2 {
        bail!(
            "--ensemble {}: an ensemble needs at least 2 members (a spread needs two \
             draws; 8 or more for a 95th percentile)",
            e.members
        );
    }
    if !(e.epsilon > 0.0 && e.epsilon < 0.5) {
        bail!(
            "--epsilon {:?}: must lie in (0, 0.5), the distance each particle moves as a \
             fraction of dp (default 1e-6; 1e-12 is a round-off-level change)",
            e.epsilon
        );
    }
    if let Some(s) = base
        .set
        .iter()
        .find(|s| s.trim_start().starts_with("simulation.perturbation"))
    {
        bail!("--set {s}: --ensemble sets simulation.perturbation for each member; drop the --set");
    }
    let loaded = run::load(&base.scene, &base.set)?;
    if loaded.scene.simulation.perturbation.is_some() {
        bail!(
            "{}: `simulation.perturbation`: --ensemble sets it for each member; remove it \
             from the scene",
            base.scene.display()
        );
    }
    Ok(())
}

/// The stack of a member's threads: the command's own workers' (main.rs).
const MEMBER_STACK: usize = 8 << 20;

/// Members at a time and threads per member on a machine of `cores`.
fn schedule(members: usize, cores: usize) -> (usize, usize) {
    let jobs = members.min(cores).max(1);
    (jobs, (cores / jobs).max(1))
}

/// Run the ensemble; returns each member's report (an error as its message).
pub fn run(base: &RunOptions, e: &Ensemble) -> Result<Vec<Result<RunReport, String>>> {
    check(base, e)?;
    std::fs::create_dir_all(&base.out)
        .with_context(|| format!("cannot create output directory {}", base.out.display()))?;
    // the global pool holds `--threads` (default: the cores)
    let cores = rayon::current_num_threads().max(1);
    let (jobs, threads) = schedule(e.members, cores);
    let bar = if base.interactive {
        let b = ProgressBar::new(e.members as u64);
        b.set_style(
            ProgressStyle::with_template(
                "{spinner} members {pos}/{len} [{bar:30}] {elapsed_precise} (eta {eta}) {msg}",
            )
            .unwrap_or_else(|_| ProgressStyle::default_bar())
            .progress_chars("=> "),
        );
        b.set_message(format!("{jobs} at a time, {threads} thread(s) each"));
        b
    } else {
        ProgressBar::hidden()
    };
    let next = AtomicUsize::new(0);
    let reports: Mutex<Vec<Option<Result<RunReport, String>>>> =
        Mutex::new((0..e.members).map(|_| None).collect());
    std::thread::scope(|scope| {
        for _ in 0..jobs {
            scope.spawn(|| {
                let pool = rayon::ThreadPoolBuilder::new()
                    .num_threads(threads)
                    .stack_size(MEMBER_STACK)
                    .build();
                loop {
                    let m = next.fetch_add(1, Ordering::SeqCst);
                    if m >= e.members {
                        break;
                    }
                    let o = member_options(base, e, m);
                    let r = match &pool {
                        Ok(p) => p.install(|| run::run(&o)),
                        Err(err) => Err(anyhow::anyhow!("cannot start a thread pool: {err}")),
                    };
                    let r = r.map_err(|err| format!("{err:#}"));
                    if let Ok(mut all) = reports.lock() {
                        all[m] = Some(r);
                    }
                    bar.inc(1);
                }
            });
        }
    });
    bar.finish_and_clear();
    let reports = reports
        .into_inner()
        .map_err(|_| anyhow::anyhow!("a member's thread panicked"))?;
    let reports: Vec<Result<RunReport, String>> = reports
        .into_iter()
        .map(|r| r.unwrap_or_else(|| Err("did not run".into())))
        .collect();
    write(base, e, &reports)?;
    Ok(reports)
}

/// The columns reduced: every series column but time and the counters, each by peak,
/// min and final, and a load (a force, a moment) also by its time integral.
fn reductions(o: &Observable) -> &'static [Reduction] {
    use Reduction::*;
    if o.integer || o.name == "time" || o.name == "dt" {
        return &[];
    }
    match o.unit {
        Unit::Force | Unit::Moment => &[Peak, Min, Final, Integral],
        _ => &[Peak, Min, Final],
    }
}

/// One row of the ensemble table.
struct Row {
    column: String,
    reduction: Reduction,
    unit: String,
    /// A force or a moment.
    load: bool,
    spread: Spread,
}

/// The statistics of every reduced column over the finished members (those that ran to
/// their end without a blow-up).
fn table(layout: &Layout, finished: &[&[Sample]]) -> Vec<Row> {
    let mut rows = Vec::new();
    for o in observables(layout).iter().filter(|o| o.series) {
        for &how in reductions(o) {
            let x: Vec<f64> = finished
                .iter()
                .map(|s| {
                    let t: Vec<f64> = s.iter().map(|s| s.time).collect();
                    let v: Vec<f64> = s.iter().map(|s| o.real(s)).collect();
                    how.of(&t, &v)
                })
                .collect();
            let d = layout.dim;
            let unit = match (how, o.unit) {
                (Reduction::Integral, Unit::Force) => Unit::Momentum.symbol(d).to_string(),
                (Reduction::Integral, u) => format!("{} s", u.symbol(d)),
                (_, u) => u.symbol(d).to_string(),
            };
            rows.push(Row {
                column: o.name.clone(),
                reduction: how,
                unit,
                load: matches!(o.unit, Unit::Force | Unit::Moment),
                spread: Spread::of(&x),
            });
        }
    }
    rows
}

fn write(base: &RunOptions, e: &Ensemble, reports: &[Result<RunReport, String>]) -> Result<()> {
    let finished: Vec<(usize, &RunReport)> = reports
        .iter()
        .enumerate()
        .filter_map(|(m, r)| {
            r.as_ref()
                .ok()
                .filter(|r| r.blowup.is_none())
                .map(|r| (m, r))
        })
        .collect();
    let Some((_, first)) = finished.first() else {
        bail!(
            "no member of the ensemble finished: {}",
            member_lines(base, e, reports).join("; ")
        );
    };
    let layout = &first.layout;
    let samples: Vec<&[Sample]> = finished.iter().map(|(_, r)| &r.samples[..]).collect();
    let rows = table(layout, &samples);
    let mut csv = String::from("column,reduction,unit,members,mean,sd,min,max,p95\n");
    for r in &rows {
        let s = &r.spread;
        csv += &format!(
            "{},{},{},{},{:.9e},{:.9e},{:.9e},{:.9e},{:.9e}\n",
            r.column,
            r.reduction.name(),
            r.unit,
            s.members,
            s.mean,
            s.sd,
            s.min,
            s.max,
            s.p95
        );
    }
    std::fs::write(base.out.join("ensemble.csv"), csv)?;
    let members: Vec<Value> = reports
        .iter()
        .enumerate()
        .map(|(m, r)| {
            let status = match r {
                Ok(r) if r.blowup.is_none() => "finished".to_string(),
                Ok(r) => format!(
                    "blow-up: {}",
                    r.blowup.as_ref().map_or(String::new(), |b| b.to_string())
                ),
                Err(msg) => format!("error: {msg}"),
            };
            json!({
                "member": m,
                "seed": e.seed + m as u64,
                "out": member_dir(base, m),
                "status": status,
            })
        })
        .collect();
    let stats: Vec<Value> = rows
        .iter()
        .map(|r| {
            let s = &r.spread;
            json!({
                "column": r.column, "reduction": r.reduction.name(), "unit": r.unit,
                "members": s.members, "mean": s.mean, "sd": s.sd, "min": s.min,
                "max": s.max, "p95": s.p95,
            })
        })
        .collect();
    let doc = json!({
        "scene": base.scene.display().to_string(),
        "set": base.set,
        "members": e.members,
        "epsilon": e.epsilon,
        "seed": e.seed,
        "finished": finished.len(),
        "runs": members,
        "statistics": stats,
    });
    std::fs::write(
        base.out.join("ensemble.json"),
        serde_json::to_string_pretty(&doc)?,
    )?;
    if base.plots {
        let dir = base.out.join("plots");
        std::fs::create_dir_all(&dir)?;
        envelope(&dir.join("ensemble.png"), base, layout, &samples, e)?;
    }
    if base.interactive {
        let barriers: Vec<String> = layout.barriers.iter().map(|(b, _)| b.clone()).collect();
        summary(base, e, reports, &rows, finished.len(), &barriers);
    }
    Ok(())
}

fn member_dir(base: &RunOptions, m: usize) -> PathBuf {
    base.out.join(format!("member_{m:02}"))
}

fn member_lines(
    base: &RunOptions,
    e: &Ensemble,
    reports: &[Result<RunReport, String>],
) -> Vec<String> {
    reports
        .iter()
        .enumerate()
        .filter_map(|(m, r)| {
            let why = match r {
                Ok(r) => r.blowup.as_ref()?.to_string(),
                Err(msg) => msg.clone(),
            };
            Some(format!(
                "member {m} (seed {}, {}): {why}",
                e.seed + m as u64,
                member_dir(base, m).display()
            ))
        })
        .collect()
}

/// The barriers' loads (and, without barriers, the bodies' and the kinetic energy) with
/// their spread, on stdout.
fn summary(
    base: &RunOptions,
    e: &Ensemble,
    reports: &[Result<RunReport, String>],
    rows: &[Row],
    finished: usize,
    barriers: &[String],
) {
    println!(
        "ensemble of {} members (ε = {:e} dp, seeds {}–{}): {finished} finished",
        e.members,
        e.epsilon,
        e.seed,
        e.seed + e.members as u64 - 1
    );
    for line in member_lines(base, e, reports) {
        println!("  left out: {line}");
    }
    // each barrier's force and its parts (not its panels, not its moment): the peak and
    // the impulse of each component, the peak of the largest resultant
    let loads: Vec<&Row> = rows
        .iter()
        .filter(|r| {
            r.load
                && barriers.iter().any(|b| {
                    let Some(c) = r
                        .column
                        .strip_prefix(b.as_str())
                        .and_then(|c| c.strip_prefix('.'))
                    else {
                        return false;
                    };
                    match r.reduction {
                        Reduction::Peak => c.starts_with("force") || c == "peak_force",
                        Reduction::Integral => c.starts_with("force"),
                        _ => false,
                    }
                })
        })
        .collect();
    let shown: Vec<&Row> = if loads.is_empty() {
        rows.iter()
            .filter(|r| r.column == "kinetic_energy_total" && r.reduction == Reduction::Peak)
            .collect()
    } else {
        loads
    };
    let width = shown.iter().map(|r| r.column.len()).max().unwrap_or(0);
    for r in shown {
        let s = &r.spread;
        println!(
            "  {:<width$}  {:<8}  {:>11.4e} ± {:<9.2e} [min {:.4e}, max {:.4e}, p95 {:.4e}] {}",
            r.column,
            r.reduction.name(),
            s.mean,
            s.sd,
            s.min,
            s.max,
            s.p95,
            r.unit
        );
    }
    println!(
        "  every column: {}; members in {}",
        base.out.join("ensemble.csv").display(),
        base.out.join("member_NN").display()
    );
}

/// The envelope figure: a panel per barrier load (total, and with water its grain and
/// water parts, along x), each member's curve and the mean ± sd band; without
/// barriers, the kinetic energy.
fn envelope(
    path: &Path,
    base: &RunOptions,
    layout: &Layout,
    members: &[&[Sample]],
    e: &Ensemble,
) -> Result<()> {
    let table = observables(layout);
    let mut wanted: Vec<&Observable> = table
        .iter()
        .filter(|o| {
            layout.barriers.iter().any(|(b, _)| {
                o.name == format!("{b}.force.x")
                    || (layout.water
                        && (o.name == format!("{b}.force_grains.x")
                            || o.name == format!("{b}.force_water.x")))
            })
        })
        .collect();
    if wanted.is_empty() {
        wanted = table
            .iter()
            .filter(|o| o.name == "kinetic_energy_total")
            .collect();
    }
    let bands: Vec<Band> = wanted
        .iter()
        .map(|o| Band {
            title: o.name.clone(),
            ylabel: o.heading(layout.dim),
            members: members
                .iter()
                .map(|s| s.iter().map(|s| (s.time, o.real(s))).collect())
                .collect(),
        })
        .collect();
    let title = format!(
        "{}: {} members (ε = {:e} dp)",
        base.scene
            .file_stem()
            .map_or("scene".into(), |s| s.to_string_lossy().into_owned()),
        members.len(),
        e.epsilon
    );
    plot::envelopes(path, &title, "time [s]", &bands)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_spread_is_numpys() {
        // numpy: mean 4.5, std(ddof=1) 2.449489742783178, percentile(95) 7.65
        let s = Spread::of(&[3.0, 1.0, 8.0, 5.0, 2.0, 7.0, 4.0, 6.0]);
        assert_eq!((s.members, s.min, s.max), (8, 1.0, 8.0));
        assert!((s.mean - 4.5).abs() < 1e-15);
        assert!((s.sd - 2.449489742783178).abs() < 1e-14);
        assert!((s.p95 - 7.65).abs() < 1e-14, "{}", s.p95);
        let one = Spread::of(&[2.0]);
        assert!(one.sd.is_nan() && one.p95 == 2.0);
    }

    #[test]
    fn reductions_integrate_by_trapezoids() {
        let t = [0.0, 1.0, 3.0];
        let x = [0.0, 2.0, 0.0];
        assert_eq!(Reduction::Integral.of(&t, &x), 3.0);
        assert_eq!(Reduction::Peak.of(&t, &x), 2.0);
        assert_eq!(Reduction::Final.of(&t, &x), 0.0);
    }

    #[test]
    fn members_share_the_cores() {
        assert_eq!(schedule(8, 2), (2, 1));
        assert_eq!(schedule(2, 8), (2, 4));
        assert_eq!(schedule(3, 1), (1, 1));
    }
}
