//! The cases of `granmix bench`: a bundled scene at one or more resolutions, a metric
//! and its reference. One small constructor per family of cases; [`cases`] lists them
//! in the order `granmix bench --list` prints them. The accuracy suite runs every case
//! with a reference ([`crate::bench::accuracy`]).

use crate::bench::metric::pores::{ConsolidationRef, DarcyRef};
use crate::bench::metric::rondon::Column;
use crate::bench::metric::{
    collapse_3d, CraterRef, EarthPressureRef, Level, Metric, DISC_IN_TANK_CA,
};
use crate::bench::soil_model::Model;

pub(crate) struct Case {
    pub(crate) name: String,
    pub(crate) scene: &'static str,
    /// Resolution label and its overrides.
    pub(crate) levels: Vec<Level>,
    /// Overrides shared by all levels.
    pub(crate) common: Vec<String>,
    pub(crate) metric: Metric,
    /// Relative tolerance at the finest level.
    pub(crate) tolerance: Option<f64>,
    pub(crate) note: &'static str,
    /// A soil model put on every material of the scene (the models suite's way), else
    /// the scene's own.
    pub(crate) model: Option<Model>,
}

impl Case {
    /// A case without shared overrides and without a tolerance (reported only).
    fn new(
        name: impl Into<String>,
        scene: &'static str,
        levels: Vec<Level>,
        metric: Metric,
        note: &'static str,
    ) -> Self {
        Case {
            name: name.into(),
            scene,
            levels,
            common: Vec::new(),
            metric,
            tolerance: None,
            note,
            model: None,
        }
    }

    /// With these overrides at every level.
    fn common(mut self, set: Vec<String>) -> Self {
        self.common = set;
        self
    }

    /// Under this soil model instead of the scene's.
    fn model(mut self, model: Model) -> Self {
        self.model = Some(model);
        self
    }

    /// Within this relative error at the finest level.
    fn tolerance(mut self, tolerance: f64) -> Self {
        self.tolerance = Some(tolerance);
        self
    }
}

/// The level `label` at spacing `dp` (m).
fn dp(label: &str, dp: f64) -> Level {
    (label.into(), vec![format!("simulation.dp={dp}")])
}

/// The level `label`: the scene as it is.
fn as_is(label: &str) -> Level {
    (label.into(), Vec::new())
}

fn strings(set: &[&str]) -> Vec<String> {
    set.iter().map(|s| s.to_string()).collect()
}

/// Every case, in the order of `granmix bench --list`.
pub(crate) fn cases() -> Vec<Case> {
    [
        collapses(),
        vec![geostatic(), bagnold(), sphinxsys_collapse(), flume_impact()],
        crater_grid(),
        crater_pairs(),
        vec![blocks(), retained_layer()],
        water(),
        pores(),
        speeds(),
    ]
    .into_iter()
    .flatten()
    .collect()
}

/// Column collapses: 3D at three aspect ratios against Lube 2004, 2D against Lube 2005.
fn collapses() -> Vec<Case> {
    let mut v = Vec::new();
    for a in [0.5, 1.0, 1.5] {
        let (levels, common, metric) = collapse_3d(a);
        v.push(
            Case::new(
                format!("collapse_3d_a{a}"),
                "column_collapse_3d.toml",
                levels,
                metric,
                "Lube et al. 2004: r∞ = r0 (1 + 1.24 a)",
            )
            .common(common)
            .tolerance(0.05),
        );
    }
    let collapse_2d = |name: &str, phi: f64, note| {
        Case::new(
            name,
            "column_collapse_2d.toml",
            vec![dp("dp=4mm", 0.004), dp("dp=2mm", 0.002)],
            Metric::Runout(0.2 * (1.0 + 1.2 * 0.5)),
            note,
        )
        .common(vec![format!("materials.0.friction_angle={phi}")])
    };
    v.push(
        collapse_2d(
            "collapse_2d",
            30.0,
            "Lube et al. 2005 (quasi-2D), φ = 30° as Lube's sands: L∞ = L0 (1 + 1.2 a), ±15 %",
        )
        .tolerance(0.15),
    );
    v.push(collapse_2d(
        "collapse_2d_aluminium",
        21.9,
        "VALIDATION §3 material (φ = 21.9°) against Lube 2005; outside Lube's material range, reported only",
    ));
    v
}

fn geostatic() -> Case {
    Case::new(
        "geostatic",
        "geostatic_layer.toml",
        vec![
            dp("dp=20mm", 0.02),
            dp("dp=10mm", 0.01),
            dp("dp=5mm", 0.005),
        ],
        Metric::ProbeSigmaYy(-2040.0 * 9.81 * 0.1),
        "σ_v = −ρ g (H − z) at mid-depth",
    )
    .common(strings(&["simulation.end_time=1.0"]))
    .tolerance(0.03)
}

/// μ(I) down an incline (`bagnold_incline.toml`): the steady depth-averaged velocity
/// against Bagnold's.
fn bagnold() -> Case {
    Case::new(
        "bagnold_incline",
        "bagnold_incline.toml",
        vec![as_is("H/20"), dp("H/40", 2.5e-4)],
        Metric::Bagnold(crate::bench::metric::BagnoldRef::GLASS_BEADS),
        "μ(I) layer H = 10 mm on tan θ = 0.42, periodic: depth-averaged velocity over the \
         last second against Bagnold's (2/5) I_θ √(φ g cos θ) H^{3/2}/d = 0.08627 m/s",
    )
    .tolerance(0.03)
}

/// SPHinXsys's 2D column collapse (`column_collapse_sphinxsys.toml`, its dp = 2 mm as
/// is): the mechanical energy at 0.8 s against its regression record.
fn sphinxsys_collapse() -> Case {
    Case::new(
        "sphinxsys_collapse",
        "column_collapse_sphinxsys.toml",
        vec![dp("4 mm", 0.004), as_is("2 mm")],
        Metric::SoilEnergy(13.7905),
        "SPHinXsys's column collapse (tests/2d_examples/test_2d_column_collapse, dp = 2 mm): \
         Σ m (½ v² + g y) at 0.8 s against its record, 13.7905 J/m (asked 2 %)",
    )
    .tolerance(0.02)
}

/// Moriguchi et al. (2009)'s flume at 45° (`flume_impact.toml`, seed 001 §5.3): the
/// wall's post-peak force, reported (the experiment's values are not reachable).
fn flume_impact() -> Case {
    Case::new(
        "flume_impact",
        "flume_impact.toml",
        vec![dp("dp=25mm", 0.025), as_is("dp=12.5mm")],
        Metric::ForceReport("wall", 0.5),
        "50 kg of sand down a 45° flume onto a wall 1.8 m below the gate (Moriguchi et al. \
         2009; seed 001 §5.3): the wall's force along the flume over the last 0.5 s (of 2 s), \
         reported; its peak is wall.peak_force in series.csv",
    )
}

/// The crater of R = 0.02 m, μ = 0.3, H = 0.2 m that the pairs and the accuracy suite
/// run.
pub(crate) const CRATER: CraterRef = CraterRef {
    radius: 0.02,
    mu: 0.3,
    height: 0.2,
    surface: 0.1,
};

/// Uehara's craters: two ball radii, two friction coefficients, three drop heights.
fn crater_grid() -> Vec<Case> {
    let mut v = Vec::new();
    for radius in [0.0125, 0.02] {
        for mu in [0.3, 0.5] {
            for height in [0.05, 0.1, 0.2] {
                let r = CraterRef {
                    radius,
                    mu,
                    height,
                    ..CRATER
                };
                v.push(
                    Case::new(
                        format!("crater_R{radius}_mu{mu}_H{height}"),
                        "impact_crater.toml",
                        vec![dp("dp=4mm", 0.004)],
                        Metric::Crater(r),
                        "Uehara et al. 2003, seed 000 Eq. (62); grid mean within 7 %",
                    )
                    .common(r.overrides())
                    .tolerance(0.15),
                );
            }
        }
    }
    v
}

/// One crater under two schemes: multi-rate against single-rate, elastic against rigid.
fn crater_pairs() -> Vec<Case> {
    let pair = |name: &str, key: &str, values: [&str; 2], note| {
        let levels = values
            .iter()
            .map(|x| {
                (
                    x.to_string(),
                    vec!["simulation.dp=0.004".into(), format!("{key}=\"{x}\"")],
                )
            })
            .collect();
        Case::new(
            name,
            "impact_crater.toml",
            levels,
            Metric::Crater(CRATER),
            note,
        )
        .common(CRATER.overrides())
        .tolerance(0.15)
    };
    vec![
        pair(
            "crater_schemes",
            "simulation.time_stepping",
            ["multi-rate", "single-rate"],
            "multi-rate against single-rate, seed 000 Table 3 (6.5× at κ = 9, dp = 4 mm)",
        ),
        pair(
            "crater_models",
            "bodies.0.model",
            ["elastic", "rigid"],
            "rigid against elastic ball: depth within 3 %",
        ),
    ]
}

fn blocks() -> Case {
    Case::new(
        "blocks",
        "blocks_impact.toml",
        vec![as_is("dp=1.25mm")],
        Metric::BlockLanding(0.4),
        "seed 000 Figs. 13–14: flow arrives ≈ 0.25 s, block 2 lands ≈ 0.4 s (±0.02 s), β → 0°",
    )
    .tolerance(0.05)
}

fn retained_layer() -> Case {
    Case::new(
        "retained_layer",
        "retained_layer_2d.toml",
        vec![
            dp("dp=7.5mm", 0.0075),
            dp("dp=5mm", 0.005),
            dp("dp=3.75mm", 0.00375),
        ],
        Metric::EarthPressure(EarthPressureRef {
            density: 2040.0,
            height: 0.15,
            phi: 30.0,
        }),
        "layer built quasi-statically: K at 3 s within [K_a, K0] (Rankine, Jaky)",
    )
    .tolerance(0.0)
}

/// Water alone: the resting tank, the dam break, Poiseuille flow.
/// The resting tank (H = 0.5 m, dp = 20 mm) run to 30 s: its kinetic energy per volume over
/// 25–30 s against 1e-8 ρ_w g H², with the scheme's options in `extra`.
fn resting_tank(name: &'static str, note: &'static str, extra: &[&str]) -> Case {
    let mut set = strings(&["simulation.end_time=30.0", "simulation.output_interval=0.5"]);
    set.extend(strings(extra));
    Case::new(
        name,
        "hydrostatic_tank.toml",
        vec![dp("dp=20mm", 0.02)],
        Metric::RestingEnergy(0.25, 1e-8 * 1000.0 * 9.81 * 0.25),
        note,
    )
    .common(set)
    .tolerance(0.0)
}

/// A disc of 2 ρ_w (R = 0.05 m) resting on the floor under water,
/// `disc_resting_in_water.toml` (released 0.1 dp above the floor at every level, the
/// water settling over its first 0.2 s): the mean contact force over 0.25–0.35 s against
/// W − ρ_w g V (issue 42's 2 %).
fn resting_disc() -> Case {
    let r: f64 = 0.05;
    let level = |label: &str, n: f64| -> Level {
        let dp = r / n;
        (
            label.into(),
            vec![
                format!("simulation.dp={dp}"),
                format!("bodies.0.shape.center=[0.15,{}]", r + 0.1 * dp),
            ],
        )
    };
    Case::new(
        "resting_disc",
        "disc_resting_in_water.toml",
        vec![
            level("R/10", 10.0),
            level("R/20", 20.0),
            level("R/40", 40.0),
        ],
        Metric::RestingContact(
            0.25,
            (2000.0 - 1000.0) * 9.81 * std::f64::consts::PI * r * r,
        ),
        "disc of 2 ρ_w resting on the floor under water: mean contact force over 0.25–0.35 s \
         against W − ρ_w g V (asked 2 %)",
    )
    .tolerance(0.02)
}

fn water() -> Vec<Case> {
    vec![
        Case::new(
            "water_tank",
            "hydrostatic_tank.toml",
            vec![as_is("dp=10mm")],
            Metric::WaterWallLoad(0.5 * 1000.0 * 9.81 * 0.25),
            "resting tank H = 0.5 m: side-wall load ½ ρ_w g H² at 3 s",
        )
        .common(strings(&["simulation.end_time=3.0"]))
        .tolerance(0.01),
        resting_tank(
            "water_tank_rest",
            "resting tank H = 0.5 m, settled: kinetic energy per volume over 25–30 s under 1e-8 ρ_w g H²",
            &[],
        ),
        resting_tank(
            "water_tank_rest_muscl",
            "resting tank H = 0.5 m with the MUSCL reconstruction of the dissipation (water.muscl): kinetic energy per volume over 25–30 s under 1e-8 ρ_w g H²",
            &["water.muscl=true"],
        ),
        Case::new(
            "rising_disc",
            "boulder_in_water.toml",
            vec![
                dp("R/10", 0.005),
                dp("R/20", 0.0025),
                dp("R/40", 0.00125),
            ],
            Metric::StartingAcceleration(0.05, 500.0 * 9.81 / (500.0 + DISC_IN_TANK_CA * 1000.0)),
            "disc of ρ_w/2 released in still water: mean acceleration over R/10 against \
             (ρ_w − ρ_b) g/(ρ_b + C_a ρ_w), C_a = 1.0468 in this tank (1 unbounded; \
             asked 5 % at R/20)",
        )
        .common(strings(&["simulation.end_time=0.065"]))
        .tolerance(0.05),
        resting_disc(),
        Case::new(
            "dam_break_2d",
            "dam_break_2d.toml",
            vec![as_is("a/40")],
            Metric::DamFront(0.05715),
            "surge front against Martin & Moyce (1952) n² = 2, T ≤ 3 (largest error)",
        )
        .tolerance(0.05),
        Case::new(
            "standing_wave",
            "standing_wave_2d.toml",
            vec![
                dp("dp=h/25", 0.02),
                dp("dp=h/50", 0.01),
                dp("dp=h/100", 0.005),
            ],
            Metric::StandingWave(crate::bench::metric::wave::WaveRef::TANK),
            "first sloshing mode, h = 0.5 m, L = 1 m: log decrement per period against the \
             physical 1.95e-3 (error: their difference, asked ≤ 0.05), period against linear \
             theory (asked 1 %)",
        )
        .tolerance(0.05),
        Case::new(
            "sphinxsys_standing_wave",
            "sphinxsys_standing_wave.toml",
            vec![dp("H/25", 0.04), dp("H/50", 0.02)],
            Metric::SphinxsysWave,
            "SPHinXsys's standing wave, H = 1 m, L = 2 m, A = 0.1 m, inviscid, 10 s: log \
             decrement per period of the gauge at the antinode against SPHinXsys's probe \
             at H/50 (0.016), fitted alike (error: their difference, asked ≤ 0.01); \
             sphinxsys_wave.png",
        )
        .tolerance(0.01),
        Case::new(
            "lobovsky",
            "lobovsky_dam_break.toml",
            vec![
                dp("H/40", 0.0075),
                dp("H/80", 0.00375),
                dp("H/160", 0.001875),
            ],
            Metric::Lobovsky,
            "dam break H = 0.3 m against Lobovsky et al. (2014): largest RMS of the water \
             levels H1–H4 over t √(g/H) ≤ 6 in units of H (asked ≤ 0.05); sensor 1's arrival \
             and mean pressure beside it (lobovsky.png)",
        )
        .tolerance(0.05),
        Case::new(
            "poiseuille_2d",
            "poiseuille_2d.toml",
            vec![as_is("H/40")],
            Metric::Poiseuille(crate::bench::metric::PoiseuilleRef::SEED_001),
            "seed 001 §2.1: centreline velocity against Morris et al. (1997), t = 5, 10, 20, 80 s",
        )
        .tolerance(0.02),
    ]
}

/// Soils with pores: seepage, a submerged layer, consolidation, a saturated collapse.
fn pores() -> Vec<Case> {
    vec![
        Case::new(
            "seepage_column",
            "seepage_column.toml",
            vec![as_is("dp=10mm")],
            Metric::Darcy(DarcyRef::COLUMN),
            "U-tube permeameter, upward flow i ≈ 0.7: discharge against Darcy q = k_h i (largest error, t ≥ 0.3 s)",
        )
        .tolerance(0.03),
        Case::new(
            "submerged_layer",
            "submerged_layer.toml",
            vec![as_is("H/30")],
            Metric::ProbeSigmaYy(-(1600.0 + 0.4 * 1000.0 - 1000.0) * 9.81 * 0.15),
            "saturated layer at rest: effective σ_v at mid-depth against ρ' g H/2",
        )
        .tolerance(0.03),
        Case::new(
            "consolidation",
            "consolidation_layer.toml",
            vec![as_is("H/10")],
            Metric::Consolidation(ConsolidationRef::LAYER),
            "Terzaghi: settlement against the series at U = 50 % and 90 %",
        )
        .common(strings(&[
            "simulation.end_time=0.6",
            "simulation.output_interval=0.001",
        ]))
        .tolerance(0.05),
        Case::new(
            "saturated_collapse_2d",
            "saturated_collapse_2d.toml",
            vec![
                as_is("saturated"),
                ("dry".into(), strings(&["materials[0].saturated=false"])),
            ],
            Metric::RunoutReport,
            "2D collapse a = 0.5, 5000 grains (+ 5000 pore water): run-out, saturated beside dry",
        ),
        Case::new(
            "rondon_dense",
            "submerged_collapse_dense.toml",
            vec![dp("dp=4mm", 0.004)],
            Metric::Rondon(Column::Dense),
            "Rondon et al. (2011), dense column (φ0 = 0.60) in a viscous fluid: front against \
             the data at 2, 5, 10 s and at the end (asked 15 %); basal excess pressure's \
             sign, extreme (−126 Pa) and relaxation by 30 s beside it (rondon.png)",
        )
        .tolerance(0.15),
        Case::new(
            "rondon_loose",
            "submerged_collapse_loose.toml",
            vec![dp("dp=4mm", 0.004)],
            Metric::Rondon(Column::Loose),
            "Rondon et al. (2011), loose column (φ0 = 0.55) in a viscous fluid: front against \
             the data at 1, 2 s and at the end (asked 15 %); basal excess pressure's sign, \
             extreme (+144 Pa) and relaxation by 20 s beside it (rondon.png)",
        )
        .tolerance(0.15),
    ]
}

/// Throughput cases: no reference, particle-steps per second and the stage table.
fn speeds() -> Vec<Case> {
    let speed = |name: &str, scene, level: Level, common: &[&str], note| {
        Case::new(name, scene, vec![level], Metric::Speed, note).common(strings(common))
    };
    let first_015_s = ["simulation.end_time=0.15", "simulation.settle_ratio=0.5"];
    vec![
        speed(
            "speed_saturated_2d",
            "saturated_collapse_2d.toml",
            as_is("dp=2mm"),
            &first_015_s,
            "saturated 2D collapse, 5000 grains + 5000 pore water, first 0.15 s",
        ),
        speed(
            "debris_flow_saturated",
            "debris_flow_saturated.toml",
            as_is("dp=20mm"),
            &[],
            "saturated debris flow with 3 boulders into a barrier, 2D, to rest",
        ),
        speed(
            "speed_water_2d",
            "dam_break_2d.toml",
            as_is("a/40"),
            &[],
            "2D dam break, 3200 water particles, T ≤ 3.15",
        ),
        speed(
            "speed_water_3d",
            "dam_break_3d.toml",
            as_is("a/20"),
            &[],
            "3D dam break, 8000 water particles, T ≤ 3.15",
        ),
        speed(
            "speed_2d",
            "column_collapse_2d.toml",
            dp("dp=2mm", 0.002),
            &first_015_s,
            "2D collapse, 5000 particles, first 0.15 s",
        ),
        speed(
            "speed_3d",
            "column_collapse_3d.toml",
            dp("r0/20", 0.005),
            &["simulation.end_time=0.05"],
            "3D collapse a = 1, 25 k particles, first 0.05 s",
        ),
        speed(
            "speed_2d_mu_i",
            "column_collapse_2d.toml",
            dp("dp=2mm", 0.002),
            &first_015_s,
            "speed_2d under μ(I) (the models suite's rule): its cost over Drucker–Prager",
        )
        .model(Model::MuI),
        speed(
            "speed_3d_mu_i",
            "column_collapse_3d.toml",
            dp("r0/20", 0.005),
            &["simulation.end_time=0.05"],
            "speed_3d under μ(I) (the models suite's rule): its cost over Drucker–Prager",
        )
        .model(Model::MuI),
        speed(
            "speed_debris",
            "debris_barrier.toml",
            as_is("dp=0.125m"),
            &[],
            "3D debris flow, 8.3 k fine particles and five rigid boulders into a slit dam (coupling and contact on), the whole 6 s",
        ),
    ]
}
