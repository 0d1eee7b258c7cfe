//! `granmix bench --suite stability`: where the solver breaks, and that it breaks
//! loudly. Each sweep raises one parameter from a safe value until the run stops with
//! the stability guard's diagnostic (or the sweep's range ends); the largest value
//! that ran through is reported with the first failure's diagnostic. A run that ends
//! without a diagnostic but with a wrong state (particles escaped, a hang) counts as a
//! silent failure and fails the suite.

use crate::run::load;
use anyhow::Result;
use granmix_core::run::simulation::Sample;
use granmix_core::AnySimulation;
use indicatif::{ProgressBar, ProgressStyle};
use serde_json::{json, Value};
use std::path::Path;
use std::time::Instant;

/// What a sweep measures at each value, besides whether it ran.
#[derive(Clone, Copy)]
enum Measure {
    /// Final run-out (m).
    Runout,
    /// Penetration of the first body below the bed surface at `surface` (m); `radius`
    /// of the body.
    Depth { surface: f64, radius: f64 },
    /// Kinetic energy of the last half of the run over its peak.
    RestingEnergy,
}

struct Sweep {
    name: &'static str,
    scene: &'static str,
    /// Parameter and unit, for the report.
    parameter: &'static str,
    values: Vec<f64>,
    set: fn(f64) -> Vec<String>,
    common: Vec<&'static str>,
    /// Overrides that shrink the sweep for `--quick` (the CI smoke run).
    quick: Vec<&'static str>,
    measure: Measure,
    note: &'static str,
}

fn sweeps() -> Vec<Sweep> {
    let depth = Measure::Depth {
        surface: 0.1,
        radius: 0.02,
    };
    vec![
        Sweep {
            name: "cfl",
            scene: "column_collapse_2d.toml",
            parameter: "CFL number of Eq. (51)",
            values: vec![0.1, 0.2, 0.4, 0.6, 0.8, 1.0, 1.2, 1.5, 2.0, 3.0, 5.0],
            set: |v| vec![format!("simulation.cfl={v}")],
            common: vec!["simulation.dp=0.004", "simulation.end_time=0.6"],
            quick: vec!["simulation.dp=0.008", "simulation.end_time=0.05"],
            measure: Measure::Runout,
            note: "2D collapse (VALIDATION §3 material), dp = 4 mm, 1250 particles",
        },
        Sweep {
            name: "stiffness_ratio",
            scene: "stability_impact_2d.toml",
            parameter: "E_coarse / E_fine",
            values: vec![10.0, 100.0, 1e3, 1e4, 1e5],
            set: |v| vec![format!("solids.0.youngs_modulus={}", v * 2e6)],
            common: vec![],
            quick: vec!["simulation.dp=0.008", "simulation.end_time=0.01"],
            measure: depth,
            note: "elastic disc (R = 20 mm) at 2 m/s into a loose bed (E = 2 MPa), multi-rate",
        },
        Sweep {
            name: "impact_speed",
            scene: "stability_impact_2d.toml",
            parameter: "impact speed (m/s)",
            values: vec![1.0, 2.0, 5.0, 10.0, 15.0, 20.0],
            set: |v| vec![format!("bodies.0.velocity=[0.0, {}]", -v)],
            common: vec!["simulation.end_time=0.05"],
            quick: vec!["simulation.dp=0.008", "simulation.end_time=0.01"],
            measure: depth,
            note: "elastic disc (R = 20 mm, E = 200 MPa) into a loose bed (E = 2 MPa)",
        },
        Sweep {
            name: "lattice_jitter",
            scene: "column_collapse_2d.toml",
            parameter: "initial lattice perturbation (± fraction of dp)",
            values: vec![0.0, 0.05, 0.1, 0.2, 0.3],
            set: |v| vec![format!("regions.0.jitter={v}")],
            common: vec!["simulation.dp=0.004", "simulation.end_time=0.6"],
            quick: vec!["simulation.dp=0.008", "simulation.end_time=0.05"],
            measure: Measure::Runout,
            note: "2D collapse, dp = 4 mm, particles displaced uniformly in ±jitter·dp",
        },
        Sweep {
            name: "long_run",
            scene: "column_collapse_2d.toml",
            parameter: "physical time (s)",
            values: vec![100.0],
            set: |v| vec![format!("simulation.end_time={v}")],
            common: vec!["simulation.dp=0.008", "simulation.output_interval=0.5"],
            quick: vec!["simulation.end_time=1.0"],
            measure: Measure::RestingEnergy,
            note: "2D collapse left to rest for 100 s, dp = 8 mm (300 particles): kinetic \
                   energy must stay ≤ 1e-6 of its peak over the second half, no particle \
                   may leave the tank",
        },
    ]
}

impl Measure {
    fn label(&self) -> &'static str {
        match self {
            Measure::Runout => "run-out (m)",
            Measure::Depth { .. } => "penetration depth (m)",
            Measure::RestingEnergy => "kinetic energy over the 2nd half / peak",
        }
    }
}

/// One run of a sweep.
struct Outcome {
    /// None: ran through; Some: the guard's diagnostic (or the silent failure found).
    failure: Option<String>,
    /// The failure is the guard's (loud), not a wrong state found afterwards.
    loud: bool,
    value: Option<f64>,
    wall: f64,
    steps: u64,
    particles: usize,
    kappa: usize,
    dt_fine: f64,
    dt_coarse: f64,
}

/// Fine steps a run may take: generous (the estimate at rest times 50, at least
/// 10⁶), so that only a collapsing time step reaches it.
fn step_budget(end: f64, dt0: f64) -> u64 {
    ((end / dt0.max(1e-300)) * 50.0).clamp(1e6, 1e9) as u64
}

/// A run the scene check or the set-up refused: a loud failure with its message.
fn refused(msg: String) -> Outcome {
    Outcome {
        failure: Some(format!("refused: {msg}")),
        loud: true,
        value: None,
        wall: 0.0,
        steps: 0,
        particles: 0,
        kappa: 0,
        dt_fine: 0.0,
        dt_coarse: 0.0,
    }
}

fn run_one(scene: &Path, set: &[String], measure: Measure, quiet: bool) -> Result<Outcome> {
    let loaded = match load(scene, set) {
        Ok(l) => l,
        Err(e) => return Ok(refused(format!("{e:#}"))),
    };
    let mut sim = match AnySimulation::new(&loaded) {
        Ok(s) => s,
        Err(e) => return Ok(refused(e.to_string())),
    };
    let end = loaded.scene.simulation.end_time;
    let every = loaded.scene.simulation.output_interval.min(end);
    let budget = step_budget(end, sim.stable_dt());
    let bar = if quiet {
        ProgressBar::hidden()
    } else {
        let b = ProgressBar::new(1000);
        b.set_style(
            ProgressStyle::with_template("    {bar:30} {percent:>3}% t = {msg} s, ETA {eta}")
                .expect("template"),
        );
        b
    };
    let t0 = Instant::now();
    let mut samples: Vec<Sample> = vec![sim.sample()];
    let mut failure = None;
    let mut loud = true;
    let mut k = 1u64;
    loop {
        let t = (k as f64 * every).min(end);
        if let Err(b) = sim.advance_to(t) {
            failure = Some(b.to_string());
            break;
        }
        samples.push(sim.sample());
        bar.set_position((1000.0 * t / end) as u64);
        bar.set_message(format!("{t:.3}"));
        if sim.steps() > budget {
            failure = Some(format!(
                "stalled: {} fine steps by t = {t:.4e} s (budget {budget}); the time step \
                 collapsed",
                sim.steps()
            ));
            loud = false;
            break;
        }
        if t >= end {
            break;
        }
        k += 1;
    }
    bar.finish_and_clear();
    let wall = t0.elapsed().as_secs_f64();
    let last = samples.last().cloned().unwrap_or_default();
    if failure.is_none() {
        if let Some(msg) = escaped(&sim) {
            failure = Some(msg);
            loud = false;
        }
    }
    let stopped = failure.is_some();
    let value = match measure {
        _ if stopped => None,
        Measure::Runout => Some(last.runout),
        Measure::Depth { surface, radius } => {
            let up = sim.dimension() - 1;
            last.bodies
                .first()
                .map(|b| surface - (b.position[up] - radius))
        }
        Measure::RestingEnergy => {
            let peak = samples.iter().map(|s| s.kinetic_energy).fold(0.0, f64::max);
            let late = samples
                .iter()
                .filter(|s| s.time >= 0.5 * end)
                .map(|s| s.kinetic_energy)
                .fold(0.0, f64::max);
            let ratio = if peak > 0.0 { late / peak } else { 0.0 };
            if failure.is_none() && end >= 10.0 && ratio > 1e-6 {
                failure = Some(format!(
                    "kinetic energy over the second half reaches {ratio:.2e} of its peak \
                     (bound 1e-6): the pile does not come to rest"
                ));
                loud = false;
            }
            Some(ratio)
        }
    };
    Ok(Outcome {
        failure,
        loud,
        value,
        wall,
        steps: sim.steps(),
        particles: sim.fine_count() + sim.coarse_count(),
        kappa: last.kappa,
        dt_fine: last.dt_fine,
        dt_coarse: last.dt_coarse,
    })
}

/// A fine particle outside the walls' bounding box (its open top excepted).
fn escaped(sim: &AnySimulation) -> Option<String> {
    let f = sim.frame();
    if f.wall_pos.is_empty() {
        return None;
    }
    let d = sim.dimension();
    let up = d - 1;
    let mut lo = [f32::INFINITY; 3];
    let mut hi = [f32::NEG_INFINITY; 3];
    for w in &f.wall_pos {
        for k in 0..d {
            lo[k] = lo[k].min(w[k]);
            hi[k] = hi[k].max(w[k]);
        }
    }
    for (p, id) in f.fine.iter().map(|r| (&r.position, &r.id)) {
        for k in 0..d {
            if p[k] < lo[k] || (k != up && p[k] > hi[k]) {
                return Some(format!(
                    "fine particle {id} left the domain: at {:?}, walls span {:?}..{:?}",
                    &p[..d],
                    &lo[..d],
                    &hi[..d]
                ));
            }
        }
    }
    None
}

/// Run the stability suite; returns true when every failure was loud.
pub fn stability(scenes: &Path, out: &Path, quick: bool, report: Option<&Path>) -> Result<bool> {
    std::fs::create_dir_all(out)?;
    let mut all_loud = true;
    let mut doc = Vec::new();
    for s in sweeps() {
        let values: Vec<f64> = if quick {
            s.values.iter().take(2).copied().collect()
        } else {
            s.values.clone()
        };
        println!("sweep {}: {} ({})", s.name, s.parameter, s.note);
        println!(
            "  {:>10} {:>9} {:>9} {:>8} {:>4} {:>10} {:>10} {:>12}  outcome",
            "value", "particles", "steps", "wall [s]", "κ", "Δt_f", "Δt_c", "measure"
        );
        let mut runs = Vec::new();
        let mut largest = None;
        let mut first_failure: Option<(f64, String, bool)> = None;
        for &v in &values {
            let mut set: Vec<String> = s.common.iter().map(|x| x.to_string()).collect();
            set.extend((s.set)(v));
            if quick {
                set.extend(s.quick.iter().map(|x| x.to_string()));
            }
            let o = run_one(&scenes.join(s.scene), &set, s.measure, quick)?;
            println!(
                "  {:>10} {:>9} {:>9} {:>8.1} {:>4} {:>10.3e} {:>10.3e} {:>12}  {}",
                v,
                o.particles,
                o.steps,
                o.wall,
                o.kappa,
                o.dt_fine,
                o.dt_coarse,
                o.value.map(|x| format!("{x:.4e}")).unwrap_or("-".into()),
                o.failure.as_deref().unwrap_or("ran through"),
            );
            runs.push(json!({
                "value": v, "particles": o.particles, "steps_fine": o.steps,
                "wall_time_s": o.wall, "kappa": o.kappa, "dt_fine": o.dt_fine,
                "dt_coarse": o.dt_coarse, "measure": o.value, "failure": o.failure,
                "loud": o.loud,
            }));
            match o.failure {
                None => largest = Some(v),
                Some(msg) => {
                    all_loud &= o.loud;
                    first_failure = Some((v, msg, o.loud));
                    break;
                }
            }
        }
        match (&largest, &first_failure) {
            (Some(l), None) => println!("  largest stable: {l} (end of the sweep)"),
            (l, Some((v, _, loud))) => println!(
                "  largest stable: {}; fails at {v} ({})",
                l.map(|x| x.to_string()).unwrap_or("none".into()),
                if *loud { "loudly" } else { "SILENTLY" }
            ),
            (None, None) => {}
        }
        doc.push(json!({
            "sweep": s.name, "scene": s.scene, "parameter": s.parameter, "note": s.note,
            "measure": s.measure.label(),
            "largest_stable": largest,
            "fails_at": first_failure.as_ref().map(|f| f.0),
            "failure": first_failure.as_ref().map(|f| f.1.clone()),
            "loud": first_failure.as_ref().map(|f| f.2),
            "runs": runs,
        }));
    }
    let doc = json!({
        "suite": "stability",
        "quick": quick,
        "threads": rayon::current_num_threads(),
        "sweeps": doc,
    });
    let path = out.join("stability.json");
    std::fs::write(&path, serde_json::to_string_pretty(&doc)?)?;
    println!("wrote {}", path.display());
    let md = markdown(&doc);
    let mpath = out.join("stability.md");
    std::fs::write(&mpath, &md)?;
    println!("wrote {}", mpath.display());
    if let Some(r) = report {
        std::fs::write(r, &md)?;
        println!("wrote {}", r.display());
    }
    Ok(all_loud)
}

/// The stability report as Markdown, generated from the suite's JSON.
pub fn markdown(doc: &Value) -> String {
    let mut s = String::from(
        "# Stability report\n\n\
         Generated by `granmix bench --suite stability` from `stability.json`; do not edit.\n\
         Each sweep raises one parameter until the run stops with the stability guard's\n\
         diagnostic. *Largest stable* is the last value that ran through; the failure is\n\
         the diagnostic the run stopped with.\n\n\
         | sweep | parameter | case | largest stable | fails at | failure mode |\n\
         |---|---|---|---|---|---|\n",
    );
    let sweeps = doc["sweeps"].as_array().cloned().unwrap_or_default();
    for w in &sweeps {
        let fmt = |v: &Value| v.as_f64().map(|x| format!("{x}")).unwrap_or("–".into());
        s += &format!(
            "| {} | {} | {} | {} | {} | {} |\n",
            w["sweep"].as_str().unwrap_or(""),
            w["parameter"].as_str().unwrap_or(""),
            w["note"].as_str().unwrap_or(""),
            fmt(&w["largest_stable"]),
            fmt(&w["fails_at"]),
            w["failure"]
                .as_str()
                .map(|f| f.replace('|', "/"))
                .unwrap_or("none in the sweep".into()),
        );
    }
    for w in &sweeps {
        s += &format!(
            "\n## {}\n\n{}; {}. Measure: {}.\n\n| value | particles | fine steps | wall [s] | κ | Δt_f [s] | Δt_c [s] | measure | outcome |\n|---|---|---|---|---|---|---|---|---|\n",
            w["sweep"].as_str().unwrap_or(""),
            w["parameter"].as_str().unwrap_or(""),
            w["note"].as_str().unwrap_or(""),
            w["measure"].as_str().unwrap_or("")
        );
        for r in w["runs"].as_array().cloned().unwrap_or_default() {
            let e = |k: &str| {
                r[k].as_f64()
                    .map(|x| format!("{x:.3e}"))
                    .unwrap_or("–".into())
            };
            s += &format!(
                "| {} | {} | {} | {:.1} | {} | {} | {} | {} | {} |\n",
                r["value"],
                r["particles"],
                r["steps_fine"],
                r["wall_time_s"].as_f64().unwrap_or(0.0),
                r["kappa"],
                e("dt_fine"),
                e("dt_coarse"),
                e("measure"),
                r["failure"]
                    .as_str()
                    .map(|f| f.replace('|', "/"))
                    .unwrap_or("ran through".into()),
            );
        }
    }
    s
}
