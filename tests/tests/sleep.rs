//! Resting particles sleep (`numerics.sleep`, docs/method.md §Sleep) and wake causally:
//! a resting layer struck at one end carries the stress wave to its other end at the
//! same time and with the same peak as without sleep.
//!
//! The layer is 1 m long and 0.1 m deep (dp = 1 cm), cohesive (c = 50 kPa) so that the
//! pulse stays elastic, and falls asleep within 25 ms of its geostatic start. At
//! 0.1 s a piston pushes its left end at 0.2 m/s for 5 ms: a compression pulse of about
//! 21 kPa near the piston, 5 kPa at the probe 0.9 m away after 23 ms of travel (the
//! free surface spreads it), at about c0 = 60 m/s. Asleep ahead of the wave, the layer
//! wakes as the front reaches it: removed, the wake-up leaves the probe at rest.

use granmix_core::run::sample::Sample;
use granmix_tests::{rel, run_text};

const LAYER: &str = r#"
[simulation]
name = "pulse"
dimension = 2
gravity = [0.0, -9.81]
end_time = 0.15
dp = 0.01
output_interval = 0.0005

[numerics]
sleep = SLEEP

[[materials]]
name = "soil"
density = 2040.0
youngs_modulus = 5.84e6
poisson_ratio = 0.3
friction_angle = 30.0
cohesion = 5e4

[[regions]]
name = "layer"
material = "soil"
shape = { type = "box", min = [0.0, 0.0], max = [1.0, 0.1] }
initial_stress = "geostatic"

[[containers]]
name = "box"
min = [-0.1, 0.0]
max = [1.0, 0.2]
open = ["+y"]

[[walls]]
name = "piston"
shape = { type = "box", min = [-0.1, 0.0], max = [0.0, 0.2] }
velocity = [0.2, 0.0]
move_between = [0.1, 0.105]

[[probes]]
name = "far"
position = [0.9, 0.05]
"#;

/// The probe's σ_xx against its mean over the 10 ms before the strike: the arrival
/// (the first sample past half the peak), the peak, and the samples.
fn pulse(sleep: bool) -> (f64, f64, Vec<Sample>) {
    let text = LAYER.replace("SLEEP", if sleep { "true" } else { "false" });
    let mut samples = Vec::new();
    run_text(&text, "pulse.toml", |s| samples.push(s.clone()));
    let sxx = |s: &Sample| {
        let far = &s.probes.iter().find(|p| p.0 == "far").unwrap().1;
        far.stress.0[0]
    };
    let before: Vec<f64> = samples
        .iter()
        .filter(|s| s.time > 0.09 && s.time < 0.1)
        .map(sxx)
        .collect();
    let base = before.iter().sum::<f64>() / before.len() as f64;
    let after: Vec<(f64, f64)> = samples
        .iter()
        .filter(|s| s.time >= 0.1)
        .map(|s| (s.time, sxx(s) - base))
        .collect();
    let peak = after.iter().map(|a| a.1).fold(0.0, f64::min);
    // never, where the wave does not arrive
    let arrival = after
        .iter()
        .find(|a| a.1 < 0.5 * peak)
        .map_or(f64::INFINITY, |a| a.0);
    (arrival, peak, samples)
}

#[test]
fn a_stress_wave_crosses_a_sleeping_layer_as_it_crosses_an_awake_one() {
    let (t_awake, peak_awake, _) = pulse(false);
    let (t_sleep, peak_sleep, samples) = pulse(true);
    eprintln!(
        "pulse at the probe: arrival {t_awake:.4} s, peak {peak_awake:.1} Pa without sleep; \
         {t_sleep:.4} s, {peak_sleep:.1} Pa with"
    );
    // the layer sleeps before the strike, but for the particles the piston holds
    let share = |t: f64| {
        let s = samples.iter().find(|s| s.time >= t).unwrap();
        s.awake_fine.unwrap()
    };
    assert!(
        share(0.095) < 0.05,
        "awake share before the strike: {}",
        share(0.095)
    );
    assert!(
        share(0.12) > 0.99,
        "awake share after the wave: {}",
        share(0.12)
    );
    // the pulse is well above the sleep thresholds (0.005 √(g dp) = 1.6 mm/s), and
    // travels at the elastic wave speed: 0.9 m in 23 ms
    assert!(
        peak_awake < -4000.0,
        "peak {peak_awake:.0} Pa without sleep"
    );
    assert!(
        (t_awake - 0.1 - 0.0235).abs() < 0.002,
        "arrival {t_awake} s without sleep"
    );
    assert!(
        (t_sleep - t_awake).abs() < 0.0005 * 0.5,
        "arrival {t_sleep} s with sleep against {t_awake} s without"
    );
    assert!(
        rel(peak_sleep, peak_awake) < 0.01,
        "peak {peak_sleep:.1} Pa with sleep against {peak_awake:.1} Pa without"
    );
}
