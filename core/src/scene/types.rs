//! The scene file schema (TOML). Units are SI, angles in degrees.
//! Documented for users in `docs/scenes.md`; keep the two in step.

use super::soil_model::{DilatancySpec, HardeningSpec, MuISpec, YieldSurface};
use crate::numerics::math::Real;
use nalgebra::{Rotation3, Vector3};
use serde::Deserialize;

/// A whole scene: one simulation, its materials, particle regions, walls and outputs.
#[derive(Debug, Clone, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct Scene {
    pub simulation: SimulationSpec,
    #[serde(default)]
    pub numerics: NumericsSpec,
    #[serde(default)]
    pub materials: Vec<MaterialSpec>,
    #[serde(default)]
    pub regions: Vec<RegionSpec>,
    /// The water family (`[water]`, with its `[[water.regions]]`).
    #[serde(default)]
    pub water: Option<super::WaterSpec>,
    /// Coarse-grain (boulder) materials.
    #[serde(default)]
    pub solids: Vec<SolidSpec>,
    /// Coarse grains: rigid or elastic bodies.
    #[serde(default)]
    pub bodies: Vec<BodySpec>,
    /// Randomly placed rocks of random convex shape (2D), expanded into `bodies` at load.
    #[serde(default)]
    pub rock_fills: Vec<RockFillSpec>,
    #[serde(default)]
    pub contact: ContactSpec,
    #[serde(default)]
    pub walls: Vec<WallSpec>,
    #[serde(default)]
    pub containers: Vec<ContainerSpec>,
    #[serde(default)]
    pub barriers: Vec<WallSpec>,
    #[serde(default)]
    pub probes: Vec<ProbeSpec>,
    #[serde(default)]
    pub gauges: Vec<GaugeSpec>,
    #[serde(default)]
    pub observe: ObserveSpec,
    /// Meshes and terrain grids read from files named by shapes (filled by the loader).
    #[serde(skip)]
    pub assets: crate::shapes::assets::Assets,
    /// What each `[[rock_fills]]` entry placed (filled by the loader).
    #[serde(skip)]
    pub rock_reports: Vec<RockFillReport>,
}

/// `[simulation]`: dimension, gravity, resolution, time span and stability bounds.
#[derive(Debug, Clone, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct SimulationSpec {
    /// Free-text name used in reports.
    #[serde(default)]
    pub name: Option<String>,
    /// 2 (plane strain) or 3.
    pub dimension: usize,
    /// Gravitational acceleration (m/s²), one component per dimension.
    pub gravity: Vec<f64>,
    /// Physical end time (s).
    pub end_time: f64,
    /// Initial particle spacing dp (m).
    pub dp: f64,
    /// CFL number of Eq. (51). Default 0.4.
    #[serde(default = "default_cfl")]
    pub cfl: f64,
    /// Interval between snapshots and time-series rows (s).
    pub output_interval: f64,
    /// Speed bound (m/s): any particle faster than this stops the run. Default 100.
    #[serde(default = "default_max_speed")]
    pub max_speed: f64,
    /// Stop early once the kinetic energy has fallen below this fraction of its peak
    /// (checked at output times after `settle_min_time`). Off by default.
    #[serde(default)]
    pub settle_ratio: Option<f64>,
    /// Earliest time (s) at which the settle criterion may stop the run. Default 0.
    #[serde(default)]
    pub settle_min_time: f64,
    /// Gravity rises smoothly from 0 to its full value over this time (s),
    /// g(t) = g ½(1 − cos(π t/T)), to build a resting state quasi-statically. 0: off.
    #[serde(default)]
    pub gravity_ramp: f64,
    /// The kinetic energy must stay below `settle_ratio` × peak over this long (s)
    /// before the run counts as settled. Default 0.1 s.
    #[serde(default = "default_settle_window")]
    pub settle_window: f64,
    /// `"multi-rate"` (κ coarse sub-steps per fine step, Eqs. 51–60) or `"single-rate"`
    /// (one Δt = min(Δt_f, Δt_c) for all, Eq. 53). Default multi-rate.
    #[serde(default)]
    pub time_stepping: TimeStepping,
    /// CFL number of the coarse step, Eq. (52). Default 0.4.
    #[serde(default = "default_cfl")]
    pub cfl_coarse: f64,
    /// Memory budget (bytes): a scene whose estimated memory exceeds it is refused
    /// before any particle is built. 0 (default): 80 % of the machine's available memory.
    #[serde(default)]
    pub memory_budget: f64,
    /// Where a set `memory_budget` came from, as messages name it: the scene key
    /// (`None`), or what the caller gave it as (e.g. `--memory-budget` on the command
    /// line, the FMU parameter `memory_budget`). Not a scene key.
    #[serde(skip)]
    pub memory_budget_origin: Option<String>,
    /// A periodic axis: the domain repeats between `min` and `max` along it (water
    /// scenes, e.g. channel flow between plates). Off by default.
    #[serde(default)]
    pub periodic: Option<PeriodicSpec>,
    /// A seeded displacement of every soil and water particle's start by
    /// `amplitude`·dp: an ensemble member (docs/sweeps.md, *Ensembles*). Off by default.
    #[serde(default)]
    pub perturbation: Option<PerturbationSpec>,
}

/// `simulation.perturbation`: the seed of the directions and the distance, in dp.
#[derive(Debug, Clone, Deserialize, PartialEq)]
#[serde(deny_unknown_fields)]
pub struct PerturbationSpec {
    /// Decides every particle's direction; members of an ensemble differ by it alone.
    pub seed: u64,
    /// The distance each particle moves, as a fraction ε of dp, in (0, 0.5). Default
    /// 1e-6.
    #[serde(default = "default_perturbation_amplitude")]
    pub amplitude: f64,
}

/// ε = 1e-6: far below any physical length of a scene, far above round-off.
pub fn default_perturbation_amplitude() -> f64 {
    1e-6
}

/// `simulation.periodic`: the periodic axis and the period's two planes.
#[derive(Debug, Clone, Deserialize, PartialEq)]
#[serde(deny_unknown_fields)]
pub struct PeriodicSpec {
    /// `"x"`, `"y"` or (3D) `"z"`.
    pub axis: String,
    /// The planes bounding one period along the axis (m); max − min is a whole number
    /// of dp.
    pub min: f64,
    pub max: f64,
}

impl SimulationSpec {
    /// |g| (m/s²); 0 without gravity.
    pub fn gravity_norm(&self) -> f64 {
        self.gravity.iter().map(|x| x * x).sum::<f64>().sqrt()
    }

    /// The scheme as written in scene files.
    pub fn time_stepping_name(&self) -> &'static str {
        match self.time_stepping {
            TimeStepping::MultiRate => "multi-rate",
            TimeStepping::SingleRate => "single-rate",
        }
    }
}

/// Time-stepping scheme of fine and coarse grains.
#[derive(Debug, Clone, Copy, serde::Serialize, Deserialize, PartialEq, Eq, Default)]
#[serde(rename_all = "kebab-case")]
pub enum TimeStepping {
    #[default]
    MultiRate,
    SingleRate,
}

fn one() -> f64 {
    1.0
}
fn default_cfl() -> f64 {
    0.4
}
fn default_settle_window() -> f64 {
    0.1
}
fn default_max_speed() -> f64 {
    100.0
}

/// `[numerics]`: method coefficients; defaults follow seed 000.
#[derive(Debug, Clone, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct NumericsSpec {
    /// Dissipation-limiter coefficient η of Eq. (23). Default 20·d.
    #[serde(default)]
    pub eta: Option<f64>,
    /// MUSCL reconstruction of the fine grains' Riemann dissipation: each pair's
    /// velocities taken to its midpoint with the velocity gradient of the last sweep,
    /// minmod-limited, so that a resolved (linear) shear is not dissipated. Default
    /// false.
    #[serde(default)]
    pub muscl: bool,
    /// Stress-diffusion coefficient ζ of Eq. (25). Default 0.1; 0 switches it off.
    #[serde(default = "default_zeta")]
    pub stress_diffusion: f64,
    /// ξ of the accumulated hourglass penalty (stiffness ξ G on the non-affine
    /// displacement of elastic particles). Default 0.1; 0 gives seed 000's scheme.
    #[serde(default = "default_hourglass")]
    pub hourglass: f64,
    /// Relaxation time of the stored hourglass penalty in acoustic times h/c0: each
    /// fine step keeps exp(−Δt c0 / (N h)) of it, so that a deposit at rest carries
    /// its load by its stress alone. Default 100.
    #[serde(default = "default_hourglass_memory")]
    pub hourglass_memory: f64,
    /// Smoothing length over particle spacing, h/dp. Default 1.3.
    #[serde(default = "default_h_ratio")]
    pub smoothing_ratio: f64,
    /// Exponent n of the artificial-stress factor f_ij^n, Eq. (27). Default 2.55.
    #[serde(default = "default_as_n")]
    pub artificial_stress_exponent: f64,
    /// ε of Eq. (30). Default 0.5.
    #[serde(default = "default_as_eps")]
    pub artificial_stress_epsilon: f64,
    /// Verlet-list skin in units of dp. Default 0.3.
    #[serde(default = "default_skin")]
    pub neighbor_skin: f64,
    /// Layers of dummy wall particles. Default 4.
    #[serde(default = "default_layers")]
    pub wall_layers: usize,
    /// Coulomb friction coefficient of fine grains sliding on walls, bounding the
    /// tangential wall force by μ_w times the normal one. Default 0 (seed 000's walls).
    #[serde(default)]
    pub wall_friction: f64,
    /// Pressure in the jump term of Eq. (19) as the continuity equation uses it.
    #[serde(default)]
    pub continuity_jump: ContinuityJump,
    /// Deviatoric stress of the dummy wall particles (Eqs. 32–35).
    #[serde(default)]
    pub wall_stress: WallStress,
    /// Hold each soil's density at or above its density at the apex of the yield cone,
    /// ρ0 (1 − p_t/K) with p_t = k_c/(3α_φ) (ρ0 for a cohesionless soil): the
    /// volumetric counterpart of the tension cut-off of Eq. (11). Default true; false
    /// integrates the continuity equation alone.
    #[serde(default = "default_density_floor")]
    pub density_floor: bool,
    /// The seepage drag of each soil–water pair against the soil's velocity at the
    /// pair's midpoint (its velocity gradients), instead of the soil particle's own.
    /// Default false.
    #[serde(default)]
    pub seepage_midpoint: bool,
    /// Resting fine grains sleep: a particle whose speed, change of speed per step
    /// and velocity gradient stay below `sleep_speed`, `sleep_speed / sleep_steps`
    /// and `sleep_speed / h` for `sleep_steps` steps is frozen until a restless
    /// neighbour, a coarse grain, a barrier or a moving wall wakes it
    /// (docs/method.md §Sleep). Default false.
    #[serde(default)]
    pub sleep: bool,
    /// The speed below which a particle may rest (m/s). Default 0.005 √(g dp).
    #[serde(default)]
    pub sleep_speed: Option<f64>,
    /// The acceleration below which a particle may rest (m/s²). Default |g|.
    #[serde(default)]
    pub sleep_acceleration: Option<f64>,
    /// Consecutive quiet steps before a particle sleeps. Default 100.
    #[serde(default)]
    pub sleep_steps: Option<u32>,
}

/// The deviatoric stress a dummy wall particle carries against a fine particle; its
/// pressure is always Eq. (35)'s, P_w = P_i + ρ_i r max(0, g·(r_w − r_i)/r).
#[derive(Debug, Clone, Copy, serde::Serialize, Deserialize, PartialEq, Eq, Default)]
#[serde(rename_all = "kebab-case")]
pub enum WallStress {
    /// The particle's deviatoric stress at the same share of the Drucker–Prager
    /// strength (Eq. 4) at the wall's pressure as the particle uses at its own:
    /// the stress extrapolated to the wall as Eq. (35) extrapolates the pressure.
    #[default]
    Extrapolated,
    /// The particle's own deviatoric stress (seed 000's mirror).
    Mirrored,
}

/// Which pressure enters the jump (P_L − P_R) of Eq. (19) in the continuity equation
/// (the momentum equation always uses the stress).
#[derive(Debug, Clone, Copy, serde::Serialize, Deserialize, PartialEq, Eq, Default)]
#[serde(rename_all = "kebab-case")]
pub enum ContinuityJump {
    /// K (ρ/ρ0 − 1), from the particle's own density: the jump diffuses density
    /// towards uniform and vanishes in a uniform deposit at rest.
    #[default]
    Density,
    /// −tr(σ)/3 relative to the geostatic state (seed 000's Eq. 21 with the
    /// correction of Eq. 26).
    Stress,
}

impl Default for NumericsSpec {
    fn default() -> Self {
        NumericsSpec {
            eta: None,
            muscl: false,
            stress_diffusion: default_zeta(),
            hourglass: default_hourglass(),
            hourglass_memory: default_hourglass_memory(),
            smoothing_ratio: default_h_ratio(),
            artificial_stress_exponent: default_as_n(),
            artificial_stress_epsilon: default_as_eps(),
            neighbor_skin: default_skin(),
            wall_layers: default_layers(),
            wall_friction: 0.0,
            continuity_jump: ContinuityJump::default(),
            wall_stress: WallStress::default(),
            density_floor: default_density_floor(),
            seepage_midpoint: false,
            sleep: false,
            sleep_speed: None,
            sleep_acceleration: None,
            sleep_steps: None,
        }
    }
}

fn default_density_floor() -> bool {
    true
}

fn default_zeta() -> f64 {
    0.1
}
fn default_hourglass() -> f64 {
    0.1
}
fn default_hourglass_memory() -> f64 {
    100.0
}
fn default_h_ratio() -> f64 {
    1.3
}
fn default_as_n() -> f64 {
    2.55
}
fn default_as_eps() -> f64 {
    0.5
}
fn default_skin() -> f64 {
    0.3
}
fn default_layers() -> usize {
    4
}

/// `[[materials]]`: elastic–plastic Drucker–Prager soil (seed 000 Eqs. 4–12), on the
/// cone `yield_surface`, with optional friction hardening (`hardening`) or the μ(I)
/// rheology (`mu_i`).
#[derive(Debug, Clone, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct MaterialSpec {
    pub name: String,
    /// Initial density ρ0 (kg/m³).
    pub density: f64,
    /// Young's modulus E (Pa).
    pub youngs_modulus: f64,
    /// Poisson's ratio ν.
    pub poisson_ratio: f64,
    /// Friction angle φ (degrees); φ_e, the angle at zero plastic strain, with
    /// `hardening`. Required, except with `mu_i` (whose μ_s sets it: φ = atan μ_s).
    #[serde(default)]
    pub friction_angle: Option<f64>,
    /// The Drucker–Prager cone the friction angle and cohesion are fitted on. Default
    /// `plane_strain` (seed 000 Eq. 6); `shear` with `mu_i`.
    #[serde(default)]
    pub yield_surface: Option<YieldSurface>,
    /// Friction hardening and softening on the accumulated plastic strain (seed 004
    /// Eq. 43). Default none: perfect plasticity.
    #[serde(default)]
    pub hardening: Option<HardeningSpec>,
    /// The μ(I) rheology (Jop et al. 2006) in place of a fixed friction angle.
    #[serde(default)]
    pub mu_i: Option<MuISpec>,
    /// State-dependent dilatancy (Pailha & Pouliquen 2009). Default none: ψ is
    /// `dilation_angle`.
    #[serde(default)]
    pub dilatancy: Option<DilatancySpec>,
    /// Cohesion c (Pa). Default 0.
    #[serde(default)]
    pub cohesion: f64,
    /// Dilation angle ψ (degrees). Default 0.
    #[serde(default)]
    pub dilation_angle: f64,
    /// Porosity n, in (0, 1): the pore fraction of the soil's volume (its `density`
    /// is the dry bulk density, (1 − n) times the grains'). Needed with any key below.
    #[serde(default)]
    pub porosity: Option<f64>,
    /// Intrinsic permeability k (m²) of the seepage force f = (μ/k)(u_w − u_s), seed
    /// 001 Eq. (10). Give it or `grain_size`; without either, water passes the soil
    /// freely.
    #[serde(default)]
    pub permeability: Option<f64>,
    /// Mean grain diameter d (m): k from Kozeny–Carman, k = n³ d² / (180 (1 − n)²).
    #[serde(default)]
    pub grain_size: Option<f64>,
    /// Fill the soil's pores with water particles at start-up, at the hydrostatic pore
    /// pressure below the region's top. Default false.
    #[serde(default)]
    pub saturated: bool,
}

impl MaterialSpec {
    /// φ in degrees: `friction_angle`, or atan μ_s with `mu_i` (NaN if neither is
    /// given; `scene::validate` refuses such a scene).
    pub fn static_friction_angle(&self) -> f64 {
        match (self.friction_angle, &self.mu_i) {
            (Some(phi), _) => phi,
            (None, Some(m)) => m.mu_s.atan().to_degrees(),
            (None, None) => f64::NAN,
        }
    }

    /// The cone φ and c are fitted on: `yield_surface`, else `shear` with `mu_i` and
    /// `plane_strain` without.
    pub fn surface(&self) -> YieldSurface {
        match (self.yield_surface, &self.mu_i) {
            (Some(y), _) => y,
            (None, Some(_)) => YieldSurface::Shear,
            (None, None) => YieldSurface::PlaneStrain,
        }
    }
}

/// Initial stress of a region.
#[derive(Debug, Clone, Copy, Deserialize, PartialEq, Eq, Default)]
#[serde(rename_all = "lowercase")]
pub enum InitialStress {
    /// Stress-free start.
    #[default]
    Zero,
    /// K0 geostatic profile: σ_v = −ρ0 g (z_top − z), σ_h = K0 σ_v, K0 = 1 − sin φ.
    Geostatic,
}

/// `[[regions]]`: a block of fine-grain particles.
#[derive(Debug, Clone, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct RegionSpec {
    pub name: String,
    pub material: String,
    pub shape: ShapeSpec,
    #[serde(default)]
    pub initial_stress: InitialStress,
    /// Initial velocity (m/s). Default at rest.
    #[serde(default)]
    pub velocity: Option<Vec<f64>>,
    /// Random displacement of each particle off the lattice, uniform in ±jitter·dp
    /// along every axis (fraction of dp, 0 to 0.3). Default 0: a regular lattice.
    #[serde(default)]
    pub jitter: f64,
    /// Seed of the jitter's random sequence (the same seed gives the same particles).
    #[serde(default = "default_jitter_seed")]
    pub jitter_seed: u64,
}

fn default_jitter_seed() -> u64 {
    1
}

/// A shape, selected by `type`.
#[derive(Debug, Clone, Deserialize)]
#[serde(tag = "type", rename_all = "lowercase", deny_unknown_fields)]
pub enum ShapeSpec {
    /// Axis-aligned box [min, max].
    Box { min: Vec<f64>, max: Vec<f64> },
    /// Vertical cylinder (3D) standing on `base` (centre of its bottom face).
    Cylinder {
        base: Vec<f64>,
        radius: f64,
        height: f64,
    },
    /// Sphere (3D) or disc (2D).
    Sphere { center: Vec<f64>, radius: f64 },
    /// Ring (2D annulus) or hollow ball (3D spherical shell) between `inner_radius` and
    /// `radius`.
    Ring {
        center: Vec<f64>,
        inner_radius: f64,
        radius: f64,
    },
    /// Simple polygon (2D), vertices in order.
    Polygon { vertices: Vec<Vec<f64>> },
    /// Convex polyhedron (3D): the convex hull of `vertices`.
    Polyhedron { vertices: Vec<Vec<f64>> },
    /// Closed triangle mesh (3D) from an `.obj` or `.stl` file (path relative to the
    /// scene file), scaled about its origin by `scale` and shifted by `offset`.
    Mesh {
        file: String,
        #[serde(default = "one")]
        scale: f64,
        #[serde(default)]
        offset: Option<Vec<f64>>,
    },
    /// Terrain (3D, walls only) from an ESRI ASCII grid (`.asc`, path relative to the
    /// scene file); the ground is the solid side. `offset` shifts it.
    Heightmap {
        file: String,
        #[serde(default)]
        offset: Option<Vec<f64>>,
    },
    /// A plane through `point` with outward `normal` (pointing into the material side);
    /// wall layers are placed behind it over a patch of half-widths `half_extent`
    /// (one value in 2D, two in 3D).
    Plane {
        point: Vec<f64>,
        normal: Vec<f64>,
        #[serde(deserialize_with = "super::one_or_many::numbers")]
        half_extent: Vec<f64>,
    },
}

/// `[[walls]]` and `[[barriers]]`: solid boundaries of dummy particles (Eqs. 32–35).
/// Barriers additionally report their load.
#[derive(Debug, Clone, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct WallSpec {
    pub name: String,
    pub shape: ShapeSpec,
    /// Prescribed rigid velocity (m/s). Default fixed.
    #[serde(default)]
    pub velocity: Option<Vec<f64>>,
    /// `[start, stop]` (s): the wall moves with `velocity` only for start ≤ t < stop.
    /// Default: always.
    #[serde(default)]
    pub move_between: Option<Vec<f64>>,
    /// Point about which the moment is reported (barriers). Default: shape centre.
    #[serde(default)]
    pub reference_point: Option<Vec<f64>>,
    /// Barriers only: the barrier's rigid motion comes from a co-simulation partner
    /// (FMU inputs `<name>.displacement.*` or `<name>.velocity.*`) instead of
    /// `velocity`. Default none (fixed or prescribed).
    #[serde(default)]
    pub input: Option<BarrierInput>,
    /// Barriers only: split the barrier into a grid of panels whose loads are reported
    /// separately, `[n]` in 2D and `[n1, n2]` in 3D along the barrier's extent (every
    /// axis but its thinnest, ascending). Default: one panel.
    #[serde(default)]
    pub panels: Option<Vec<usize>>,
    /// Water passes through it; grains (fine and coarse) do not: a screen, a sieve
    /// under a soil column, a permeable barrier. Default false.
    #[serde(default)]
    pub permeable: bool,
}

/// Which FMU inputs drive an input-driven barrier.
#[derive(Debug, Clone, Copy, Deserialize, PartialEq, Eq)]
#[serde(rename_all = "lowercase")]
pub enum BarrierInput {
    /// `<name>.displacement.*`: the barrier moves to the given rigid displacement from its
    /// initial place over each communication step.
    Displacement,
    /// `<name>.velocity.*`: the barrier moves with the given velocity over each step.
    Velocity,
}

/// `[[containers]]`: a box of walls around [min, max] with some faces open.
/// Each closed face is reported as a barrier named `<name>.<face>` when `report_loads`.
#[derive(Debug, Clone, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct ContainerSpec {
    pub name: String,
    pub min: Vec<f64>,
    pub max: Vec<f64>,
    /// Faces left open, from "-x", "+x", "-y", "+y", "-z", "+z". Default: the top.
    #[serde(default)]
    pub open: Option<Vec<String>>,
    /// Report the load on each face as a barrier.
    #[serde(default)]
    pub report_loads: bool,
}

/// `[[probes]]`: kernel-averaged stress and velocity at a point, written to the time series.
#[derive(Debug, Clone, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct ProbeSpec {
    pub name: String,
    pub position: Vec<f64>,
}

/// `[[gauges]]`: a water-level gauge, a vertical line from a base point on the floor;
/// it reads the depth of water above the base, written to the time series.
#[derive(Debug, Clone, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct GaugeSpec {
    pub name: String,
    /// The base point (m), on the floor below the line.
    pub position: Vec<f64>,
}

/// `[observe]`: how observables are measured.
#[derive(Debug, Clone, Deserialize, Default)]
#[serde(deny_unknown_fields)]
pub struct ObserveSpec {
    /// Origin of the run-out measurement: horizontal coordinates (x in 2D, [x, y] in 3D).
    /// 3D run-out is radial from it; 2D run-out is the distance along `runout_direction`.
    #[serde(default)]
    pub runout_origin: Option<Vec<f64>>,
    /// 2D only: +1 measures towards +x, −1 towards −x. Default +1.
    #[serde(default)]
    pub runout_direction: Option<f64>,
}

/// `[[solids]]`: a coarse-grain material (Neo-Hookean, Eqs. 39–40; also the contact
/// stiffness of rigid bodies).
#[derive(Debug, Clone, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct SolidSpec {
    pub name: String,
    /// Density ρ0 (kg/m³).
    pub density: f64,
    /// Young's modulus E (Pa).
    pub youngs_modulus: f64,
    /// Poisson's ratio ν.
    pub poisson_ratio: f64,
}

/// How a coarse grain deforms.
#[derive(Debug, Clone, Copy, serde::Serialize, Deserialize, PartialEq, Eq)]
#[serde(rename_all = "lowercase")]
pub enum BodyModel {
    /// Total-Lagrangian SPH, Neo-Hookean with Kelvin–Voigt damping (Eqs. 36–47).
    Elastic,
    /// Six degrees of freedom (three in 2D), mass and inertia from its particles.
    Rigid,
}

/// `[[bodies]]`: one coarse grain (boulder, block, ring), filled with particles.
#[derive(Debug, Clone, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct BodySpec {
    pub name: String,
    /// A `[[solids]]` name.
    pub material: String,
    pub model: BodyModel,
    pub shape: ShapeSpec,
    /// Rotation of the shape about its centre: an angle in 2D (degrees, counter-clockwise),
    /// or `[rx, ry, rz]` in 3D (degrees, applied about x, then y, then z). Default none.
    #[serde(default, deserialize_with = "super::one_or_many::some_numbers")]
    pub rotation: Option<Vec<f64>>,
    /// Initial velocity (m/s). Default at rest.
    #[serde(default)]
    pub velocity: Option<Vec<f64>>,
    /// Initial angular velocity (rad/s): one value in 2D, three in 3D. Default none.
    #[serde(default)]
    pub angular_velocity: Option<Vec<f64>>,
    /// Rigid bodies only: held in place (still takes loads and contacts). Default false.
    #[serde(default)]
    pub fixed: bool,
}

/// Contact force law between coarse grains, and between coarse grains and walls.
#[derive(Debug, Clone, Copy, serde::Serialize, Deserialize, PartialEq, Eq, Default)]
#[serde(rename_all = "kebab-case")]
pub enum ContactModel {
    /// Linear spring–dashpot normal force with a Coulomb-capped tangential spring.
    #[default]
    SpringDashpot,
    /// Hertz normal force (k ∝ √δ) with Mindlin tangential stiffness.
    HertzMindlin,
}

/// `[contact]`: contact and coarse–fine friction.
#[derive(Debug, Clone, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct ContactSpec {
    #[serde(default)]
    pub model: ContactModel,
    /// Coulomb friction coefficient between coarse grains, and with walls. Default 0.5.
    #[serde(default = "default_mu")]
    pub friction: f64,
    /// Coefficient of restitution of a binary collision. Default 0.5.
    #[serde(default = "default_restitution")]
    pub restitution: f64,
    /// Normal stiffness override (N/m in 3D, N/m per metre in 2D). Default from the
    /// solids' Young's moduli: k = E* dp^(d−2).
    #[serde(default)]
    pub stiffness: Option<f64>,
    /// Coulomb friction coefficient between coarse and fine grains, μ_cf. Default 0
    /// (seed 000's frictionless coupling).
    #[serde(default)]
    pub mu_cf: f64,
}

impl Default for ContactSpec {
    fn default() -> Self {
        ContactSpec {
            model: ContactModel::default(),
            friction: default_mu(),
            restitution: default_restitution(),
            stiffness: None,
            mu_cf: 0.0,
        }
    }
}

fn default_mu() -> f64 {
    0.5
}
fn default_restitution() -> f64 {
    0.5
}

/// `[[rock_fills]]`: coarse grains of random convex polygonal shape placed at random,
/// without overlap, inside a region until they make up `content` of its area (seed 000
/// §6.1: rock block content, RBC). Reproducible: the same `seed` gives the same rocks.
#[derive(Debug, Clone, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct RockFillSpec {
    /// Rocks are named `<name>_0`, `<name>_1`, ….
    pub name: String,
    /// A `[[solids]]` name.
    pub material: String,
    pub model: BodyModel,
    /// Where the rocks go: every rock lies inside this shape, `clearance` from its edge.
    pub region: ShapeSpec,
    /// Rock area over region area, in [0, 0.5].
    pub content: f64,
    /// Equivalent diameter D = 2√(A/π) of each rock (m).
    pub size: f64,
    /// Relative spread of D: each rock draws D(1 + s·u), u uniform in [−1, 1]. Default 0.
    #[serde(default)]
    pub size_spread: f64,
    /// Polygon vertices per rock before the convex hull, 5 to 24. Default 9.
    #[serde(default = "default_rock_vertices")]
    pub vertices: usize,
    /// Largest length-to-width ratio of a rock, ≥ 1. Default 1.6.
    #[serde(default = "default_rock_aspect")]
    pub max_aspect: f64,
    /// Random seed. Default 0.
    #[serde(default)]
    pub seed: u64,
    /// Smallest gap between two rocks and between a rock and the region's edge (m).
    /// Default 2 dp, so that fine grains fill every gap.
    #[serde(default)]
    pub clearance: Option<f64>,
}

fn default_rock_vertices() -> usize {
    9
}
fn default_rock_aspect() -> f64 {
    1.6
}

/// What one `[[rock_fills]]` entry placed.
#[derive(Debug, Clone, Default)]
pub struct RockFillReport {
    pub name: String,
    pub rocks: usize,
    /// Placed rock area over region area.
    pub content: f64,
}

/// Rotation of a body spec: an angle about z in 2D, x-then-y-then-z angles in 3D.
pub fn spec_rotation(b: &BodySpec, d: usize) -> Rotation3<Real> {
    let r = b.rotation.as_deref().unwrap_or(&[]);
    let deg = |k: usize| r.get(k).copied().unwrap_or(0.0).to_radians();
    if d == 2 {
        Rotation3::from_axis_angle(&Vector3::z_axis(), deg(0))
    } else {
        Rotation3::from_axis_angle(&Vector3::z_axis(), deg(2))
            * Rotation3::from_axis_angle(&Vector3::y_axis(), deg(1))
            * Rotation3::from_axis_angle(&Vector3::x_axis(), deg(0))
    }
}
