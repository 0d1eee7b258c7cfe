//! The linear standing wave of `standing_wave_2d.toml` (issue 42): the water scheme's
//! numerical dissipation against the physical decay, and its period against linear
//! theory.
//!
//! The first sloshing mode of a closed tank, η = A cos(k x) cos(ω t), k = π/L, carries
//! a horizontal momentum P_x(t) = (2 ρ A ω / k²) sin(ω t) per unit width, whatever the
//! depth. Unlike the kinetic energy it is signed and linear in the wave, so the
//! incoherent motion of the particles (a resting tank's jitter) averages out of it:
//! its zero crossings give the period and its extrema between them the decay.

use granmix_core::run::oscillation::{damped, Oscillation};
use granmix_core::run::simulation::Sample;
use serde_json::{json, Value};

/// A standing wave of the first mode in a 2D tank `length` long, water `depth` deep,
/// kinematic viscosity `nu` (m²/s), gravity `g`.
#[derive(Clone, Copy)]
pub(crate) struct WaveRef {
    pub(crate) length: f64,
    pub(crate) depth: f64,
    pub(crate) nu: f64,
    pub(crate) g: f64,
}

impl WaveRef {
    /// `standing_wave_2d.toml`: L = 1 m, h = 0.5 m, ν = 1e-6 m²/s.
    pub(crate) const TANK: WaveRef = WaveRef {
        length: 1.0,
        depth: 0.5,
        nu: 1e-6,
        g: 9.81,
    };

    fn k(&self) -> f64 {
        std::f64::consts::PI / self.length
    }

    /// ω of linear theory: ω² = g k tanh(k h).
    pub(crate) fn omega(&self) -> f64 {
        let k = self.k();
        (self.g * k * (k * self.depth).tanh()).sqrt()
    }

    /// The period 2π/ω of linear theory.
    pub(crate) fn period(&self) -> f64 {
        2.0 * std::f64::consts::PI / self.omega()
    }

    /// The physical decay rate of the amplitude (1/s): the interior's 2 ν k² (Lamb 1932,
    /// §348) plus the Stokes layers on the floor and on both end walls (no-slip). A
    /// layer under an outer velocity U sin ωt dissipates ½ ρ U² √(ν ω/2) per unit area
    /// (Landau & Lifshitz, *Fluid Mechanics*, §24); the potential flow gives
    /// U = A ω sin(kx)/sinh(kh) on the floor and A ω sinh(k(z + h))/sinh(kh) on the end
    /// walls, and the wave holds ¼ ρ g A² L, so γ = D/(2E).
    pub(crate) fn gamma(&self) -> f64 {
        let (k, h, l, w) = (self.k(), self.depth, self.length, self.omega());
        let layer = 0.5 * (self.nu * w / 2.0).sqrt() * (w / (k * h).sinh()).powi(2);
        let floor = layer * l / 2.0;
        let walls = layer * 2.0 * ((2.0 * k * h).sinh() / (4.0 * k) - h / 2.0);
        let energy = 0.25 * self.g * l;
        2.0 * self.nu * k * k + (floor + walls) / (2.0 * energy)
    }

    /// The physical log decrement per period, γ T.
    pub(crate) fn decrement(&self) -> f64 {
        self.gamma() * self.period()
    }

    /// The period and decay of the water's horizontal momentum in `samples`
    /// ([`damped`]); None with fewer than two extrema.
    pub(crate) fn fit(samples: &[Sample]) -> Option<Oscillation> {
        let p: Vec<(f64, f64)> = samples
            .iter()
            .filter_map(|s| s.water.as_ref().map(|w| (s.time, w.momentum[0])))
            .collect();
        damped(&p)
    }

    /// The bench's record of a run: both fits next to linear theory and the physical
    /// decay, printed as a line.
    pub(crate) fn report(&self, samples: &[Sample]) -> Value {
        let fit = Self::fit(samples);
        let (t, d) = (self.period(), self.decrement());
        match fit {
            Some(f) => {
                println!(
                    "{:<27} period {:.4} s against {:.4} s of linear theory ({:+.2} %, asked 1 %); \
                     log decrement {:.4} per period against the physical {:.2e} (asked ≤ 0.05), \
                     over {} half periods",
                    "",
                    f.period,
                    t,
                    100.0 * (f.period / t - 1.0),
                    f.decrement(),
                    d,
                    f.half_periods
                );
                json!({
                    "period_s": f.period, "period_linear_s": t,
                    "period_rel_error": f.period / t - 1.0,
                    "decrement": f.decrement(), "decrement_physical": d,
                    "gamma_per_s": f.gamma, "gamma_physical_per_s": self.gamma(),
                    "half_periods": f.half_periods,
                })
            }
            None => json!({ "period_linear_s": t, "decrement_physical": d }),
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Linear theory for the bundled tank (L = 1, h = 0.5): T = 1.1818 s; the physical
    /// decay is the Stokes layers' (≈ 1.6e-3 /s) plus the interior's 2 ν k² = 1.97e-5 /s.
    #[test]
    fn linear_theory_of_the_tank() {
        let r = WaveRef::TANK;
        assert!((r.period() - 1.18182).abs() < 1e-4, "{}", r.period());
        let interior = 2.0 * 1e-6 * std::f64::consts::PI.powi(2);
        assert!((interior - 1.974e-5).abs() < 1e-8);
        assert!((r.gamma() - 1.65e-3).abs() < 0.02e-3, "{}", r.gamma());
        assert!(
            (r.decrement() - 1.95e-3).abs() < 0.03e-3,
            "{}",
            r.decrement()
        );
    }
}
