//! `granmix check`: validate a scene and estimate its cost.

use crate::run::load;
use anyhow::Result;
use granmix_core::AnySimulation;
use std::path::Path;

/// Nominal throughput used for the cost estimate (particle-steps per second per core),
/// from `granmix bench` on the reference machine.
const NOMINAL_PSS_PER_CORE: [f64; 2] = [1.5e6, 0.35e6];

pub fn check(scene: &Path, set: &[String]) -> Result<()> {
    let loaded = load(scene, set)?;
    let mut sim = AnySimulation::new(&loaded).map_err(|e| anyhow::anyhow!("{e}"))?;
    let s = &loaded.scene.simulation;
    println!("{}: valid {}D scene", scene.display(), s.dimension);
    for (name, n) in sim.region_counts() {
        println!("  region {name:<20} {n:>10} fine particles");
    }
    println!("  walls {:>34} dummy particles", sim.wall_count());
    for b in sim.barrier_names() {
        println!("  barrier {b}");
    }
    let bodies = sim.body_summaries();
    const LISTED: usize = 12;
    for (name, model, n, mass) in bodies.iter().take(LISTED) {
        println!("  body {name:<22} {n:>10} particles  {model:<7}  mass {mass:.4e} kg");
    }
    if bodies.len() > LISTED {
        let rest = &bodies[LISTED..];
        let n: usize = rest.iter().map(|b| b.2).sum();
        println!("  … {} more bodies {n:>10} particles", rest.len());
    }
    for r in &loaded.scene.rock_reports {
        println!(
            "  rock fill {:<17} {:>6} rocks  content {:.1} %",
            r.name,
            r.rocks,
            100.0 * r.content
        );
    }
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
    let cores = rayon::current_num_threads() as f64;
    let pss = NOMINAL_PSS_PER_CORE[s.dimension - 2] * cores;
    let (n, steps) = if sim.fine_count() > 0 {
        let steps = (s.end_time / dt).ceil();
        println!(
            "  Δt (Eq. 51, at rest) {dt:.3e} s → ~{steps:.0} fine steps to t = {} s",
            s.end_time
        );
        (sim.fine_count() as f64, steps)
    } else {
        // coarse grains only: one coarse step per solver step (the output interval
        // caps it where contacts allow longer steps)
        let step = dt_c.min(s.output_interval);
        let steps = (s.end_time / step).ceil();
        println!(
            "  no fine grains: Δt = {step:.3e} s → ~{steps:.0} steps to t = {} s",
            s.end_time
        );
        (sim.coarse_count() as f64, steps)
    };
    println!(
        "  cost ~{:.3e} particle-steps ≈ {:.0} s on {cores} core(s)",
        n * steps,
        n * steps / pss
    );
    Ok(())
}
