//! The records a simulation hands out: observations at a sampling time ([`Sample`]
//! with its barrier, body and probe parts) and particle snapshots for writers
//! ([`Frame`], [`ParticleRecord`]).

use crate::numerics::math::{Real, Sym};
#[cfg(feature = "zero-copy")]
use iceoryx2_bb_elementary_traits::zero_copy_send::ZeroCopySend;

/// Kernel-weighted (Shepard) average of stress and velocity at a point.
#[derive(Clone, Debug, Default, serde::Serialize, serde::Deserialize)]
pub struct ProbeValue {
    pub stress: Sym,
    pub velocity: [Real; 3],
    /// Number of particles within the kernel support.
    pub support: usize,
    /// Kernel-weighted (Shepard) water pressure at the point (Pa); None without water
    /// within the kernel support.
    #[serde(default)]
    pub water_pressure: Option<Real>,
    /// Kernel-weighted (Shepard) water velocity at the point (m/s); None without water
    /// within the kernel support.
    #[serde(default)]
    pub water_velocity: Option<[Real; 3]>,
}

/// Barrier load over a sampling interval.
#[derive(Clone, Debug, Default, serde::Serialize, serde::Deserialize)]
pub struct BarrierSample {
    pub name: String,
    /// Impulse over the interval divided by its length (N, or N/m in 2D).
    pub force: [Real; 3],
    /// Moment about the reference point, impulse-averaged (N·m, or N·m/m in 2D).
    pub moment: [Real; 3],
    /// Largest resultant force of any single step in the interval.
    pub peak_force: Real,
    /// Force of the last step.
    pub last_force: [Real; 3],
    /// Impulse-averaged force on each panel (scene key `panels`; empty without), in
    /// panel order (`crate::geometry::panels`). The panels' forces sum to `force`.
    pub panels: Vec<[Real; 3]>,
    /// The water's part of each panel's force, in panel order (empty without panels).
    #[serde(default)]
    pub panels_water: Vec<[Real; 3]>,
    /// The water's part of `force` (pressure and viscous traction), impulse-averaged.
    /// Zero without water.
    pub force_water: [Real; 3],
    /// The grains' part of `force`, `force − force_water` (computed here, once, for
    /// every output: CSV, MCAP, FMU, summary, plots).
    #[serde(default)]
    pub force_grains: [Real; 3],
    /// The grains' part of each panel's force, `panels − panels_water`, in panel order
    /// (empty without panels).
    #[serde(default)]
    pub panels_grains: Vec<[Real; 3]>,
}

/// The labels of a barrier's panels with `counts` panels per direction, in panel
/// order (that of [`BarrierSample::panels`]): `panel_<p>` along one direction (2D),
/// `panel_<i>_<j>` on a grid (3D); none for more directions than a barrier has. Every
/// output names its panels by these: the CSV series, the summary, the FMU variables.
pub fn panel_labels(counts: &[usize]) -> Option<Vec<String>> {
    match counts {
        [] => Some(Vec::new()),
        [n] => Some((0..*n).map(|p| format!("panel_{p}")).collect()),
        [n1, n2] => Some(
            (0..n1 * n2)
                .map(|p| format!("panel_{}_{}", p / n2, p % n2))
                .collect(),
        ),
        _ => None,
    }
}

impl BarrierSample {
    /// The sample of barrier `name` with its loads (`force`, `moment`, `peak_force`,
    /// `last_force`), its panels' and the water's parts; the grains' parts derive from
    /// them here.
    pub fn new(
        name: String,
        (force, moment, peak_force, last_force): ([Real; 3], [Real; 3], Real, [Real; 3]),
        (panels, panels_water): (Vec<[Real; 3]>, Vec<[Real; 3]>),
        force_water: [Real; 3],
    ) -> Self {
        let minus = |a: &[Real; 3], b: &[Real; 3]| [a[0] - b[0], a[1] - b[1], a[2] - b[2]];
        let panels_grains = panels
            .iter()
            .enumerate()
            .map(|(p, f)| minus(f, &panels_water.get(p).copied().unwrap_or_default()))
            .collect();
        BarrierSample {
            name,
            force,
            moment,
            peak_force,
            last_force,
            force_grains: minus(&force, &force_water),
            panels,
            panels_water,
            force_water,
            panels_grains,
        }
    }
}

/// The water family at a sampling time.
#[derive(Clone, Debug, Default, serde::Serialize, serde::Deserialize)]
pub struct WaterSample {
    pub particles: usize,
    /// Σ ½ m v² (J, or J/m in 2D).
    pub kinetic_energy: Real,
    /// −Σ m g·x (J, or J/m in 2D).
    pub potential_energy: Real,
    /// The surge front: the largest x of any water particle (m); none without water
    /// particles.
    pub front: Option<Real>,
    /// Largest water speed at the end of the last step (m/s).
    pub max_speed: Real,
    /// Σ m v.
    pub momentum: [Real; 3],
    /// The lowest water pressure of any particle at the sample (Pa); 0 without
    /// particles. Water has no tensile strength: a value well below zero is the
    /// scheme's (acoustic ringing), not the flow's.
    #[serde(default)]
    pub min_pressure: Real,
    /// The impulse the grains of a saturated soil took over from the pore water's
    /// surplus mass since the start (N·s, or N·s/m in 2D; docs/method.md §Pore-pressure
    /// feedback): the grains' and the water's momentum less it is what the seepage
    /// exchanges conserve. Zero without a soil with pores.
    #[serde(default)]
    pub carried: [Real; 3],
}

/// The fine grains' density relative to their material's: ρ/ρ0 per particle,
/// summarised as median, 10th percentile and minimum (issue 41: a cohesionless soil
/// with ψ = 0 cannot dilate, so a ratio well below 1 is the scheme's, not the soil's).
#[derive(Clone, Copy, Debug, Default, PartialEq, serde::Serialize, serde::Deserialize)]
pub struct DensityRatio {
    pub median: Real,
    pub p10: Real,
    pub min: Real,
}

/// State of one coarse grain (3D layout; z = 0 in 2D, rotation about z).
#[derive(Clone, Debug, Default, serde::Serialize, serde::Deserialize)]
pub struct BodySample {
    pub name: String,
    /// Centre of mass (m).
    pub position: [Real; 3],
    /// Orientation quaternion (w, x, y, z).
    pub orientation: [Real; 4],
    pub velocity: [Real; 3],
    pub angular_velocity: [Real; 3],
    /// Force from fine grains and contacts over the last fine step, gravity excluded
    /// (N, or N/m in 2D).
    pub force: [Real; 3],
    /// Torque about the centre of mass (N·m, or N·m/m in 2D).
    pub torque: [Real; 3],
    /// The fine grains' part of `force` (Eq. 50).
    pub fine_force: [Real; 3],
    /// The water's part of `force` (pressure, with buoyancy, and viscous drag).
    pub water_force: [Real; 3],
    /// `force` and `torque` impulse-averaged over the whole sampling interval (every
    /// fine step weighted by its length), as the FMU reports them.
    pub mean_force: [Real; 3],
    pub mean_torque: [Real; 3],
    /// Active contacts in the last sub-step.
    pub contacts: usize,
}

/// Observations at one sampling time.
#[derive(Clone, Debug, Default, serde::Serialize, serde::Deserialize)]
pub struct Sample {
    pub time: Real,
    pub steps: u64,
    pub dt: Real,
    /// Σ ½ m v² of the fine grains alone (J, or J/m in 2D); the coarse grains' is
    /// `coarse_kinetic_energy`, the water's `water.kinetic_energy`.
    pub kinetic_energy: Real,
    /// −Σ m g·x of the fine grains alone (J, or J/m in 2D).
    pub potential_energy: Real,
    /// Deposit run-out of fine and coarse grains together (m; `crate::run::observe::runout`).
    pub runout: Real,
    /// Largest fine-grain speed at the end of the last step (m/s); the coarse grains'
    /// is `coarse_max_speed`, the water's `water.max_speed`.
    pub max_speed: Real,
    /// The fine grains' ρ/ρ0 (median, 10th percentile, minimum); None without fine grains.
    #[serde(default)]
    pub density_ratio: Option<DensityRatio>,
    /// The share of fine particles awake at the sample (None where they do not sleep).
    #[serde(default)]
    pub awake_fine: Option<Real>,
    /// Largest coarse-grain particle speed (m/s); 0 without coarse grains.
    #[serde(default)]
    pub coarse_max_speed: Real,
    pub barriers: Vec<BarrierSample>,
    pub probes: Vec<(String, ProbeValue)>,
    /// Each water-level gauge's depth of water above its base (m).
    #[serde(default)]
    pub gauges: Vec<(String, Real)>,
    /// Coarse sub-steps so far, and κ of the last full step (not one shortened to
    /// land on an output time).
    pub steps_coarse: u64,
    pub kappa: usize,
    /// Fine step Δt_f (Eq. 51) and coarse sub-step Δt_c of the last step.
    pub dt_fine: Real,
    pub dt_coarse: Real,
    /// Kinetic energy of the coarse grains (J, or J/m in 2D).
    pub coarse_kinetic_energy: Real,
    /// Elastic strain energy of elastic coarse grains, Eq. (39).
    pub strain_energy: Real,
    /// Energy stored in the contact springs.
    pub contact_energy: Real,
    /// Potential energy of the coarse grains in gravity.
    pub coarse_potential_energy: Real,
    /// Total linear momentum of fine and coarse grains.
    pub momentum: [Real; 3],
    pub bodies: Vec<BodySample>,
    /// The water (None without `[water]`).
    pub water: Option<WaterSample>,
}

/// A snapshot of every particle for writers (VTK): the fine, coarse and water particles as
/// [`ParticleRecord`]s, with what only a full snapshot carries beside them.
#[derive(Clone, Debug, Default)]
pub struct Frame {
    pub time: Real,
    /// Fine particles.
    pub fine: Vec<ParticleRecord>,
    /// Density of each fine particle (kg/m³).
    pub density: Vec<f32>,
    /// Stress of each fine particle, xx yy zz xy xz yz (Pa, tension positive).
    pub stress: Vec<[f32; 6]>,
    /// 1 for each fine particle awake, 0 asleep (empty where they do not sleep).
    pub awake: Vec<u8>,
    /// Coarse-grain particles.
    pub coarse: Vec<ParticleRecord>,
    /// Force from the fine grains on each coarse particle (Eq. 50).
    pub coarse_fine_force: Vec<[f32; 3]>,
    /// Force from the water on each coarse particle (pressure, with buoyancy, and
    /// viscous drag); zero without water.
    pub coarse_water_force: Vec<[f32; 3]>,
    pub wall_pos: Vec<[f32; 3]>,
    pub wall_object: Vec<u16>,
    /// Water particles (pressure from the equation of state; `group` 0).
    pub water: Vec<ParticleRecord>,
    /// Density of each water particle (kg/m³).
    pub water_density: Vec<f32>,
}

/// One particle as every bulk sink sees it (the particle channel, recordings, VTK
/// snapshots): 52 bytes, 3D layout (z = 0 in 2D), single precision. Fine particles
/// carry their material index in `group`, coarse-grain particles their body index;
/// coarse particles have no pressure or plastic strain (0), water no plastic strain;
/// `family` says which ([`FAMILY_FINE`], [`FAMILY_COARSE`], [`FAMILY_WATER`]). `#[repr(C)]` with an
/// explicit type name: the particle channel sends it as it is (feature `zero-copy`,
/// which `granmix-ipc` turns on), and subscribers in other languages declare the same
/// layout (`docs/ipc.md`).
#[derive(Clone, Copy, Debug, Default, PartialEq)]
#[cfg_attr(
    feature = "zero-copy",
    derive(iceoryx2_bb_derive_macros::ZeroCopySend),
    type_name("granmix::ParticleRecord")
)]
#[repr(C)]
pub struct ParticleRecord {
    /// Position (m).
    pub position: [f32; 3],
    /// Velocity (m/s).
    pub velocity: [f32; 3],
    /// Pressure −tr(σ)/3 (Pa); 0 for coarse grains.
    pub pressure: f32,
    /// Accumulated plastic strain (Eq. 10); 0 for coarse grains.
    pub plastic_strain: f32,
    /// Particle id (fine: the stable id; coarse: the index among coarse particles).
    pub id: u32,
    /// Material index (fine) or body index (coarse); 0 for water.
    pub group: u32,
    /// The particle's family: [`FAMILY_FINE`], [`FAMILY_COARSE`] or [`FAMILY_WATER`].
    pub family: u32,
    /// Pore pressure (Pa): for a fine particle the water's pressure interpolated at it
    /// (0 without water near), for water its own; 0 for coarse grains.
    pub pore_pressure: f32,
    /// `pore_pressure` less the hydrostatic pressure below the water surface of the
    /// particle's vertical column, ρ_w g (z_s − z) (Pa); 0 for coarse grains and where
    /// no water is near.
    pub excess_pore_pressure: f32,
    /// Porosity n of a fine particle, following its density: 1 − n = (1 − n0) ρ/ρ0
    /// with n0 its material's `materials[].porosity` (issue 44); 0 for a soil without
    /// pores, for coarse grains and for water.
    pub porosity: f32,
}

/// [`ParticleRecord::family`] of a fine-grain particle.
pub const FAMILY_FINE: u32 = 0;
/// [`ParticleRecord::family`] of a coarse-grain particle.
pub const FAMILY_COARSE: u32 = 1;
/// [`ParticleRecord::family`] of a water particle.
pub const FAMILY_WATER: u32 = 2;
