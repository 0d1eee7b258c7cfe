//! `granmix check`: validate a scene, estimate its particles, memory and cost without
//! building it (core/src/estimate/mod.rs), and refuse it when it exceeds the memory budget.
//! `--exact` builds it and prints the exact counts.

use crate::run::load_budgeted;
use anyhow::{bail, Result};
use granmix_core::estimate::budget::{budget, human_bytes, over_budget, passes};
use granmix_core::estimate::{estimate, rest_dt, RestDt};
use granmix_core::input::LoadedScene;
use granmix_core::scene::resolution::Resolution;
use granmix_core::scene::KeyError;
use granmix_core::AnySimulation;
use std::path::Path;

/// Nominal throughput used for the cost estimate (particle-steps per second per core),
/// from `granmix bench` on the reference machine.
const NOMINAL_PSS_PER_CORE: [f64; 2] = [1.5e6, 0.35e6];

/// Bodies listed one by one; the rest are summed.
const LISTED: usize = 12;

pub fn check(scene: &Path, set: &[String], exact: bool, flag: Option<f64>) -> Result<()> {
    let loaded = load_budgeted(scene, set, flag)?;
    let s = &loaded.scene.simulation;
    println!("{}: valid {}D scene", scene.display(), s.dimension);
    if let Some(p) = &s.periodic {
        println!(
            "  periodic along {} with period {:?} m ([{:?}, {:?}])",
            p.axis,
            p.max - p.min,
            p.min,
            p.max
        );
    }
    materials(&loaded);
    let res = Resolution::of_scene(&loaded.scene);
    let e = estimate(&loaded.scene, &res);
    let b = budget(&loaded.scene);
    if exact && passes(&e, &b) {
        return check_exact(&loaded, &e);
    }
    println!(
        "  estimated at dp = {:?} m (without building; --exact builds):",
        s.dp
    );
    for (name, n) in &e.regions {
        println!("  region {name:<20} {n:>10.3e} fine particles");
    }
    for (name, n) in &e.water {
        println!("  water {name:<21} {n:>10.3e} water particles at the start");
    }
    for (name, n) in &e.inflows {
        println!(
            "  inflow {name:<20} {n:>10.3e} water particles let in by t = {:?} s (counted in \
             the memory; outflows may remove some)",
            s.end_time
        );
    }
    println!("  walls {:>34.3e} dummy particles", e.walls);
    for (name, n) in e.bodies.iter().take(LISTED) {
        println!("  body {name:<22} {n:>10.3e} particles");
    }
    if e.bodies.len() > LISTED {
        let rest = &e.bodies[LISTED..];
        let n: f64 = rest.iter().map(|b| b.1).sum();
        println!("  … {} more bodies {n:>10.3e} particles", rest.len());
    }
    rock_reports(&loaded);
    println!(
        "  memory ~{} ({:.0} / {:.0} / {:.0} bytes per fine / wall / coarse particle, {} in \
         cell grids of {:.3e} cells); budget {} ({})",
        human_bytes(e.bytes),
        e.per_particle[0],
        e.per_particle[1],
        e.per_particle[2],
        human_bytes(e.grid_bytes),
        e.cells,
        human_bytes(b.bytes),
        b.origin
    );
    if !passes(&e, &b) {
        bail!(
            "{}",
            loaded.locate(KeyError::new("simulation.dp", over_budget(&e, &b)))
        );
    }
    let bound = rest_dt(&loaded.scene, &res);
    if e.coarse() > 0.0 {
        println!(
            "  Δt_c (Eq. 52 and contacts): run `granmix check --exact` to build and measure it"
        );
    }
    let grains_or_water = e.fine() + e.water() + e.inflow() > 0.0;
    let (n, step) = if grains_or_water {
        (e.mean_stepped(), bound.dt)
    } else {
        (e.coarse(), s.output_interval)
    };
    cost(&loaded, n, step, grains_or_water, &bound);
    Ok(())
}

/// Build the scene and print its exact counts, Δt and cost (the budget checked first,
/// in the build).
fn check_exact(loaded: &LoadedScene, e: &granmix_core::estimate::Estimate) -> Result<()> {
    let mut sim = AnySimulation::new(loaded).map_err(|e| anyhow::anyhow!("{e}"))?;
    println!("  built (exact counts):");
    for (name, n) in sim.region_counts() {
        println!("  region {name:<20} {n:>10} fine particles");
    }
    if sim.has_water() {
        println!(
            "  water {:>34} water particles at the start",
            sim.water_count()
        );
    }
    for (name, n) in &e.inflows {
        println!(
            "  inflow {name:<20} {n:>10.3e} water particles let in by t = {:?} s (estimated)",
            loaded.scene.simulation.end_time
        );
    }
    println!("  walls {:>34} dummy particles", sim.wall_count());
    for b in sim.barrier_names() {
        println!("  barrier {b}");
    }
    let bodies = sim.body_summaries();
    for (name, model, n, mass) in bodies.iter().take(LISTED) {
        println!("  body {name:<22} {n:>10} particles  {model:<7}  mass {mass:.4e} kg");
    }
    if bodies.len() > LISTED {
        let rest = &bodies[LISTED..];
        let n: usize = rest.iter().map(|b| b.2).sum();
        println!("  … {} more bodies {n:>10} particles", rest.len());
    }
    rock_reports(loaded);
    let dt = sim.stable_dt();
    let mut dt_c = f64::INFINITY;
    if sim.coarse_count() > 0 {
        let (c, kappa) = sim.coarse_estimate();
        dt_c = c;
        println!(
            "  Δt_c (Eq. 52 and contacts, at rest) {dt_c:.3e} s → κ = {kappa} ({})",
            loaded.scene.simulation.time_stepping_name()
        );
    }
    let stepped = (sim.fine_count() + sim.water_count()) as f64 + 0.5 * e.inflow();
    let fine = stepped > 0.0;
    let (n, step) = if fine {
        (stepped, dt)
    } else {
        (
            sim.coarse_count() as f64,
            dt_c.min(loaded.scene.simulation.output_interval),
        )
    };
    let res = Resolution::of_scene(&loaded.scene);
    cost(loaded, n, step, fine, &rest_dt(&loaded.scene, &res));
    Ok(())
}

/// Each soil's model: the cone its friction angle is fitted on, and its hardening or
/// μ(I) (docs/method.md §Soil models).
fn materials(loaded: &LoadedScene) {
    for m in &loaded.scene.materials {
        let surface = m.surface();
        let model = match (&m.hardening, &m.mu_i) {
            (Some(h), _) => format!(
                ", hardening to φ_p = {}° at ε_p = {}, softening to φ_r = {}° (seed 004 Eq. 43)",
                h.peak_angle, h.peak_strain, h.residual_angle
            ),
            (None, Some(mu)) => format!(
                ", μ(I): μ_s = {}, μ_2 = {}, I_0 = {}, d = {} m, ρ_s = {} kg/m³",
                mu.mu_s, mu.mu_2, mu.i_0, mu.grain_diameter, mu.grain_density
            ),
            (None, None) => String::new(),
        };
        let psi = match (&m.dilatancy, m.porosity) {
            (Some(d), Some(n)) => format!(
                "tan ψ = {} (φ − {}/(1 + {} √I_m)) from φ0 = {:.3}",
                d.k,
                d.phi_c,
                d.b,
                1.0 - n
            ),
            _ => format!("ψ = {}°", m.dilation_angle),
        };
        println!(
            "  material {:<18} φ = {:.2}°, c = {} Pa, {psi} on the `{}` cone{model}",
            m.name,
            m.static_friction_angle(),
            m.cohesion,
            surface.name()
        );
    }
}

fn rock_reports(loaded: &LoadedScene) {
    for r in &loaded.scene.rock_reports {
        println!(
            "  rock fill {:<17} {:>6} rocks  content {:.1} %",
            r.name,
            r.rocks,
            100.0 * r.content
        );
    }
}

/// Print the step count and the cost of `n` particles stepped at `step`, and the
/// `bound` that sets the fine and water step (the estimate's, at rest).
fn cost(loaded: &LoadedScene, n: f64, step: f64, fine: bool, bound: &RestDt) {
    let s = &loaded.scene.simulation;
    let steps = (s.end_time / step).ceil();
    if fine {
        println!(
            "  Δt (Eq. 51, at rest) {step:.3e} s → ~{} steps to t = {:?} s",
            short(steps),
            s.end_time
        );
        if bound.dt.is_finite() {
            println!("    set by {} (`{}`)", bound.what, bound.key);
        }
    } else {
        // coarse grains only: one coarse step per solver step (the output interval
        // caps it where contacts allow longer steps)
        println!(
            "  no fine grains: Δt = {step:.3e} s → ~{} steps to t = {:?} s",
            short(steps),
            s.end_time
        );
    }
    let cores = rayon::current_num_threads() as f64;
    let pss = NOMINAL_PSS_PER_CORE[s.dimension - 2] * cores;
    println!(
        "  cost ~{:.3e} particle-steps ≈ {} s on {cores} core(s)",
        n * steps,
        short(n * steps / pss)
    );
}

/// A count or duration in its shortest readable form: whole below ten million, else
/// with an exponent (never hundreds of digits).
fn short(x: f64) -> String {
    if x.abs() < 1e7 {
        format!("{x:.0}")
    } else {
        format!("{x:.3e}")
    }
}
