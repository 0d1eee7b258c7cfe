//! Barrier scenes: load history of a flow hitting a barrier, the earth pressure of a
//! retained layer at rest (built slowly and loaded at once), and the active pressure
//! behind a yielding barrier.

use granmix_core::run::runner::RunEnd;
use granmix_tests::run;

/// granular_barrier_2d: zero load before the front arrives, a peak after arrival, and a
/// steady load once the deposit is at rest (kinetic energy < 1e-4 of its peak).
#[test]
fn barrier_load_history() {
    let (s, end, _) = run(
        "granular_barrier_2d.toml",
        &["simulation.dp=0.005", "simulation.end_time=2.0"],
    );
    assert!(
        matches!(end, RunEnd::Settled),
        "deposit did not come to rest: {end:?}"
    );
    let barrier_x = 0.35;
    let fx = |k: usize| s[k].barriers[0].force[0];
    // arrival: first sample whose run-out reaches the barrier face (within 2h = 2.6 dp)
    let arrival = s
        .iter()
        .position(|x| x.runout >= barrier_x - 2.6 * 0.005)
        .expect("front reaches the barrier");
    for x in &s[..arrival.saturating_sub(1)] {
        assert_eq!(
            x.barriers[0].peak_force, 0.0,
            "load before arrival at t = {}",
            x.time
        );
    }
    let (kpeak, peak) =
        (0..s.len())
            .map(|k| (k, fx(k)))
            .fold((0, 0.0), |a, b| if b.1 > a.1 { b } else { a });
    assert!(
        peak > 0.0 && kpeak >= arrival,
        "peak {peak} N/m at sample {kpeak}, arrival at {arrival}"
    );
    let n = s.len();
    let steady = fx(n - 1);
    assert!(steady > 0.0, "a deposit rests against the barrier");
    assert!(
        peak > 1.2 * steady,
        "impact peak {peak:.1} N/m above the static load {steady:.1} N/m"
    );
    // steady: the last few samples agree within 2 %
    for k in n.saturating_sub(4)..n {
        assert!(
            (fx(k) - steady).abs() <= 0.02 * steady,
            "load still changing: {} vs {steady}",
            fx(k)
        );
    }
    let ke_peak = s.iter().map(|x| x.kinetic_energy).fold(0.0, f64::max);
    assert!(s[n - 1].kinetic_energy < 1e-4 * ke_peak);
}

/// ½ ρ g H² of the retained layer (ρ = 2040 kg/m³, H = 0.15 m), per unit width.
const RETAINED_UNIT: f64 = 0.5 * 2040.0 * 9.81 * 0.15 * 0.15;

/// The barrier load of the last sample as K = F / (½ ρ g H²), after checking that it
/// is steady: every sample of the last `window` seconds within `band` of it.
fn settled_k(s: &[granmix_core::run::simulation::Sample], window: f64, band: f64) -> f64 {
    let last = s.last().expect("samples");
    let kf = last.barriers[0].force[0] / RETAINED_UNIT;
    for x in s.iter().filter(|x| x.time >= last.time - window) {
        let kx = x.barriers[0].force[0] / RETAINED_UNIT;
        assert!(
            (kx - kf).abs() <= band * kf,
            "load still changing at t = {}: K = {kx:.4} against {kf:.4} at t = {}",
            x.time,
            last.time
        );
    }
    kf
}

/// retained_layer_2d as shipped: the layer is built quasi-statically (gravity ramped
/// over 0.2 s) behind a fixed barrier. Once it is at rest the horizontal load per unit
/// width lies between the active and the at-rest earth pressure, ½ K ρ g H² with K from
/// K_a = (1 − sin φ)/(1 + sin φ) (Rankine) to K0 = 1 − sin φ (Jaky). The stress
/// diffusion of Eq. (26) relaxes the horizontal stress gradient towards K0 ρ g, and the
/// layer comes to rest just below K0 (K = 0.498, 0.497, 0.496 at 3 s for dp = 7.5, 5,
/// 3.75 mm; with seed 000's mirrored wall stress it reached K0 from above, 0.505, 0.501,
/// 0.499; `granmix bench --case retained_layer` holds every level to the band itself);
/// at this test's dp = 7.5 mm the upper bound carries 2 %.
#[test]
fn retained_layer_at_rest_between_active_and_at_rest() {
    let (s, end, _) = run(
        "retained_layer_2d.toml",
        &["simulation.dp=0.0075", "simulation.end_time=2.0"],
    );
    assert!(!matches!(end, RunEnd::Blowup(_)), "{end:?}");
    let last = s.last().expect("samples");
    assert!(
        last.time >= 2.0 - 1e-9,
        "stopped early at t = {}",
        last.time
    );
    // at rest: mean speed far below any flow, √(2 KE/m) < 1e-4 √(g H)
    let (m, g, h) = (2040.0 * 0.6 * 0.15, 9.81, 0.15);
    assert!(
        last.kinetic_energy < 1e-8 * 0.5 * m * g * h,
        "layer not at rest: kinetic energy {:.3e} J/m",
        last.kinetic_energy
    );
    let k = settled_k(&s, 0.5, 0.01);
    let phi = 30f64.to_radians();
    let (ka, k0) = ((1.0 - phi.sin()) / (1.0 + phi.sin()), 1.0 - phi.sin());
    assert!(
        k >= ka && k <= 1.02 * k0,
        "K = {k:.4} outside [K_a, K0] = [{ka:.3}, {k0:.3}] (+2 % at this resolution)"
    );
}

/// retained_layer_2d loaded by full gravity at t = 0. It must come to rest (kinetic
/// energy < 1e-4 of its peak) with a steady load. A suddenly applied load overshoots
/// (the layer compresses to about twice its static strain, as a step-loaded spring
/// does) and the unloading locks in lateral stress, as overconsolidation does: the
/// settled load lies between the at-rest value K0 = 1 − sin φ (Jaky) and K0 OCR^(sin φ)
/// with OCR = 2 (Mayne & Kulhawy 1982). Without hourglass control the layer never
/// settles and the load drifts below K0.
#[test]
fn retained_layer_loaded_at_once_is_overconsolidated() {
    let (s, end, _) = run(
        "retained_layer_2d.toml",
        &[
            "simulation.dp=0.0075",
            "simulation.end_time=2.0",
            "simulation.gravity_ramp=0",
        ],
    );
    assert!(
        matches!(end, RunEnd::Settled),
        "layer did not come to rest: {end:?}"
    );
    let phi = 30f64.to_radians();
    let k0 = 1.0 - phi.sin();
    let (lo, hi) = (k0, k0 * 2f64.powf(phi.sin()));
    let kf = settled_k(&s[s.len().saturating_sub(5)..], f64::INFINITY, 0.01);
    assert!(
        kf >= lo && kf <= hi,
        "settled K = {kf:.3} (t = {}) outside [{lo:.3}, {hi:.3}]",
        s[s.len() - 1].time
    );
}

/// active_earth_pressure_2d: once the barrier yields outward (≥ 1 mm), the load drops
/// from the at-rest value to the active one, ½ K ρ g H² with K between Coulomb
/// (δ = φ, horizontal component K_a cos δ) and Rankine (δ = 0), ±10 %.
#[test]
fn yielding_barrier_reaches_active_pressure() {
    let (s, end, _) = run("active_earth_pressure_2d.toml", &[]);
    assert!(!matches!(end, RunEnd::Blowup(_)), "{end:?}");
    let (rho, g, h) = (2040.0, 9.81, 0.15);
    let phi: f64 = 30f64.to_radians();
    let unit = 0.5 * rho * g * h * h;
    let delta = phi;
    let coulomb = phi.cos().powi(2)
        / (delta.cos() * (1.0 + ((phi + delta).sin() * phi.sin() / delta.cos()).sqrt()).powi(2));
    let (lo, hi) = (
        0.9 * coulomb * delta.cos(),
        1.1 * (1.0 - phi.sin()) / (1.0 + phi.sin()),
    );
    let k = |t: f64| {
        let x = s
            .iter()
            .min_by(|a, b| (a.time - t).abs().total_cmp(&(b.time - t).abs()))
            .unwrap();
        x.barriers[0].force[0] / unit
    };
    let at_rest = k(0.6);
    assert!(
        at_rest > hi,
        "before yielding K = {at_rest:.3} should exceed the active range"
    );
    for t in [0.72, 0.8, 0.9] {
        let kt = k(t);
        assert!(
            kt >= lo && kt <= hi,
            "t = {t}: K = {kt:.3} outside the active range [{lo:.3}, {hi:.3}]"
        );
    }
}
