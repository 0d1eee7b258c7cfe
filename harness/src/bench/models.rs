//! `granmix bench --suite models`: the soil-model verdict table (issue 43). Every soil
//! case with a reference runs under each soil model at the bench's levels, and the
//! report holds, for each model, the error at the finest level against run time and the
//! issue's criteria: the 3D collapse against Lube (5 % at the finest level, the error
//! falling with resolution), the crater grid against seed 000 Eq. (62) (each run within
//! 15 % and the mean within 7 % at dp = 4 mm, the corners also at 2 mm), the retained
//! layer inside [K_a, K0], the geostatic layer within 3 %, SPHinXsys's collapse energy
//! within 2 %.
//!
//! A model is applied to every `[[materials]]` entry of the scene after the case's own
//! overrides; the variant is written beside the run (`model_scene.toml`) and run with
//! the level's overrides.

use crate::bench::cases::{cases, Case};
use crate::bench::metric::{Level, Metric};
use crate::bench::soil_model::{Model, MODELS};
use crate::bench::suite::SuiteOptions;
use crate::plot::{loglog, Curve};
use crate::run::{run, RunOptions};
use anyhow::{bail, Result};
use serde_json::{json, Value};
use std::path::Path;

/// The suite's cases: the 3D collapses (to r0/25), the 2D collapses, the geostatic and
/// retained layers, SPHinXsys's collapse, and the crater grid at dp = 4 mm with its
/// four corners (R and μ at their extremes, H = 0.2 m) also at 2 mm.
pub(crate) fn model_cases() -> Vec<Case> {
    let wanted = |name: &str| {
        name.starts_with("collapse_")
            || name.starts_with("crater_R")
            || matches!(name, "geostatic" | "retained_layer" | "sphinxsys_collapse")
    };
    cases()
        .into_iter()
        .filter(|c| wanted(&c.name))
        .map(|mut c| {
            if c.name.starts_with("crater_R") && c.name.ends_with("_H0.2") {
                c.levels
                    .push(("dp=2mm".into(), vec!["simulation.dp=0.002".into()]));
            }
            c
        })
        .collect()
}

/// Run the suite: every case under every model, or the runs `--case`, `--model` and
/// `--level` select. With `--resume` the report also holds every run outside the
/// selection already recorded under `--out` with the same inputs, so that a table
/// filled by several partial invocations is written whole.
pub fn models(o: &SuiteOptions) -> Result<()> {
    let all = model_cases();
    check_selection(o, &all)?;
    std::fs::create_dir_all(o.out)?;
    println!(
        "{:<26} {:<17} {:<9} {:>9} {:>9} {:>11} {:>11} {:>8}",
        "case", "model", "level", "particles", "wall [s]", "value", "reference", "error"
    );
    let mut runs = Vec::new();
    // with --quick, a case whose scene an earlier case ran (the crater grid after its
    // first) is skipped: a smoke run of the same code path
    let mut smoked = std::collections::HashSet::new();
    for c in &all {
        let case_chosen = o.cases.is_empty() || o.cases.contains(&c.name);
        if o.quick && !(case_chosen && smoked.insert(c.scene)) {
            continue;
        }
        let levels = if o.quick {
            &c.levels[..1.min(c.levels.len())]
        } else {
            &c.levels[..]
        };
        // every model at a level before the next, finer one: an interrupted suite
        // leaves whole columns of the table
        for level in levels {
            for model in MODELS {
                let chosen = case_chosen
                    && (o.levels.is_empty() || o.levels.contains(&level.0))
                    && (o.models.is_empty() || o.models.iter().any(|m| m == model.name()));
                let (r, tag) = if chosen {
                    (run_one(o, c, model, level)?, "")
                } else {
                    match recorded(o, c, model, level) {
                        Some(r) => (r, " (recorded)"),
                        None => continue,
                    }
                };
                println!(
                    "{:<26} {:<17} {:<9} {:>9} {:>9.1} {:>11} {:>11} {:>8}{tag}",
                    c.name,
                    model.name(),
                    level.0,
                    r["particles"],
                    r["wall_time_s"].as_f64().unwrap_or(0.0),
                    sci(&r["value"]),
                    sci(&r["reference"]),
                    pct(&r["rel_error"]),
                );
                runs.push(r);
            }
        }
    }
    let doc = json!({
        "suite": "models", "quick": o.quick, "threads": rayon::current_num_threads(),
        "runs": runs,
    });
    let path = o.out.join("models.json");
    std::fs::write(&path, serde_json::to_string_pretty(&doc)?)?;
    let png = o.out.join("models.png");
    plot(&png, &runs)?;
    std::fs::write(o.out.join("models.md"), markdown(&doc, "models.png"))?;
    println!("wrote {}, {} and models.md", path.display(), png.display());
    if let Some(r) = o.report {
        let png = r.with_extension("png");
        plot(&png, &runs)?;
        let name = png
            .file_name()
            .map(|n| n.to_string_lossy().into_owned())
            .unwrap_or_default();
        std::fs::write(r, markdown(&doc, &name))?;
        println!("wrote {} and {}", r.display(), png.display());
    }
    Ok(())
}

/// That every `--case`, `--model` and `--level` names something of the suite.
fn check_selection(o: &SuiteOptions, all: &[Case]) -> Result<()> {
    if let Some(bad) = o.cases.iter().find(|c| !all.iter().any(|s| &s.name == *c)) {
        let names: Vec<&str> = all.iter().map(|s| s.name.as_str()).collect();
        bail!(
            "bench --suite models: unknown --case {bad:?}; cases are {}",
            names.join(", ")
        );
    }
    if let Some(bad) = o
        .models
        .iter()
        .find(|m| !MODELS.iter().any(|x| x.name() == m.as_str()))
    {
        let names: Vec<&str> = MODELS.iter().map(|m| m.name()).collect();
        bail!(
            "bench --suite models: unknown --model {bad:?}; models are {}",
            names.join(", ")
        );
    }
    let chosen: Vec<&Case> = all
        .iter()
        .filter(|c| o.cases.is_empty() || o.cases.contains(&c.name))
        .collect();
    if let Some(bad) = o
        .levels
        .iter()
        .find(|l| !chosen.iter().any(|c| c.levels.iter().any(|x| &x.0 == *l)))
    {
        let mut names: Vec<&str> = chosen
            .iter()
            .flat_map(|c| c.levels.iter().map(|l| l.0.as_str()))
            .collect();
        names.sort_unstable();
        names.dedup();
        bail!(
            "bench --suite models: no chosen case has the --level {bad:?}; their levels are {}",
            names.join(", ")
        );
    }
    Ok(())
}

/// Where the run of case `c` under `model` at `level` keeps its record, and the key
/// the record must carry to be reused: the case's overrides, the level's and the model.
fn record_of(
    o: &SuiteOptions,
    c: &Case,
    model: Model,
    (label, over): &Level,
) -> (std::path::PathBuf, Vec<String>, Value) {
    let dir = o
        .out
        .join(&c.name)
        .join(model.name())
        .join(label.replace(['/', ' ', '='], "_"));
    let mut set = over.clone();
    if o.quick {
        set.push("simulation.end_time=0.002".into());
    }
    let key = json!({"common": c.common, "set": set, "model": model.name()});
    (dir, set, key)
}

/// The record of a run outside the selection, when `--resume` finds it under `--out`.
fn recorded(o: &SuiteOptions, c: &Case, model: Model, level: &Level) -> Option<Value> {
    let (dir, _, key) = record_of(o, c, model, level);
    o.cached(&dir.join("record.json"), "key", &key)
}

/// The record of case `c` under `model` at `level`: the one under --out when --resume
/// finds it made with the same overrides, else that of a new run.
fn run_one(o: &SuiteOptions, c: &Case, model: Model, level: &Level) -> Result<Value> {
    let (dir, set, key) = record_of(o, c, model, level);
    let label = &level.0;
    let record = dir.join("record.json");
    if let Some(r) = o.cached(&record, "key", &key) {
        return Ok(r);
    }
    let variant = model.write_variant(&o.scenes.join(c.scene), &c.common, &dir)?;
    let rep = run(&RunOptions::batch(variant, dir.clone(), set))?;
    let (value, reference) = c.metric.evaluate(&rep);
    let err = c.metric.error(value, reference);
    let r = json!({
        "case": c.name, "model": model.name(), "level": label, "key": key,
        "particles": rep.particles, "wall_time_s": rep.wall_time,
        "value": value, "reference": reference, "rel_error": err,
        "band": matches!(c.metric, Metric::EarthPressure(_)),
        "blowup": rep.blowup.as_ref().map(|b| b.to_string()),
    });
    std::fs::write(&record, serde_json::to_string_pretty(&r)?)?;
    Ok(r)
}

fn sci(v: &Value) -> String {
    v.as_f64().map_or("-".into(), |x| format!("{x:.4e}"))
}

fn pct(v: &Value) -> String {
    v.as_f64()
        .map_or("-".into(), |e| format!("{:.2} %", 100.0 * e))
}

/// Error against wall time, one curve per model over the cases' finest levels.
fn plot(png: &Path, runs: &[Value]) -> Result<()> {
    let curves: Vec<Curve> = MODELS
        .iter()
        .map(|m| {
            let mut points: Vec<(f64, f64)> = finest(runs)
                .into_iter()
                .filter(|r| r["model"] == m.name())
                .filter_map(|r| Some((r["wall_time_s"].as_f64()?, r["rel_error"].as_f64()?)))
                .map(|(w, e)| (w.max(1e-3), e.max(1e-4)))
                .collect();
            points.sort_by(|a, b| a.0.total_cmp(&b.0));
            Curve {
                label: m.name().into(),
                points,
            }
        })
        .filter(|c| !c.points.is_empty())
        .collect();
    if curves.is_empty() {
        return Ok(());
    }
    loglog(
        png,
        "granmix bench --suite models: error at each case's finest level against run time",
        "wall time [s]",
        "relative error",
        &curves,
        &[(0.05, "5 %".into())],
    )
}

/// For each case and model, the run at the last level that ran (the finest).
fn finest(runs: &[Value]) -> Vec<&Value> {
    let mut out: Vec<&Value> = Vec::new();
    for r in runs {
        match out
            .iter_mut()
            .find(|o| o["case"] == r["case"] && o["model"] == r["model"])
        {
            Some(o) => *o = r,
            None => out.push(r),
        }
    }
    out
}

/// The run of `case` under `model` at `level`.
fn find<'a>(runs: &'a [Value], case: &str, model: &str, level: &str) -> Option<&'a Value> {
    runs.iter()
        .find(|r| r["case"] == case && r["model"] == model && r["level"] == level)
}

/// A criterion of the issue for one model: whether it holds (None: not all its runs
/// are there) and what was measured.
type Verdict = (Option<bool>, String);

/// The criteria, each evaluated for `model`.
fn criteria(runs: &[Value], model: &str) -> Vec<(&'static str, Verdict)> {
    let err = |case: &str, level: &str| {
        find(runs, case, model, level).and_then(|r| r["rel_error"].as_f64())
    };
    let single = |case: &str, level: &str, tol: f64| -> Verdict {
        match err(case, level) {
            Some(e) => (Some(e <= tol), format!("{:.2} %", 100.0 * e)),
            None => (None, "not run".into()),
        }
    };
    let mut v = vec![
        (
            "3D collapse (Lube): within 5 % at r0/25 for a = 0.5, 1, 1.5, the error falling from r0/20",
            collapse_verdict(runs, model),
        ),
        (
            "crater grid at dp = 4 mm: each within 15 %, mean within 7 %",
            crater_grid_verdict(runs, model, "dp=4mm", false),
        ),
        (
            "crater corners (H = 0.2 m) at dp = 2 mm: each within 15 %, mean within 7 %",
            crater_grid_verdict(runs, model, "dp=2mm", true),
        ),
        (
            "retained layer inside [K_a, K0] (dp = 3.75 mm)",
            retained_verdict(runs, model),
        ),
    ];
    v.push((
        "geostatic layer within 3 % (finest level)",
        finest(runs)
            .into_iter()
            .find(|r| r["case"] == "geostatic" && r["model"] == model)
            .and_then(|r| r["rel_error"].as_f64())
            .map_or((None, "not run".into()), |e| {
                (Some(e < 0.03), format!("{:.2} %", 100.0 * e))
            }),
    ));
    v.push((
        "SPHinXsys collapse energy at 0.8 s within 2 % (dp = 2 mm)",
        single("sphinxsys_collapse", "2 mm", 0.02),
    ));
    v
}

/// The 3D collapses: 5 % at r0/25, and the error falling from r0/20 to r0/25.
fn collapse_verdict(runs: &[Value], model: &str) -> Verdict {
    let err = |case: &str, level: &str| {
        find(runs, case, model, level).and_then(|r| r["rel_error"].as_f64())
    };
    let collapse: Vec<Option<(f64, f64)>> = ["0.5", "1", "1.5"]
        .iter()
        .map(|a| {
            let c = format!("collapse_3d_a{a}");
            err(&c, "r0/20").zip(err(&c, "r0/25"))
        })
        .collect();
    // a run-out's signed error (value against reference) at `level`, for a = 0.5, 1, 1.5
    let signed = |level: &str| -> Vec<String> {
        ["0.5", "1", "1.5"]
            .iter()
            .filter_map(|a| {
                let r = find(runs, &format!("collapse_3d_a{a}"), model, level)?;
                let e = r["value"].as_f64()? / r["reference"].as_f64()? - 1.0;
                Some(format!("a = {a}: {:+.1} %", 100.0 * e))
            })
            .collect()
    };
    match collapse.iter().copied().collect::<Option<Vec<_>>>() {
        Some(e) => (
            Some(e.iter().all(|(e20, e25)| *e25 < 0.05 && e25 <= e20)),
            e.iter()
                .map(|(a, b)| format!("{:.1} → {:.1} %", 100.0 * a, 100.0 * b))
                .collect::<Vec<_>>()
                .join("; "),
        ),
        // r0/20 alone: no verdict, but the run-outs so far
        None => match signed("r0/20") {
            at20 if at20.is_empty() => (None, "not run".into()),
            at20 => (None, format!("r0/25 not run; at r0/20 {}", at20.join(", "))),
        },
    }
}

/// The crater grid at `level` (only its H = 0.2 m corners if `corners`).
fn crater_grid_verdict(runs: &[Value], model: &str, level: &str, corners: bool) -> Verdict {
    let e: Vec<f64> = runs
        .iter()
        .filter(|r| r["model"] == model && r["level"] == level)
        .filter(|r| {
            r["case"]
                .as_str()
                .is_some_and(|c| c.starts_with("crater_R"))
        })
        .filter(|r| !corners || r["case"].as_str().is_some_and(|c| c.ends_with("_H0.2")))
        .filter_map(|r| r["rel_error"].as_f64())
        .collect();
    let want = if corners { 4 } else { 12 };
    if e.is_empty() {
        return (None, "not run".into());
    }
    let max = e.iter().copied().fold(0.0, f64::max);
    let mean = e.iter().sum::<f64>() / e.len() as f64;
    let within = e.iter().filter(|x| **x < 0.15).count();
    let text = format!(
        "largest {:.1} %, mean {:.1} %, {within} within 15 %",
        100.0 * max,
        100.0 * mean
    );
    if e.len() < want {
        // a partial grid: no verdict yet, unless a run already fails it
        let failed = max >= 0.15;
        return (
            failed.then_some(false),
            format!("{} of {want} runs: {text}", e.len()),
        );
    }
    (Some(max < 0.15 && mean < 0.07), text)
}

/// The retained layer's K inside [K_a, K0].
fn retained_verdict(runs: &[Value], model: &str) -> Verdict {
    match find(runs, "retained_layer", model, "dp=3.75mm") {
        Some(r) => {
            let (k, k0) = (r["value"].as_f64(), r["reference"].as_f64());
            let e = r["rel_error"].as_f64();
            match (k, k0, e) {
                (Some(k), Some(k0), Some(e)) => (
                    Some(e <= 0.0),
                    format!("K = {k:.3} (K0 = {k0:.3}; {:.2} % outside)", 100.0 * e),
                ),
                _ => (Some(false), "no K (blow-up?)".into()),
            }
        }
        None => (None, "not run".into()),
    }
}

/// The crater grid's μ dependence: for each ball and height run at both frictions, the
/// depth at μ = 0.3 over the depth at μ = 0.5 under each model, beside Eq. (62)'s
/// (D ∝ 1/μ, with H_drop = H + D: about 1.7). Empty when no pair has run.
fn crater_ratios(runs: &[Value]) -> String {
    // the μ = 0.3 runs of the grid, each with its μ = 0.5 partner (same R, H, level)
    let mut pairs: Vec<(&str, &str)> = Vec::new();
    for r in runs {
        let (case, level) = (
            r["case"].as_str().unwrap_or(""),
            r["level"].as_str().unwrap_or(""),
        );
        if case.starts_with("crater_R")
            && case.contains("_mu0.3_")
            && !pairs.contains(&(case, level))
        {
            pairs.push((case, level));
        }
    }
    let mut rows = String::new();
    for (low, level) in pairs {
        let high = low.replace("_mu0.3_", "_mu0.5_");
        let depth = |case: &str, model: &str, key: &str| {
            find(runs, case, model, level).and_then(|x| x[key].as_f64())
        };
        let ratio = |model: &str, key: &str| {
            depth(low, model, key)
                .zip(depth(&high, model, key))
                .map(|(a, b)| a / b)
        };
        let cells: Vec<Option<f64>> = MODELS.iter().map(|m| ratio(m.name(), "value")).collect();
        if cells.iter().all(Option::is_none) {
            continue;
        }
        let eq62 = MODELS.iter().find_map(|m| ratio(m.name(), "reference"));
        let (r, h) = low
            .trim_start_matches("crater_R")
            .split_once("_mu0.3_H")
            .unwrap_or(("?", "?"));
        rows += &format!(
            "| {} | {r} | {h} | {} |",
            level.trim_start_matches("dp="),
            eq62.map_or("–".into(), |e| format!("{e:.3}"))
        );
        for c in cells {
            rows += &c.map_or(" – |".into(), |c| format!(" {c:.3} |"));
        }
        rows += "\n";
    }
    if rows.is_empty() {
        return rows;
    }
    let mut s = String::from(
        "\n## Crater depth at μ = 0.3 over μ = 0.5\n\n\
         Eq. (62) makes the depth scale as 1/μ; the ratio shows how much of that each model \
         gives, apart from the depth itself.\n\n| dp | R [m] | H [m] | Eq. (62) |",
    );
    for m in MODELS {
        s += &format!(" `{}` |", m.name());
    }
    s += "\n|---|---|---|---|";
    s += &"---|".repeat(MODELS.len());
    s += "\n";
    s + &rows
}

/// The report as Markdown, generated from the suite's JSON.
pub(crate) fn markdown(doc: &Value, plot: &str) -> String {
    let runs = doc["runs"].as_array().cloned().unwrap_or_default();
    let mut s = format!(
        "# Soil models: the verdict table\n\n\
         Generated by `granmix bench --suite models` from `models.json`; do not edit. {} \
         thread(s). Every soil case with a reference, under each soil model, applied to \
         every material of the scene after the case's own settings (issue 43). *error* is \
         relative to the reference (for the retained layer, the distance outside \
         [K_a, K0] relative to K0).\n\n\
         | model | what it is |\n|---|---|\n",
        doc["threads"]
    );
    for m in MODELS {
        s += &format!("| `{}` | {} |\n", m.name(), m.formula());
    }
    if doc["quick"] == true {
        s += "\n**A smoke run (`--quick`): each case at its coarsest level for a few steps. \
              Not a verdict.**\n";
    }
    s += &format!("\n![error against run time, one curve per model]({plot})\n");
    s += &criteria_table(&runs);
    s += &crater_ratios(&runs);
    s += &finest_table(&runs);
    s += &every_run(&runs);
    s
}

/// The criteria, one column per model.
fn criteria_table(runs: &[Value]) -> String {
    let mut s = String::new();
    s += "\n## The issue's criteria\n\n| criterion |";
    for m in MODELS {
        s += &format!(" `{}` |", m.name());
    }
    s += "\n|---|";
    s += &"---|".repeat(MODELS.len());
    s += "\n";
    let per_model: Vec<Vec<(&str, Verdict)>> =
        MODELS.iter().map(|m| criteria(runs, m.name())).collect();
    for (k, (what, _)) in per_model[0].iter().enumerate() {
        s += &format!("| {what} |");
        for c in &per_model {
            let (ok, measured) = &c[k].1;
            let mark = match ok {
                Some(true) => "met: ",
                Some(false) => "**not met**: ",
                None => "",
            };
            s += &format!(" {mark}{measured} |");
        }
        s += "\n";
    }
    s
}

/// Each case at its finest level: its error and wall time under each model.
fn finest_table(runs: &[Value]) -> String {
    let mut s = String::new();
    s += "\n## Error at each case's finest level (wall time)\n\n| case | level |";
    for m in MODELS {
        s += &format!(" `{}` |", m.name());
    }
    s += "\n|---|---|";
    s += &"---|".repeat(MODELS.len());
    s += "\n";
    let fin = finest(runs);
    let mut cases: Vec<(&str, &str)> = Vec::new();
    for r in &fin {
        let key = (
            r["case"].as_str().unwrap_or(""),
            r["level"].as_str().unwrap_or(""),
        );
        if !cases.iter().any(|c| c.0 == key.0) {
            cases.push(key);
        }
    }
    for (case, level) in cases {
        s += &format!("| {case} | {level} |");
        for m in MODELS {
            let cell = fin
                .iter()
                .find(|r| r["case"] == case && r["model"] == m.name())
                .map(|r| {
                    let e = r["rel_error"].as_f64().map_or_else(
                        || {
                            r["blowup"]
                                .as_str()
                                .map_or("–".into(), |_| "blow-up".to_string())
                        },
                        |e| format!("{:.2} %", 100.0 * e),
                    );
                    format!("{e} ({:.0} s)", r["wall_time_s"].as_f64().unwrap_or(0.0))
                })
                .unwrap_or("–".into());
            s += &format!(" {cell} |");
        }
        s += "\n";
    }
    s
}

/// Every run, one row each.
fn every_run(runs: &[Value]) -> String {
    let mut s = String::new();
    s += "\n## Every run\n\n| case | model | level | particles | wall [s] | value | reference | error |\n|---|---|---|---|---|---|---|---|\n";
    for r in runs {
        s += &format!(
            "| {} | {} | {} | {} | {:.1} | {} | {} | {} |\n",
            r["case"].as_str().unwrap_or(""),
            r["model"].as_str().unwrap_or(""),
            r["level"].as_str().unwrap_or(""),
            r["particles"],
            r["wall_time_s"].as_f64().unwrap_or(0.0),
            sci(&r["value"]),
            sci(&r["reference"]),
            r["blowup"].as_str().map_or_else(
                || pct(&r["rel_error"]),
                |b| format!("blow-up: {}", b.replace('|', "/"))
            ),
        );
    }
    s
}

#[cfg(test)]
mod tests {
    use super::*;

    /// `--model` and `--level` must name a model and a level of the chosen cases: the
    /// 2 mm level belongs to the crater corners only.
    #[test]
    fn the_selection_names_what_the_suite_has() {
        let all = model_cases();
        let dir = Path::new(".");
        let pick = |cases: &[String], models: &[String], levels: &[String]| {
            let o = SuiteOptions {
                scenes: dir,
                out: dir,
                quick: false,
                report: None,
                cases,
                models,
                levels,
                resume: false,
            };
            check_selection(&o, &all).map_err(|e| e.to_string())
        };
        let s = |v: &[&str]| v.iter().map(|x| x.to_string()).collect::<Vec<_>>();
        assert!(pick(&[], &s(&["compression_cone"]), &s(&["dp=2mm"])).is_ok());
        assert!(pick(&s(&["crater_R0.02_mu0.5_H0.2"]), &[], &s(&["dp=2mm"])).is_ok());
        let e = pick(&s(&["crater_R0.02_mu0.5_H0.1"]), &[], &s(&["dp=2mm"])).unwrap_err();
        assert!(e.contains("dp=4mm"), "{e}");
        let e = pick(&[], &s(&["cone"]), &[]).unwrap_err();
        assert!(e.contains("compression_cone"), "{e}");
    }

    /// The 3D collapse at r0/20 alone gives no verdict but states each run-out's signed
    /// error.
    #[test]
    fn the_collapse_at_r0_20_alone_is_reported_without_a_verdict() {
        let runs: Vec<Value> = [("0.5", 0.14), ("1", 0.175), ("1.5", 0.29)]
            .iter()
            .map(|(a, v)| {
                json!({"case": format!("collapse_3d_a{a}"), "model": "shear", "level": "r0/20",
                       "value": v, "reference": 0.175, "rel_error": 0.0})
            })
            .collect();
        let (verdict, text) = &criteria(&runs, "shear")[0].1;
        assert_eq!(*verdict, None);
        assert!(
            text.contains("a = 0.5: -20.0 %") && text.contains("a = 1.5: +65.7 %"),
            "{text}"
        );
    }

    /// The criteria read the grid's runs: a run 16 % off fails the grid.
    #[test]
    fn the_grid_criterion_fails_on_one_run_over_15_percent() {
        let runs: Vec<Value> = (0..12)
            .map(|k| {
                json!({"case": format!("crater_R{k}"), "model": "shear", "level": "dp=4mm",
                       "rel_error": if k == 0 { 0.16 } else { 0.01 }})
            })
            .collect();
        let c = criteria(&runs, "shear");
        let grid = &c
            .iter()
            .find(|(w, _)| w.starts_with("crater grid"))
            .unwrap()
            .1;
        assert_eq!(grid.0, Some(false), "{}", grid.1);
        // a partial grid has no verdict until a run fails it
        let verdict = |runs: &[Value]| {
            criteria(runs, "shear")
                .into_iter()
                .find(|(w, _)| w.starts_with("crater grid"))
                .unwrap()
                .1
        };
        assert_eq!(verdict(&runs[1..4]).0, None, "{}", verdict(&runs[1..4]).1);
        assert_eq!(verdict(&runs[..4]).0, Some(false));
        assert!(verdict(&runs[..4]).1.starts_with("4 of 12 runs"));
    }

    /// The ratio table divides the μ = 0.3 depth by the μ = 0.5 one, per model.
    #[test]
    fn the_crater_ratio_is_the_depth_at_mu_03_over_mu_05() {
        let run = |mu: &str, value: f64, reference: f64| {
            json!({"case": format!("crater_R0.02_mu{mu}_H0.1"), "model": "shear",
                   "level": "dp=4mm", "value": value, "reference": reference})
        };
        let t = crater_ratios(&[run("0.3", 0.03, 0.034), run("0.5", 0.02, 0.02)]);
        assert!(
            t.contains("| 4mm | 0.02 | 0.1 | 1.700 | – | – | – | 1.500 | – |"),
            "{t}"
        );
        assert!(crater_ratios(&[run("0.3", 0.03, 0.034)]).is_empty());
    }
}
