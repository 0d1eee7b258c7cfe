//! The stability guard stops a run with a diagnostic instead of producing NaNs.

use granmix_core::runner::{self, RunEnd};
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
            assert!(["velocity", "position", "density", "stress", "speed"]
                .contains(&b.quantity.as_str()))
        }
        other => panic!("expected a blow-up diagnostic, got {other:?}"),
    }
}
