//! The added mass of a body released in still water (issue 42). The longest water test
//! (R/dp = 40, about five minutes): its own module, whose name sorts first, so that it
//! starts with the suite instead of last.

use granmix_tests::{rel, run};

const RHO: f64 = 1000.0;
const G: f64 = 9.81;

/// A disc of ρ_w/2 released from rest at mid-depth of `boulder_in_water.toml` starts
/// rising with (ρ_w − ρ_b) g/(ρ_b + C_a ρ_w), C_a = 1 (a circle in potential flow):
/// its mean acceleration over its first R/10 of travel, at R/dp = 40, within 5 %.
/// Coarser, the error is first order in dp/R (+18 %, +9.5 %, +2.6 % at R/dp = 10, 20,
/// 40; docs/method.md §Water).
#[test]
fn rising_disc_starts_with_the_added_mass() {
    let (r, rho_b) = (0.05, 500.0);
    let want = (RHO - rho_b) * G / (rho_b + RHO);
    let (samples, _, _) = run(
        "boulder_in_water.toml",
        &["simulation.dp=0.00125", "simulation.end_time=0.06"],
    );
    let y0 = samples[0].bodies[0].position[1];
    let goal = 0.1 * r;
    let k = samples
        .iter()
        .position(|s| s.bodies[0].position[1] - y0 >= goal)
        .expect("the disc rose R/10");
    let (a, b) = (&samples[k - 1], &samples[k]);
    let (da, db) = (a.bodies[0].position[1] - y0, b.bodies[0].position[1] - y0);
    let t = a.time + (goal - da) / (db - da) * (b.time - a.time);
    let acc = 2.0 * goal / (t * t);
    assert!(
        rel(acc, want) < 0.05,
        "mean acceleration {acc:.3} m/s² against {want:.3} m/s²"
    );
}
