//! `granmix bench --suite fmi`: what the FMI layer costs per `fmi2DoStep`.
//!
//! The bundled FMU scene (`fmu_barrier_2d`, a layer against a displacement-driven
//! barrier) is unpacked as a master unpacks it and driven in this process through the
//! exported C functions ([`granmix_fmu::ffi::LocalInstance`]). Each communication step
//! is one master cycle:
//! fmi2SetReal of the input, fmi2DoStep, fmi2GetReal of every Real output and
//! fmi2GetInteger of the step counters. The cycle is timed from the first C entry to
//! the last return; the solver's own time (its `advance_to`, timed inside the model) is
//! taken from it, and the rest is the FMI layer: entry checks, the barrier drive, the
//! end-of-step sample, the step history and the getters and setters. Step sizes of 1,
//! 10 and 100 stable solver steps per communication step. The calls come from a worker
//! of the solver's thread pool, where every granmix command runs; a master's own thread
//! also pays the hand-over to the pool, inside the solver's `advance_to` and so counted
//! as solver time, which makes the layer's share measured here the larger one.

use anyhow::{bail, Context, Result};
use granmix_fmu::ffi::LocalInstance;
use granmix_fmu::granular::Granular;
use granmix_fmu::model::Model;
use granmix_fmu::variables::{Causality, Kind};
use serde_json::{json, Value};
use std::path::Path;
use std::time::Instant;

/// The scene measured.
const SCENE: &str = "fmu_barrier_2d.toml";
/// Solver steps per communication step.
const LEVELS: [u32; 3] = [1, 10, 100];
/// The layer's budget at 10 solver steps per communication step (share of the solver).
const BUDGET: f64 = 0.01;

/// Value references a master cycle sets and reads.
struct Refs {
    inputs: Vec<u32>,
    reals: Vec<u32>,
    integers: Vec<u32>,
    steps_fine: usize,
}

fn refs(resources: &Path) -> Result<Refs> {
    let model = Granular::from_resources(resources).map_err(anyhow::Error::msg)?;
    let vars = model.variables();
    let of = |c: Causality, k: Kind| -> Vec<u32> {
        (0..vars.len() as u32)
            .filter(|&i| vars[i as usize].causality == c && vars[i as usize].kind == k)
            .collect()
    };
    let integers = of(Causality::Output, Kind::Integer);
    let steps_fine = integers
        .iter()
        .position(|&i| vars[i as usize].name == "steps.fine")
        .context("the FMU has no `steps.fine` output")?;
    Ok(Refs {
        inputs: of(Causality::Input, Kind::Real),
        reals: of(Causality::Output, Kind::Real),
        integers,
        steps_fine,
    })
}

/// Timings of one level.
struct Level {
    per_step: u32,
    comm_steps: usize,
    /// Solver steps per communication step, measured.
    fine_per_comm: f64,
    /// Medians over the communication steps (s).
    cycle: f64,
    solver: f64,
    layer: f64,
    /// Sums over the communication steps (s).
    cycle_sum: f64,
    solver_sum: f64,
}

impl Level {
    /// The layer's time against the solver's, from the medians.
    fn share(&self) -> f64 {
        self.layer / self.solver
    }
    /// The same from the sums.
    fn share_of_sums(&self) -> f64 {
        (self.cycle_sum - self.solver_sum) / self.solver_sum
    }
}

fn median(mut v: Vec<f64>) -> f64 {
    v.sort_by(f64::total_cmp);
    v[v.len() / 2]
}

/// A fresh instance advanced past its start, its time and the solver's step size.
fn warmed(guid: &str, resources: &Path, r: &Refs) -> Result<(LocalInstance, f64, f64)> {
    let mut inst = LocalInstance::new("fmi-bench", guid, resources).map_err(anyhow::Error::msg)?;
    let mut ints = vec![0; r.integers.len()];
    let mut t = 0.0;
    for _ in 0..20 {
        inst.do_step(t, 1e-3).map_err(anyhow::Error::msg)?;
        t += 1e-3;
    }
    inst.get_integer(&r.integers, &mut ints)
        .map_err(anyhow::Error::msg)?;
    let before = ints[r.steps_fine];
    // one long step: its n solver steps end on t + h, so h/n ≤ Δt < h/(n − 1)
    let h = 0.02;
    inst.do_step(t, h).map_err(anyhow::Error::msg)?;
    t += h;
    inst.get_integer(&r.integers, &mut ints)
        .map_err(anyhow::Error::msg)?;
    let n = ints[r.steps_fine] - before;
    if n < 2 {
        bail!("{SCENE}: {n} solver step(s) in {h} s, expected many");
    }
    Ok((inst, t, h / n as f64))
}

fn measure(
    guid: &str,
    resources: &Path,
    r: &Refs,
    per_step: u32,
    comm_steps: usize,
) -> Result<Level> {
    let (mut inst, mut t, dt) = warmed(guid, resources, r)?;
    // a hair under `per_step` solver steps, so the last one is shortened, not split
    let h = per_step as f64 * dt * 0.995;
    let inputs = vec![0.0; r.inputs.len()];
    let mut reals = vec![0.0; r.reals.len()];
    let mut ints = vec![0; r.integers.len()];
    inst.get_integer(&r.integers, &mut ints)
        .map_err(anyhow::Error::msg)?;
    let fine0 = ints[r.steps_fine];
    let (mut cycle, mut solver) = (Vec::new(), Vec::new());
    for _ in 0..comm_steps {
        let s0 = inst.solver_seconds();
        let start = Instant::now();
        inst.set_real(&r.inputs, &inputs)
            .map_err(anyhow::Error::msg)?;
        inst.do_step(t, h).map_err(anyhow::Error::msg)?;
        inst.get_real(&r.reals, &mut reals)
            .map_err(anyhow::Error::msg)?;
        inst.get_integer(&r.integers, &mut ints)
            .map_err(anyhow::Error::msg)?;
        cycle.push(start.elapsed().as_secs_f64());
        solver.push(inst.solver_seconds() - s0);
        t += h;
    }
    let fine_per_comm = (ints[r.steps_fine] - fine0) as f64 / comm_steps as f64;
    let layer: Vec<f64> = cycle.iter().zip(&solver).map(|(c, s)| c - s).collect();
    Ok(Level {
        per_step,
        comm_steps,
        fine_per_comm,
        cycle_sum: cycle.iter().sum(),
        solver_sum: solver.iter().sum(),
        cycle: median(cycle),
        solver: median(solver),
        layer: median(layer),
    })
}

/// Run the suite on `scenes`/fmu_barrier_2d.toml, print the table and write
/// `out`/fmi.json (and the Markdown `report`). Returns whether the layer stayed within
/// 1 % of the solver at 10 solver steps per communication step.
pub fn fmi(scenes: &Path, out: &Path, quick: bool, report: Option<&Path>) -> Result<bool> {
    let scene = scenes.join(SCENE);
    let resources = out.join("fmi").join("resources");
    let guid = granmix_fmu::package::write_resources(&scene, &[], &resources)
        .map_err(anyhow::Error::msg)?;
    let r = refs(&resources)?;
    let threads = rayon::current_num_threads();
    let levels = LEVELS
        .iter()
        .map(|&k| {
            let n = if quick {
                5
            } else {
                (4000 / k as usize).clamp(100, 2000)
            };
            measure(&guid, &resources, &r, k, n)
        })
        .collect::<Result<Vec<Level>>>()?;
    println!("FMI layer per fmi2DoStep, {SCENE} ({threads} thread(s)); medians over the steps");
    println!(
        "{:>10} {:>10} {:>12} {:>12} {:>12} {:>10} {:>10}",
        "solver/comm", "comm steps", "cycle [µs]", "solver [µs]", "layer [µs]", "layer", "(sums)"
    );
    for l in &levels {
        println!(
            "{:>10.2} {:>10} {:>12.2} {:>12.2} {:>12.2} {:>9.3}% {:>9.3}%",
            l.fine_per_comm,
            l.comm_steps,
            1e6 * l.cycle,
            1e6 * l.solver,
            1e6 * l.layer,
            100.0 * l.share(),
            100.0 * l.share_of_sums()
        );
    }
    let at10 = levels.iter().find(|l| l.per_step == 10).map(Level::share);
    let within = at10.is_some_and(|s| s < BUDGET);
    println!(
        "at 10 solver steps per communication step the layer costs {:.3} % of the solver (budget {:.0} %)",
        100.0 * at10.unwrap_or(f64::NAN),
        100.0 * BUDGET
    );
    let doc = json!({
        "scene": SCENE,
        "threads": threads,
        "quick": quick,
        "budget_at_10": BUDGET,
        "levels": levels.iter().map(|l| json!({
            "solver_steps_per_comm_step_asked": l.per_step,
            "solver_steps_per_comm_step": l.fine_per_comm,
            "comm_steps": l.comm_steps,
            "cycle_median_s": l.cycle,
            "solver_median_s": l.solver,
            "layer_median_s": l.layer,
            "layer_share": l.share(),
            "layer_share_of_sums": l.share_of_sums(),
        })).collect::<Vec<Value>>(),
    });
    std::fs::create_dir_all(out)?;
    let path = out.join("fmi.json");
    std::fs::write(&path, serde_json::to_string_pretty(&doc)?)?;
    println!("wrote {}", path.display());
    if let Some(p) = report {
        std::fs::write(p, markdown(&levels, threads))?;
        println!("wrote {}", p.display());
    }
    Ok(within)
}

fn markdown(levels: &[Level], threads: usize) -> String {
    let mut s = format!(
        "FMI layer per `fmi2DoStep` on `{SCENE}`, {threads} thread(s), medians over the \
         communication steps (`granmix bench --suite fmi`):\n\n\
         | solver steps per communication step | communication steps | cycle [µs] | solver [µs] | FMI layer [µs] | layer / solver |\n\
         |---|---|---|---|---|---|\n"
    );
    for l in levels {
        s += &format!(
            "| {:.2} | {} | {:.2} | {:.2} | {:.2} | {:.3} % |\n",
            l.fine_per_comm,
            l.comm_steps,
            1e6 * l.cycle,
            1e6 * l.solver,
            1e6 * l.layer,
            100.0 * l.share()
        );
    }
    s
}
