//! `granmix bench --suite accuracy`: run time against error. Every validation case
//! with a reference runs at three or more resolutions, under each scheme that applies
//! (multi-rate and single-rate stepping, elastic and rigid boulders). Each run records
//! wall time, particle-steps per second, peak resident memory and the error against the
//! reference. The suite writes `accuracy.json`, `accuracy.png` (error against wall
//! time, log–log, one curve per case and scheme) and a Markdown report generated from
//! the JSON (`--report docs/benchmarks.md`), with the multi-rate speed-up next to seed
//! 000 Table 3.

use crate::bench::accuracy_series::{series, Series};
use crate::bench::metric::Level;
use crate::bench::suite::SuiteOptions;
use crate::plot::{loglog, Curve};
use crate::run::{run, RunOptions};
use anyhow::Result;
use serde_json::{json, Value};
use std::path::Path;

/// Zero the process's peak resident set (Linux `clear_refs` 5) so that the next
/// reading of VmHWM is the peak of what runs in between.
fn reset_peak_rss() {
    let _ = std::fs::write("/proc/self/clear_refs", "5");
}

/// Process CPU time (user + system) in seconds, from `/proc/self/stat` (USER_HZ = 100).
/// Unlike wall time it is little affected by other jobs sharing the machine.
fn cpu_time() -> Option<f64> {
    let s = std::fs::read_to_string("/proc/self/stat").ok()?;
    // fields after the parenthesised command name; utime and stime are fields 14 and 15
    let rest = &s[s.rfind(')')? + 2..];
    let f: Vec<&str> = rest.split_whitespace().collect();
    let ticks: f64 = f.get(11)?.parse::<f64>().ok()? + f.get(12)?.parse::<f64>().ok()?;
    Some(ticks / 100.0)
}

/// `bench --suite accuracy --list`: one line per series, its scheme, scene and levels.
pub fn list() {
    let all = series();
    let width = all
        .iter()
        .map(|s| s.case.chars().count())
        .max()
        .unwrap_or(0);
    for s in &all {
        let lv: Vec<&str> = s.levels.iter().map(|l| l.0.as_str()).collect();
        println!(
            "{:<width$} {:<22} {:<26} [{}]",
            s.case,
            s.scheme,
            s.scene,
            lv.join(", ")
        );
    }
}

/// Run the accuracy suite.
pub fn accuracy(o: &SuiteOptions) -> Result<()> {
    let all = series();
    if let Some(bad) = o.cases.iter().find(|c| !all.iter().any(|s| &s.case == *c)) {
        let mut names: Vec<&str> = all.iter().map(|s| s.case.as_str()).collect();
        names.dedup();
        anyhow::bail!(
            "bench --suite accuracy: unknown --case {bad:?}; cases are {}",
            names.join(", ")
        );
    }
    let earlier = match o.report {
        Some(r) if !o.cases.is_empty() => Some(earlier_runs(r, o.quick)?),
        _ => None,
    };
    std::fs::create_dir_all(o.out)?;
    let mut runs = Vec::new();
    println!(
        "{:<24} {:<22} {:<8} {:>9} {:>9} {:>11} {:>9} {:>11} {:>11} {:>8}",
        "case",
        "scheme",
        "level",
        "particles",
        "wall [s]",
        "Mpart-st/s",
        "RSS [MB]",
        "value",
        "reference",
        "error"
    );
    // with --quick, a series whose scene and scheme an earlier one ran (the crater grid's
    // nine scene-default runs after its first) is skipped: a smoke run of the same code path
    let mut smoked = std::collections::HashSet::new();
    for s in all
        .iter()
        .filter(|s| o.cases.is_empty() || o.cases.iter().any(|c| c == &s.case))
    {
        if o.quick && !smoked.insert((s.scene, s.scheme.as_str())) {
            println!(
                "{:<24} {:<22} (quick: skipped, same scene and scheme as above)",
                s.case, s.scheme
            );
            continue;
        }
        let levels = if o.quick {
            &s.levels[..1.min(s.levels.len())]
        } else {
            &s.levels[..]
        };
        for level in levels {
            let r = run_level(o, s, level)?;
            print_row(s, &level.0, &r);
            runs.push(r);
        }
    }
    let doc = json!({
        "suite": "accuracy", "quick": o.quick, "threads": rayon::current_num_threads(),
        "runs": runs,
    });
    write_outputs(o, &doc, earlier.as_ref())
}

/// The report's earlier runs (its JSON beside it), which a run of some cases only
/// (`--case`) is merged into; read before anything runs, so that a missing file stops
/// the suite at once.
fn earlier_runs(report: &Path, quick: bool) -> Result<Value> {
    let data = report.with_extension("json");
    if quick {
        anyhow::bail!(
            "bench --suite accuracy --quick --report {}: a smoke run is not merged into a report",
            report.display()
        );
    }
    let text = std::fs::read_to_string(&data).map_err(|e| {
        anyhow::anyhow!(
            "bench --suite accuracy --case … --report {}: the report's runs ({}) keep the \
             other cases' sections, and they cannot be read ({e}); run the whole suite to \
             write them",
            report.display(),
            data.display()
        )
    })?;
    serde_json::from_str(&text).map_err(|e| anyhow::anyhow!("{}: {e}", data.display()))
}

/// One curve of (wall time, error) per case and scheme, in the order of `runs`.
fn curves(runs: &[Value]) -> Vec<Curve> {
    let mut out: Vec<Curve> = Vec::new();
    for r in runs {
        let (Some(e), Some(w)) = (r["rel_error"].as_f64(), r["wall_time_s"].as_f64()) else {
            continue;
        };
        let label = format!(
            "{} ({})",
            r["case"].as_str().unwrap_or(""),
            r["scheme"].as_str().unwrap_or("")
        );
        let point = (w.max(1e-3), e.max(1e-16));
        match out.iter_mut().find(|c| c.label == label) {
            Some(c) => c.points.push(point),
            None => out.push(Curve {
                label,
                points: vec![point],
            }),
        }
    }
    out
}

/// The report's runs after a run of some cases only (`--case`): the report's earlier
/// runs (its JSON beside it) with those of the cases run now replaced by the new ones,
/// in the suite's order of cases. The report then keeps every other case's section.
fn merged(earlier: &Value, doc: &Value) -> Value {
    let new = doc["runs"].as_array().cloned().unwrap_or_default();
    let ran: Vec<&str> = new.iter().filter_map(|r| r["case"].as_str()).collect();
    // each run keeps the thread count it ran at (records before the field: the doc's)
    let stamped = |d: &Value| -> Vec<Value> {
        let mut runs = d["runs"].as_array().cloned().unwrap_or_default();
        for r in &mut runs {
            if r.get("threads").is_none_or(Value::is_null) {
                r["threads"] = d["threads"].clone();
            }
        }
        runs
    };
    let mut runs: Vec<Value> = stamped(earlier)
        .into_iter()
        .filter(|r| !r["case"].as_str().is_some_and(|c| ran.contains(&c)))
        .chain(stamped(doc))
        .collect();
    let order: Vec<String> = series().into_iter().map(|s| s.case).collect();
    let rank = |r: &Value| {
        let c = r["case"].as_str().unwrap_or("");
        order.iter().position(|o| o == c).unwrap_or(order.len())
    };
    // stable: the levels of a case keep their order
    runs.sort_by_key(rank);
    let mut counts: Vec<&Value> = runs.iter().map(|r| &r["threads"]).collect();
    counts.dedup();
    let threads = match counts[..] {
        [one] => one.clone(),
        _ => Value::Null,
    };
    json!({
        "suite": "accuracy", "quick": false, "threads": threads, "runs": runs,
    })
}

/// The record of series `s` at `level`: the one under --out when --resume finds it made
/// with the same overrides, else that of a new run (written there).
fn run_level(o: &SuiteOptions, s: &Series, (label, over): &Level) -> Result<Value> {
    let mut set = s.common.clone();
    set.extend(over.iter().cloned());
    if o.quick {
        set.push("simulation.end_time=0.002".into());
    }
    let dir = o
        .out
        .join(&s.case)
        .join(s.scheme.replace([',', ' '], "_"))
        .join(label.replace(['/', ' '], "_"));
    let record = dir.join("record.json");
    if let Some(r) = o.cached(&record, "overrides", &json!(set)) {
        return Ok(r);
    }
    let data = s.metric.data(o.scenes)?;
    reset_peak_rss();
    let cpu0 = cpu_time();
    let rep = run(&RunOptions::batch(
        o.scenes.join(s.scene),
        dir.clone(),
        set.clone(),
    ))?;
    let cpu = cpu_time().zip(cpu0).map(|(b, a)| b - a);
    let rss = crate::bench::scale::peak_rss();
    let title = format!("{} ({}), {label}", s.case, s.scheme);
    let (value, reference, detail) = s.metric.scored(&rep, data.as_ref(), (&dir, &title))?;
    let err = s.metric.error(value, reference);
    if let Some(b) = &rep.blowup {
        eprintln!("{} {} {label}: {b}", s.case, s.scheme);
    }
    let r = json!({
        "case": s.case, "scheme": s.scheme, "level": label, "scene": s.scene,
        "note": s.note, "overrides": set, "particles": rep.particles,
        "steps_fine": rep.summary["steps_fine"], "steps_coarse": rep.summary["steps_coarse"],
        "kappa": rep.summary["kappa"], "dt_fine": rep.summary["dt_fine"],
        "dt_coarse": rep.summary["dt_coarse"], "wall_time_s": rep.wall_time,
        "cpu_time_s": cpu,
        "threads": rayon::current_num_threads(),
        "particle_steps_per_s": rep.particle_steps_per_s, "peak_rss_bytes": rss,
        "value": value, "reference": reference, "rel_error": err,
        "blowup": rep.blowup.as_ref().map(|b| b.to_string()),
        "lobovsky": detail.clone().filter(|_| matches!(s.metric, crate::bench::metric::Metric::Lobovsky)),
        "rondon": detail.filter(|_| matches!(s.metric, crate::bench::metric::Metric::Rondon(_))),
    });
    std::fs::write(&record, serde_json::to_string_pretty(&r)?)?;
    Ok(r)
}

/// A number of a record in scientific notation, or `none`.
fn sci(v: &Value, none: &str) -> String {
    v.as_f64()
        .map(|x| format!("{x:.4e}"))
        .unwrap_or(none.into())
}

/// One row of the suite's table: run `r` of series `s` at level `label`.
fn print_row(s: &Series, label: &str, r: &Value) {
    let fmt = |k: &str| sci(&r[k], "-");
    println!(
        "{:<24} {:<22} {:<8} {:>9} {:>9.1} {:>11.3} {:>9.0} {:>11} {:>11} {:>8}",
        s.case,
        s.scheme,
        label,
        r["particles"],
        r["wall_time_s"].as_f64().unwrap_or(0.0),
        r["particle_steps_per_s"].as_f64().unwrap_or(0.0) / 1e6,
        r["peak_rss_bytes"].as_f64().unwrap_or(0.0) / 1e6,
        fmt("value"),
        fmt("reference"),
        r["rel_error"]
            .as_f64()
            .map(|e| format!("{:.2}%", 100.0 * e))
            .unwrap_or("-".into()),
    );
}

/// accuracy.json, accuracy.png and accuracy.md under --out, and the report with its
/// plot and its JSON beside it where --report names one. A run of some cases only
/// (`--case`) is merged into the report's JSON, so that the report keeps the others.
fn write_outputs(o: &SuiteOptions, doc: &Value, earlier: Option<&Value>) -> Result<()> {
    let path = o.out.join("accuracy.json");
    std::fs::write(&path, serde_json::to_string_pretty(doc)?)?;
    println!("wrote {}", path.display());
    let runs = doc["runs"].as_array().cloned().unwrap_or_default();
    let png = o.out.join("accuracy.png");
    let plotted = plot(&png, &runs)?;
    if plotted {
        println!("wrote {}", png.display());
    }
    std::fs::write(o.out.join("accuracy.md"), markdown(doc, "accuracy.png"))?;
    let Some(r) = o.report else {
        return Ok(());
    };
    let doc = match earlier {
        Some(e) => merged(e, doc),
        None => doc.clone(),
    };
    // the plot goes beside the report, under the report's name
    let png = r.with_extension("png");
    let name = png
        .file_name()
        .map(|n| n.to_string_lossy().into_owned())
        .unwrap_or_default();
    let runs = doc["runs"].as_array().cloned().unwrap_or_default();
    plot(&png, &runs)?;
    std::fs::write(r, markdown(&doc, &name))?;
    let data = r.with_extension("json");
    std::fs::write(&data, serde_json::to_string_pretty(&doc)?)?;
    println!(
        "wrote {}, {} and {}",
        r.display(),
        png.display(),
        data.display()
    );
    Ok(())
}

/// Error against wall time, one curve per case and scheme; false if no run has both.
fn plot(png: &Path, runs: &[Value]) -> Result<bool> {
    let curves = curves(runs);
    if curves.is_empty() {
        return Ok(false);
    }
    loglog(
        png,
        "granmix bench --suite accuracy: error against run time",
        "wall time [s]",
        "relative error",
        &curves,
        &[(0.05, "5 %".into())],
    )?;
    Ok(true)
}

/// One row of seed 000 Table 3: dp (mm), particles, Δt_f, Δt_c, κ, single-rate and
/// multi-rate minutes, speed-up.
type Table3Row = (f64, &'static str, f64, f64, u32, f64, f64, f64);

/// Seed 000 Table 3 (R = 0.02 m, H = 0.2 m, 0.1 s, 32 cores).
const TABLE3: [Table3Row; 3] = [
    (4.0, "51.2 k", 6.1e-5, 7.4e-6, 9, 9.7, 1.5, 6.5),
    (2.0, "426.0 k", 3.1e-5, 3.7e-6, 9, 138.0, 19.9, 6.9),
    (1.5, "1009.9 k", 2.3e-5, 2.8e-6, 9, 439.2, 57.6, 7.6),
];

/// The benchmark report as Markdown, generated from the suite's JSON.
pub fn markdown(doc: &Value, plot: &str) -> String {
    let runs = doc["runs"].as_array().cloned().unwrap_or_default();
    let mut s = format!(
        "# Benchmarks: run time against error\n\n\
         Generated by `granmix bench --suite accuracy` from `accuracy.json`; do not edit.\n\
         {} Every `granmix bench` case with a reference runs here, at three\n\
         resolutions where the suite defines them (at the bench's own levels otherwise),\n\
         under each scheme that applies; the crater of R = 0.02 m, μ = 0.3, H = 0.2 m\n\
         also stands for the bench's `crater_schemes` and `crater_models`. *error* is\n\
         relative to the reference (for the rings, the momentum drift itself; 0 inside a\n\
         band or under a bound). *cpu* is the process's user + system time,\n\
         which other jobs on the machine disturb less than the wall time.\n\n\
         ![error against wall time, one curve per case and scheme]({plot})\n",
        threads_text(doc, &runs)
    );
    let mut cases: Vec<String> = Vec::new();
    for r in &runs {
        let c = r["case"].as_str().unwrap_or("").to_string();
        if !cases.contains(&c) {
            cases.push(c);
        }
    }
    for c in &cases {
        let mine: Vec<&Value> = runs.iter().filter(|r| r["case"] == c.as_str()).collect();
        s += &format!(
            "\n## {c}\n\n{}\n\n| scheme | level | particles | wall [s] | cpu [s] | Mparticle-steps/s | peak RSS [MB] | value | reference | error |\n|---|---|---|---|---|---|---|---|---|---|\n",
            mine.first().and_then(|r| r["note"].as_str()).unwrap_or("")
        );
        for r in mine {
            s += &report_row(r);
        }
    }
    s + &speedup_table(doc, &runs)
}

/// One run of the report's table of its case.
fn report_row(r: &Value) -> String {
    let f = |k: &str| sci(&r[k], "–");
    format!(
        "| {} | {} | {} | {:.1} | {} | {:.3} | {} | {} | {} | {} |\n",
        r["scheme"].as_str().unwrap_or(""),
        r["level"].as_str().unwrap_or(""),
        r["particles"],
        r["wall_time_s"].as_f64().unwrap_or(0.0),
        r["cpu_time_s"]
            .as_f64()
            .map(|x| format!("{x:.1}"))
            .unwrap_or("–".into()),
        r["particle_steps_per_s"].as_f64().unwrap_or(0.0) / 1e6,
        r["peak_rss_bytes"]
            .as_f64()
            .map(|x| format!("{:.0}", x / 1e6))
            .unwrap_or("–".into()),
        f("value"),
        f("reference"),
        r["rel_error"]
            .as_f64()
            .map(|e| format!("{:.2} %", 100.0 * e))
            .unwrap_or(
                r["blowup"]
                    .as_str()
                    .map(|b| format!("blow-up: {}", b.replace('|', "/")))
                    .unwrap_or("–".into())
            ),
    )
}

/// The report's thread count: the one of every run, or the most common one and the
/// cases run at another (a partial run merged into the report).
fn threads_text(doc: &Value, runs: &[Value]) -> String {
    if let Some(n) = doc["threads"].as_u64() {
        return format!("{n} thread(s).");
    }
    let mut tally: Vec<(u64, Vec<&str>)> = Vec::new();
    for r in runs {
        let (n, c) = (
            r["threads"].as_u64().unwrap_or(0),
            r["case"].as_str().unwrap_or(""),
        );
        match tally.iter_mut().find(|t| t.0 == n) {
            Some(t) if !t.1.contains(&c) => t.1.push(c),
            Some(_) => {}
            None => tally.push((n, vec![c])),
        }
    }
    tally.sort_by_key(|t| std::cmp::Reverse(t.1.len()));
    let mut s = format!("{} thread(s)", tally.first().map_or(0, |t| t.0));
    for (n, cases) in tally.iter().skip(1) {
        s += &format!(", {} at {n}", cases.join(", "));
    }
    s + "."
}

/// The multi-rate speed-up of the crater runs next to seed 000 Table 3.
fn speedup_table(doc: &Value, runs: &[Value]) -> String {
    let crater = |scheme: &str, level: &str| {
        runs.iter().find(|r| {
            r["case"] == "crater_R0.02_mu0.3_H0.2" && r["scheme"] == scheme && r["level"] == level
        })
    };
    let mut s = String::from(
        "\n## Multi-rate speed-up (crater R = 0.02 m, H = 0.2 m) against seed 000 Table 3\n\n\
          | source | dp [mm] | particles | Δt_f [s] | Δt_c [s] | κ | single-rate | multi-rate | speed-up (wall) | speed-up (cpu) |\n\
          |---|---|---|---|---|---|---|---|---|---|\n",
    );
    for (dp, n, dtf, dtc, k, single, multi, up) in TABLE3 {
        s += &format!(
            "| seed 000 (32 cores) | {dp} | {n} | {dtf:.1e} | {dtc:.1e} | {k} | {single} min | {multi} min | {up}× | – |\n"
        );
    }
    for level in ["6 mm", "5 mm", "4 mm"] {
        if let (Some(m), Some(si)) = (
            crater("multi-rate, elastic", level),
            crater("single-rate, elastic", level),
        ) {
            let (tm, ts) = (
                m["wall_time_s"].as_f64().unwrap_or(0.0),
                si["wall_time_s"].as_f64().unwrap_or(0.0),
            );
            s += &format!(
                "| granmix ({} threads) | {} | {} | {:.2e} | {:.2e} | {} | {:.2} min | {:.2} min | {:.2}× | {} |\n",
                m.get("threads").filter(|t| !t.is_null()).unwrap_or(&doc["threads"]),
                level.trim_end_matches(" mm"),
                m["particles"],
                m["dt_fine"].as_f64().unwrap_or(0.0),
                m["dt_coarse"].as_f64().unwrap_or(0.0),
                m["kappa"],
                ts / 60.0,
                tm / 60.0,
                ts / tm.max(1e-12),
                si["cpu_time_s"]
                    .as_f64()
                    .zip(m["cpu_time_s"].as_f64())
                    .map(|(a, b)| format!("{:.2}×", a / b.max(1e-12)))
                    .unwrap_or("–".into())
            );
        }
    }
    s
}
#[cfg(test)]
mod tests {
    use super::*;
    use crate::bench::accuracy_series::COVERED_BY;

    /// Issue 39: every bench case with a reference has a section in the committed
    /// report, docs/benchmarks.md (directly or through the case that stands for it), so
    /// a case added to the bench without regenerating the report fails here.
    #[test]
    fn every_bench_case_with_a_reference_is_in_the_report() {
        let report = std::fs::read_to_string(
            Path::new(env!("CARGO_MANIFEST_DIR")).join("../docs/benchmarks.md"),
        )
        .expect("docs/benchmarks.md");
        let all = series();
        let mut missing = Vec::new();
        for c in crate::bench::cases::cases() {
            if !c.metric.has_reference() {
                continue;
            }
            let name = COVERED_BY
                .iter()
                .find(|(n, _)| *n == c.name)
                .map_or(c.name.as_str(), |(_, by)| by);
            assert!(
                all.iter().any(|s| s.case == name),
                "bench case {} is not in the accuracy suite",
                c.name
            );
            if !report.contains(&format!("\n## {name}\n")) {
                missing.push(c.name.clone());
            }
        }
        assert!(
            missing.is_empty(),
            "docs/benchmarks.md has no section for {missing:?}: add them with \
             `granmix bench --suite accuracy --case NAME --report docs/benchmarks.md`"
        );
    }

    /// A run of some cases replaces those cases' runs in the report's and keeps the
    /// others, in the suite's order of cases and each case's order of levels.
    #[test]
    fn a_partial_run_replaces_only_its_cases() {
        let run = |case: &str, level: &str, value: f64| json!({"case": case, "scheme": "s", "level": level, "value": value});
        let earlier = json!({"threads": 2, "runs": [
            run("collapse_2d", "8 mm", 1.0),
            run("geostatic", "H/10", 2.0),
            run("geostatic", "H/20", 3.0),
        ]});
        let now = json!({"threads": 2, "runs": [
            run("geostatic", "H/10", 4.0),
            run("geostatic", "H/20", 5.0),
            run("collapse_3d_a0.5", "r0/10", 6.0),
        ]});
        let m = merged(&earlier, &now);
        let got: Vec<(String, f64)> = m["runs"]
            .as_array()
            .unwrap()
            .iter()
            .map(|r| {
                (
                    r["case"].as_str().unwrap().to_string(),
                    r["value"].as_f64().unwrap(),
                )
            })
            .collect();
        let want = [
            ("collapse_3d_a0.5", 6.0),
            ("collapse_2d", 1.0),
            ("geostatic", 4.0),
            ("geostatic", 5.0),
        ];
        assert_eq!(got.len(), want.len(), "{got:?}");
        let mut one = now.clone();
        one["threads"] = json!(1);
        let mixed = merged(&earlier, &one);
        assert!(mixed["threads"].is_null(), "{mixed}");
        assert_eq!(mixed["runs"][1]["threads"], 2, "{mixed}");
        assert_eq!(mixed["runs"][2]["threads"], 1, "{mixed}");
        let runs = mixed["runs"].as_array().unwrap();
        assert_eq!(
            threads_text(&mixed, runs),
            "1 thread(s), collapse_2d at 2.",
            "{mixed}"
        );
        for ((c, v), (wc, wv)) in got.iter().zip(want) {
            assert_eq!((c.as_str(), *v), (wc, wv), "{got:?}");
        }
    }
}
