//! Landing on a target time: the one loop that steps a simulation until exactly `t`,
//! its last step shortened to end there. The CLI runner (each output time), the
//! `Simulation::advance_to` of the API and the FMU's `fmi2DoStep` all land through it.

use super::params::StepStats;
use crate::numerics::guard::Blowup;
use crate::numerics::math::Real;

/// A simulation that takes steps of at most a given length.
pub trait Stepping {
    /// The simulated time.
    fn now(&self) -> Real;
    /// Set the simulated time to `t` (a round-off away from it).
    fn set_now(&mut self, t: Real);
    /// Take one step no longer than `max_dt` (Δt and κ of Eqs. 51–53).
    fn step_at_most(&mut self, max_dt: Real) -> Result<StepStats, Blowup>;
}

/// Relative distance to the target below which the simulation counts as there.
const LANDED: Real = 1e-12;

/// Step `sim` until exactly `t`, calling `on_step` after every step. A remainder
/// below 10⁻¹² t is not stepped, and the clock is set to `t` then and after a last
/// step that overshoots by round-off.
pub fn land_on<S: Stepping + ?Sized>(
    sim: &mut S,
    t: Real,
    on_step: &mut dyn FnMut(&S),
) -> Result<(), Blowup> {
    while sim.now() < t {
        let remaining = t - sim.now();
        if remaining <= LANDED * t.abs().max(1e-300) {
            sim.set_now(t);
            break;
        }
        sim.step_at_most(remaining)?;
        if t - sim.now() < 0.0 {
            sim.set_now(t);
        }
        on_step(sim);
    }
    Ok(())
}
