//! Barrier panels: the step-averaged panel forces sum to the barrier total, and the
//! load is distributed as the soil's weight suggests (more on the lower panels of a
//! retaining barrier).

use granmix_core::input::load_scene_file;
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

/// Two rigid blocks of different weight resting on a paneled barrier floor: once they
/// are at rest, each panel carries exactly the weight of the block on it (ρ A g per
/// unit width), and the panels sum to the barrier's total.
#[test]
fn contact_loads_land_on_the_panel_under_each_block() {
    let text = r#"
[simulation]
name = "panel_blocks"
dimension = 2
gravity = [0.0, -9.81]
end_time = 0.5
dp = 0.01
output_interval = 0.01

[[solids]]
name = "light"
density = 1000.0
youngs_modulus = 1e7
poisson_ratio = 0.25

[[solids]]
name = "heavy"
density = 2500.0
youngs_modulus = 1e7
poisson_ratio = 0.25

[[bodies]]
name = "a"
material = "light"
model = "rigid"
shape = { type = "box", min = [0.1, 0.006], max = [0.3, 0.106] }

[[bodies]]
name = "b"
material = "heavy"
model = "rigid"
shape = { type = "box", min = [0.6, 0.006], max = [0.9, 0.066] }

[[barriers]]
name = "floor"
shape = { type = "box", min = [0.0, -0.05], max = [1.0, 0.0] }
panels = [2]

[contact]
model = "spring-dashpot"
friction = 0.5
restitution = 0.1
"#;
    let (_, mut sim) = granmix_tests::build_text(text, "panel_blocks.toml");
    sim.sample();
    sim.advance_to(0.4).expect("settle");
    sim.sample();
    sim.advance_to(0.5).expect("advance");
    let s = sim.sample();
    let b = &s.barriers[0];
    assert_eq!(b.panels.len(), 2);
    let g = 9.81;
    let weights = [1000.0 * 0.2 * 0.1 * g, 2500.0 * 0.3 * 0.06 * g];
    for (k, w) in weights.iter().enumerate() {
        let fy = -b.panels[k][1];
        assert!(
            (fy - w).abs() <= 0.01 * w,
            "panel {k}: carries {fy} N/m, block weight {w} N/m"
        );
        assert!(
            b.panels[k][0].abs() <= 0.01 * w,
            "panel {k}: shear {}",
            b.panels[k][0]
        );
    }
    for k in 0..2 {
        let sum: f64 = b.panels.iter().map(|p| p[k]).sum();
        assert!(
            (sum - b.force[k]).abs() <= 1e-12 * weights[1],
            "component {k}"
        );
    }
}
