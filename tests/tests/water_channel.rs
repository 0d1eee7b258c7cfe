//! Poiseuille flow between plates, periodic along the channel (seed 001 §2.1, its
//! parameters; `models/scenes/poiseuille_2d.toml`): the velocity profile against the
//! transient series solution of Morris, Fox & Zhu (1997), and the plates' load against
//! the wall shear of the same solution.

use granmix_core::AnySimulation;
use granmix_tests::{load, refusal, rel};

const A: f64 = 1e-4;
const H: f64 = 0.1;
const NU: f64 = 1e-4;
const RHO: f64 = 1000.0;
const L: f64 = 0.1;

/// u(y, t), seed 001 Eq. (28).
fn u_exact(y: f64, t: f64) -> f64 {
    let mut u = A / (2.0 * NU) * y * (H - y);
    for n in 0..200 {
        let k = (2 * n + 1) as f64;
        let pi = std::f64::consts::PI;
        u -= 4.0 * A * H * H / (NU * pi.powi(3) * k.powi(3))
            * (pi * y * k / H).sin()
            * (-k * k * pi * pi * NU * t / (H * H)).exp();
    }
    u
}

/// The shear load on one plate, seed 001 Eq. (31) at y = 0, per metre of depth.
fn plate_force(t: f64) -> f64 {
    let pi = std::f64::consts::PI;
    let mut f = RHO * A * H * L / 2.0;
    for n in 0..5000 {
        let k = (2 * n + 1) as f64;
        f -=
            4.0 * RHO * A * H * L / (pi * pi * k * k) * (-k * k * pi * pi * NU * t / (H * H)).exp();
    }
    f
}

/// Relative L2 error of the particles' u_x against Eq. (28) at time t.
fn profile_error(sim: &AnySimulation, t: f64) -> f64 {
    let frame = sim.frame();
    let (mut num, mut den) = (0.0, 0.0);
    for p in &frame.water {
        let want = u_exact(p.position[1] as f64, t);
        num += (p.velocity[0] as f64 - want).powi(2);
        den += want * want;
    }
    (num / den).sqrt()
}

/// At H/40 (the seed's resolution): the profile within 3 % (relative L2) at t = 5, 10
/// and 20 s and within 2 % at steady state (t = 80 s); the centreline velocity within
/// 0.4 % at each (0.21 % measured; 0.72 % with the walls clamped to push only, which
/// water without a free surface is not); each plate's load, averaged
/// over the last second as the series reports it, within 2 % of Eq. (31) averaged
/// the same way. The check fails with the viscosity 5 % off.
#[test]
fn poiseuille_flow_follows_the_series_solution() {
    for (viscosity, must_pass) in [(0.1, true), (0.105, false)] {
        let mu = format!("water.viscosity={viscosity}");
        let loaded = load("poiseuille_2d.toml", &[mu.as_str()]);
        let mut sim = AnySimulation::new(&loaded).unwrap_or_else(|e| panic!("{e}"));
        let mut report = Vec::new();
        let mut ok = true;
        for (t, tol) in [(5.0, 0.03), (10.0, 0.03), (20.0, 0.03), (80.0, 0.02)] {
            sim.advance_to(t - 1.0).unwrap();
            sim.sample();
            sim.advance_to(t).unwrap();
            let e = profile_error(&sim, t);
            let s = sim.sample();
            let want = (0..400)
                .map(|k| plate_force(t - 1.0 + (k as f64 + 0.5) / 400.0))
                .sum::<f64>()
                / 400.0;
            for b in &s.barriers {
                let f = b.force_water[0];
                report.push(format!("t={t} {}: {f:.5e} vs {want:.5e}", b.name));
                ok &= rel(f, want) < 0.02 && f == b.force[0];
            }
            report.push(format!("t={t}: L2 {:.3} %", 100.0 * e));
            ok &= e < tol;
            // the probe at the centreline: 0.21 % at worst; 0.72 % with the walls'
            // no-tension clamp, which a channel without a free surface must not take
            let u = s
                .probes
                .iter()
                .find(|p| p.0 == "centre")
                .and_then(|p| p.1.water_velocity)
                .expect("probe centre")[0];
            let ec = rel(u, u_exact(0.5 * H, s.time));
            report.push(format!("t={t}: centreline {:.3} %", 100.0 * ec));
            ok &= ec < 0.004;
        }
        assert_eq!(ok, must_pass, "μ = {viscosity}: {report:#?}");
    }
}

/// A period that is not a whole number of spacings, one under three list radii, an
/// axis the scene lacks, soil beside water in a periodic scene, a container closed across the
/// axis, and water outside the period are refused, naming the key.
#[test]
fn bad_periodic_input_names_the_key() {
    let scene = std::fs::read_to_string(granmix_tests::scene_path("poiseuille_2d.toml")).unwrap();
    let periodic = "periodic = { axis = \"x\", min = 0.0, max = 0.1 }";
    assert!(scene.contains(periodic));
    let with = |p: &str| scene.replace(periodic, p);
    for (text, key, words) in [
        (
            with("periodic = { axis = \"x\", min = 0.0, max = 0.101 }"),
            "`simulation.periodic.max`",
            "whole number",
        ),
        (
            with("periodic = { axis = \"x\", min = 0.09, max = 0.1 }"),
            "`simulation.periodic.max`",
            "three neighbour-list radii",
        ),
        (
            with("periodic = { axis = \"z\", min = 0.0, max = 0.1 }"),
            "`simulation.periodic.axis`",
            "2D scene",
        ),
        (
            scene.replace("open = [\"-x\", \"+x\"]", "open = [\"-x\"]"),
            "`containers[0].open`",
            "\"+x\"",
        ),
        (
            scene.replace("max = [0.1, 0.1] }", "max = [0.12, 0.1] }"),
            "`simulation.periodic`",
            "outside the period",
        ),
        (
            format!(
                "{scene}\n[[materials]]\nname = \"sand\"\ndensity = 2000.0\nfriction_angle = 30.0\n\
                 youngs_modulus = 1e6\npoisson_ratio = 0.3\n[[regions]]\nname = \"bed\"\nmaterial = \"sand\"\n\
                 shape = {{ type = \"box\", min = [0.0, 0.0], max = [0.1, 0.01] }}\n"
            ),
            "`regions`",
            "not both together",
        ),
    ] {
        let e = refusal(&text);
        assert!(e.contains(key) && e.contains(words), "{key}: {e}");
    }
}
