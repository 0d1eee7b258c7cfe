//! One coarse grain: its particle range, mass properties and rigid-body state.
//!
//! Body-level vectors are 3D in both dimensions (z = 0 in 2D, rotation about z only),
//! so one rigid-body code serves 2D and 3D.

use crate::numerics::math::Real;
use crate::scene::BodyModel;
use nalgebra::{Matrix3, UnitQuaternion, Vector3};

/// A coarse grain.
#[derive(Clone, Debug, serde::Serialize, serde::Deserialize)]
pub struct Body<const D: usize> {
    pub name: String,
    pub model: BodyModel,
    /// Index into the solid materials.
    pub material: usize,
    /// Particle range `start..end`.
    pub start: usize,
    pub end: usize,
    /// Held in place (rigid only).
    pub fixed: bool,
    /// Mass (kg, or kg/m in 2D), including particles trimmed from a rigid interior.
    pub mass: Real,
    /// Centre of mass (m).
    pub com: Vector3<Real>,
    /// Velocity of the centre of mass (m/s).
    pub vel: Vector3<Real>,
    /// Orientation (rigid: exact; elastic: rotation part of the best-fit deformation).
    pub orientation: UnitQuaternion<Real>,
    /// Angular momentum about the centre of mass, world frame.
    pub ang_mom: Vector3<Real>,
    /// Angular velocity (rad/s), world frame.
    pub omega: Vector3<Real>,
    /// Inertia tensor about the centre of mass, body frame, and its inverse.
    pub inertia: Matrix3<Real>,
    pub inv_inertia: Matrix3<Real>,
    /// Force and torque (about the centre of mass) from fine grains and contacts,
    /// impulse-averaged over the last fine step (gravity excluded).
    pub force: Vector3<Real>,
    pub torque: Vector3<Real>,
    /// The part of `force` exerted by the fine grains (Eq. 50).
    pub fine_force: Vector3<Real>,
    /// The part of `force` exerted by the water (pressure, buoyancy and viscous drag).
    #[serde(default)]
    pub water_force: Vector3<Real>,
    /// Contacts active in the last sub-step.
    pub contacts: usize,
    /// What the water particles miss of the body's Archimedes force over the last fine
    /// step, whose reaction the body's contacts carry
    /// ([`water_buoyancy`](crate::interactions::water_buoyancy)); zero off contact.
    #[serde(default)]
    pub uplift: Vector3<Real>,
    /// Gap partners found at the start of the last fine step: surface particles within
    /// a spacing of a wall or of another body ([`gap_water`](crate::interactions::gap_water)).
    #[serde(default)]
    pub gaps: usize,
}

impl<const D: usize> Body<D> {
    pub fn is_rigid(&self) -> bool {
        self.model == BodyModel::Rigid
    }

    /// Rotation matrix of the orientation.
    pub fn rotation(&self) -> Matrix3<Real> {
        *self.orientation.to_rotation_matrix().matrix()
    }

    /// Inverse inertia tensor in the world frame, R I⁻¹ Rᵀ.
    pub fn world_inv_inertia(&self) -> Matrix3<Real> {
        let r = self.rotation();
        r * self.inv_inertia * r.transpose()
    }

    /// Kinetic energy of the rigid motion, ½ M v² + ½ ω·L.
    pub fn rigid_kinetic_energy(&self) -> Real {
        0.5 * self.mass * self.vel.norm_squared() + 0.5 * self.omega.dot(&self.ang_mom)
    }

    /// Particle count.
    pub fn len(&self) -> usize {
        self.end - self.start
    }
    pub fn is_empty(&self) -> bool {
        self.end == self.start
    }
}
