//! The water family (docs/method.md §Water): the resting tank against hydrostatics, the
//! 2D dam break against Martin & Moyce (1952), exact momentum exchange between water
//! particles, and bad `[water]` input.

use granmix_core::input::load_scene_str;
use granmix_core::AnySimulation;
use granmix_tests::{build_text, load, rel, run, run_built};

const RHO: f64 = 1000.0;
const G: f64 = 9.81;

/// `hydrostatic_tank.toml` (H = 0.5 m, dp = 0.01 m) settled for 3 s: below the top two
/// layers every particle's pressure lies within 1 % of ρ_w g (H − z), each side wall
/// carries ½ ρ_w g H² within 1 % (all of it water), and the floor the water's weight.
#[test]
fn resting_tank_is_hydrostatic() {
    let (h, dp) = (0.5, 0.01);
    let (samples, _, sim) = run("hydrostatic_tank.toml", &["simulation.end_time=3.0"]);
    let frame = sim.frame();
    let mut worst: f64 = 0.0;
    for p in &frame.water {
        let z = p.position[1] as f64;
        if z < h - 2.0 * dp {
            let want = RHO * G * (h - z);
            worst = worst.max(rel(p.pressure as f64, want));
        }
    }
    assert!(
        worst < 0.01,
        "pressure off hydrostatic by {:.3} %",
        100.0 * worst
    );
    // loads averaged over the last 0.5 s
    let tail: Vec<_> = samples.iter().filter(|s| s.time > 2.5).collect();
    let mean = |b: usize, k: usize, water: bool| {
        tail.iter()
            .map(|s| {
                let bs = &s.barriers[b];
                if water {
                    bs.force_water[k]
                } else {
                    bs.force[k]
                }
            })
            .sum::<f64>()
            / tail.len() as f64
    };
    let names: Vec<_> = samples[0].barriers.iter().map(|b| b.name.clone()).collect();
    let side = 0.5 * RHO * G * h * h;
    let mass: f64 = {
        let loaded = load("hydrostatic_tank.toml", &[]);
        let sim = AnySimulation::new(&loaded).unwrap();
        sim.frame()
            .water_density
            .iter()
            .map(|&r| r as f64 * dp * dp)
            .sum()
    };
    for (b, name) in names.iter().enumerate() {
        let (k, want) = match name.as_str() {
            "tank.left" => (0, -side),
            "tank.right" => (0, side),
            "tank.bottom" => (1, -mass * G),
            _ => continue,
        };
        let (f, fw) = (mean(b, k, false), mean(b, k, true));
        assert!(rel(f, want) < 0.01, "{name}: {f:.2} N/m vs {want:.2} N/m");
        assert_eq!(f, fw, "{name}: the load is all water");
    }
}

/// Martin & Moyce (1952) Table 2, n² = 2: Z = x/a against T = t √(2g/a).
const MM_T: [f64; 13] = [
    0.41, 0.84, 1.19, 1.43, 1.63, 1.83, 1.98, 2.20, 2.32, 2.51, 2.65, 2.83, 2.98,
];
const MM_Z: [f64; 13] = [
    1.11, 1.22, 1.44, 1.67, 1.89, 2.11, 2.33, 2.56, 2.78, 3.00, 3.22, 3.44, 3.67,
];

/// The surge front of `dam_break_2d.toml` (a/40) against Martin & Moyce within 5 % for
/// 2 ≤ T ≤ 3. Earlier the front leads the experiment by up to 10 % (docs/method.md
/// §Water: the gate of the experiment, and every resolution leads there).
#[test]
fn dam_break_front_follows_martin_and_moyce() {
    let a = 0.05715;
    let (samples, _, _) = run("dam_break_2d.toml", &[]);
    let t: Vec<f64> = samples
        .iter()
        .map(|s| s.time * (2.0 * G / a).sqrt())
        .collect();
    let z: Vec<f64> = samples
        .iter()
        .map(|s| s.water.as_ref().unwrap().front / a)
        .collect();
    let at = |tt: f64| {
        let k = t.iter().position(|&x| x >= tt).unwrap();
        let f = (tt - t[k - 1]) / (t[k] - t[k - 1]);
        z[k - 1] + f * (z[k] - z[k - 1])
    };
    for (tm, zm) in MM_T.iter().zip(MM_Z) {
        if *tm >= 1.98 {
            let zs = at(*tm);
            assert!(rel(zs, zm) < 0.05, "T = {tm}: Z = {zs:.3} vs {zm}");
        }
    }
}

const BLOB: &str = r#"
[simulation]
dimension = 2
gravity = [0.0, 0.0]
end_time = 0.04
dp = 0.01
output_interval = 0.005

[water]
speed_scale = 1.0

[[water.regions]]
name = "a"
shape = { type = "box", min = [0.0, 0.0], max = [0.2, 0.2] }
velocity = [0.5, 0.0]

[[water.regions]]
name = "b"
shape = { type = "box", min = [0.21, 0.0], max = [0.41, 0.2] }
velocity = [-0.5, 0.3]
"#;

/// Two blocks of water collide without walls or gravity: every pair force is added to
/// both particles with opposite signs, so Σ m v stays what it was to round-off.
#[test]
fn water_pairs_conserve_momentum() {
    let (loaded, mut sim) = build_text(BLOB, "blob.toml");
    let (mut p, mut ke) = (Vec::new(), Vec::new());
    run_built(&loaded, &mut sim, |s| {
        let w = s.water.as_ref().unwrap();
        p.push(w.momentum);
        ke.push(w.kinetic_energy);
    });
    let scale: f64 = 400.0 * RHO * 1e-4 * 0.5;
    for m in &p {
        for k in 0..2 {
            assert!(
                (m[k] - p[0][k]).abs() < 1e-12 * scale,
                "{m:?} vs {:?}",
                p[0]
            );
        }
    }
    // the blocks did collide: a tenth of the kinetic energy went into compression
    let least = ke.iter().copied().fold(f64::INFINITY, f64::min);
    assert!(least < 0.9 * ke[0], "kinetic energy {ke:?}");
}

fn bad(text: &str) -> String {
    let err = match load_scene_str(text, "bad.toml", &[]) {
        Err(e) => e.to_string(),
        Ok(l) => match AnySimulation::new(&l) {
            Err(e) => e.to_string(),
            Ok(_) => panic!("accepted:\n{text}"),
        },
    };
    err
}

/// A negative viscosity and a sound speed below the expected flow speed (given, or
/// derived from the water's height) are refused with the key and its line.
#[test]
fn bad_water_input_names_key_and_line() {
    let tank = std::fs::read_to_string(granmix_tests::scene_path("hydrostatic_tank.toml")).unwrap();
    let e = bad(&tank.replace("viscosity = 1.0e-3", "viscosity = -1.0e-3"));
    assert!(
        e.contains("bad.toml:") && e.contains("`water.viscosity`") && e.contains("≥ 0"),
        "{e}"
    );
    // √(2 g H) = 3.13 m/s for H = 0.5 m
    let e = bad(&tank.replace(
        "viscosity = 1.0e-3",
        "viscosity = 1.0e-3\nsound_speed = 2.0",
    ));
    assert!(
        e.contains("`water.sound_speed`") && e.contains("below the expected flow speed"),
        "{e}"
    );
    assert!(e.contains("bad.toml:1"), "{e}");
    let e = bad(&tank.replace(
        "viscosity = 1.0e-3",
        "viscosity = 1.0e-3\nsound_speed = 20.0\nspeed_scale = 30.0",
    ));
    assert!(
        e.contains("`water.sound_speed`") && e.contains("300"),
        "{e}"
    );
    let e = bad(&tank.replace(
        "[[water.regions]]\nname = \"water\"",
        "[[water.regionz]]\nname = \"water\"",
    ));
    assert!(e.contains("regionz"), "{e}");
}

const DISC: &str = r#"
[simulation]
dimension = 2
gravity = [0.0, 0.0]
end_time = 0.05
dp = 0.005
output_interval = 0.005

[water]
speed_scale = 1.0

[[water.regions]]
name = "pool"
shape = { type = "box", min = [0.0, 0.0], max = [0.3, 0.3] }

[[solids]]
name = "rock"
density = 2000.0
youngs_modulus = 1e9
poisson_ratio = 0.25

[[bodies]]
name = "disc"
material = "rock"
model = "rigid"
shape = { type = "sphere", center = [0.15, 0.15], radius = 0.04 }
velocity = [0.8, 0.3]
"#;

/// A rigid disc driven through water with no walls and no gravity: what the water gives
/// the body over each step is what the body gives the water, so the total momentum of
/// water and body stays what it was to round-off (and the body does slow down).
#[test]
fn water_and_body_exchange_momentum_exactly() {
    let (loaded, mut sim) = build_text(DISC, "disc.toml");
    // the rigid body's own mass: its interior particles are trimmed, so the
    // particles' Σ m v (`Sample::momentum`) is not the body's momentum
    let mass = sim.body_summaries()[0].3;
    let mut rows = Vec::new();
    run_built(&loaded, &mut sim, |s| {
        let (w, v) = (s.water.as_ref().unwrap().momentum, s.bodies[0].velocity);
        rows.push(([w[0] + mass * v[0], w[1] + mass * v[1]], v[0]));
    });
    let scale = mass * 0.8;
    for (p, _) in &rows {
        for k in 0..2 {
            assert!(
                (p[k] - rows[0].0[k]).abs() < 1e-12 * scale,
                "total momentum {p:?} vs {:?}",
                rows[0].0
            );
        }
    }
    let (v0, v1) = (rows[0].1, rows.last().unwrap().1);
    assert!(
        v1 < 0.9 * v0,
        "the water did not slow the disc: {v0} → {v1} m/s"
    );
}
