//! A rigid block landing flat on a wall rebounds with the scene's coefficient of
//! restitution. With many particles touching at once, each contact's dashpot must
//! see its share of the body's mass: the linear spring–dashpot then gives exactly
//! v_out = e v_in (Cundall–Strack damping ratio from e), and never more energy out
//! than went in.

use granmix_tests::build_text;

fn rebound(restitution: f64, dimension: usize, cfl: f64) -> f64 {
    let (gravity, velocity, shape, wall) = if dimension == 2 {
        (
            "[0.0, 0.0]",
            "[0.0, -1.0]",
            "{ type = \"box\", min = [0.1, 0.004], max = [0.3, 0.104] }",
            "{ type = \"box\", min = [0.0, -0.05], max = [0.4, 0.0] }",
        )
    } else {
        (
            "[0.0, 0.0, 0.0]",
            "[0.0, 0.0, -1.0]",
            "{ type = \"box\", min = [0.1, 0.1, 0.004], max = [0.2, 0.2, 0.054] }",
            "{ type = \"box\", min = [0.0, 0.0, -0.05], max = [0.3, 0.3, 0.0] }",
        )
    };
    let text = format!(
        r#"
[simulation]
name = "landing"
dimension = {dimension}
gravity = {gravity}
end_time = 0.05
dp = 0.01
output_interval = 0.001
cfl_coarse = {cfl}

[[solids]]
name = "rock"
density = 2500.0
youngs_modulus = 1e8
poisson_ratio = 0.25

[[bodies]]
name = "block"
material = "rock"
model = "rigid"
shape = {shape}
velocity = {velocity}

[[walls]]
name = "floor"
shape = {wall}

[contact]
model = "spring-dashpot"
friction = 0.5
restitution = {restitution}
"#
    );
    let (_, mut sim) = build_text(&text, "landing.toml");
    let up = dimension - 1;
    let mut out: f64 = 0.0;
    for n in 1..=50 {
        sim.advance_to(n as f64 * 1e-3).expect("advance");
        let s = sim.sample();
        let b = &s.bodies[0];
        out = out.max(b.velocity[up]);
        assert!(
            b.velocity.iter().map(|v| v * v).sum::<f64>() <= 1.0 + 1e-9,
            "t = {}: the block left faster than it came ({:?})",
            s.time,
            b.velocity
        );
    }
    out
}

/// At the default coarse CFL (0.4: about 16 sub-steps per collision) the rebound is
/// within a few per cent of e, and the error falls at second order with the sub-step:
/// at CFL 0.1 it is within 0.5 % for any e.
#[test]
fn flat_landing_rebounds_with_the_restitution_coefficient() {
    for dimension in [2, 3] {
        for (e, tol) in [(0.1, 0.07), (0.5, 0.02), (0.9, 0.01)] {
            let v = rebound(e, dimension, 0.4);
            assert!(
                (v - e).abs() <= tol * e,
                "{dimension}D, e = {e}, CFL 0.4: rebound speed {v} m/s from 1 m/s"
            );
            let v = rebound(e, dimension, 0.1);
            assert!(
                (v - e).abs() <= 0.005 * e,
                "{dimension}D, e = {e}, CFL 0.1: rebound speed {v} m/s from 1 m/s"
            );
        }
    }
}

#[test]
fn damping_ratio_inverts_the_no_pull_restitution() {
    use granmix_core::interactions::contact::{
        damping_ratio_for_restitution, restitution_of_damping,
    };
    for e in [1e-6, 0.01, 0.1, 0.135, 0.2, 0.5, 0.9, 0.999] {
        let z = damping_ratio_for_restitution(e);
        assert!(
            (restitution_of_damping(z) - e).abs() <= 1e-12,
            "e = {e}, ζ = {z}"
        );
    }
    // e(ζ) is continuous across critical damping, where it is e⁻²
    let c = (-2.0f64).exp();
    assert!((restitution_of_damping(1.0 - 1e-7) - c).abs() < 1e-5);
    assert!((restitution_of_damping(1.0 + 1e-7) - c).abs() < 1e-5);
    // small damping: e ≈ exp(−πζ) as for the dashpot that may pull
    assert!((restitution_of_damping(1e-3) - (-std::f64::consts::PI * 1e-3).exp()).abs() < 1e-5);
}
