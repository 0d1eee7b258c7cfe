//! The stability guard stops a run with a diagnostic instead of producing NaNs.

use granmix_core::run::runner::{self, RunEnd};
use granmix_core::AnySimulation;
use granmix_tests::load;

#[test]
fn speed_bound_stops_with_diagnostic() {
    let loaded = load(
        "column_collapse_2d.toml",
        &["simulation.dp=0.01", "simulation.max_speed=0.2"],
    );
    let mut sim = AnySimulation::new(&loaded).unwrap();
    let end = runner::run(&mut sim, &loaded.scene.simulation, |_, _| true, |_| {});
    let RunEnd::Blowup(b) = end else {
        panic!("expected the guard to stop the run, got {end:?}")
    };
    assert_eq!(b.quantity, "speed");
    assert!(b.value > 0.2 && b.limit == Some(0.2));
    assert!(b.step > 0 && b.time > 0.0 && b.position.len() == 2);
    let msg = b.to_string();
    assert!(
        msg.contains("simulation.max_speed") && msg.contains(&format!("particle {}", b.particle)),
        "{msg}"
    );
}

#[test]
fn non_finite_state_stops_with_diagnostic() {
    // A CFL far beyond the stable limit makes the explicit scheme diverge; the run must
    // stop at the first non-finite or runaway value, never hand back NaN.
    let loaded = load(
        "column_collapse_2d.toml",
        &[
            "simulation.dp=0.01",
            "simulation.cfl=1.0",
            "simulation.max_speed=1e30",
        ],
    );
    let mut loaded = loaded;
    loaded.scene.simulation.cfl = 8.0; // bypasses the scene check on purpose
    let mut sim = AnySimulation::new(&loaded).unwrap();
    let end = runner::run(
        &mut sim,
        &loaded.scene.simulation,
        |_, s| s.kinetic_energy.is_finite(),
        |_| {},
    );
    match end {
        RunEnd::Blowup(b) => {
            let known = ["velocity", "position", "density", "stress", "speed"];
            assert!(
                known.contains(&b.quantity.as_str())
                    || b.quantity == granmix_core::numerics::guard::DENSITY_CHANGE,
                "{b}"
            )
        }
        other => panic!("expected a blow-up diagnostic, got {other:?}"),
    }
}

/// A boulder launched faster than `simulation.max_speed` is rejected by the scene
/// check; one that only exceeds it in flight stops the run with the speed diagnostic,
/// naming the body.
#[test]
fn runaway_boulder_stops_with_diagnostic() {
    let loaded = load(
        "stability_impact_2d.toml",
        &[
            "simulation.dp=0.008",
            "bodies.0.shape.center=[0.15, 0.18]",
            "bodies.0.velocity=[0.0, -90.0]",
        ],
    );
    let too_fast = granmix_core::input::load_scene_file(
        &granmix_tests::scene_path("stability_impact_2d.toml"),
        &["bodies.0.velocity=[0.0, -150.0]".to_string()],
    )
    .expect_err("a boulder faster than max_speed must be rejected");
    assert!(
        too_fast.to_string().contains("bodies[0].velocity")
            && too_fast.to_string().contains("max_speed"),
        "{too_fast}"
    );
    let mut loaded = loaded;
    loaded.scene.simulation.max_speed = 50.0; // below the launch speed, past the check
    let mut sim = AnySimulation::new(&loaded).unwrap();
    let end = runner::run(&mut sim, &loaded.scene.simulation, |_, _| true, |_| {});
    let RunEnd::Blowup(b) = end else {
        panic!("expected the guard to stop the run, got {end:?}")
    };
    assert_eq!(b.quantity, "speed");
    assert_eq!(b.body.as_deref(), Some("disc"));
    assert_eq!(b.limit, Some(50.0));
    assert!(b.to_string().contains("body `disc`"), "{b}");
}

/// A wall object sent to infinity stops the run with a diagnostic naming it (issue 38:
/// a barrier driven with an infinite velocity was lost while every step reported OK
/// with a zero load). The FMU refuses such a command before stepping; here it is
/// applied directly, as a bug in a front could.
#[test]
fn a_wall_sent_to_infinity_stops_the_run() {
    for v in [f64::INFINITY, f64::NAN, 150.0] {
        let loaded = load("fmu_barrier_2d.toml", &[]);
        let mut sim = AnySimulation::new(&loaded).unwrap();
        sim.drive_barrier(0, [v, 0.0, 0.0]).unwrap();
        let Err(b) = sim.advance_to(1e-3) else {
            panic!("a barrier at {v} m/s passed the guard")
        };
        let msg = b.to_string();
        assert!(msg.contains("wall object `barrier`"), "{msg}");
        let quantity = if v.is_finite() { "speed" } else { "velocity" };
        assert_eq!(b.quantity, quantity, "{msg}");
    }
}

/// A barrier's prescribed motion enters Δt: no wall moves more than CFL·h per step
/// (the driven barrier of fmu_barrier_2d at 200 m/s: CFL·h/|v| = 0.4 · 0.013 / 200).
#[test]
fn a_moving_wall_bounds_the_time_step() {
    let loaded = load("fmu_barrier_2d.toml", &[]);
    let mut sim = AnySimulation::new(&loaded).unwrap();
    let at_rest = sim.stable_dt();
    sim.drive_barrier(0, [200.0, 0.0, 0.0]).unwrap();
    let moving = sim.stable_dt();
    let bound = 0.4 * 1.3 * 0.01 / 200.0;
    assert!(at_rest > 2.0 * bound, "{at_rest}");
    assert!(
        (moving - bound).abs() <= 1e-12 * bound,
        "{moving} against {bound}"
    );
}
