//! `granmix bench`: named cases at several resolutions. Each run reports particle-steps
//! per second, time per stage and the error against the case's reference; the set is
//! written as JSON plus a PNG of error against run time.
//!
//! The benchmark lab, beside the command-line front end: the cases ([`cases`]) and
//! their metrics against the references ([`metric`]), the suites (`--suite accuracy`:
//! [`accuracy`], [`accuracy_series`]; `models`: [`models`], [`soil_model`];
//! `stability`: [`stability`]; `scale`: [`scale`]; `fmi`: [`fmi`]; their shared record
//! keeping: [`suite`]) and the channel's throughput ([`ipc`], `granmix bench-ipc`).

pub mod accuracy;
pub mod accuracy_series;
pub mod cases;
pub mod fmi;
pub mod ipc;
pub mod metric;
pub mod models;
pub mod scale;
pub mod soil_model;
pub mod stability;
pub mod suite;

use crate::bench::cases::{cases, Case};
use crate::bench::metric::{Level, Metric};
use crate::plot::{loglog, Curve};
use crate::run::{run, RunOptions};
use anyhow::{bail, Result};
use serde_json::{json, Value};
use std::path::{Path, PathBuf};
use std::process::ExitCode;

#[derive(clap::Args)]
pub struct BenchArgs {
    /// Cases to run (default: all). See --list.
    #[arg(long = "case")]
    cases: Vec<String>,
    /// Only the coarsest resolution of each case.
    #[arg(long)]
    quick: bool,
    /// List the cases (with --suite accuracy or models: the suite's) and exit.
    #[arg(long)]
    list: bool,
    /// With --suite models: only this soil model (repeatable; default all), e.g.
    /// `--model compression_cone`.
    #[arg(long = "model")]
    models: Vec<String>,
    /// With --suite models: only this level (repeatable; default all), by its label as
    /// `--list` prints it, e.g. `--level dp=4mm`.
    #[arg(long = "level")]
    levels: Vec<String>,
    /// Directory with the bundled scenes.
    #[arg(long, default_value = "models/scenes")]
    scenes: PathBuf,
    /// Output directory for bench.json, bench.png and run outputs.
    #[arg(long, default_value = "out/bench")]
    out: PathBuf,
    /// Run a suite instead of the validation cases: `accuracy` (run time against
    /// error, every scheme, three resolutions), `stability` (where the solver breaks,
    /// and that it breaks loudly), `scale` (throughput and memory from 10 k to 2 M
    /// particles), `fmi` (the FMI layer's time per fmi2DoStep against the solver's) or
    /// `models` (every soil case under each soil model: the verdict table).
    #[arg(long, value_parser = ["accuracy", "stability", "scale", "fmi", "models"])]
    suite: Option<String>,
    /// Also write the suite's Markdown report here (e.g. docs/stability.md).
    #[arg(long)]
    report: Option<PathBuf>,
    /// With --suite accuracy or models: reuse the record of each run already made with
    /// the same overrides under --out, so that an interrupted suite continues where it
    /// stopped.
    #[arg(long)]
    resume: bool,
}

/// `granmix bench`: a suite, the list of cases, or the cases themselves.
pub fn bench(a: &BenchArgs) -> Result<ExitCode> {
    if let Some(suite) = &a.suite {
        return run_suite(suite, a);
    }
    let all = cases();
    if a.list {
        list(&all);
        return Ok(ExitCode::SUCCESS);
    }
    for name in &a.cases {
        if !all.iter().any(|c| &c.name == name) {
            bail!("unknown bench case `{name}`; run `granmix bench --list`");
        }
    }
    let chosen: Vec<&Case> = all
        .iter()
        .filter(|c| a.cases.is_empty() || a.cases.contains(&c.name))
        .collect();
    run_cases(a, &chosen)
}

/// One of the suites of `--suite`, with its exit code.
fn run_suite(suite: &str, a: &BenchArgs) -> Result<ExitCode> {
    if suite != "models" && !(a.models.is_empty() && a.levels.is_empty()) {
        bail!(
            "bench: --model and --level select runs of --suite models only, not of --suite {suite}"
        );
    }
    if a.list {
        return match suite {
            "models" => {
                list(&crate::bench::models::model_cases());
                let names: Vec<&str> = crate::bench::soil_model::MODELS
                    .iter()
                    .map(|m| m.name())
                    .collect();
                println!("each under the models {}", names.join(", "));
                Ok(ExitCode::SUCCESS)
            }
            "accuracy" => {
                crate::bench::accuracy::list();
                Ok(ExitCode::SUCCESS)
            }
            _ => bail!(
                "bench --list --suite {suite}: this suite has no named cases to list; --list \
                 lists the bench cases, or those of --suite accuracy or models"
            ),
        };
    }
    let fail = |ok: bool, why: &str| {
        if ok {
            ExitCode::SUCCESS
        } else {
            eprintln!("{why}");
            ExitCode::from(1)
        }
    };
    let suite_options = crate::bench::suite::SuiteOptions {
        scenes: &a.scenes,
        out: &a.out,
        quick: a.quick,
        report: a.report.as_deref(),
        cases: &a.cases,
        models: &a.models,
        levels: &a.levels,
        resume: a.resume,
    };
    Ok(match suite {
        "stability" => {
            let loud = crate::bench::stability::stability(
                &a.scenes,
                &a.out,
                a.quick,
                a.report.as_deref(),
            )?;
            fail(
                loud,
                "a sweep failed without the guard's diagnostic (see above)",
            )
        }
        "accuracy" => {
            crate::bench::accuracy::accuracy(&suite_options)?;
            ExitCode::SUCCESS
        }
        "models" => {
            crate::bench::models::models(&suite_options)?;
            ExitCode::SUCCESS
        }
        "fmi" => {
            let within = crate::bench::fmi::fmi(&a.scenes, &a.out, a.quick, a.report.as_deref())?;
            fail(
                within || a.quick,
                "the FMI layer costs more than 1 % of the solver at 10 solver steps per \
                 communication step",
            )
        }
        _ => {
            crate::bench::scale::scale(&a.scenes, &a.out, a.quick, a.report.as_deref())?;
            ExitCode::SUCCESS
        }
    })
}

/// `--list`: one line per case, its scene, levels and note.
pub(crate) fn list(all: &[Case]) {
    let width = all
        .iter()
        .map(|c| c.name.chars().count())
        .max()
        .unwrap_or(0);
    for c in all {
        let lv: Vec<&str> = c.levels.iter().map(|l| l.0.as_str()).collect();
        println!(
            "{:<width$} {:<26} [{}]  {}",
            c.name,
            c.scene,
            lv.join(", "),
            c.note
        );
    }
}

/// Run `chosen` at their levels (the coarsest alone with `--quick`), print a row per
/// run, the cross-run comparisons, and write bench.json and bench.png.
fn run_cases(a: &BenchArgs, chosen: &[&Case]) -> Result<ExitCode> {
    std::fs::create_dir_all(&a.out)?;
    let mut records = Vec::new();
    let mut curves = Vec::new();
    let mut failed = false;
    println!(
        "{:<18} {:<8} {:>9} {:>8} {:>9} {:>12} {:>10} {:>11} {:>11} {:>8}",
        "case",
        "level",
        "particles",
        "steps",
        "wall [s]",
        "Mpart-st/s",
        "fine only",
        "value",
        "reference",
        "error"
    );
    for c in chosen {
        let levels = if a.quick {
            &c.levels[..1.min(c.levels.len())]
        } else {
            &c.levels[..]
        };
        let mut pts = Vec::new();
        for (k, level) in levels.iter().enumerate() {
            let finest = k + 1 == levels.len() && !a.quick;
            let run = run_level(a, c, level, finest)?;
            failed |= run.failed;
            pts.extend(run.point);
            records.push(run.record);
        }
        if !pts.is_empty() {
            curves.push(Curve {
                label: c.name.clone(),
                points: pts,
            });
        }
    }
    let comparisons = compare(&records);
    for line in comparisons.iter().filter_map(|c| c["text"].as_str()) {
        println!("{line}");
    }
    failed |= comparisons
        .iter()
        .any(|c| c["pass"].as_bool() == Some(false));
    let doc = json!({
        "threads": rayon::current_num_threads(),
        "runs": records,
        "comparisons": comparisons,
    });
    let jpath = a.out.join("bench.json");
    std::fs::write(&jpath, serde_json::to_string_pretty(&doc)?)?;
    println!("wrote {}", jpath.display());
    if !curves.is_empty() {
        plot(&a.out.join("bench.png"), chosen, &curves)?;
    }
    if failed {
        eprintln!("some cases missed their tolerance at the finest level (see above)");
        return Ok(ExitCode::from(1));
    }
    Ok(ExitCode::SUCCESS)
}

/// One run of a case at one level.
struct LevelRun {
    /// Its record in bench.json.
    record: Value,
    /// It blew up, or missed its tolerance at the finest level.
    failed: bool,
    /// Its point of bench.png, (wall time, error), when it has an error.
    point: Option<(f64, f64)>,
}

/// Run case `c` at `level` (the `finest` one is held to the tolerance), printed as a
/// row with its stages.
fn run_level(a: &BenchArgs, c: &Case, (label, over): &Level, finest: bool) -> Result<LevelRun> {
    let dir = a.out.join(&c.name).join(label.replace('/', "_"));
    let data = c.metric.data(&a.scenes)?;
    // under a soil model the shared overrides are in the variant scene already
    let (scene, set) = match c.model {
        Some(m) => (
            m.write_variant(&a.scenes.join(c.scene), &c.common, &dir)?,
            over.clone(),
        ),
        None => (a.scenes.join(c.scene), [&c.common[..], over].concat()),
    };
    let rep = run(&RunOptions::batch(scene, dir.clone(), set))?;
    let title = format!("{}, {label}", c.name);
    let (value, reference, detail) = c.metric.scored(&rep, data.as_ref(), (&dir, &title))?;
    let err = c.metric.error(value, reference);
    let mut failed = finest && err.zip(c.tolerance).is_some_and(|(e, tol)| e > tol);
    if let Some(b) = &rep.blowup {
        failed = true;
        eprintln!("{}: {label}: {b}", c.name);
    }
    let fmt = |x: Option<f64>| x.map(|v| format!("{v:.4}")).unwrap_or("-".into());
    println!(
        "{:<18} {:<8} {:>9} {:>8} {:>9.1} {:>12.3} {:>10.3} {:>11} {:>11} {:>8}",
        c.name,
        label,
        rep.particles,
        rep.summary["steps_fine"],
        rep.wall_time,
        rep.particle_steps_per_s / 1e6,
        rep.fine_particle_steps_per_s / 1e6,
        fmt(value),
        fmt(reference),
        err.map(|e| format!("{:.2}%", 100.0 * e))
            .unwrap_or("-".into()),
    );
    if let Some(f) = detail
        .as_ref()
        .filter(|_| matches!(c.metric, Metric::ForceReport(..)))
    {
        println!(
            "  peak force along x {} N at {} s ({})",
            fmt(f["peak_force_x"].as_f64()),
            fmt(f["peak_time"].as_f64()),
            dir.join("force.png").display()
        );
    }
    let stages = rep.summary["stages"].clone();
    print_stages(&stages, rep.wall_time);
    let record = json!({
        "case": c.name, "level": label, "scene": c.scene, "note": c.note,
        "model": c.model.map(|m| m.name()),
        "particles": rep.particles, "steps_fine": rep.summary["steps_fine"],
        "wall_time_s": rep.wall_time, "particle_steps_per_s": rep.particle_steps_per_s,
        "fine_particle_steps_per_s": rep.fine_particle_steps_per_s,
        "stages": stages, "value": value, "reference": reference, "rel_error": err,
        "tolerance": c.tolerance, "status": rep.summary["status"],
        "steps_coarse": rep.summary["steps_coarse"], "kappa": rep.summary["kappa"],
        "dt_fine": rep.summary["dt_fine"], "dt_coarse": rep.summary["dt_coarse"],
        "blocks": matches!(c.metric, Metric::BlockLanding(_))
            .then(|| block_json(&rep.samples)),
        "lobovsky": detail.clone().filter(|_| matches!(c.metric, Metric::Lobovsky)),
        "rondon": detail.clone().filter(|_| matches!(c.metric, Metric::Rondon(_))),
        "force": detail.filter(|_| matches!(c.metric, Metric::ForceReport(..))),
        "wave": match c.metric {
            Metric::StandingWave(w) => Some(w.report(&rep.samples)),
            _ => None,
        },
    });
    Ok(LevelRun {
        record,
        failed,
        point: err.map(|e| (rep.wall_time, e.max(1e-6))),
    })
}

/// bench.png: error against run time, one curve per case, the cases' tolerances as
/// lines.
fn plot(png: &Path, chosen: &[&Case], curves: &[Curve]) -> Result<()> {
    let mut tols: Vec<f64> = chosen.iter().filter_map(|c| c.tolerance).collect();
    tols.sort_by(f64::total_cmp);
    tols.dedup();
    let hlines: Vec<(f64, String)> = tols
        .iter()
        .map(|t| (*t, format!("tolerance {:.0} %", 100.0 * t)))
        .collect();
    loglog(
        png,
        "granmix bench: error against run time",
        "wall time [s]",
        "relative error",
        curves,
        &hlines,
    )?;
    println!("wrote {}", png.display());
    Ok(())
}

fn print_stages(stages: &Value, wall: f64) {
    if let Some(m) = stages.as_object() {
        let parts: Vec<String> = m
            .iter()
            .map(|(k, v)| {
                format!(
                    "{k} {:.0}%",
                    100.0 * v.as_f64().unwrap_or(0.0) / wall.max(1e-12)
                )
            })
            .collect();
        println!("{:<27} stages: {}", "", parts.join(", "));
    }
}

/// Cross-run checks: the crater grid mean, multi-rate against single-rate, rigid
/// against elastic.
/// Lobovský's sensor 1 at the finest level: its arrival within 0.1 of t √(g/H) and its
/// mean pressure over 3 ≤ t √(g/H) ≤ 6 within 15 % of the experiment's.
fn lobovsky_checks(r: &Value) -> Vec<Value> {
    let Some(s1) = r["sensors"].as_array().and_then(|s| s.first()) else {
        return Vec::new();
    };
    let mut out = Vec::new();
    if let (Some(a), Some(b)) = (s1["arrival"].as_f64(), s1["arrival_data"].as_f64()) {
        let d = a - b;
        out.push(json!({
            "name": "lobovsky_arrival", "arrival": a, "arrival_data": b,
            "difference": d, "tolerance": 0.1, "pass": d.abs() <= 0.1,
            "text": format!(
                "Lobovsky sensor 1 at H/160: arrives at t √(g/H) = {a:.3} against {b:.3} \
                 (difference {d:+.3}, tolerance 0.1)"
            ),
        }));
    }
    if let Some(e) = s1["mean_rel_error"].as_f64() {
        out.push(json!({
            "name": "lobovsky_mean_pressure", "mean": s1["mean"], "mean_data": s1["mean_data"],
            "rel_error": e, "tolerance": 0.15, "pass": e.abs() <= 0.15,
            "text": format!(
                "Lobovsky sensor 1 at H/160: mean p/(ρgH) over 3 ≤ t √(g/H) ≤ 6 {:.3} against \
                 {:.3} ({:+.1} %, tolerance 15 %); peak {:.2} against the experiment's {:.2}",
                s1["mean"].as_f64().unwrap_or(f64::NAN),
                s1["mean_data"].as_f64().unwrap_or(f64::NAN),
                100.0 * e,
                s1["peak"].as_f64().unwrap_or(f64::NAN),
                s1["peak_data"].as_f64().unwrap_or(f64::NAN),
            ),
        }));
    }
    out
}

/// The checks across cases of a bench run (`comparisons` in its report).
fn compare(records: &[Value]) -> Vec<Value> {
    let mut out = Vec::new();
    crater_grid(records, &mut out);
    standing_wave_period(records, &mut out);
    mu_i_costs(records, &mut out);
    if let Some(r) = find(records, "lobovsky", "H/160").map(|r| &r["lobovsky"]) {
        out.extend(lobovsky_checks(r));
    }
    multi_rate(records, &mut out);
    rigid_against_elastic(records, &mut out);
    out
}

/// The record of `case` at `level`.
fn find<'a>(records: &'a [Value], case: &str, level: &str) -> Option<&'a Value> {
    records
        .iter()
        .find(|r| r["case"] == case && r["level"] == level)
}

/// The crater grid's mean error over its twelve runs.
fn crater_grid(records: &[Value], out: &mut Vec<Value>) {
    let grid: Vec<f64> = records
        .iter()
        .filter(|r| {
            r["case"]
                .as_str()
                .is_some_and(|c| c.starts_with("crater_R"))
        })
        .filter_map(|r| r["rel_error"].as_f64())
        .collect();
    if !grid.is_empty() {
        let mean = grid.iter().sum::<f64>() / grid.len() as f64;
        let full = grid.len() == 12;
        out.push(json!({
            "name": "crater_grid_mean",
            "runs": grid.len(),
            "mean_rel_error": mean,
            "tolerance": 0.07,
            "pass": !full || mean <= 0.07,
            "text": format!(
                "crater grid: {} run(s), mean |error| {:.2} % (tolerance 7 % over the 12 runs)",
                grid.len(),
                100.0 * mean
            ),
        }));
    }
}

/// The standing wave's period against linear theory.
fn standing_wave_period(records: &[Value], out: &mut Vec<Value>) {
    if let Some(w) = find(records, "standing_wave", "dp=h/50").map(|r| &r["wave"]) {
        if let Some(e) = w["period_rel_error"].as_f64() {
            out.push(json!({
                "name": "standing_wave_period",
                "period_s": w["period_s"], "period_linear_s": w["period_linear_s"],
                "period_rel_error": e, "tolerance": 0.01,
                "pass": e.abs() <= 0.01,
                "text": format!(
                    "standing wave at dp = h/50 (issue 42): period {:.2} % off linear theory (tolerance 1 %)",
                    100.0 * e
                ),
            }));
        }
    }
}

/// What μ(I) costs over Drucker–Prager on the speed cases.
fn mu_i_costs(records: &[Value], out: &mut Vec<Value>) {
    for (dp_case, mu_case, level) in [
        ("speed_2d", "speed_2d_mu_i", "dp=2mm"),
        ("speed_3d", "speed_3d_mu_i", "r0/20"),
    ] {
        let rate =
            |case| find(records, case, level).and_then(|r| r["particle_steps_per_s"].as_f64());
        if let (Some(dp), Some(mu)) = (rate(dp_case), rate(mu_case)) {
            let cost = dp / mu - 1.0;
            out.push(json!({
                "name": format!("{mu_case}_cost"),
                "cost": cost, "tolerance": 0.15, "pass": cost <= 0.15,
                "text": format!(
                    "{mu_case}: μ(I) costs {:+.1} % over Drucker–Prager ({:.3} against {:.3} \
                     M particle-steps/s; issue 43 asks at most 15 %; one run each, alternate \
                     them for a verdict)",
                    100.0 * cost, mu / 1e6, dp / 1e6
                ),
            }));
        }
    }
}

/// Multi-rate against single-rate stepping on the crater.
fn multi_rate(records: &[Value], out: &mut Vec<Value>) {
    if let (Some(m), Some(s)) = (
        find(records, "crater_schemes", "multi-rate"),
        find(records, "crater_schemes", "single-rate"),
    ) {
        let (dm, ds) = (m["value"].as_f64(), s["value"].as_f64());
        let (tm, ts) = (m["wall_time_s"].as_f64(), s["wall_time_s"].as_f64());
        if let (Some(dm), Some(ds), Some(tm), Some(ts)) = (dm, ds, tm, ts) {
            let diff = (dm - ds).abs() / ds;
            let speedup = ts / tm;
            out.push(json!({
                "name": "multi_rate_vs_single_rate",
                "depth_multi": dm, "depth_single": ds, "depth_rel_diff": diff,
                "wall_multi_s": tm, "wall_single_s": ts, "speedup": speedup,
                "kappa": m["kappa"], "dt_fine": m["dt_fine"], "dt_coarse": m["dt_coarse"],
                "reference": "seed 000 Table 3: κ = 9, 9.7 min → 1.5 min (6.5×) on 32 cores",
                "pass": diff <= 0.02 && speedup >= 6.5,
                "text": format!(
                    "multi-rate vs single-rate: depth {:.4} vs {:.4} m ({:.2} %, tolerance 2 %), \
                     wall {:.1} s vs {:.1} s, speed-up {:.2}× (≥ 6.5×), κ = {}, Δt_f = {:.3e} s, Δt_c = {:.3e} s",
                    dm, ds, 100.0 * diff, tm, ts, speedup, m["kappa"],
                    m["dt_fine"].as_f64().unwrap_or(0.0), m["dt_coarse"].as_f64().unwrap_or(0.0)
                ),
            }));
        }
    }
}

/// A rigid ball against an elastic one on the crater.
fn rigid_against_elastic(records: &[Value], out: &mut Vec<Value>) {
    if let (Some(e), Some(r)) = (
        find(records, "crater_models", "elastic"),
        find(records, "crater_models", "rigid"),
    ) {
        if let (Some(de), Some(dr), Some(te), Some(tr)) = (
            e["value"].as_f64(),
            r["value"].as_f64(),
            e["wall_time_s"].as_f64(),
            r["wall_time_s"].as_f64(),
        ) {
            let diff = (dr - de).abs() / de;
            out.push(json!({
                "name": "rigid_vs_elastic",
                "depth_elastic": de, "depth_rigid": dr, "depth_rel_diff": diff,
                "wall_elastic_s": te, "wall_rigid_s": tr, "speed_ratio": te / tr,
                "pass": diff <= 0.03,
                "text": format!(
                    "rigid vs elastic ball: depth {:.4} vs {:.4} m ({:.2} %, tolerance 3 %), \
                     wall {:.1} s vs {:.1} s (rigid {:.2}× faster)",
                    dr, de, 100.0 * diff, tr, te, te / tr
                ),
            }));
        }
    }
}

/// §6 blocks: arrival, topple and landing times and β(t) of block 2, as JSON and a line
/// of text next to seed 000's figures.
fn block_json(samples: &[granmix_core::run::simulation::Sample]) -> Value {
    let e = granmix_core::run::observe::block_events(samples, "block1", "block2");
    let t = |x: Option<f64>| x.map(|v| format!("{v:.3} s")).unwrap_or("never".into());
    println!(
        "{:<27} flow reaches block 1 at {} (seed ≈ 0.25 s); block 2 starts to topple at {}, \
         lands at {} (seed ≈ 0.4 s, β ≈ 0° by ≈ 0.45 s); β at the end {:.1}°",
        "",
        t(e.arrival),
        t(e.topple),
        t(e.landing),
        e.final_beta
    );
    json!({
        "arrival_s": e.arrival, "topple_s": e.topple, "landing_s": e.landing,
        "final_beta_deg": e.final_beta,
        "beta_deg": e.beta.iter().map(|(t, b)| [*t, *b]).collect::<Vec<_>>(),
        "reference": "seed 000 Figs. 13–14: arrival ≈ 0.25 s, landing ≈ 0.4 s, β ≈ 0° by ≈ 0.45 s (±0.02 s)",
    })
}
