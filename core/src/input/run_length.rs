//! How long a run is, vetted at load: a scene whose time step at rest is not a normal
//! positive number, whose output interval is shorter than that step, or whose output
//! or step count is not finite or beyond a stated bound is refused, as is gravity that
//! would carry a particle past the speed bound within one step, and a permeability
//! too small for the implicit seepage drag to resolve. Each of these would
//! otherwise pass `check` and then never finish, or stop the run at its first step.

use crate::estimate::flow_speed::WaterSpeed;
use crate::estimate::{rest_dt_bound, RestDt};
use crate::numerics::math::Real;
use crate::scene::resolution::Resolution;
use crate::scene::{KeyError, Scene};

/// Most steps a run may take: thirty years at a million steps a second. Real scenes
/// take 1e4–1e7; the bound only refuses runs that could never finish (a scene at a
/// spacing far too fine for any machine is refused for its memory instead, when it is
/// built or checked).
pub const MAX_STEPS: Real = 1e12;
/// Most outputs (series rows, snapshots) a run may write.
pub const MAX_OUTPUTS: Real = 1e6;
/// The strongest seepage coupling the implicit close of the drag resolves: Δt μ /
/// (k ρ_d) at the step at rest. Its Schur complement subtracts terms that large from
/// the particle's mass, so about log10 of it of the 16 digits are lost; at 1e6 the
/// close still meets its 1e-10 tolerance.
pub const MAX_SEEPAGE_COUPLING: Real = 1e6;
/// The CFL number a scene takes by default: a bound that the default CFL would meet
/// is blamed on `simulation.cfl`.
const DEFAULT_CFL: Real = 0.4;

/// Refuse a run that would not finish, or would stop at its first step; `water` is the
/// water's speeds ([`check_water_start`](super::water_start::check_water_start)).
pub fn check_run_length(
    scene: &Scene,
    res: &Resolution,
    water: Option<&WaterSpeed>,
) -> Result<(), KeyError> {
    let sim = &scene.simulation;
    let bound = rest_dt_bound(scene, res, water);
    let dt = bound.dt;
    let fail = |key: &str, msg: String| Err(KeyError::new(key, msg));
    if dt.is_nan() || dt <= 0.0 || (dt.is_finite() && !dt.is_normal()) {
        return fail(
            &culprit(scene, &bound),
            format!(
                "the time step at rest Δt = {dt:?} s ({}) is not a normal positive number; \
                 the run could not advance",
                bound.what
            ),
        );
    }
    if dt.is_finite() && sim.output_interval < dt {
        return fail(
            "simulation.output_interval",
            format!(
                "output_interval = {:?} s is shorter than the time step at rest Δt = {dt:?} s \
                 ({}); outputs cannot come more often than steps: take output_interval ≥ \
                 {dt:.3e} s",
                sim.output_interval, bound.what
            ),
        );
    }
    let outputs = sim.end_time / sim.output_interval;
    if outputs.is_nan() || outputs > MAX_OUTPUTS {
        return fail(
            "simulation.end_time",
            format!(
                "end_time = {:?} s at output_interval = {:?} s gives {outputs:.3e} outputs, \
                 over the bound of {MAX_OUTPUTS:.0e}; shorten end_time or lengthen \
                 output_interval",
                sim.end_time, sim.output_interval
            ),
        );
    }
    let steps = sim.end_time / dt.min(sim.output_interval);
    if steps.is_nan() || steps > MAX_STEPS {
        return fail(
            &culprit(scene, &bound),
            format!(
                "the time step at rest Δt = {dt:?} s ({}) gives {steps:.3e} steps to end_time \
                 = {:?} s, over the bound of {MAX_STEPS:.0e} steps; the run would not finish",
                bound.what, sim.end_time
            ),
        );
    }
    if let (true, Some(w)) = (
        dt.is_finite(),
        water.and(crate::estimate::flow_speed::water_spec(scene)),
    ) {
        for (i, m) in scene.materials.iter().enumerate() {
            let Some(p) = crate::fine::pores::Pores::of(m) else {
                continue;
            };
            let coupling = dt * w.viscosity / (p.permeability * m.density);
            if coupling.is_nan() || coupling > MAX_SEEPAGE_COUPLING {
                let key = if m.permeability.is_some() {
                    "permeability"
                } else {
                    "grain_size"
                };
                let k_min = dt * w.viscosity / (MAX_SEEPAGE_COUPLING * m.density);
                return fail(
                    &format!("materials[{i}].{key}"),
                    format!(
                        "the permeability k = {:?} m² of material `{}` locks the soil to its \
                         pore water {coupling:.3e} times within the time step at rest (Δt μ / \
                         (k ρ_d) with Δt = {dt:.3e} s, μ = {:?} Pa·s): the implicit seepage \
                         drag resolves up to {MAX_SEEPAGE_COUPLING:.0e}. Over the run this soil \
                         is impermeable; give k ≥ {k_min:.1e} m²",
                        p.permeability, m.name, w.viscosity
                    ),
                );
            }
        }
    }
    // |g| without squaring (1e308² would overflow)
    let g = sim.gravity.iter().fold(0.0, |a: Real, x| a.hypot(*x));
    let gain = g * dt;
    if dt.is_finite() && (gain.is_nan() || gain > sim.max_speed) {
        return fail(
            "simulation.gravity",
            format!(
                "gravity |g| = {g:?} m/s² speeds a particle up by {:.3e} m/s within one time \
                 step (Δt = {dt:.3e} s), past simulation.max_speed = {:?} m/s: the run would \
                 stop at its first step",
                g * dt,
                sim.max_speed
            ),
        );
    }
    Ok(())
}

/// The key to blame for a step that is too short: `simulation.cfl` when the default
/// CFL would give an acceptable step, else the key of the bound.
fn culprit(scene: &Scene, bound: &RestDt) -> String {
    let sim = &scene.simulation;
    let at_default = bound.dt * DEFAULT_CFL / sim.cfl;
    let steps = sim.end_time / at_default.min(sim.output_interval);
    if bound.acoustic && at_default.is_normal() && steps <= MAX_STEPS {
        "simulation.cfl".into()
    } else {
        bound.key.clone()
    }
}
