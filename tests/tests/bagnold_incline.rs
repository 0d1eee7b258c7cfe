//! Steady flow down an incline with μ(I) (`bagnold_incline.toml`; docs/method.md §Soil
//! models): a layer H = 10 mm deep, periodic along the slope, of glass beads
//! (μ_s = 0.383, μ_2 = 0.643, I_0 = 0.279, d = 0.5 mm, ρ_s = 2500 kg/m³, φ = 0.6).
//! - At tan θ = 0.42 it reaches Bagnold's profile (GDR MiDi 2004; Jop, Forterre &
//!   Pouliquen 2006): I = I_θ = I_0 (tan θ − μ_s)/(μ_2 − tan θ) at every depth,
//!   u(z) = (2/3) I_θ √(φ g cos θ) (H^{3/2} − (H − z)^{3/2})/d. The depth-averaged
//!   velocity ū = (2/5) I_θ √(φ g cos θ) H^{3/2}/d and u at a quarter, half and three
//!   quarters of the depth within 3 % over 1.5–2 s (steady); the bed carries the
//!   layer's weight along the slope within 1 %.
//! - At tan θ = 0.35 < μ_s it does not flow: its mean velocity stays below 1 % of the
//!   flowing layer's.
//!
//! μ_s 1 % high slows the steady flow by 10 % (I_θ falls from 0.0463 to 0.0415), and a
//! wall that scaled a μ(I) particle's shear to the static cone let the layer slide on
//! its bed; both fail the first test. μ_s = 0.34 fails the second.

use granmix_core::run::simulation::Sample;
use granmix_tests::{rel, run};

const G: f64 = 9.81;
/// μ(I) of glass beads (Jop et al. 2006).
const MU_S: f64 = 0.383;
const MU_2: f64 = 0.643;
const I_0: f64 = 0.279;
/// Depth and period (m), grain diameter (m), solid fraction, bulk density (kg/m³).
const H: f64 = 0.01;
const L: f64 = 0.006;
const D: f64 = 5.0e-4;
const PHI: f64 = 0.6;
const RHO: f64 = 1500.0;

/// `simulation.gravity` of a slope tan θ = `t`: g (sin θ, −cos θ).
fn gravity(t: f64) -> String {
    let th = t.atan();
    format!("simulation.gravity=[{}, {}]", G * th.sin(), -G * th.cos())
}

/// Bagnold's u(z) on tan θ = `t`.
fn bagnold(t: f64, z: f64) -> f64 {
    let th = t.atan();
    let i = I_0 * (t - MU_S) / (MU_2 - t);
    (2.0 / 3.0) * i * (PHI * G * th.cos()).sqrt() * (H.powf(1.5) - (H - z).powf(1.5)) / D
}

/// Depth-averaged downslope velocity: the layer's momentum over its mass.
fn mean_velocity(s: &Sample) -> f64 {
    s.momentum[0] / (RHO * H * L)
}

/// Probe `name`'s downslope velocity.
fn probe(s: &Sample, name: &str) -> f64 {
    s.probes
        .iter()
        .find(|p| p.0 == name)
        .expect("probe")
        .1
        .velocity[0]
}

#[test]
fn mu_i_layer_reaches_bagnold_profile() {
    let t = 0.42;
    // steady from 1.5 s (the bench averages the scene's last second, to 2.5 s)
    let end = "simulation.end_time=2.0";
    let (samples, _, _) = run("bagnold_incline.toml", &[&gravity(t), end]);
    let steady: Vec<&Sample> = samples.iter().filter(|s| s.time >= 1.5 - 1e-9).collect();
    assert!(steady.len() >= 10, "{} samples after 1.5 s", steady.len());
    let avg =
        |f: &dyn Fn(&Sample) -> f64| steady.iter().map(|s| f(s)).sum::<f64>() / steady.len() as f64;
    // ū: the mean of u(z) over the depth, (3/5) u(H)
    let u_bar = avg(&mean_velocity);
    let u_ref = 0.6 * bagnold(t, H);
    eprintln!("ū = {u_bar:.5} m/s, Bagnold's {u_ref:.5} m/s");
    assert!(
        rel(u_bar, u_ref) < 0.03,
        "ū = {u_bar:.5} m/s against Bagnold's {u_ref:.5} m/s ({:+.2} %)",
        100.0 * (u_bar / u_ref - 1.0)
    );
    for (name, z) in [
        ("quarter", 0.25 * H),
        ("half", 0.5 * H),
        ("three_quarters", 0.75 * H),
    ] {
        let (u, u_ref) = (avg(&|s| probe(s, name)), bagnold(t, z));
        eprintln!("u({name}) = {u:.5} m/s, Bagnold's {u_ref:.5} m/s");
        assert!(
            rel(u, u_ref) < 0.03,
            "u({:.2} mm) = {u:.5} m/s against Bagnold's {u_ref:.5} m/s",
            z * 1e3
        );
    }
    let weight = RHO * G * t.atan().sin() * H * L;
    // the layer drags its bed downslope
    let base = avg(&|s| {
        s.barriers
            .iter()
            .find(|b| b.name == "bed.bottom")
            .expect("bed")
            .force[0]
    });
    eprintln!("base shear {base:.5} N/m, weight along the slope {weight:.5} N/m");
    assert!(
        rel(base, weight) < 0.01,
        "base shear {base:.5} N/m against the weight along the slope {weight:.5} N/m"
    );
}

#[test]
fn mu_i_layer_rests_below_mu_s() {
    let end = "simulation.end_time=0.5";
    let (samples, _, _) = run("bagnold_incline.toml", &[&gravity(0.35), end]);
    let flowing = 0.6 * bagnold(0.42, H);
    let fastest = samples
        .iter()
        .map(mean_velocity)
        .fold(0.0_f64, |a, u| a.max(u.abs()));
    eprintln!("tan θ = 0.35: fastest mean velocity {fastest:.2e} m/s");
    assert!(
        fastest < 0.01 * flowing,
        "on tan θ = 0.35 < μ_s the layer moves at up to {fastest:.2e} m/s, against \
         {flowing:.4} m/s flowing on tan θ = 0.42"
    );
}
