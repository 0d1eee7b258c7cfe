//! VALIDATION.md §8: soil–rock-mixture slope (seed 000 §6.1, Table 1). Friction between
//! rock and soil shortens the run-out: seed 004 and its ref. [15] (MPM–DEM) report it
//! for μ_cf = 1 against 0, which the test compares. Run at dp = 1 m, a quarter of the
//! rock size (the bundled scene uses seed 000's 0.5 m), with the same rock placement
//! (20 % rock, seed 1) for both runs; the run-out is the deposit front measured from the
//! toe.
//!
//! The fronts part from the start of the failure (m from the toe, μ_cf = 0 against 1):
//! 13 / 11 at 3 s, 19 / 15 at 3.5 s, 24 / 19 at 4 s (against 0.5: 24 / 20 at 4 s, 48 / 38
//! at 6 s, 80 / 59 at the scene's 10 s). Stopping at 3.5 s keeps a 21 % gap (the test
//! asks for 10 %) in 70 s; the 10 s deposits are `granmix run srm_slope.toml`'s.

use granmix_core::run::runner::RunEnd;
use granmix_tests::run;

fn runout(mu_cf: f64) -> f64 {
    let mu = format!("contact.mu_cf={mu_cf}");
    let (s, end, _) = run(
        "srm_slope.toml",
        &["simulation.dp=1.0", "simulation.end_time=3.5", &mu],
    );
    assert!(matches!(end, RunEnd::EndTime), "μ_cf = {mu_cf}: {end:?}");
    let last = s.last().expect("samples");
    assert!(
        last.runout > 10.0,
        "μ_cf = {mu_cf}: the slope should fail and run out past its toe, front at {} m",
        last.runout
    );
    last.runout
}

#[test]
fn coarse_fine_friction_shortens_the_runout() {
    // the two runs side by side, each on its own thread (granmix_tests::on_own_pool)
    let (smooth, rough) = std::thread::scope(|s| {
        let smooth = s.spawn(|| runout(0.0));
        let rough = runout(1.0);
        (smooth.join().expect("the μ_cf = 0 run"), rough)
    });
    eprintln!("run-out at 3.5 s, 20 % rock: {smooth} m (μ_cf = 0), {rough} m (μ_cf = 1)");
    // the two fronts differ by 4 m (19 and 15 m); a tenth of the smooth run-out is
    // above the dp = 1 m binning of the front
    assert!(
        rough < 0.9 * smooth,
        "μ_cf = 1 gives {rough} m, not clearly shorter than {smooth} m at μ_cf = 0"
    );
}
