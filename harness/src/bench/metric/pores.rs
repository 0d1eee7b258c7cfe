//! References of the saturated-soil benchmarks (VALIDATION §12): Darcy's law through
//! the seepage column and Terzaghi's consolidation of a loaded layer.

use granmix_core::run::simulation::Sample;

const RHO_W: f64 = 1000.0;
const G: f64 = 9.81;

/// Darcy through the seepage column: permeability k (m²), viscosity μ (Pa·s), the
/// piezometers `low` and `high` dz apart.
#[derive(Clone, Copy)]
pub(crate) struct DarcyRef {
    pub(crate) permeability: f64,
    pub(crate) viscosity: f64,
    pub(crate) dz: f64,
}

impl DarcyRef {
    /// `seepage_column.toml`.
    pub(crate) const COLUMN: DarcyRef = DarcyRef {
        permeability: 1e-9,
        viscosity: 1e-3,
        dz: 0.12,
    };

    /// Largest |q/(k_h i) − 1| over the samples from 0.3 s (the quasi-steady flow),
    /// q the water's velocity less the sand's at the piezometers, i their gradient.
    pub(crate) fn error(&self, samples: &[Sample]) -> Option<f64> {
        let kh = self.permeability * RHO_W * G / self.viscosity;
        let mut worst: Option<f64> = None;
        for s in samples.iter().filter(|s| s.time >= 0.3) {
            let probe = |n: &str| s.probes.iter().find(|p| p.0 == n).map(|p| &p.1);
            let (lo, hi) = (probe("low")?, probe("high")?);
            let i = (lo.water_pressure? - hi.water_pressure?) / (RHO_W * G * self.dz) - 1.0;
            let q = 0.5
                * (lo.water_velocity?[1] - lo.velocity[1] + hi.water_velocity?[1] - hi.velocity[1]);
            worst = Some(worst.unwrap_or(0.0).max((q / (kh * i) - 1.0).abs()));
        }
        worst
    }
}

/// Terzaghi's consolidation of `consolidation_layer.toml`: layer height, permeability,
/// viscosity, Young's modulus and Poisson's ratio of the clay, the water's c0 and the
/// surcharge's load (Pa).
#[derive(Clone, Copy)]
pub(crate) struct ConsolidationRef {
    pub(crate) height: f64,
    pub(crate) permeability: f64,
    pub(crate) viscosity: f64,
    pub(crate) youngs: f64,
    pub(crate) poisson: f64,
    pub(crate) sound_speed: f64,
    pub(crate) load: f64,
}

impl ConsolidationRef {
    pub(crate) const LAYER: ConsolidationRef = ConsolidationRef {
        height: 0.1,
        permeability: 7e-11,
        viscosity: 1e-3,
        youngs: 2e5,
        poisson: 0.3,
        sound_speed: 50.0,
        load: 5000.0 * G * 0.05,
    };

    /// (m_v, c_v, s0, s∞): c_v = k / (μ (m_v + 1/(ρ_w c0²))), s∞ = Δσ H m_v, s0 = s∞ (1 − B).
    fn constants(&self) -> (f64, f64, f64, f64) {
        let (e, nu) = (self.youngs, self.poisson);
        let mv = 1.0 / (e / (3.0 * (1.0 - 2.0 * nu)) + 4.0 / 3.0 * e / (2.0 * (1.0 + nu)));
        let storage = 1.0 / (RHO_W * self.sound_speed * self.sound_speed);
        let cv = self.permeability / (self.viscosity * (mv + storage));
        let s_inf = self.load * self.height * mv;
        (mv, cv, s_inf * storage / (mv + storage), s_inf)
    }

    /// Degree of consolidation U(t) = 1 − Σ 2/M² exp(−M² T), T = c_v t / H².
    fn degree(&self, t: f64) -> f64 {
        let (_, cv, _, _) = self.constants();
        let tv = cv * t / (self.height * self.height);
        1.0 - (0..200)
            .map(|m| {
                let big = std::f64::consts::PI * (2 * m + 1) as f64 / 2.0;
                2.0 / (big * big) * (-big * big * tv).exp()
            })
            .sum::<f64>()
    }

    /// Largest relative error of the settlement against s0 + (s∞ − s0) U(t) at the
    /// samples nearest U = 50 % and 90 %, the settlement the time integral of the
    /// probe `top`'s (the clay's top) vertical velocity.
    pub(crate) fn error(&self, samples: &[Sample]) -> Option<f64> {
        let (_, _, s0, s_inf) = self.constants();
        let mut settled = vec![(0.0, 0.0)];
        for w in samples.windows(2) {
            let v = |s: &Sample| {
                s.probes
                    .iter()
                    .find(|p| p.0 == "top")
                    .map(|p| p.1.velocity[1])
            };
            let step = -0.5 * (v(&w[0])? + v(&w[1])?) * (w[1].time - w[0].time);
            let last = settled.last()?.1;
            settled.push((w[1].time, last + step));
        }
        let mut worst: Option<f64> = None;
        for target in [0.5, 0.9] {
            let (t, s) = settled
                .iter()
                .min_by(|a, b| {
                    (self.degree(a.0) - target)
                        .abs()
                        .total_cmp(&(self.degree(b.0) - target).abs())
                })
                .copied()?;
            let want = s0 + (s_inf - s0) * self.degree(t);
            worst = Some(worst.unwrap_or(0.0).max((s - want).abs() / want));
        }
        worst
    }
}
