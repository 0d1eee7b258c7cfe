//! Friction check against the infinite-slope limit of a cohesionless soil: a slope
//! stands when its angle β < φ and slides when β > φ (Mohr–Coulomb; the plane-strain
//! Drucker–Prager constants of Eq. (6) match it). Starting from the level-ground K0
//! stress, a pile 4° below φ adjusts and comes to rest; a pile 4° above keeps flowing
//! (speeds over the last 0.1 s of 0.6 s).

use granmix_tests::run_text;

fn max_speed_late(slope_deg: f64, phi: f64) -> f64 {
    let len = 0.3;
    let h = len * slope_deg.to_radians().tan();
    let text = format!(
        r#"
[simulation]
dimension = 2
gravity = [0.0, -9.81]
end_time = 0.6
dp = 0.004
output_interval = 0.02

[[materials]]
name = "sand"
density = 2040.0
youngs_modulus = 5.84e6
poisson_ratio = 0.3
friction_angle = {phi}

[[regions]]
name = "pile"
material = "sand"
initial_stress = "geostatic"
shape = {{ type = "polygon", vertices = [[0.0, 0.0], [{len}, 0.0], [0.0, {h}]] }}

[[containers]]
name = "tank"
min = [0.0, 0.0]
max = [0.6, 0.3]
open = ["+x", "+y"]
"#
    );
    let mut late = 0.0f64;
    run_text(&text, "slope.toml", |s| {
        if s.time >= 0.5 {
            late = late.max(s.max_speed);
        }
    });
    late
}

#[test]
fn slope_stands_below_friction_angle_and_slides_above() {
    let phi = 21.9;
    let below = max_speed_late(phi - 4.0, phi);
    let above = max_speed_late(phi + 4.0, phi);
    assert!(
        below < 0.01,
        "a {:.1}° slope (φ = {phi}°) still moves at {below:.3} m/s",
        phi - 4.0
    );
    assert!(
        above > 0.1,
        "a {:.1}° slope (φ = {phi}°) only moves at {above:.3} m/s",
        phi + 4.0
    );
}
