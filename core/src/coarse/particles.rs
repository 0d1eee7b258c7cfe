//! Coarse-grain particle state: structure of arrays over all bodies.

use crate::numerics::math::{Real, Vect};

/// The particles of all coarse grains. Each body owns a contiguous range.
#[derive(Clone, Debug, Default, serde::Serialize, serde::Deserialize)]
pub struct CoarseParticles<const D: usize> {
    pub pos: Vec<Vect<D>>,
    pub vel: Vec<Vect<D>>,
    /// Rigid: offset from the centre of mass in the body frame. Elastic: the reference
    /// position r⁰ (Eq. 36).
    pub local: Vec<Vect<D>>,
    /// Outward unit normal of the nearest surface, in the body frame (rigid) or the
    /// reference configuration (elastic); zero where the direction is undefined.
    pub local_normal: Vec<Vect<D>>,
    /// Current outward unit normal n^c of Eq. (48).
    pub normal: Vec<Vect<D>>,
    pub mass: Vec<Real>,
    /// Owning body.
    pub body: Vec<u32>,
    /// Within one dp of the surface: takes part in contacts.
    pub surface: Vec<bool>,
    /// Depth below the body's surface in the reference configuration (m).
    pub depth: Vec<Real>,
    /// Force from the fine grains, Eq. (50), held over one fine step.
    pub f_fine: Vec<Vect<D>>,
    /// Force from the water, held over one fine step.
    #[serde(default)]
    pub f_water: Vec<Vect<D>>,
    /// Contact force of the current sub-step.
    pub f_contact: Vec<Vect<D>>,
    /// Position at the start of the fine step (for Eq. 60).
    pub pos_start: Vec<Vect<D>>,
    /// Time-averaged velocity over the last fine step, Eq. (60).
    pub vbar: Vec<Vect<D>>,
}

impl<const D: usize> CoarseParticles<D> {
    pub fn len(&self) -> usize {
        self.pos.len()
    }
    pub fn is_empty(&self) -> bool {
        self.pos.is_empty()
    }

    /// Append one particle.
    #[allow(clippy::too_many_arguments)]
    pub fn push(
        &mut self,
        pos: Vect<D>,
        vel: Vect<D>,
        local: Vect<D>,
        local_normal: Vect<D>,
        normal: Vect<D>,
        mass: Real,
        body: u32,
        depth: Real,
        dp: Real,
    ) {
        let surface = depth < dp;
        self.pos.push(pos);
        self.vel.push(vel);
        self.local.push(local);
        self.local_normal.push(local_normal);
        self.normal.push(normal);
        self.mass.push(mass);
        self.body.push(body);
        self.surface.push(surface);
        self.depth.push(depth);
        self.f_fine.push(Vect::<D>::zeros());
        self.f_water.push(Vect::<D>::zeros());
        self.f_contact.push(Vect::<D>::zeros());
        self.pos_start.push(pos);
        self.vbar.push(vel);
    }

    /// Bytes held.
    pub fn bytes(&self) -> usize {
        use std::mem::size_of;
        self.pos.capacity() * size_of::<Vect<D>>() * 9
            + self.mass.capacity() * size_of::<Real>()
            + self.body.capacity() * 4
            + self.surface.capacity()
    }
}
