//! The run loop shared by the CLI, the benchmarks and the tests: step to each output
//! time (landing exactly on it), sample, and stop at the end time or once settled.

use crate::numerics::guard::Blowup;
use crate::run::any::AnySimulation;
use crate::run::sample::Sample;
use crate::scene::SimulationSpec;
use crate::step::land_on;

/// How a run ended.
#[derive(Clone, Debug, PartialEq)]
pub enum RunEnd {
    /// Reached `end_time`.
    EndTime,
    /// Kinetic energy stayed below `settle_ratio` × its peak for `settle_window`.
    Settled,
    /// The stability guard stopped the run.
    Blowup(Blowup),
    /// The sample callback asked to stop.
    Stopped,
}

/// Run `sim` under the timing rules of `spec`. `on_sample` is called at t = 0 and at
/// every output time and may return `false` to stop; `on_step` after every step.
pub fn run(
    sim: &mut AnySimulation,
    spec: &SimulationSpec,
    mut on_sample: impl FnMut(&mut AnySimulation, &Sample) -> bool,
    mut on_step: impl FnMut(&AnySimulation),
) -> RunEnd {
    let end = spec.end_time;
    let first = sim.sample();
    if !on_sample(sim, &first) {
        return RunEnd::Stopped;
    }
    let mut ke_peak: f64 = 0.0;
    // time since which the kinetic energy has stayed below the settle threshold
    let mut quiet_since: Option<f64> = None;
    let mut k = 1u64;
    loop {
        let target = (k as f64 * spec.output_interval).min(end);
        if let Err(b) = land_on(sim, target, &mut on_step) {
            return RunEnd::Blowup(b);
        }
        let s = sim.sample();
        if !on_sample(sim, &s) {
            return RunEnd::Stopped;
        }
        ke_peak = ke_peak.max(s.kinetic_energy);
        if let Some(r) = spec.settle_ratio {
            if ke_peak > 0.0 && s.kinetic_energy < r * ke_peak {
                let since = *quiet_since.get_or_insert(s.time);
                if s.time >= spec.settle_min_time && s.time - since >= spec.settle_window {
                    return RunEnd::Settled;
                }
            } else {
                quiet_since = None;
            }
        }
        if target >= end {
            return RunEnd::EndTime;
        }
        k += 1;
    }
}
