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
    let sim = AnySimulation::new(&loaded).map_err(|e| anyhow::anyhow!("{e}"))?;
    let s = &loaded.scene.simulation;
    println!("{}: valid {}D scene", scene.display(), s.dimension);
    for (name, n) in sim.region_counts() {
        println!("  region {name:<20} {n:>10} fine particles");
    }
    println!("  walls {:>34} dummy particles", sim.wall_count());
    for b in sim.barrier_names() {
        println!("  barrier {b}");
    }
    let dt = sim.stable_dt();
    let steps = (s.end_time / dt).ceil();
    let n = sim.fine_count() as f64;
    let cores = rayon::current_num_threads() as f64;
    let pss = NOMINAL_PSS_PER_CORE[s.dimension - 2] * cores;
    println!(
        "  Δt (Eq. 51, at rest) {dt:.3e} s → ~{steps:.0} fine steps to t = {} s",
        s.end_time
    );
    println!(
        "  cost ~{:.3e} particle-steps ≈ {:.0} s on {cores} core(s)",
        n * steps,
        n * steps / pss
    );
    Ok(())
}
