//! The step-averaged body load the FMU reports (`BodySample::mean_force`) is the
//! impulse over the sampling interval: a free rigid boulder's momentum change equals
//! (mean force + m g) × interval.

use granmix_core::input::load_scene_file;
use granmix_core::AnySimulation;
use std::path::Path;

#[test]
fn mean_body_force_is_the_interval_impulse() {
    let scene = Path::new(env!("CARGO_MANIFEST_DIR")).join("../models/scenes/debris_barrier.toml");
    let loaded = load_scene_file(&scene, &[]).expect("scene");
    let g = loaded.scene.simulation.gravity.clone();
    let mut sim = AnySimulation::new(&loaded).expect("simulation");
    let masses: Vec<f64> = sim.body_summaries().iter().map(|b| b.3).collect();
    let mut prev = sim.sample();
    let h = 4e-3;
    for n in 1..=3 {
        sim.advance_to(n as f64 * h).expect("advance");
        let s = sim.sample();
        for (i, (b, b0)) in s.bodies.iter().zip(&prev.bodies).enumerate() {
            for k in 0..3 {
                let dp = masses[i] * (b.velocity[k] - b0.velocity[k]);
                let impulse = (b.mean_force[k] + masses[i] * g[k]) * h;
                let scale = masses[i] * g.iter().map(|x| x.abs()).sum::<f64>() * h
                    + b.mean_force[k].abs() * h;
                assert!(
                    (dp - impulse).abs() <= 1e-9 * scale,
                    "body {} axis {k}: momentum change {dp}, impulse {impulse}",
                    b.name
                );
            }
        }
        prev = s;
    }
}
