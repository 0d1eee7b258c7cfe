//! Cohesive soil (c > 0, artificial stress of Eqs. 27–31 active): an unsupported
//! vertical cut stands below its critical height and collapses above it.
//! Reference: H_c = (4c/γ) tan(45° + φ/2) (Terzaghi; Rankine upper bound).

use granmix_tests::{build_text, run_built};

fn scene(height: f64) -> String {
    format!(
        r#"
[simulation]
dimension = 2
gravity = [0.0, -9.81]
end_time = 1.5
dp = 0.1
output_interval = 0.05

[[materials]]
name = "clay"
density = 2000.0
youngs_modulus = 2.0e7
poisson_ratio = 0.3
friction_angle = 15.0
cohesion = 8400.0

[[regions]]
name = "cut"
material = "clay"
shape = {{ type = "box", min = [0.0, 0.0], max = [2.0, {height}] }}
initial_stress = "geostatic"

[[containers]]
name = "ground"
min = [0.0, 0.0]
max = [8.0, 10.0]
open = ["+x", "+y"]
"#
    )
}

/// Largest displacement of the cut face (particles initially within one dp of x = 2 m).
fn face_displacement(height: f64) -> f64 {
    let (loaded, mut sim) = build_text(&scene(height), "cut.toml");
    let f0 = sim.frame();
    let face: Vec<u32> = f0
        .fine
        .iter()
        .filter(|p| p.position[0] > 1.9)
        .map(|p| p.id)
        .collect();
    let x0: std::collections::HashMap<u32, f32> =
        f0.fine.iter().map(|p| (p.id, p.position[0])).collect();
    run_built(&loaded, &mut sim, |_| {});
    let f = sim.frame();
    f.fine
        .iter()
        .filter(|p| face.contains(&p.id))
        .map(|p| (p.position[0] - x0[&p.id]) as f64)
        .fold(0.0, f64::max)
}

#[test]
fn vertical_cut_stands_below_critical_height_and_fails_above() {
    let (c, phi, gamma): (f64, f64, f64) = (8400.0, 15f64.to_radians(), 2000.0 * 9.81);
    let hc = 4.0 * c / gamma * (std::f64::consts::FRAC_PI_4 + phi / 2.0).tan();
    assert!((hc - 2.23).abs() < 0.01);
    let stands = face_displacement(0.5 * hc);
    assert!(stands < 0.02, "a cut of H_c/2 moved {stands:.3} m");
    let fails = face_displacement(2.0 * hc);
    assert!(fails > 0.3, "a cut of 2 H_c moved only {fails:.3} m");
}
