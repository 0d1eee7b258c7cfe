//! VALIDATION.md §1: geostatic layer at rest.
//! σ_v(z) = −ρ g (H − z) within 3 % at mid-depth, base reaction = weight within 1 %,
//! σ_h/σ_v within [1 − sin φ, 1], and the layer stays at rest: its kinetic energy, from
//! the small start-up transient, decays (seed 000's scheme without hourglass control
//! grows a zero-energy mode to 150 times the start-up value by 0.25 s).

use granmix_tests::{rel, run};

#[test]
fn geostatic_layer_stress_and_base_reaction() {
    // coarse resolution (dp = H/20), 1 s
    let (samples, end, _) = run(
        "geostatic_layer.toml",
        &["simulation.dp=0.01", "simulation.end_time=1.0"],
    );
    assert!(
        !matches!(end, granmix_core::run::runner::RunEnd::Blowup(_)),
        "{end:?}"
    );
    let ke_max = |t0: f64, t1: f64| {
        samples
            .iter()
            .filter(|x| x.time >= t0 && x.time <= t1)
            .map(|x| x.kinetic_energy)
            .fold(0.0, f64::max)
    };
    let (early, late) = (ke_max(0.0, 0.05), ke_max(0.5, 1.0));
    assert!(
        early > 0.0 && late <= 0.1 * early,
        "kinetic energy {late:.2e} J/m after 0.5 s against {early:.2e} J/m at the start"
    );
    let (rho, g, h, w, phi) = (2040.0, 9.81, 0.2, 1.0, 30f64.to_radians());
    let last = samples.last().unwrap();
    let mid = &last.probes.iter().find(|p| p.0 == "mid").unwrap().1;
    let sv = mid.stress.0[1];
    let sv_ref = -rho * g * h / 2.0;
    assert!(
        rel(sv, sv_ref) < 0.03,
        "σ_v at mid-depth {sv:.1} Pa vs {sv_ref:.1} Pa"
    );
    let ratio = mid.stress.0[0] / sv;
    assert!(
        ratio >= 1.0 - phi.sin() - 0.03 && ratio <= 1.0,
        "σ_h/σ_v = {ratio:.3}"
    );
    let base = last
        .barriers
        .iter()
        .find(|b| b.name == "box.bottom")
        .unwrap();
    let weight = rho * g * h * w;
    assert!(
        rel(-base.force[1], weight) < 0.01,
        "base reaction {:.1} N/m vs weight {weight:.1} N/m",
        -base.force[1]
    );
}
