//! The series of `granmix bench --suite accuracy`: a case under one scheme at three or
//! more resolutions, coarsest first. One small constructor per family of series;
//! [`series`] lists them in the report's order, then every bench case with a
//! reference that they do not run, at the bench's own levels.

use crate::bench::cases::{cases, CRATER};
use crate::bench::metric::{collapse_3d, Level, Metric, DISC_IN_TANK_CA};

/// One curve: a case under one scheme at several resolutions.
pub(crate) struct Series {
    pub(crate) case: String,
    pub(crate) scheme: String,
    pub(crate) scene: &'static str,
    /// Resolution label and its overrides, coarsest first.
    pub(crate) levels: Vec<Level>,
    pub(crate) common: Vec<String>,
    pub(crate) metric: Metric,
    pub(crate) note: &'static str,
}

impl Series {
    /// A series without shared overrides.
    fn new(
        case: impl Into<String>,
        scheme: &str,
        scene: &'static str,
        levels: Vec<Level>,
        metric: Metric,
        note: &'static str,
    ) -> Self {
        Series {
            case: case.into(),
            scheme: scheme.into(),
            scene,
            levels,
            common: Vec::new(),
            metric,
            note,
        }
    }

    /// With these overrides at every level.
    fn common(mut self, set: Vec<String>) -> Self {
        self.common = set;
        self
    }
}

/// Levels at the spacings `dps` (m), labelled in `unit` (m) and `name` ("8 mm").
fn dp_levels(dps: &[f64], unit: f64, name: &str) -> Vec<Level> {
    dps.iter()
        .map(|d| {
            (
                format!("{}{name}", d / unit),
                vec![format!("simulation.dp={d}")],
            )
        })
        .collect()
}

/// Levels at fractions `ns` of a length `of` (m), labelled `name/n` ("a/40").
fn fractions(name: &str, of: f64, ns: &[f64]) -> Vec<Level> {
    ns.iter()
        .map(|n| {
            (
                format!("{name}/{n}"),
                vec![format!("simulation.dp={}", of / n)],
            )
        })
        .collect()
}

/// Every series, in the report's order.
pub(crate) fn series() -> Vec<Series> {
    let mut v: Vec<Series> = [
        collapses(),
        craters(),
        vec![incline()],
        water(),
        vec![rubber_rings()],
    ]
    .into_iter()
    .flatten()
    .collect();
    v.extend(bench_cases_not_covered(&v));
    v
}

/// Column collapses (3D at three aspect ratios, 2D) and the geostatic layer.
fn collapses() -> Vec<Series> {
    let mut v: Vec<Series> = [0.5, 1.0, 1.5]
        .into_iter()
        .map(|a| {
            let (levels, common, metric) = collapse_3d(a);
            Series::new(
                format!("collapse_3d_a{a}"),
                "single-rate",
                "column_collapse_3d.toml",
                levels,
                metric,
                "Lube et al. 2004: r∞ = r0 (1 + 1.24 a)",
            )
            .common(common)
        })
        .collect();
    v.push(
        Series::new(
            "collapse_2d",
            "single-rate",
            "column_collapse_2d.toml",
            dp_levels(&[0.008, 0.004, 0.002], 0.001, " mm"),
            Metric::Runout(0.2 * (1.0 + 1.2 * 0.5)),
            "Lube et al. 2005 (quasi-2D), φ = 30°: L∞ = L0 (1 + 1.2 a)",
        )
        .common(vec!["materials.0.friction_angle=30".into()]),
    );
    v.push(
        Series::new(
            "geostatic",
            "single-rate",
            "geostatic_layer.toml",
            dp_levels(&[0.02, 0.01, 0.005], 0.001, " mm"),
            Metric::ProbeSigmaYy(-2040.0 * 9.81 * 0.1),
            "σ_v = −ρ g (H − z) at mid-depth",
        )
        .common(vec!["simulation.end_time=1.0".into()]),
    );
    v
}

/// The crater of R = 0.02 m, μ = 0.3, H = 0.2 m under three schemes.
fn craters() -> Vec<Series> {
    [
        ("multi-rate, elastic", None),
        (
            "single-rate, elastic",
            Some("simulation.time_stepping=\"single-rate\""),
        ),
        ("multi-rate, rigid", Some("bodies.0.model=\"rigid\"")),
    ]
    .into_iter()
    .map(|(scheme, set)| {
        let mut common = CRATER.overrides();
        common.extend(set.map(String::from));
        Series::new(
            "crater_R0.02_mu0.3_H0.2",
            scheme,
            "impact_crater.toml",
            dp_levels(&[0.006, 0.005, 0.004], 0.001, " mm"),
            Metric::Crater(CRATER),
            "Uehara et al. 2003, seed 000 Eq. (62)",
        )
        .common(common)
    })
    .collect()
}

/// A block sliding down a 30° incline against ½ g (sin θ − μ cos θ) t².
fn incline() -> Series {
    let g = 9.81_f64;
    let (theta, mu, t) = (30f64.to_radians(), 0.3, 0.5);
    let slide = 0.5 * g * (theta.sin() - mu * theta.cos()) * t * t;
    Series::new(
        "incline",
        "rigid",
        "incline_block.toml",
        dp_levels(&[0.02, 0.01, 0.005], 0.001, " mm"),
        Metric::Slide(slide),
        "½ g (sin θ − μ cos θ) t², θ = 30°, μ = 0.3, t = 0.5 s",
    )
}

/// Water: the resting tank, a rising disc, the dam breaks, Poiseuille flow.
fn water() -> Vec<Series> {
    let a = 0.05715;
    let dam_break = |case: &str, scene, ns: &[f64]| {
        Series::new(
            case,
            "water",
            scene,
            fractions("a", a, ns),
            Metric::DamFront(a),
            "largest error of the surge front against Martin & Moyce (1952), T ≤ 3",
        )
    };
    vec![
        Series::new(
            "water_tank",
            "water",
            "hydrostatic_tank.toml",
            dp_levels(&[0.02, 0.01, 0.005], 0.001, " mm"),
            Metric::WaterWallLoad(0.5 * 1000.0 * 9.81 * 0.25),
            "resting tank H = 0.5 m: side-wall load ½ ρ_w g H²",
        )
        .common(vec!["simulation.end_time=3.0".into()]),
        Series::new(
            "water_tank_rest",
            "water",
            "hydrostatic_tank.toml",
            dp_levels(&[0.04, 0.02, 0.01], 0.001, " mm"),
            Metric::RestingEnergy(0.25, 1e-8 * 1000.0 * 9.81 * 0.25),
            "resting tank H = 0.5 m: kinetic energy per volume over 25–30 s under 1e-8 ρ_w g H²",
        )
        .common(vec![
            "simulation.end_time=30.0".into(),
            "simulation.output_interval=0.5".into(),
        ]),
        Series::new(
            "rising_disc",
            "water",
            "boulder_in_water.toml",
            fractions("R", 0.05, &[10.0, 20.0, 40.0]),
            Metric::StartingAcceleration(0.05, 500.0 * 9.81 / (500.0 + DISC_IN_TANK_CA * 1000.0)),
            "disc of ρ_w/2 released in still water: mean acceleration over R/10 against (ρ_w − ρ_b) g/(ρ_b + C_a ρ_w), C_a = 1.0468 in this tank",
        )
        .common(vec!["simulation.end_time=0.065".into()]),
        dam_break("dam_break_2d", "dam_break_2d.toml", &[20.0, 40.0, 80.0]),
        dam_break("dam_break_3d", "dam_break_3d.toml", &[10.0, 15.0, 20.0]),
        Series::new(
            "poiseuille_2d",
            "water",
            "poiseuille_2d.toml",
            fractions("H", 0.1, &[20.0, 40.0, 80.0]),
            Metric::Poiseuille(crate::bench::metric::PoiseuilleRef::SEED_001),
            "seed 001 §2.1: centreline velocity against Morris et al. (1997), t = 5, 10, 20, 80 s",
        ),
    ]
}

/// Rubber rings colliding: the total momentum's drift.
fn rubber_rings() -> Series {
    Series::new(
        "rubber_rings",
        "multi-rate, elastic",
        "rubber_rings.toml",
        dp_levels(&[0.001, 0.0007, 0.0005], 0.001, " mm"),
        Metric::MomentumDrift,
        "total momentum conserved: drift relative to Σ|p| at the start",
    )
}

/// Bench cases whose runs the accuracy suite makes under another name: the crater of
/// R = 0.02 m, μ = 0.3, H = 0.2 m runs under all three schemes there.
pub(crate) const COVERED_BY: [(&str, &str); 2] = [
    ("crater_schemes", "crater_R0.02_mu0.3_H0.2"),
    ("crater_models", "crater_R0.02_mu0.3_H0.2"),
];

/// Every `granmix bench` case with a reference that the series above do not run,
/// at the bench's own levels and under the scene's own scheme, so that the report
/// covers every case with a reference (issue 39).
fn bench_cases_not_covered(explicit: &[Series]) -> Vec<Series> {
    cases()
        .into_iter()
        .filter(|c| c.metric.has_reference())
        .filter(|c| !explicit.iter().any(|s| s.case == c.name))
        .filter(|c| !COVERED_BY.iter().any(|(name, _)| *name == c.name))
        .map(|c| Series {
            case: c.name,
            scheme: "scene default".into(),
            scene: c.scene,
            levels: c.levels,
            common: c.common,
            metric: c.metric,
            note: c.note,
        })
        .collect()
}
