//! The records a simulation hands out: observations at a sampling time ([`Sample`]
//! with its barrier, body and probe parts) and particle snapshots for writers
//! ([`Frame`], [`ParticleState`]).

use crate::math::{Real, Sym};

/// Kernel-weighted (Shepard) average of stress and velocity at a point.
#[derive(Clone, Debug, Default, serde::Serialize, serde::Deserialize)]
pub struct ProbeValue {
    pub stress: Sym,
    pub velocity: [Real; 3],
    /// Number of particles within the kernel support.
    pub support: usize,
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
    /// panel order (`crate::panels`). The panels' forces sum to `force`.
    pub panels: Vec<[Real; 3]>,
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
    pub kinetic_energy: Real,
    pub potential_energy: Real,
    pub runout: Real,
    pub max_speed: Real,
    pub barriers: Vec<BarrierSample>,
    pub probes: Vec<(String, ProbeValue)>,
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
}

/// A particle snapshot in 3D layout (z = 0 in 2D), for writers.
#[derive(Clone, Debug, Default)]
pub struct Frame {
    pub time: Real,
    pub pos: Vec<[f32; 3]>,
    pub vel: Vec<[f32; 3]>,
    pub pressure: Vec<f32>,
    pub density: Vec<f32>,
    pub plastic_strain: Vec<f32>,
    pub stress: Vec<[f32; 6]>,
    pub id: Vec<u32>,
    pub material: Vec<u16>,
    pub wall_pos: Vec<[f32; 3]>,
    pub wall_object: Vec<u16>,
    /// Coarse-grain particles.
    pub coarse_pos: Vec<[f32; 3]>,
    pub coarse_vel: Vec<[f32; 3]>,
    pub coarse_body: Vec<u32>,
    /// Force from the fine grains on each coarse particle (Eq. 50).
    pub coarse_fine_force: Vec<[f32; 3]>,
}

/// One particle as handed to bulk sinks (the particle channel, recordings): 3D layout
/// (z = 0 in 2D), single precision. Fine particles carry their material index in
/// `group`, coarse-grain particles their body index; coarse particles have no pressure
/// or plastic strain (0).
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct ParticleState {
    /// Position (m).
    pub position: [f32; 3],
    /// Velocity (m/s).
    pub velocity: [f32; 3],
    /// Pressure −tr(σ)/3 (Pa).
    pub pressure: f32,
    /// Accumulated plastic strain (Eq. 10).
    pub plastic_strain: f32,
    /// Particle id (fine: the stable id; coarse: the index among coarse particles).
    pub id: u32,
    /// Material index (fine) or body index (coarse).
    pub group: u32,
}
