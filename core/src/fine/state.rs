//! Fine-grain particle state: structure of arrays.

use crate::numerics::math::{Real, Sym, Vect};
use crate::numerics::permute::{cycle_apply, PermuteScratch};
use nalgebra::{SMatrix, SVector};

/// Updated-Lagrangian SPH particles of the fine grains.
#[derive(Clone, Debug, Default, serde::Serialize, serde::Deserialize)]
pub struct FineParticles<const D: usize> {
    pub pos: Vec<Vect<D>>,
    pub vel: Vec<Vect<D>>,
    pub rho: Vec<Real>,
    /// dρ/dt from the last continuity sweep (Eq. 15).
    pub drho: Vec<Real>,
    /// Cauchy stress, tension positive.
    pub stress: Vec<Sym>,
    /// Accumulated deviatoric plastic strain.
    pub plastic_strain: Vec<Real>,
    pub mass: Vec<Real>,
    /// Material index.
    pub material: Vec<u16>,
    /// Stable id (the particle's index at creation), kept through re-sorting.
    pub id: Vec<u32>,
    /// Velocity gradient L of Eq. (24) from the last continuity sweep (single
    /// precision: it only enters the hourglass penalty).
    pub vel_grad: Vec<SMatrix<f32, D, D>>,
    /// Accumulated hourglass acceleration (see [`hourglass`](super::hourglass)).
    pub hourglass: Vec<SVector<f32, D>>,
    /// Share of the accumulated hourglass penalty kept through the last stress update:
    /// 1 when it stayed elastic, ε_e/(ε_e + Δε_p) after a return mapping (see
    /// [`hourglass`](super::hourglass)).
    pub hourglass_kept: Vec<f32>,
    /// Consecutive quiet steps of each particle, up to the sleep rule's window: at
    /// the window it sleeps ([`sleep`](crate::numerics::sleep)); 0 without sleep.
    #[serde(default)]
    pub quiet: Vec<u16>,
}

impl<const D: usize> FineParticles<D> {
    pub fn len(&self) -> usize {
        self.pos.len()
    }
    pub fn is_empty(&self) -> bool {
        self.pos.is_empty()
    }

    pub fn push(
        &mut self,
        pos: Vect<D>,
        vel: Vect<D>,
        rho: Real,
        mass: Real,
        stress: Sym,
        material: u16,
    ) {
        self.id.push(self.pos.len() as u32);
        self.pos.push(pos);
        self.vel.push(vel);
        self.rho.push(rho);
        self.drho.push(0.0);
        self.stress.push(stress);
        self.plastic_strain.push(0.0);
        self.mass.push(mass);
        self.material.push(material);
        self.vel_grad.push(SMatrix::zeros());
        self.hourglass.push(SVector::zeros());
        self.hourglass_kept.push(1.0);
        self.quiet.push(0);
    }

    /// Release the spare capacity left by filling the arrays one particle at a time.
    pub fn shrink_to_fit(&mut self) {
        self.pos.shrink_to_fit();
        self.vel.shrink_to_fit();
        self.rho.shrink_to_fit();
        self.drho.shrink_to_fit();
        self.stress.shrink_to_fit();
        self.plastic_strain.shrink_to_fit();
        self.mass.shrink_to_fit();
        self.material.shrink_to_fit();
        self.id.shrink_to_fit();
        self.vel_grad.shrink_to_fit();
        self.hourglass.shrink_to_fit();
        self.hourglass_kept.shrink_to_fit();
        self.quiet.shrink_to_fit();
    }

    /// Bytes held by the particle arrays.
    pub fn bytes(&self) -> usize {
        use std::mem::size_of;
        self.pos.capacity() * size_of::<Vect<D>>()
            + self.vel.capacity() * size_of::<Vect<D>>()
            + (self.rho.capacity()
                + self.drho.capacity()
                + self.plastic_strain.capacity()
                + self.mass.capacity())
                * size_of::<Real>()
            + self.stress.capacity() * size_of::<Sym>()
            + self.material.capacity() * 2
            + self.id.capacity() * 4
            + self.vel_grad.capacity() * size_of::<SMatrix<f32, D, D>>()
            + self.hourglass.capacity() * size_of::<SVector<f32, D>>()
            + self.hourglass_kept.capacity() * size_of::<f32>()
            + self.quiet.capacity() * 2
    }

    /// Reorder every array by `order` (new index k holds old particle order[k]), in
    /// place. The arrays are permuted by following the cycles of `order`, so the only
    /// extra memory is one mark bit per particle in `scratch` (a gathered copy would
    /// hold a second copy of the largest array). No allocation after warm-up.
    pub fn permute(&mut self, order: &[u32], scratch: &mut PermuteScratch) {
        cycle_apply(&mut self.pos, order, scratch);
        cycle_apply(&mut self.vel, order, scratch);
        cycle_apply(&mut self.rho, order, scratch);
        cycle_apply(&mut self.drho, order, scratch);
        cycle_apply(&mut self.plastic_strain, order, scratch);
        cycle_apply(&mut self.mass, order, scratch);
        cycle_apply(&mut self.stress, order, scratch);
        cycle_apply(&mut self.material, order, scratch);
        cycle_apply(&mut self.id, order, scratch);
        cycle_apply(&mut self.vel_grad, order, scratch);
        cycle_apply(&mut self.hourglass, order, scratch);
        cycle_apply(&mut self.hourglass_kept, order, scratch);
        cycle_apply(&mut self.quiet, order, scratch);
    }
}
