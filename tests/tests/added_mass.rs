//! The added mass of a body released in still water (issue 42): its own module, whose
//! name sorts first, so that one of the longer water tests starts with the suite.

use granmix_core::run::simulation::Sample;
use granmix_tests::run;

const RHO: f64 = 1000.0;
const G: f64 = 9.81;

/// A disc of ρ_w/2 released from rest at mid-depth of `boulder_in_water.toml` starts
/// rising with (ρ_w − ρ_b) g/(ρ_b + C_a ρ_w). C_a is the potential-flow added mass of a
/// circle in this tank, rigid sides and floor 6 R away and the free surface 6 R above
/// (φ = 0 there at an impulsive start): 1.046765, from a boundary-element solution
/// (docs/method.md §Water; 1 unbounded). Its mean acceleration over its first R/10 of
/// travel, with the water filled to the body's true surface ([`water_at_bodies`]): +1.2 %,
/// −2.0 % and −0.9 % at R/dp = 10, 20 and 40. Filled half a spacing off the surface, as
/// before, the disc displaced more than its volume and read +22 %, +13 % and +5.8 %.
/// Tested at R/dp = 10 within issue 42's 5 %; R/dp = 20 (the resolution the issue asks,
/// eight times the cost) and 40 are the bench's: `granmix bench --case rising_disc`.
///
/// [`water_at_bodies`]: granmix_core::world::water_at_bodies
#[test]
fn rising_disc_starts_with_the_added_mass() {
    let (r, rho_b) = (0.05, 500.0);
    let want = (RHO - rho_b) * G / (rho_b + 1.046765 * RHO);
    let n = 10.0;
    let dp = format!("simulation.dp={}", r / n);
    let (samples, _, _) = run("boulder_in_water.toml", &[&dp, "simulation.end_time=0.065"]);
    let y0 = samples[0].bodies[0].position[1];
    let goal = 0.1 * r;
    let k = samples
        .iter()
        .position(|s| s.bodies[0].position[1] - y0 >= goal)
        .expect("the disc rose R/10");
    let (a, b) = (&samples[k - 1], &samples[k]);
    let (da, db) = (a.bodies[0].position[1] - y0, b.bodies[0].position[1] - y0);
    let t = a.time + (goal - da) / (db - da) * (b.time - a.time);
    let accel = 2.0 * goal / (t * t);
    let err = accel / want - 1.0;
    assert!(
        err.abs() < 0.05,
        "R/dp = {n}: mean acceleration {accel:.4} m/s² against {want:.4} m/s² ({:+.2} %)",
        100.0 * err
    );
}

/// A disc of 2 ρ_w resting on the floor of `disc_resting_in_water.toml` (a 0.3 m wide
/// tank under 0.25 m of water; released 0.1 dp above the floor, the water's settling
/// phase over its first 0.2 s): its contact force is its weight less its
/// buoyancy, W − ρ_w g V, within issue 42's 2 % as the mean over 0.25–0.35 s, at R/dp = 10
/// (R/dp = 20, eight times the cost, is the bench's `resting_disc`). Measured: −0.15 % and
/// −0.11 % at R/dp = 10 and 20 (in the scene's own 0.6 m tank, over 1.0–1.2 s:
/// −0.8 % at both). Without the water in the contact's gap ([`water_buoyancy`],
/// [`gap_water`]) it read 260–290 N/m against 77 N/m: no water particle fits under the
/// disc where the gap is narrower than a spacing. With the water filled half a spacing off
/// the disc it read −1.6 % (and −4.9 % at R/dp = 20); leaving the film's pressure in gave
/// −7 %, leaving the gap's water out altogether +240 %.
///
/// [`water_buoyancy`]: granmix_core::interactions::water_buoyancy
/// [`gap_water`]: granmix_core::interactions::gap_water
#[test]
fn resting_disc_keeps_its_buoyancy() {
    let (r, rho_b) = (0.05_f64, 2000.0);
    let vol = std::f64::consts::PI * r * r;
    let want = (rho_b - RHO) * G * vol;
    // the scene as it stands: R/dp = 10, the centre 0.1 dp above y = R
    let n = 10.0;
    let (samples, _, _) = run("disc_resting_in_water.toml", &[]);
    let (mean, err) = mean_contact(&samples, 0.25, 1, want);
    assert!(
        err.abs() < 0.02,
        "R/dp = {n}: contact force {mean:.2} N/m over 0.25–0.35 s against \
         W − ρ_w g V = {want:.2} N/m ({:+.2} %)",
        100.0 * err
    );
}

/// A sphere of 2 ρ_w resting on the floor of a 0.14 m square tank under 0.12 m of water
/// (`sphere_in_water.toml` made smaller; R/dp = 10, released 0.1 dp above the floor,
/// the water's settling phase over its first 0.1 s): its contact force is its weight
/// less its buoyancy, W − ρ_w g V = 5.137 N, within issue 42's 2 % as the mean over
/// 0.125–0.2 s. Measured: +0.14 % (in a 0.16 m tank, 0.25–0.35 s: ±0.06 %). Without the
/// water in the contact's gap ([`water_buoyancy`]) it read 22 % high (in a 0.2 m tank
/// under 0.15 m of water).
///
/// [`water_buoyancy`]: granmix_core::interactions::water_buoyancy
#[test]
fn resting_sphere_keeps_its_buoyancy() {
    let (r, rho_b, dp) = (0.05_f64, 2000.0, 0.005);
    let centre = format!("bodies.0.shape.center=[0.07,0.07,{}]", r + 0.1 * dp);
    let set = [
        "solids.0.density=2000",
        "water.regions.0.shape.max=[0.14,0.14,0.12]",
        "containers.0.max=[0.14,0.14,0.2]",
        "water.settle_time=0.1",
        "simulation.end_time=0.2",
        "simulation.output_interval=0.025",
        &centre,
    ];
    let (samples, _, _) = run("sphere_in_water.toml", &set);
    let vol = 4.0 / 3.0 * std::f64::consts::PI * r.powi(3);
    let want = (rho_b - RHO) * G * vol;
    let (mean, err) = mean_contact(&samples, 0.125, 2, want);
    assert!(
        err.abs() < 0.02,
        "contact force {mean:.4} N over 0.125–0.2 s against W − ρ_w g V = {want:.4} N \
         ({:+.2} %)",
        100.0 * err
    );
}

/// The mean contact force along `axis` on the first body (its force less the water's and
/// the grains') over the samples from `from` on, and its relative error against `want`.
fn mean_contact(samples: &[Sample], from: f64, axis: usize, want: f64) -> (f64, f64) {
    let window: Vec<f64> = samples
        .iter()
        .filter(|s| s.time >= from - 1e-9)
        .map(|s| {
            let b = &s.bodies[0];
            b.force[axis] - b.water_force[axis] - b.fine_force[axis]
        })
        .collect();
    assert!(window.len() >= 4, "{} samples from {from} s", window.len());
    let mean = window.iter().sum::<f64>() / window.len() as f64;
    (mean, mean / want - 1.0)
}
