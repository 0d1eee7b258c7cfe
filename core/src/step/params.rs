//! The method parameters of a run (defaults from seed 000), the Δt/κ choice of
//! Eqs. (51)–(53) and the gravity ramp.

use crate::interactions::contact::ContactLaw;
use crate::numerics::math::Real;
use crate::numerics::sleep::SleepRule;
use crate::scene::resolution::Resolution;
use crate::scene::{ContinuityJump, Scene, TimeStepping, WallStress};

/// Method parameters of one run (one struct per subsystem; defaults from seed 000).
#[derive(Clone, Debug, PartialEq, serde::Serialize, serde::Deserialize)]
pub struct StepParams {
    /// Smoothing length h = smoothing_ratio · dp (1.3 dp).
    pub h: Real,
    /// CFL number of Eq. (51).
    pub cfl: Real,
    /// Limiter coefficient η of Eq. (23).
    pub eta: Real,
    /// MUSCL reconstruction of the fine grains' Riemann jump (`numerics.muscl`).
    #[serde(default)]
    pub muscl: bool,
    /// Stress-diffusion ζ of Eq. (25).
    pub zeta: Real,
    /// ξ of the hourglass penalty (0: off).
    pub hourglass: Real,
    /// Relaxation time of the stored penalty, in acoustic times h/c0.
    pub hourglass_memory: Real,
    /// Gravity ramp time (s); 0: full gravity from the start.
    pub gravity_ramp: Real,
    /// Verlet skin (m).
    pub skin: Real,
    /// Speed bound of the stability guard (m/s).
    pub max_speed: Real,
    /// Artificial stress (n, ε), only with cohesive materials.
    pub artificial: Option<(Real, Real)>,
    /// Coulomb coefficient between coarse and fine grains, μ_cf.
    pub mu_cf: Real,
    /// Coulomb coefficient of fine grains on walls (0: off).
    pub wall_friction: Real,
    /// Multi-rate (κ coarse sub-steps per fine step) or single-rate.
    pub scheme: TimeStepping,
    /// Pressure of the continuity equation's jump term.
    pub continuity_jump: ContinuityJump,
    /// Deviatoric stress of the dummy wall particles.
    pub wall_stress: WallStress,
    /// Soil densities held at or above their floor
    /// ([`FineMaterial::density_floor`](crate::fine::material::FineMaterial::density_floor)).
    pub density_floor: bool,
    /// The seepage drag at each pair's midpoint (`numerics.seepage_midpoint`).
    pub seepage_midpoint: bool,
    /// The contact law of coarse grains (seeds 001, 004).
    pub contact: ContactLaw,
    /// CFL^c of Eq. (52).
    pub cfl_coarse: Real,
    /// The fine grains' sleep rule (`numerics.sleep`; None: every particle is stepped).
    #[serde(default)]
    pub sleep: Option<SleepRule>,
}

impl StepParams {
    /// The parameters of `s` at resolution `res`.
    pub fn from_scene(s: &Scene, res: &Resolution) -> Self {
        let d = s.simulation.dimension as Real;
        let n = &s.numerics;
        let cohesive = s.materials.iter().any(|m| m.cohesion > 0.0);
        StepParams {
            h: res.h,
            cfl: s.simulation.cfl,
            eta: n.eta.unwrap_or(20.0 * d),
            muscl: n.muscl,
            zeta: n.stress_diffusion,
            hourglass: n.hourglass,
            hourglass_memory: n.hourglass_memory,
            gravity_ramp: s.simulation.gravity_ramp,
            skin: res.skin,
            max_speed: s.simulation.max_speed,
            artificial: cohesive
                .then_some((n.artificial_stress_exponent, n.artificial_stress_epsilon)),
            mu_cf: s.contact.mu_cf,
            wall_friction: n.wall_friction,
            scheme: s.simulation.time_stepping,
            continuity_jump: n.continuity_jump,
            wall_stress: n.wall_stress,
            density_floor: n.density_floor,
            seepage_midpoint: n.seepage_midpoint,
            contact: ContactLaw::from_spec(&s.contact, res.dp, s.simulation.dimension),
            cfl_coarse: s.simulation.cfl_coarse,
            sleep: n.sleep.then(|| sleep_rule(s, res)),
        }
    }
}

/// The sleep rule of `s` at resolution `res`: the speed 0.005 √(g dp) unless the
/// scene sets `numerics.sleep_speed` (a grain at that speed has ½ v² = 1.25e-5 g dp,
/// the energy of a fall of 1/80,000 of its size), the acceleration g (an unbalanced
/// force below the grain's weight) unless it sets `numerics.sleep_acceleration`, 100
/// quiet steps unless it sets `numerics.sleep_steps`.
fn sleep_rule(s: &Scene, res: &Resolution) -> SleepRule {
    let g = s.simulation.gravity_norm();
    let speed = s
        .numerics
        .sleep_speed
        .unwrap_or(0.005 * (g * res.dp).sqrt());
    let accel = s.numerics.sleep_acceleration.unwrap_or(g);
    let steps = s.numerics.sleep_steps.unwrap_or(100) as u16;
    SleepRule::new(speed, accel, steps, res.h)
}

/// Statistics of one step.
#[derive(Clone, Copy, Debug, Default)]
pub struct StepStats {
    pub vmax: Real,
    pub rebuilt: bool,
    /// Coarse sub-steps in this step.
    pub kappa: usize,
}

/// Step size and sub-step count of one fine step (Eqs. 51–53).
///
/// Multi-rate: Δt = min(Δt_f, `max_dt`) and κ = ⌈Δt/Δt_c⌉; when the two steps are
/// within 25 % of each other, κ = 1 and Δt = min(Δt, Δt_c) instead. Single-rate:
/// Δt = min(Δt_f, Δt_c, `max_dt`), κ = 1 (Eq. 53). Without fine grains the step is the
/// coarse one.
pub fn choose_step(dt_f: Real, dt_c: Real, max_dt: Real, scheme: TimeStepping) -> (Real, usize) {
    let single = dt_f.min(dt_c).min(max_dt);
    if scheme == TimeStepping::SingleRate || !dt_f.is_finite() || !dt_c.is_finite() {
        return (single, 1);
    }
    let dt = dt_f.min(max_dt);
    let r = dt / dt_c;
    if r <= 1.25 {
        (single, 1)
    } else {
        (dt, r.ceil() as usize)
    }
}

/// Factor on gravity at time `t` for a ramp of length `ramp`: ½(1 − cos(π t/ramp)),
/// then 1. Smooth (zero rate at both ends), so the ramp excites no wave of its own.
pub fn gravity_ramp(t: Real, ramp: Real) -> Real {
    if ramp > 0.0 && t < ramp {
        0.5 * (1.0 - (std::f64::consts::PI * t / ramp).cos())
    } else {
        1.0
    }
}

#[cfg(test)]
mod ramp_tests {
    use super::gravity_ramp;

    #[test]
    fn gravity_ramp_is_smooth_and_reaches_full_gravity() {
        assert_eq!(gravity_ramp(0.3, 0.0), 1.0);
        assert_eq!(gravity_ramp(0.0, 0.2), 0.0);
        assert!((gravity_ramp(0.1, 0.2) - 0.5).abs() < 1e-15);
        assert!((gravity_ramp(0.2 - 1e-9, 0.2) - 1.0).abs() < 1e-12);
        assert_eq!(gravity_ramp(0.25, 0.2), 1.0);
        // zero rate at the start: the first steps barely load the grains
        assert!(gravity_ramp(0.002, 0.2) < 1e-3);
    }
}
