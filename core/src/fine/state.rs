//! Fine-grain particle state: structure of arrays.

use crate::math::{Real, Sym, Vect};

/// Updated-Lagrangian SPH particles of the fine grains.
#[derive(Clone, Debug, Default)]
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
    }

    /// Reorder every array by `order` (new index k holds old particle order[k]).
    /// `scratch` buffers are reused so that no allocation happens after warm-up.
    pub fn permute(&mut self, order: &[u32], scratch: &mut PermuteScratch<D>) {
        fn apply<T: Copy + Send + Sync>(v: &mut Vec<T>, order: &[u32], tmp: &mut Vec<T>) {
            use rayon::prelude::*;
            tmp.clear();
            tmp.par_extend(order.par_iter().map(|&o| v[o as usize]));
            std::mem::swap(v, tmp);
        }
        apply(&mut self.pos, order, &mut scratch.vec);
        apply(&mut self.vel, order, &mut scratch.vec);
        apply(&mut self.rho, order, &mut scratch.real);
        apply(&mut self.drho, order, &mut scratch.real);
        apply(&mut self.plastic_strain, order, &mut scratch.real);
        apply(&mut self.mass, order, &mut scratch.real);
        apply(&mut self.stress, order, &mut scratch.sym);
        apply(&mut self.material, order, &mut scratch.u16);
        apply(&mut self.id, order, &mut scratch.u32);
    }
}

/// Reusable buffers for [`FineParticles::permute`].
#[derive(Clone, Default, Debug)]
pub struct PermuteScratch<const D: usize> {
    vec: Vec<Vect<D>>,
    real: Vec<Real>,
    sym: Vec<Sym>,
    u16: Vec<u16>,
    u32: Vec<u32>,
}
