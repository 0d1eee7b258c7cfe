//! The added mass of a body released in still water (issue 42): its own module, whose
//! name sorts first, so that one of the longer water tests starts with the suite.

use granmix_tests::run;

const RHO: f64 = 1000.0;
const G: f64 = 9.81;

/// A disc of ρ_w/2 released from rest at mid-depth of `boulder_in_water.toml` starts
/// rising with (ρ_w − ρ_b) g/(ρ_b + C_a ρ_w), C_a = 1 (a circle in potential flow).
/// Its mean acceleration over its first R/10 of travel converges to it from above, about
/// first order in dp/R: +18.2 %, +9.5 % and +2.6 % at R/dp = 10, 20 and 40
/// (docs/method.md §Water). Tested at R/dp = 10 and 20: above the reference at both, the
/// error at R/dp = 20 under 10 % and at most 0.6 of the error at R/dp = 10 (first order
/// halves it). The 5 % at R/dp = 40 (five minutes) is the bench's: `granmix bench --case
/// rising_disc`.
#[test]
fn rising_disc_starts_with_the_added_mass() {
    let (r, rho_b) = (0.05, 500.0);
    let want = (RHO - rho_b) * G / (rho_b + RHO);
    let [coarse, fine] = [10.0, 20.0].map(|n| {
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
        2.0 * goal / (t * t)
    });
    let (e10, e20) = (coarse / want - 1.0, fine / want - 1.0);
    assert!(
        e10 > 0.0 && e20 > 0.0 && e20 < 0.10 && e20 <= 0.6 * e10,
        "mean acceleration {coarse:.4} and {fine:.4} m/s² at R/dp = 10 and 20 against \
         {want:.4} m/s² ({:+.2} %, {:+.2} %)",
        100.0 * e10,
        100.0 * e20
    );
}

/// A disc of 2 ρ_w resting on the floor of `boulder_in_water.toml` (R/dp = 10, released
/// 0.1 dp above it, the water's settling phase over its first 0.5 s): its contact force
/// is its weight less its buoyancy, W − ρ_w g V. Without the water in the contact's gap
/// ([`water_buoyancy`], [`gap_water`]) it read 260–290 N/m against 77 N/m: no water
/// particle fits under the disc where the gap is narrower than a spacing. Measured with
/// it, as the mean over 1.0–1.2 s: −1.3 to −1.8 % at R/dp = 10 and −3.7 to −4.9 % at
/// R/dp = 20 (docs/method.md §Water), so the test asks for 5 % at R/dp = 10; the 2 % of
/// issue 42 is not met yet. Leaving the film's pressure in gives −7 %, leaving the gap's
/// water out altogether +240 %.
///
/// [`water_buoyancy`]: granmix_core::interactions::water_buoyancy
/// [`gap_water`]: granmix_core::interactions::gap_water
#[test]
fn resting_disc_keeps_its_buoyancy() {
    let (r, rho_b, dp) = (0.05_f64, 2000.0, 0.005);
    let centre = format!("bodies.0.shape.center=[0.3,{}]", r + 0.1 * dp);
    let set = [
        "solids.0.density=2000",
        "water.settle_time=0.5",
        "simulation.end_time=1.2",
        "simulation.output_interval=0.05",
        &centre,
    ];
    let (samples, _, _) = run("boulder_in_water.toml", &set);
    let vol = std::f64::consts::PI * r * r;
    let want = (rho_b - RHO) * G * vol;
    let window: Vec<f64> = samples
        .iter()
        .filter(|s| s.time >= 1.0 - 1e-9)
        .map(|s| {
            let b = &s.bodies[0];
            b.force[1] - b.water_force[1] - b.fine_force[1]
        })
        .collect();
    assert!(window.len() >= 4, "{} samples over 1.0–1.2 s", window.len());
    let mean = window.iter().sum::<f64>() / window.len() as f64;
    let err = mean / want - 1.0;
    assert!(
        err.abs() < 0.05,
        "contact force {mean:.2} N/m against W − ρ_w g V = {want:.2} N/m ({:+.2} %)",
        100.0 * err
    );
}
