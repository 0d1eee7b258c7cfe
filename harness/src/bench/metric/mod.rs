//! How a benchmark case is scored: the metrics and the reference solutions they are
//! held against (VALIDATION §2 collapses, seed 000 Eq. (62) craters, earth pressure at
//! rest).

pub mod lobovsky;
pub mod pores;
pub mod rondon;
pub mod sphinxsys_wave;
pub mod wave;

use granmix_core::run::simulation::Sample;

/// How a case is scored.
#[derive(Clone, Copy)]
pub(crate) enum Metric {
    /// Final run-out against a reference length (m).
    Runout(f64),
    /// Mid-depth vertical stress against −ρ g H/2 (Pa) from the probe `mid`.
    ProbeSigmaYy(f64),
    /// Crater depth of the first body (ball) against Eq. (62) of seed 000.
    Crater(CraterRef),
    /// Throughput only (short run).
    Speed,
    /// §6 blocks: the time block 2 lands (β first within 5° of 0) against seed 000's
    /// ≈ 0.4 s; arrival and the final β are reported beside it.
    BlockLanding(f64),
    /// §5 incline: distance the first body slid by the end, against the analytic
    /// ½ g (sin θ − μ cos θ) t² (m).
    Slide(f64),
    /// §7 rings: largest change of the total momentum over the run, relative to the
    /// bodies' summed momentum magnitude at the start (2 KE₀ / v₀); reference 0.
    MomentumDrift,
    /// Earth pressure at rest: K = F_x / (½ ρ g H²) of the first barrier at the end,
    /// against the band [K_a, K0]; the reference shown is K0, the error the distance
    /// outside the band relative to K0 (0 inside it).
    EarthPressure(EarthPressureRef),
    /// Resting water: the water's load on the barrier `tank.right` at the end against
    /// ½ ρ_w g H² (N/m in 2D).
    WaterWallLoad(f64),
    /// Dam break of a column a wide (m): the largest relative error of the surge front
    /// Z = x/a against Martin & Moyce (1952) Table 2 (n² = 2) for T = t √(2g/a) ≤ 3;
    /// reference 0.
    DamFront(f64),
    /// Poiseuille flow (seed 001 §2.1): the largest relative error of the water velocity
    /// at the probe `centre` (y = H/2) against the series solution at t = 5, 10, 20 s
    /// and the end; reference 0.
    Poiseuille(PoiseuilleRef),
    /// Resting water: the water's kinetic energy per unit volume (J/m³), averaged over
    /// the last 5 s, against a bound; the error is the excess over the bound relative
    /// to it (0 below it). (water volume m³ or m²/m, bound J/m³).
    RestingEnergy(f64, f64),
    /// A body released in still water: its mean acceleration over its first tenth of a
    /// radius of travel, 2 (R/10)/t², against (ρ_w − ρ_b) g / (ρ_b + C_a ρ_w).
    /// (radius R m, reference m/s²).
    StartingAcceleration(f64, f64),
    /// Seepage column: the largest |q/(k_h i) − 1| of the quasi-steady flow; reference 0.
    Darcy(crate::bench::metric::pores::DarcyRef),
    /// Loaded layer: the largest relative error of the settlement against Terzaghi's
    /// series at U = 50 % and 90 %; reference 0.
    Consolidation(crate::bench::metric::pores::ConsolidationRef),
    /// The final run-out, reported without a reference.
    RunoutReport,
    /// The first sloshing mode of a closed 2D tank (issue 42): the log decrement per
    /// period of the water's horizontal momentum against the physical one (Stokes
    /// layers and interior viscosity); the error is their difference. The period
    /// against linear theory is reported beside it.
    StandingWave(crate::bench::metric::wave::WaveRef),
    /// Lobovský et al. (2014)'s dam break: the largest RMS difference of the water
    /// levels H1–H4 from the experiment's over t √(g/H) ≤ 6, in units of H; reference 0.
    /// Scored with the experiment's series by the bench
    /// ([`metric_lobovsky`](crate::bench::metric::lobovsky)), which reports the sensors'
    /// arrival, mean pressure and peaks beside it.
    Lobovsky,
    /// Rondon et al. (2011)'s submerged collapse of a dense or a loose column: the
    /// largest relative error of the front at the column's checkpoints and at the end
    /// of the data; reference 0. Scored with the experiment's series by the bench
    /// ([`metric_rondon`](crate::bench::metric::rondon)), which reports the basal excess
    /// pressure's sign, extreme and relaxation beside it.
    Rondon(crate::bench::metric::rondon::Column),
    /// SPHinXsys's standing wave (issue 73): the difference of the log decrements per
    /// period of granmix's gauge and SPHinXsys's probe, fitted alike; reference 0.
    /// Scored with SPHinXsys's record by the bench
    /// ([`sphinxsys_wave`](crate::bench::metric::sphinxsys_wave)), which reports both
    /// periods beside it.
    SphinxsysWave,
    /// A μ(I) layer flowing down an incline, periodic along it: its depth-averaged
    /// velocity (momentum over mass) averaged over the last second, against Bagnold's.
    Bagnold(BagnoldRef),
    /// The soil's mechanical energy Σ m (½ v² + g·z) at the end against a reference
    /// (J/m in 2D): SPHinXsys's record of its column collapse.
    SoilEnergy(f64),
    /// A body resting on the floor under water: the mean vertical contact force on the
    /// first body (its force less the water's and the soil's) from time `.0` (s) to the
    /// end, against its weight less its buoyancy `.1` (N/m in 2D).
    RestingContact(f64, f64),
    /// The load along x on the barrier `.0`, averaged over the last `.1` seconds (the
    /// post-peak force of an impact), reported without a reference.
    ForceReport(&'static str, f64),
}

/// An experiment's series a metric is scored against, read from the reference folder.
pub(crate) enum Experiment {
    Lobovsky(crate::bench::metric::lobovsky::Lobovsky),
    Rondon(crate::bench::metric::rondon::Rondon),
    SphinxsysWave(crate::bench::metric::sphinxsys_wave::SphinxsysWave),
}

impl Metric {
    /// Whether the metric holds the run against a reference (an analytic solution, an
    /// experiment or a bound); throughput and reported-only run-outs do not.
    pub(crate) fn has_reference(&self) -> bool {
        !matches!(
            self,
            Metric::Speed | Metric::RunoutReport | Metric::ForceReport(..)
        )
    }
}

/// The added-mass coefficient of the disc in `boulder_in_water.toml` (R = 0.05 m at the
/// centre of a 0.6 m square of water, rigid sides and floor, free surface on top; an
/// impulsive start, φ = 0 on the surface): 1.046765 ± 2e-6, from a potential-flow
/// boundary-element solution (constant panels, 64 to 1024 on the circle, converging
/// as 1/N²; the same code gives 1.0000000 for the unbounded circle). Unbounded, 1.
pub(crate) const DISC_IN_TANK_CA: f64 = 1.046765;

/// The mean acceleration of the first body over its first `radius`/10 of travel from
/// rest, 2 (R/10)/t² with t interpolated between samples; None if it never got there.
pub(crate) fn starting_acceleration(samples: &[Sample], radius: f64) -> Option<f64> {
    let path: Vec<(f64, f64)> = samples
        .iter()
        .filter_map(|s| s.bodies.first().map(|b| (s.time, b.position)))
        .scan(None, |start: &mut Option<[f64; 3]>, (t, p)| {
            let p0 = *start.get_or_insert(p);
            let d =
                ((p[0] - p0[0]).powi(2) + (p[1] - p0[1]).powi(2) + (p[2] - p0[2]).powi(2)).sqrt();
            Some((t, d))
        })
        .collect();
    let goal = 0.1 * radius;
    let k = path.iter().position(|p| p.1 >= goal)?;
    if k == 0 {
        return None;
    }
    let ((t0, d0), (t1, d1)) = (path[k - 1], path[k]);
    let t = t0 + (goal - d0) / (d1 - d0) * (t1 - t0);
    Some(2.0 * goal / (t * t))
}

/// Plates H apart, body acceleration a, kinematic viscosity ν (seed 001 §2.1).
#[derive(Clone, Copy)]
pub(crate) struct PoiseuilleRef {
    pub(crate) accel: f64,
    pub(crate) height: f64,
    pub(crate) nu: f64,
}

impl PoiseuilleRef {
    /// Seed 001 §2.1: a = 1e-4 m/s², H = 0.1 m, ν = 1e-4 m²/s.
    pub(crate) const SEED_001: PoiseuilleRef = PoiseuilleRef {
        accel: 1e-4,
        height: 0.1,
        nu: 1e-4,
    };

    /// u(y, t), seed 001 Eq. (28) (Morris, Fox & Zhu 1997).
    pub(crate) fn velocity(&self, y: f64, t: f64) -> f64 {
        let (a, h, nu, pi) = (self.accel, self.height, self.nu, std::f64::consts::PI);
        let mut u = a / (2.0 * nu) * y * (h - y);
        for n in 0..200 {
            let k = (2 * n + 1) as f64;
            u -= 4.0 * a * h * h / (nu * pi.powi(3) * k.powi(3))
                * (pi * y * k / h).sin()
                * (-k * k * pi * pi * nu * t / (h * h)).exp();
        }
        u
    }

    /// Largest relative error of the probe `centre`'s water velocity against
    /// [`velocity`](Self::velocity) at y = H/2, at t = 5, 10, 20 s and the last sample.
    pub(crate) fn error(&self, samples: &[Sample]) -> Option<f64> {
        let end = samples.last()?.time;
        let mut worst: Option<f64> = None;
        for t in [5.0, 10.0, 20.0, end].into_iter().filter(|&t| t <= end) {
            let s = samples
                .iter()
                .min_by(|a, b| (a.time - t).abs().total_cmp(&(b.time - t).abs()))?;
            let u = s
                .probes
                .iter()
                .find(|p| p.0 == "centre")?
                .1
                .water_velocity?[0];
            let want = self.velocity(0.5 * self.height, s.time);
            worst = Some(worst.unwrap_or(0.0).max((u - want).abs() / want));
        }
        worst
    }
}

/// Martin & Moyce (1952) Table 2, n² = 2, a = 2.25 in: T = t √(2g/a) and Z = x/a.
pub(crate) const MARTIN_MOYCE: [(f64, f64); 13] = [
    (0.41, 1.11),
    (0.84, 1.22),
    (1.19, 1.44),
    (1.43, 1.67),
    (1.63, 1.89),
    (1.83, 2.11),
    (1.98, 2.33),
    (2.20, 2.56),
    (2.32, 2.78),
    (2.51, 3.00),
    (2.65, 3.22),
    (2.83, 3.44),
    (2.98, 3.67),
];

/// Largest relative error of the water front of `samples` against [`MARTIN_MOYCE`]
/// (front interpolated linearly between samples); None if the run ended first.
pub(crate) fn dam_front_error(samples: &[Sample], a: f64) -> Option<f64> {
    let scale = (2.0 * 9.81 / a).sqrt();
    let pts: Vec<(f64, f64)> = samples
        .iter()
        .filter_map(|s| {
            let front = s.water.as_ref()?.front?;
            Some((s.time * scale, front / a))
        })
        .collect();
    let mut worst: f64 = 0.0;
    for (tm, zm) in MARTIN_MOYCE {
        let k = pts.iter().position(|p| p.0 >= tm)?;
        if k == 0 {
            return None;
        }
        let ((t0, z0), (t1, z1)) = (pts[k - 1], pts[k]);
        let z = z0 + (tm - t0) / (t1 - t0) * (z1 - z0);
        worst = worst.max((z - zm).abs() / zm);
    }
    Some(worst)
}

/// A layer of depth `depth` (m) and bulk density φ ρ_s over a period `period` (m) on a
/// slope tan θ = `slope`, of grains of diameter `grain` (m) and density `grain_density`
/// (kg/m³) with μ(I) = μ_s + (μ_2 − μ_s)/(1 + I_0/I).
#[derive(Clone, Copy)]
pub(crate) struct BagnoldRef {
    pub(crate) slope: f64,
    pub(crate) depth: f64,
    pub(crate) period: f64,
    pub(crate) grain: f64,
    pub(crate) grain_density: f64,
    pub(crate) solid_fraction: f64,
    pub(crate) mu: (f64, f64, f64),
}

impl BagnoldRef {
    /// `bagnold_incline.toml`: glass beads (Jop et al. 2006), H = 10 mm, tan θ = 0.42.
    pub(crate) const GLASS_BEADS: BagnoldRef = BagnoldRef {
        slope: 0.42,
        depth: 0.01,
        period: 0.006,
        grain: 5e-4,
        grain_density: 2500.0,
        solid_fraction: 0.6,
        mu: (0.383, 0.643, 0.279),
    };

    /// ū = (2/5) I_θ √(φ g cos θ) H^{3/2}/d, I_θ = I_0 (tan θ − μ_s)/(μ_2 − tan θ)
    /// (GDR MiDi 2004).
    pub(crate) fn mean_velocity(&self) -> f64 {
        let (mu_s, mu_2, i_0) = self.mu;
        let i = i_0 * (self.slope - mu_s) / (mu_2 - self.slope);
        let cos = self.slope.atan().cos();
        0.4 * i * (self.solid_fraction * 9.81 * cos).sqrt() * self.depth.powf(1.5) / self.grain
    }

    /// The layer's depth-averaged velocity over the last second of `samples`.
    pub(crate) fn measured(&self, samples: &[Sample]) -> Option<f64> {
        let end = samples.last()?.time;
        let mass = self.solid_fraction * self.grain_density * self.depth * self.period;
        let tail: Vec<f64> = samples
            .iter()
            .filter(|s| s.time >= end - 1.0)
            .map(|s| s.momentum[0] / mass)
            .collect();
        (!tail.is_empty()).then(|| tail.iter().sum::<f64>() / tail.len() as f64)
    }
}

/// A level layer of height `height` and density `density` behind a vertical barrier,
/// friction angle `phi` (degrees): K_a = (1 − sin φ)/(1 + sin φ), K0 = 1 − sin φ.
#[derive(Clone, Copy)]
pub(crate) struct EarthPressureRef {
    pub(crate) density: f64,
    pub(crate) height: f64,
    pub(crate) phi: f64,
}

impl EarthPressureRef {
    /// (K_a, K0).
    pub(crate) fn band(&self) -> (f64, f64) {
        let s = self.phi.to_radians().sin();
        ((1.0 - s) / (1.0 + s), 1.0 - s)
    }
}

/// The mean of `value` over the samples from time `from` on that have one.
fn mean_from(samples: &[Sample], from: f64, value: impl Fn(&Sample) -> Option<f64>) -> Option<f64> {
    let tail: Vec<f64> = samples
        .iter()
        .filter(|s| s.time >= from)
        .filter_map(value)
        .collect();
    (!tail.is_empty()).then(|| tail.iter().sum::<f64>() / tail.len() as f64)
}

/// How far the first body moved from the first sample to the last.
fn slide(samples: &[Sample]) -> Option<f64> {
    let first = samples.first()?.bodies.first()?;
    let end = samples.last()?.bodies.first()?;
    let d2: f64 = (0..3)
        .map(|k| (end.position[k] - first.position[k]).powi(2))
        .sum();
    Some(d2.sqrt())
}

/// The largest drift of the total momentum from its start, over the momentum scale
/// 2 E_k / |v| of the first body's start.
fn momentum_drift(samples: &[Sample]) -> Option<f64> {
    let s0 = samples.first()?;
    let v0 = s0
        .bodies
        .first()
        .map(|b| b.velocity.iter().map(|x| x * x).sum::<f64>().sqrt())
        .unwrap_or(0.0);
    let scale = 2.0 * s0.coarse_kinetic_energy / v0.max(1e-300);
    let drift = samples
        .iter()
        .map(|s| {
            (0..3)
                .map(|k| (s.momentum[k] - s0.momentum[k]).powi(2))
                .sum::<f64>()
                .sqrt()
        })
        .fold(0.0, f64::max);
    Some(drift / scale.max(1e-300))
}

impl Metric {
    /// (value, reference) of a finished run.
    pub(crate) fn evaluate(&self, rep: &crate::run::RunReport) -> (Option<f64>, Option<f64>) {
        let last = rep.samples.last().cloned().unwrap_or_default();
        match *self {
            Metric::Runout(r) => (Some(last.runout), Some(r)),
            Metric::ProbeSigmaYy(r) => (
                last.probes
                    .iter()
                    .find(|p| p.0 == "mid")
                    .map(|p| p.1.stress.0[1]),
                Some(r),
            ),
            Metric::Crater(r) => (
                last.bodies
                    .first()
                    .map(|b| r.surface - (b.position[2] - r.radius)),
                Some(r.depth()),
            ),
            Metric::Speed => (None, None),
            Metric::BlockLanding(r) => (
                granmix_core::run::observe::block_events(&rep.samples, "block1", "block2").landing,
                Some(r),
            ),
            Metric::Slide(r) => (slide(&rep.samples), Some(r)),
            Metric::MomentumDrift => (momentum_drift(&rep.samples), Some(0.0)),
            Metric::WaterWallLoad(r) => (
                last.barriers
                    .iter()
                    .find(|b| b.name == "tank.right")
                    .map(|b| b.force_water[0]),
                Some(r),
            ),
            Metric::DamFront(a) => (dam_front_error(&rep.samples, a), Some(0.0)),
            Metric::Poiseuille(r) => (r.error(&rep.samples), Some(0.0)),
            Metric::Darcy(r) => (r.error(&rep.samples), Some(0.0)),
            Metric::Consolidation(r) => (r.error(&rep.samples), Some(0.0)),
            Metric::RunoutReport => (Some(last.runout), None),
            // scored by the bench, which holds the experiment's series
            Metric::Lobovsky | Metric::Rondon(_) | Metric::SphinxsysWave => (None, Some(0.0)),
            Metric::Bagnold(r) => (r.measured(&rep.samples), Some(r.mean_velocity())),
            Metric::SoilEnergy(r) => (
                rep.samples
                    .last()
                    .map(|l| l.kinetic_energy + l.potential_energy),
                Some(r),
            ),
            Metric::ForceReport(name, window) => {
                let from = last.time - window - 1e-9;
                let load = |s: &Sample| {
                    s.barriers
                        .iter()
                        .find(|b| b.name == name)
                        .map(|b| b.force[0])
                };
                (mean_from(&rep.samples, from, load), None)
            }
            Metric::RestingContact(from, r) => {
                let contact = |s: &Sample| {
                    let b = s.bodies.first()?;
                    Some(b.force[1] - b.water_force[1] - b.fine_force[1])
                };
                (mean_from(&rep.samples, from - 1e-9, contact), Some(r))
            }
            Metric::StandingWave(r) => (
                crate::bench::metric::wave::WaveRef::fit(&rep.samples).map(|f| f.decrement()),
                Some(r.decrement()),
            ),
            Metric::StartingAcceleration(radius, r) => {
                (starting_acceleration(&rep.samples, radius), Some(r))
            }
            Metric::RestingEnergy(volume, bound) => {
                let energy = |s: &Sample| s.water.as_ref().map(|w| w.kinetic_energy / volume);
                (
                    mean_from(&rep.samples, last.time - 5.0, energy),
                    Some(bound),
                )
            }
            Metric::EarthPressure(r) => {
                let unit = 0.5 * r.density * 9.81 * r.height * r.height;
                (
                    last.barriers.first().map(|b| b.force[0] / unit),
                    Some(r.band().1),
                )
            }
        }
    }

    /// The reference data a metric reads from files (Lobovský's and Rondon's series,
    /// SPHinXsys's probe record), loaded before a run so that a missing file stops the bench at once;
    /// None for the others.
    pub(crate) fn data(&self, scenes: &std::path::Path) -> anyhow::Result<Option<Experiment>> {
        use crate::bench::metric::lobovsky::{reference_dir, Lobovsky};
        match self {
            Metric::Lobovsky => {
                let dir = reference_dir(scenes, "lobovsky2014")?;
                Ok(Some(Experiment::Lobovsky(Lobovsky::load(&dir)?)))
            }
            Metric::Rondon(c) => {
                let dir = reference_dir(scenes, "rondon2011")?;
                Ok(Some(Experiment::Rondon(
                    crate::bench::metric::rondon::Rondon::load(&dir, *c)?,
                )))
            }
            Metric::SphinxsysWave => Ok(Some(Experiment::SphinxsysWave(
                crate::bench::metric::sphinxsys_wave::SphinxsysWave::load(scenes)?,
            ))),
            _ => Ok(None),
        }
    }

    /// [`evaluate`](Self::evaluate), or with the experiment's `data` its score, its
    /// report (a JSON value for the record) and its figure written into `dir`.
    pub(crate) fn scored(
        &self,
        rep: &crate::run::RunReport,
        data: Option<&Experiment>,
        (dir, title): (&std::path::Path, &str),
    ) -> anyhow::Result<(Option<f64>, Option<f64>, Option<serde_json::Value>)> {
        match data {
            Some(Experiment::Lobovsky(l)) => {
                l.plot(&rep.samples, &dir.join("lobovsky.png"), title)?;
                let r = l.report(&rep.samples);
                Ok((r["score"].as_f64(), Some(0.0), Some(r)))
            }
            Some(Experiment::Rondon(d)) => {
                d.plot(&rep.samples, &dir.join("rondon.png"), title)?;
                let r = d.report(&rep.samples);
                Ok((r["score"].as_f64(), Some(0.0), Some(r)))
            }
            Some(Experiment::SphinxsysWave(w)) => {
                w.plot(&rep.samples, &dir.join("sphinxsys_wave.png"), title)?;
                let r = w.report(&rep.samples);
                Ok((r["score"].as_f64(), Some(0.0), Some(r)))
            }
            None => {
                let (v, r) = self.evaluate(rep);
                let detail = match self {
                    Metric::ForceReport(name, _) => Some(force_history(rep, name, dir, title)?),
                    _ => None,
                };
                Ok((v, r, detail))
            }
        }
    }

    /// Relative error of `value` against `reference` (the value itself when the
    /// reference is 0); for a band, the distance outside it relative to its upper end.
    pub(crate) fn error(&self, value: Option<f64>, reference: Option<f64>) -> Option<f64> {
        match (self, value, reference) {
            (Metric::EarthPressure(b), Some(v), _) => {
                let (ka, k0) = b.band();
                Some((ka - v).max(v - k0).max(0.0) / k0)
            }
            (Metric::RestingEnergy(..), Some(v), Some(b)) => Some((v - b).max(0.0) / b),
            (Metric::StandingWave(_), Some(v), Some(r)) => Some((v - r).abs()),
            (_, Some(v), Some(0.0)) => Some(v.abs()),
            (_, Some(v), Some(r)) => Some((v - r).abs() / r.abs()),
            _ => None,
        }
    }
}

/// Eq. (62): D = (0.14/μ) (ρ_b/ρ_g)^½ (2R)^⅔ (H + D)^⅓, with the initial bed surface.
#[derive(Clone, Copy)]
pub(crate) struct CraterRef {
    pub(crate) radius: f64,
    pub(crate) mu: f64,
    pub(crate) height: f64,
    pub(crate) surface: f64,
}

impl CraterRef {
    const RHO_BALL: f64 = 2200.0;
    const RHO_BED: f64 = 1510.0;

    /// Fixed point of Eq. (62) (a contraction: D^⅓ grows slowly).
    pub(crate) fn depth(&self) -> f64 {
        let a = 0.14 / self.mu
            * (Self::RHO_BALL / Self::RHO_BED).sqrt()
            * (2.0 * self.radius).powf(2.0 / 3.0);
        let mut d = 0.0;
        for _ in 0..100 {
            d = a * (self.height + d).cbrt();
        }
        d
    }

    /// Scene overrides of this run.
    pub(crate) fn overrides(&self) -> Vec<String> {
        let v0 = (2.0 * 9.81 * self.height).sqrt();
        vec![
            format!("bodies.0.shape.radius={}", self.radius),
            format!("bodies.0.shape.center.2={}", self.surface + self.radius),
            format!("bodies.0.velocity.2={}", -v0),
            format!("materials.0.friction_angle={}", self.mu.atan().to_degrees()),
        ]
    }
}

/// A resolution label and its scene overrides.
pub(crate) type Level = (String, Vec<String>);

/// VALIDATION §2 at aspect ratio `a`: the levels r0/10, r0/15, r0/20 and r0/25 (the
/// convergence study's finest, VALIDATION §2 decision of 2026-11-25), the column
/// height override and Lube's run-out r∞ = r0 (1 + 1.24 a), r0 = 0.1 m.
pub(crate) fn collapse_3d(a: f64) -> (Vec<Level>, Vec<String>, Metric) {
    let r0 = 0.1;
    (
        [10.0, 15.0, 20.0, 25.0]
            .iter()
            .map(|k| (format!("r0/{k}"), vec![format!("simulation.dp={}", r0 / k)]))
            .collect(),
        vec![format!("regions.0.shape.height={}", a * r0)],
        Metric::Runout(r0 * (1.0 + 1.24 * a)),
    )
}

/// The load on barrier `name` against time, drawn into `dir/force.png` (force along x,
/// and the magnitude), and its peak for the record.
fn force_history(
    rep: &crate::run::RunReport,
    name: &str,
    dir: &std::path::Path,
    title: &str,
) -> anyhow::Result<serde_json::Value> {
    use crate::plot::{panels, Curve, Panel};
    let pts: Vec<(f64, [f64; 3])> = rep
        .samples
        .iter()
        .filter_map(|s| {
            s.barriers
                .iter()
                .find(|b| b.name == name)
                .map(|b| (s.time, b.force))
        })
        .collect();
    let along: Vec<(f64, f64)> = pts.iter().map(|(t, f)| (*t, f[0])).collect();
    let size: Vec<(f64, f64)> = pts
        .iter()
        .map(|(t, f)| (*t, f.iter().map(|x| x * x).sum::<f64>().sqrt()))
        .collect();
    let peak = along
        .iter()
        .copied()
        .fold(None::<(f64, f64)>, |m, p| match m {
            Some(q) if q.1 >= p.1 => Some(q),
            _ => Some(p),
        });
    panels(
        &dir.join("force.png"),
        title,
        "time [s]",
        &[Panel {
            title: format!("load on `{name}`"),
            ylabel: "force [N]".into(),
            curves: vec![
                Curve {
                    label: "along x".into(),
                    points: along,
                },
                Curve {
                    label: "magnitude".into(),
                    points: size,
                },
            ],
            include: Some((0.0, 0.0)),
        }],
    )?;
    Ok(serde_json::json!({
        "barrier": name,
        "peak_force_x": peak.map(|p| p.1),
        "peak_time": peak.map(|p| p.0),
    }))
}

#[cfg(test)]
mod tests {
    use super::*;
    use granmix_core::run::sample::BarrierSample;
    use granmix_core::run::simulation::Sample;

    /// A report whose barrier `wall` carries `loads` (N along x) at t = 0, 0.5, 1, ….
    fn report(loads: &[f64]) -> crate::run::RunReport {
        let samples = loads
            .iter()
            .enumerate()
            .map(|(k, &f)| Sample {
                time: 0.5 * k as f64,
                barriers: vec![BarrierSample {
                    name: "wall".into(),
                    force: [f, 0.0, 0.0],
                    ..Default::default()
                }],
                ..Default::default()
            })
            .collect();
        crate::run::RunReport {
            summary: serde_json::json!({}),
            samples,
            blowup: None,
            particles: 0,
            wall_time: 0.0,
            particle_steps_per_s: 0.0,
            fine_particle_steps_per_s: 0.0,
            layout: Default::default(),
        }
    }

    /// The post-peak force is the mean over the window; the peak and its time go to the
    /// record, the history to force.png.
    #[test]
    fn force_report_takes_the_tail_mean_and_the_peak() {
        let rep = report(&[0.0, 250.0, 120.0, 80.0, 100.0]);
        let m = Metric::ForceReport("wall", 1.0);
        assert_eq!(m.evaluate(&rep), (Some(100.0), None));
        assert!(!m.has_reference());
        let dir = std::env::temp_dir().join(format!("granmix-force-{}", std::process::id()));
        std::fs::create_dir_all(&dir).unwrap();
        let (_, _, detail) = m.scored(&rep, None, (&dir, "test")).unwrap();
        let d = detail.expect("the force record");
        assert_eq!(d["peak_force_x"], 250.0);
        assert_eq!(d["peak_time"], 0.5);
        assert!(dir.join("force.png").is_file());
        std::fs::remove_dir_all(&dir).unwrap();
    }
}
