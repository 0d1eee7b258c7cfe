//! `granmix run`: step a scene to its end time, writing VTK, CSV and summary.json.

use crate::series::{CsvSeries, Layout};
use crate::vtk::VtkSeries;
use anyhow::{bail, Context, Result};
use granmix_core::input::{load_scene_file, LoadedScene};
use granmix_core::run::observables::{observables, Cell};
use granmix_core::run::runner::{self, RunEnd};
use granmix_core::run::sample::BodySample;
use granmix_core::run::simulation::Sample;
use granmix_core::scene::SimulationSpec;
use granmix_core::AnySimulation;
use granmix_core::Blowup;
use granmix_core::Stage;
use granmix_ipc::{ChannelSink, FramePublisher, Recorder, SceneInfo, Sinks};
use indicatif::{ProgressBar, ProgressStyle};
use serde_json::{json, Map, Value};
use std::cell::RefCell;
use std::path::{Path, PathBuf};
use std::time::Instant;

/// Options of one run.
#[derive(Clone, Debug)]
pub struct RunOptions {
    pub scene: PathBuf,
    pub out: PathBuf,
    pub set: Vec<String>,
    /// Show a progress bar and print the stage table.
    pub interactive: bool,
    /// Write VTK snapshots.
    pub vtk: bool,
    /// Write the quick-look plot `plots/quicklook.png` (crate::quicklook).
    pub plots: bool,
    /// Publish particle frames on this service (instance name or full service name).
    pub publish: Option<String>,
    /// Publish every this many fine steps (≥ 1).
    pub publish_every: u64,
    /// Record the run to this MCAP file.
    pub record: Option<PathBuf>,
    /// The memory budget given on the command line (`--memory-budget`), in bytes.
    pub memory_budget: Option<f64>,
}

impl RunOptions {
    /// A quiet batch run (benchmarks): no progress bar, no VTK, no plot, no publishing
    /// or recording.
    pub fn batch(scene: PathBuf, out: PathBuf, set: Vec<String>) -> Self {
        RunOptions {
            scene,
            out,
            set,
            interactive: false,
            vtk: false,
            plots: false,
            publish: None,
            publish_every: 1,
            record: None,
            memory_budget: None,
        }
    }
}

/// What a run produced.
pub struct RunReport {
    pub summary: Value,
    pub samples: Vec<Sample>,
    pub blowup: Option<Blowup>,
    /// Fine and water particles.
    pub particles: usize,
    pub wall_time: f64,
    /// Fine particle-steps plus coarse particle-sub-steps per second.
    pub particle_steps_per_s: f64,
    /// Fine particle-steps per second alone (equal to the above without coarse grains).
    pub fine_particle_steps_per_s: f64,
    /// The scene's families and objects: what the series' columns are built from.
    pub layout: Layout,
}

/// Load a scene with overrides, turning errors into messages that name the file.
pub fn load(scene: &Path, set: &[String]) -> Result<LoadedScene> {
    load_scene_file(scene, set).map_err(|e| anyhow::anyhow!("{e}"))
}

/// [`load`], with the memory budget given on the command line in place of the
/// scene's, named `--memory-budget` in the messages that cite it.
pub fn load_budgeted(scene: &Path, set: &[String], budget: Option<f64>) -> Result<LoadedScene> {
    let mut loaded = load(scene, set)?;
    if let Some(b) = budget {
        loaded.scene.simulation.memory_budget = b;
        loaded.scene.simulation.memory_budget_origin = Some("--memory-budget".into());
    }
    Ok(loaded)
}

/// Run a scene to its end: load and build it, step it feeding the sinks (CSV series,
/// VTK, the particle channel, the MCAP recording), then write summary.json, bodies.json
/// and the quick-look plot.
pub fn run(opts: &RunOptions) -> Result<RunReport> {
    let loaded = load_budgeted(&opts.scene, &opts.set, opts.memory_budget)?;
    let mut sim = AnySimulation::new(&loaded).map_err(|e| anyhow::anyhow!("{e}"))?;
    std::fs::create_dir_all(&opts.out)
        .with_context(|| format!("cannot create output directory {}", opts.out.display()))?;
    std::fs::write(opts.out.join("scene.toml"), &loaded.text)?;
    let stem = opts
        .scene
        .file_stem()
        .and_then(|s| s.to_str())
        .unwrap_or("scene")
        .to_string();
    let layout = Layout::of(&sim);
    let sinks = open_sinks(opts, &loaded, &sim, &layout, &stem)?;
    let ran = step_to_end(opts, &loaded.scene.simulation, &mut sim, sinks)?;
    let skipped = skipped(opts, &sim, &ran);
    let last = ran.samples.last().cloned().unwrap_or_default();
    let summary = summary_json(opts, &loaded, &sim, &layout, &ran, &skipped);
    std::fs::write(
        opts.out.join("summary.json"),
        serde_json::to_string_pretty(&summary)?,
    )?;
    if !last.bodies.is_empty() {
        write_bodies_json(
            &opts.out.join("bodies.json"),
            layout.dim,
            layout.water,
            &ran.samples,
        )?;
    }
    if opts.plots && !ran.samples.is_empty() {
        let dir = opts.out.join("plots");
        std::fs::create_dir_all(&dir)?;
        let name = loaded.scene.simulation.name.clone().unwrap_or(stem);
        let title = format!("{name} — t = {:.3} s", last.time);
        crate::quicklook::write(&dir.join("quicklook.png"), &title, &layout, &ran.samples)?;
    }
    if opts.interactive {
        print_table(&sim, &skipped, ran.wall, (ran.pss, ran.fine_pss), &opts.out);
    }
    Ok(RunReport {
        summary,
        particles: sim.fine_count() + sim.water_count(),
        wall_time: ran.wall,
        particle_steps_per_s: ran.pss,
        fine_particle_steps_per_s: ran.fine_pss,
        samples: ran.samples,
        blowup: ran.blowup,
        layout,
    })
}

/// The run's sinks: the CSV series always, the VTK series, the particle channel and the
/// MCAP recording where asked.
fn open_sinks(
    opts: &RunOptions,
    loaded: &LoadedScene,
    sim: &AnySimulation,
    layout: &Layout,
    stem: &str,
) -> Result<Sinks> {
    let mut sinks = Sinks::default();
    sinks.push(CsvSeries::create(
        &opts.out.join("series.csv"),
        layout.clone(),
    )?);
    if opts.vtk {
        sinks.push(VtkSeries::new(&opts.out, stem));
    }
    if opts.publish_every == 0 {
        bail!("--publish-every must be at least 1");
    }
    if let Some(spec) = &opts.publish {
        let (f, c) = sim.particle_counts();
        let p = FramePublisher::open(spec, f + c)?;
        if opts.interactive {
            eprintln!(
                "publishing particle frames every {} steps on `{}`",
                opts.publish_every,
                p.name()
            );
        }
        sinks.push(ChannelSink::new(p, Some(opts.publish_every)));
    }
    if let Some(path) = &opts.record {
        sinks.push(Recorder::create(
            path,
            &SceneInfo {
                text: loaded.text.clone(),
                file: opts.scene.display().to_string(),
                name: loaded.scene.simulation.name.clone(),
                dimension: sim.dimension(),
                water: sim.has_water(),
            },
        )?);
    }
    Ok(sinks)
}

/// What stepping a run produced.
struct Ran {
    samples: Vec<Sample>,
    /// The largest kinetic energy of the grains sampled.
    ke_peak: f64,
    ended: RunEnd,
    blowup: Option<Blowup>,
    /// The channel's and the recorder's reports (None: not asked for).
    publish: Option<Value>,
    record: Option<Value>,
    /// Wall time (s), sinks included.
    wall: f64,
    /// Fine particle-steps plus coarse particle-sub-steps and water particle-steps per
    /// second, and the fine ones alone.
    pss: f64,
    fine_pss: f64,
}

/// Step `sim` to the end of `spec`, feeding `sinks` a sample at every output time and
/// a call after every step, with a progress bar when interactive; the sinks' time is
/// added to the observation stage.
fn step_to_end(
    opts: &RunOptions,
    spec: &SimulationSpec,
    sim: &mut AnySimulation,
    sinks: Sinks,
) -> Result<Ran> {
    let end = spec.end_time;
    let bar = progress_bar(opts.interactive, end);
    let mut samples: Vec<Sample> = Vec::new();
    // both callbacks feed the sinks, one at a time
    let sinks = RefCell::new(sinks);
    let io_error: RefCell<Option<anyhow::Error>> = RefCell::new(None);
    let start = Instant::now();
    let mut last_ui = Instant::now();
    let mut ke_peak: f64 = 0.0;
    let ended = runner::run(
        sim,
        spec,
        |sim, s| {
            ke_peak = ke_peak.max(s.kinetic_energy);
            samples.push(s.clone());
            match sinks.borrow_mut().sample(sim, s) {
                Ok(()) => true,
                Err(e) => {
                    *io_error.borrow_mut() = Some(e.into());
                    false
                }
            }
        },
        |sim| {
            if let Err(e) = sinks.borrow_mut().step(sim) {
                io_error.borrow_mut().get_or_insert(e.into());
            }
            if last_ui.elapsed().as_millis() > 200 {
                last_ui = Instant::now();
                let el = start.elapsed().as_secs_f64();
                bar.set_position((sim.time() * 1e6) as u64);
                bar.set_message(format!(
                    "{:.4} s / {end} s, {:.0} steps/s",
                    sim.time(),
                    sim.steps() as f64 / el.max(1e-9)
                ));
            }
        },
    );
    if let Some(e) = io_error.into_inner() {
        return Err(e);
    }
    let mut sinks = sinks.into_inner();
    let blowup = match &ended {
        RunEnd::Blowup(b) => Some(b.clone()),
        _ => None,
    };
    if blowup.is_some() {
        sinks.blowup(sim)?;
    }
    let (publish, record) = (sinks.report("publish"), sinks.report("record"));
    sinks.finish()?;
    bar.finish_and_clear();
    let wall = start.elapsed().as_secs_f64();
    // fine particle-steps plus coarse particle-sub-steps, and the fine ones alone
    let rate = |n: usize, steps: u64| n as f64 * steps as f64 / wall.max(1e-12);
    let fine_pss = rate(sim.fine_count(), sim.steps());
    let pss = fine_pss
        + rate(sim.coarse_count(), sim.coarse_steps())
        + rate(sim.water_count(), sim.water_steps());
    // the sinks count as observation: rows, snapshots and records written, frames built
    sim.timers_mut().add(Stage::Observe, sinks.seconds);
    Ok(Ran {
        samples,
        ke_peak,
        ended,
        blowup,
        publish,
        record,
        wall,
        pss,
        fine_pss,
    })
}

/// The progress bar of an interactive run to `end` (s); hidden otherwise.
fn progress_bar(interactive: bool, end: f64) -> ProgressBar {
    if !interactive {
        return ProgressBar::hidden();
    }
    let b = ProgressBar::new((end * 1e6).round() as u64);
    b.set_style(
        ProgressStyle::with_template("{spinner} [{elapsed_precise}] {bar:32} t = {msg} ETA {eta}")
            .expect("valid template")
            .progress_chars("=> "),
    );
    b
}

/// The stages this run skipped, and why: the simulation's own, and publishing and
/// recording where not asked for or not used.
fn skipped(opts: &RunOptions, sim: &AnySimulation, ran: &Ran) -> Vec<(String, String)> {
    let mut skipped = sim.skipped();
    let sent = |p: &Value| {
        p["frames_sent"].as_u64().unwrap_or(0) + p["frames_dropped"].as_u64().unwrap_or(0)
    };
    match &ran.publish {
        None => skipped.push(("publish".into(), "no --publish".into())),
        Some(p) if sent(p) == 0 => {
            skipped.push(("publish".into(), "no subscriber: no frame was built".into()))
        }
        Some(_) => {}
    }
    if opts.record.is_none() {
        skipped.push(("record".into(), "no --record".into()));
    }
    skipped
}

/// summary.json: counts, steps, memory, throughput, stages, what was skipped, the
/// channel's and the recorder's reports and the final observables.
fn summary_json(
    opts: &RunOptions,
    loaded: &LoadedScene,
    sim: &AnySimulation,
    layout: &Layout,
    ran: &Ran,
    skipped_list: &[(String, String)],
) -> Value {
    let (dim, wall, n) = (layout.dim, ran.wall, sim.fine_count());
    let mut stages = Map::new();
    for (name, secs) in sim.timers().entries() {
        stages.insert(name.to_string(), json!(secs));
    }
    let mut skipped = Map::new();
    for (name, why) in skipped_list {
        skipped.insert(name.clone(), json!(why));
    }
    let last = ran.samples.last().cloned().unwrap_or_default();
    let mut bodies = Map::new();
    for b in &last.bodies {
        bodies.insert(b.name.clone(), body_json(dim, layout.water, b));
    }
    // the SPH particles (fine grains and water) and their memory: a water-only run
    // counts its water (issue 39: it reported 0 particles and all memory per particle)
    let sph = n + sim.water_count();
    let memory = sim.fine_bytes() + sim.water_bytes();
    let water_pss = sim.water_count() as f64 * sim.water_steps() as f64 / wall.max(1e-12);
    json!({
        "scene": opts.scene.display().to_string(),
        "name": loaded.scene.simulation.name,
        "dimension": dim,
        "status": match &ran.ended { RunEnd::Blowup(_) => "blowup", RunEnd::Settled => "settled", _ => "ok" },
        "blowup": ran.blowup.as_ref().map(|b| b.to_string()),
        "particles": sph,
        "particles_fine": n,
        "wall_particles": sim.wall_count(),
        "steps_fine": sim.steps(),
        "steps_coarse": last.steps_coarse,
        "steps_water": sim.water_steps(),
        "kappa": last.kappa,
        "dt_fine": last.dt_fine,
        "dt_coarse": last.dt_coarse,
        "particles_coarse": sim.coarse_count(),
        "particles_water": sim.water_count(),
        "bodies": bodies,
        "neighbor_builds": sim.neighbor_builds(),
        "relations": relations(sim),
        "memory_bytes_fine": sim.fine_bytes(),
        "memory_bytes": memory,
        "bytes_per_particle": (sph > 0).then(|| memory as f64 / sph as f64),
        "threads": rayon::current_num_threads(),
        "simd": granmix_core::numerics::pairs::quad::Lanes::detect().name(),
        "wall_time_s": wall,
        "particle_steps_per_s": ran.pss,
        "fine_particle_steps_per_s": (n > 0).then_some(ran.fine_pss),
        "water_particle_steps_per_s": layout.water.then_some(water_pss),
        "stages": stages,
        "awake": sim.fine_awake().map(|(now, mean)| json!({
            "fine": {"final": now, "mean": mean}
        })),
        "skipped": skipped,
        "publish": ran.publish,
        "record": ran.record,
        "observables": summary_values(layout, &last, ran.ke_peak),
    })
}

/// The final values of the observables the table marks for the summary
/// ([`observables`]: each family's kinetic energy and largest speed, their total, the
/// run-out of the grains, the barrier loads split into water and grains, and the
/// panels' loads; docs/scenes.md), with the fine grains' peak kinetic energy.
fn summary_values(l: &Layout, last: &Sample, ke_peak: f64) -> Map<String, Value> {
    let mut obs = Map::new();
    for o in observables(l).iter().filter(|o| o.summary) {
        let v = match o.value(last) {
            Cell::Real(v) => json!(v),
            Cell::Count(n) => json!(n),
            Cell::Empty => Value::Null,
        };
        obs.insert(o.name.clone(), v);
    }
    if l.fine {
        obs.insert("kinetic_energy_peak".into(), json!(ke_peak));
    }
    obs
}

/// A rotation (angular velocity, torque) as JSON: the scalar about z in 2D, the
/// vector in 3D.
fn rotation_json(dim: usize, v: &[f64; 3]) -> Value {
    if dim == 2 {
        json!(v[2])
    } else {
        json!(v)
    }
}

/// One body's state and loads as JSON (summary.json and bodies.json).
fn body_json(dim: usize, water: bool, b: &BodySample) -> Value {
    let mut v = json!({
        "name": b.name,
        "position": &b.position[..dim],
        "orientation_wxyz": b.orientation,
        "velocity": &b.velocity[..dim],
        "angular_velocity": rotation_json(dim, &b.angular_velocity),
        "force": &b.force[..dim],
        "torque": rotation_json(dim, &b.torque),
        "fine_force": &b.fine_force[..dim],
        "contacts": b.contacts,
    });
    if water {
        v["water_force"] = json!(&b.water_force[..dim]);
    }
    v
}

/// Body time series as JSON: one record per output time and body.
fn write_bodies_json(path: &Path, dim: usize, water: bool, samples: &[Sample]) -> Result<()> {
    let rows: Vec<Value> = samples
        .iter()
        .map(|s| {
            json!({
                "time": s.time,
                "kappa": s.kappa,
                "bodies": s.bodies.iter().map(|b| body_json(dim, water, b)).collect::<Vec<_>>(),
            })
        })
        .collect();
    std::fs::write(path, serde_json::to_string(&json!({ "series": rows }))?)?;
    Ok(())
}

fn print_table(
    sim: &AnySimulation,
    skipped: &[(String, String)],
    wall: f64,
    (pss, fine_pss): (f64, f64),
    out: &Path,
) {
    let n = sim.fine_count();
    if sim.coarse_count() > 0 && sim.water_count() > 0 {
        // fine and water particle-steps, then with the coarse sub-steps
        let coarse = sim.coarse_count() as f64 * sim.coarse_steps() as f64 / wall.max(1e-12);
        println!(
            "\n{} fine and {} water particles, {} steps ({} water) in {:.2} s: {:.3} M \
             particle-steps/s ({:.3} M with {} coarse particles × {} sub-steps)",
            n,
            sim.water_count(),
            sim.steps(),
            sim.water_steps(),
            wall,
            (pss - coarse) / 1e6,
            pss / 1e6,
            sim.coarse_count(),
            sim.coarse_steps()
        );
    } else if sim.coarse_count() > 0 {
        println!(
            "\n{} fine particles, {} steps in {:.2} s: {:.3} M fine particle-steps/s \
             ({:.3} M with {} coarse particles × {} sub-steps)",
            n,
            sim.steps(),
            wall,
            fine_pss / 1e6,
            pss / 1e6,
            sim.coarse_count(),
            sim.coarse_steps()
        );
    } else if sim.water_count() > 0 {
        // the water's sub-steps, where it takes more than one per fine step
        let sub = if sim.water_steps() > sim.steps() {
            format!(" (water: {} sub-steps)", sim.water_steps())
        } else {
            String::new()
        };
        println!(
            "\n{} fine and {} water particles, {} steps{sub} in {:.2} s: {:.3} M particle-steps/s",
            n,
            sim.water_count(),
            sim.steps(),
            wall,
            pss / 1e6
        );
    } else {
        println!(
            "\n{} fine particles, {} steps in {:.2} s: {:.3} M particle-steps/s",
            n,
            sim.steps(),
            wall,
            pss / 1e6
        );
    }
    if let Some((now, mean)) = sim.fine_awake() {
        println!(
            "resting fine grains sleep: {:.1} % of particle-steps awake ({:.1} % at the end)",
            100.0 * mean,
            100.0 * now
        );
    }
    println!("{:<22} {:>10} {:>7}", "stage", "seconds", "share");
    for (name, secs) in sim.timers().entries() {
        println!(
            "{:<22} {:>10.3} {:>6.1}%",
            name,
            secs,
            100.0 * secs / wall.max(1e-12)
        );
    }
    if !skipped.is_empty() {
        println!("skipped for this scene:");
        for (name, why) in skipped {
            println!("  {name:<20} {why}");
        }
    }
    println!("outputs in {}", out.display());
}

/// summary.json `relations`: per relation of the scene's families, its list builds and
/// the pairs of its last build.
fn relations(sim: &AnySimulation) -> Value {
    let map: Map<String, Value> = sim
        .relations()
        .into_iter()
        .map(|(r, s)| {
            (
                r.name().to_string(),
                json!({"builds": s.builds, "pairs": s.pairs}),
            )
        })
        .collect();
    Value::Object(map)
}
