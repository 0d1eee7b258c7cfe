//! VALIDATION.md §5: a rigid block on an inclined plane (seed 004 §3.2).
//! s(t) = ½ g (sin θ − μ cos θ) t², v(t) = g (sin θ − μ cos θ) t within 1 %; no creep
//! when μ ≥ tan θ.

use granmix_core::run::simulation::Sample;
use granmix_tests::{rel, run};

const THETA_DEG: f64 = 30.0;

/// Downhill displacement and speed of the block's centre of mass.
fn downhill(samples: &[Sample]) -> (f64, f64, f64) {
    let t = THETA_DEG.to_radians();
    let d = [t.cos(), 0.0, -t.sin()];
    let (b0, b) = (&samples[0].bodies[0], &samples.last().unwrap().bodies[0]);
    let s: f64 = (0..3)
        .map(|k| (b.position[k] - b0.position[k]) * d[k])
        .sum();
    let v: f64 = (0..3).map(|k| b.velocity[k] * d[k]).sum();
    (samples.last().unwrap().time, s, v)
}

fn analytic(mu: f64, t: f64) -> (f64, f64) {
    let th = THETA_DEG.to_radians();
    let a = 9.81 * (th.sin() - mu * th.cos());
    (0.5 * a * t * t, a * t)
}

#[test]
fn sliding_block_matches_analytic_motion() {
    for mu in [0.1, 0.3, 0.5] {
        let set = format!("contact.friction={mu}");
        let (samples, _, _) = run("incline_block.toml", &[&set, "simulation.end_time=0.3"]);
        let (t, s, v) = downhill(&samples);
        let (s_ref, v_ref) = analytic(mu, t);
        assert!(
            rel(s, s_ref) < 0.01 && rel(v, v_ref) < 0.01,
            "μ = {mu}: s = {s:.6} m vs {s_ref:.6} m, v = {v:.6} m/s vs {v_ref:.6} m/s"
        );
    }
}

#[test]
fn block_sticks_when_friction_exceeds_slope() {
    // μ = 0.7 > tan 30° = 0.577: only the elastic tangential spring may yield, once.
    let (samples, _, _) = run(
        "incline_block.toml",
        &["contact.friction=0.7", "simulation.end_time=0.3"],
    );
    let (_, s, v) = downhill(&samples);
    let (_, s_mid, _) = downhill(&samples[..samples.len() / 2]);
    assert!(s.abs() < 1e-5, "block crept {s:e} m");
    assert!(
        (s - s_mid).abs() < 1e-9,
        "creep between t/2 and t: {:e} m",
        s - s_mid
    );
    assert!(v.abs() < 1e-6, "block moves at {v:e} m/s");
}
