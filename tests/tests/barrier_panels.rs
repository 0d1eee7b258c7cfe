//! Barrier panels: the step-averaged panel forces sum to the barrier total, and the
//! load is distributed as the soil's weight suggests (more on the lower panels of a
//! retaining barrier).

use granmix_core::scene::load_scene_file;
use granmix_core::AnySimulation;
use std::path::Path;

#[test]
fn panel_forces_sum_to_the_barrier_total() {
    let scene = Path::new(env!("CARGO_MANIFEST_DIR")).join("../models/scenes/fmu_barrier_2d.toml");
    let loaded = load_scene_file(&scene, &["barriers[0].panels=[4]".to_string()]).expect("scene");
    let mut sim = AnySimulation::new(&loaded).expect("simulation");
    sim.sample();
    let mut lower = 0.0;
    let mut upper = 0.0;
    for n in 1..=40 {
        sim.advance_to(n as f64 * 2.5e-3).expect("advance");
        let s = sim.sample();
        let b = &s.barriers[0];
        assert_eq!(b.panels.len(), 4);
        for k in 0..3 {
            let sum: f64 = b.panels.iter().map(|p| p[k]).sum();
            let scale = b.panels.iter().map(|p| p[k].abs()).sum::<f64>().max(1e-300);
            assert!(
                (sum - b.force[k]).abs() <= 1e-12 * scale,
                "sample {n}, component {k}: panels sum to {sum}, barrier {}",
                b.force[k]
            );
        }
        lower += b.panels[0][0];
        upper += b.panels[3][0];
    }
    // The barrier is 0.2 m high and the layer 0.1 m deep: the top panel (0.15–0.2 m)
    // carries nothing, the bottom one most.
    assert!(
        lower > 0.0 && upper.abs() < 1e-9 * lower,
        "bottom {lower}, top {upper}"
    );
}
