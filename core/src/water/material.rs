//! The water's constants and its equation of state (seed 001 Eq. 3; Tait as an
//! option).

use crate::numerics::math::Real;
use crate::scene::{EquationOfState, WallSlip, WaterSpec};

/// The fluid of a scene, with its derived constants.
#[derive(Clone, Copy, Debug, PartialEq, serde::Serialize, serde::Deserialize)]
pub struct WaterMaterial {
    /// Reference density ρ_w (kg/m³).
    pub rho0: Real,
    /// Artificial sound speed c0 (m/s).
    pub c0: Real,
    /// Dynamic viscosity μ (Pa·s).
    pub mu: Real,
    pub eos: EquationOfState,
    pub wall: WallSlip,
    /// Limiter coefficient η of the Riemann dissipation (∞: no limiter).
    pub limiter: Real,
    /// The speed c0 was chosen against (m/s).
    pub speed_scale: Real,
    /// Kernel gradient correction of the pressure force is on.
    pub correction: bool,
    /// MUSCL reconstruction of the Riemann dissipation.
    pub muscl: bool,
    /// The first step starts from the incompressible start pressure
    /// ([`water_start`](crate::interactions::water_start)).
    pub incompressible_start: bool,
    /// Walls push and never pull (the walls' P* ≥ 0); false with a saturated soil.
    pub walls_push_only: bool,
    /// Settling phase (s): velocities damped at 10/settle_time before it ends.
    pub settle_time: Real,
}

impl WaterMaterial {
    /// The material of `spec` with sound speed `c0` chosen for `speed_scale`.
    pub fn from_spec(spec: &WaterSpec, c0: Real, speed_scale: Real) -> Self {
        WaterMaterial {
            rho0: spec.density,
            c0,
            mu: spec.viscosity,
            eos: spec.equation_of_state,
            wall: spec.wall,
            limiter: spec.limiter.unwrap_or(Real::INFINITY),
            speed_scale,
            correction: spec.gradient_correction,
            muscl: spec.muscl,
            incompressible_start: spec.hydrostatic_start
                && spec.incompressible_start.unwrap_or(true),
            walls_push_only: true,
            settle_time: spec.settle_time,
        }
    }

    /// Acoustic impedance ρ_w c0 of the Riemann problem.
    #[inline(always)]
    pub fn impedance(&self) -> Real {
        self.rho0 * self.c0
    }

    /// Pressure at density ρ: c0² (ρ − ρ_w) (seed 001 Eq. 3, Morris 2000), or Tait's
    /// ρ_w c0²/7 ((ρ/ρ_w)⁷ − 1).
    #[inline(always)]
    pub fn pressure(&self, rho: Real) -> Real {
        match self.eos {
            EquationOfState::Linear => self.c0 * self.c0 * (rho - self.rho0),
            EquationOfState::Tait => {
                let r = rho / self.rho0;
                let r2 = r * r;
                self.rho0 * self.c0 * self.c0 / 7.0 * (r2 * r2 * r2 * r - 1.0)
            }
        }
    }

    /// The density at pressure `p` (inverse of [`pressure`](Self::pressure)).
    pub fn density(&self, p: Real) -> Real {
        let c2 = self.c0 * self.c0;
        match self.eos {
            EquationOfState::Linear => self.rho0 + p / c2,
            EquationOfState::Tait => self.rho0 * (1.0 + 7.0 * p / (self.rho0 * c2)).powf(1.0 / 7.0),
        }
    }

    /// The hydrostatic pressure at depth `depth` below a free surface in gravity `g`,
    /// exact for the equation of state: dp/dz = −ρ(p) g. Linear: ρ_w c0² (e^{g d/c0²} − 1);
    /// Tait: from the closed form of ∫ dp/ρ(p) = g d.
    pub fn hydrostatic_pressure(&self, g: Real, depth: Real) -> Real {
        let c2 = self.c0 * self.c0;
        match self.eos {
            EquationOfState::Linear => self.rho0 * c2 * (g * depth / c2).exp_m1(),
            EquationOfState::Tait => {
                // ρ = ρ_w (1 + 7p/(ρ_w c0²))^{1/7}: ∫ dp/ρ = (c0²/6)((1 + 7p/(ρ_w c0²))^{6/7} − 1)
                let a = (1.0 + 6.0 * g * depth / c2).powf(7.0 / 6.0);
                self.rho0 * c2 / 7.0 * (a - 1.0)
            }
        }
    }

    /// Share of the velocity kept over a step of `dt` starting at `t`: exp(−10 Δt/T)
    /// inside the settling phase [0, T), 1 after it.
    pub fn velocity_kept(&self, t: Real, dt: Real) -> Real {
        if t < self.settle_time {
            (-10.0 * dt / self.settle_time).exp()
        } else {
            1.0
        }
    }

    /// Largest stable Δt at smoothing length `h`, CFL number `cfl` and largest speed
    /// `vmax`: the acoustic limit cfl·h/(c0 + |v|max) and the viscous limit
    /// 0.125 h² ρ_w/μ (Morris et al. 1997, Eq. 11).
    pub fn stable_dt(&self, h: Real, cfl: Real, vmax: Real) -> Real {
        let acoustic = cfl * h / (self.c0 + vmax);
        let viscous = if self.mu > 0.0 {
            0.125 * h * h * self.rho0 / self.mu
        } else {
            Real::INFINITY
        };
        acoustic.min(viscous)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn water(eos: EquationOfState) -> WaterMaterial {
        WaterMaterial {
            rho0: 1000.0,
            c0: 30.0,
            mu: 1e-3,
            eos,
            wall: WallSlip::NoSlip,
            limiter: 3.0,
            speed_scale: 3.0,
            correction: true,
            muscl: false,
            incompressible_start: false,
            walls_push_only: true,
            settle_time: 0.0,
        }
    }

    /// Both equations of state invert, and agree to first order (dp/dρ = c0² at ρ_w).
    #[test]
    fn equations_of_state_invert_and_share_the_sound_speed() {
        for eos in [EquationOfState::Linear, EquationOfState::Tait] {
            let m = water(eos);
            for p in [-500.0, 0.0, 1.0, 9810.0, 5.0e4] {
                let rho = m.density(p);
                assert!(
                    (m.pressure(rho) - p).abs() < 1e-9 * p.abs().max(1.0),
                    "{eos:?} {p}"
                );
            }
            let d = 1e-4;
            let slope = (m.pressure(1000.0 + d) - m.pressure(1000.0 - d)) / (2.0 * d);
            assert!((slope / 900.0 - 1.0).abs() < 1e-6, "{eos:?}: {slope}");
        }
        // the hydrostatic column: dp/dz = ρ(p) g, by finite differences
        for eos in [EquationOfState::Linear, EquationOfState::Tait] {
            let m = water(eos);
            let (g, d, e) = (9.81, 2.0, 1e-4);
            let slope =
                (m.hydrostatic_pressure(g, d + e) - m.hydrostatic_pressure(g, d - e)) / (2.0 * e);
            let want = m.density(m.hydrostatic_pressure(g, d)) * g;
            assert!(
                (slope / want - 1.0).abs() < 1e-8,
                "{eos:?}: {slope} vs {want}"
            );
            assert_eq!(m.hydrostatic_pressure(g, 0.0), 0.0);
        }
        // Tait at 1 % compression: ρ_w c0²/7 (1.01⁷ − 1)
        let m = water(EquationOfState::Tait);
        let want = 1000.0 * 900.0 / 7.0 * (1.01f64.powi(7) - 1.0);
        assert!((m.pressure(1010.0) - want).abs() < 1e-9 * want);
    }
}
