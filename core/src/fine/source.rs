//! The per-particle data that neighbours read in the sweeps, packed into one record so
//! that a neighbour costs one or two cache lines instead of one per array.

use super::material::FineMaterial;
use super::state::FineParticles;
use crate::math::{Real, Sym, Vect};
use crate::neighbors::CHUNK;
use rayon::prelude::*;

/// Neighbour-side view of a fine particle for one step.
#[derive(Clone, Copy, Debug)]
pub struct Source<const D: usize> {
    pub pos: Vect<D>,
    pub vel: Vect<D>,
    /// Deviatoric stress σˢ.
    pub dev: Sym,
    /// Pressure P = −tr(σ)/3.
    pub p: Real,
    /// Volume m/ρ.
    pub vol: Real,
    /// Acoustic impedance ρ0 c0 (Eq. 21, reference density).
    pub z: Real,
    /// Sound speed c0 (Eq. 22).
    pub c: Real,
    /// 1/(2 z), 1/c: the pair reciprocals when both particles share a material.
    pub half_inv_z: Real,
    pub inv_c: Real,
}

impl<const D: usize> Source<D> {
    /// The record of particle `i` at position `pos` and density `rho`.
    #[inline(always)]
    fn of(p: &FineParticles<D>, mats: &[FineMaterial], i: usize, pos: Vect<D>, rho: Real) -> Self {
        let m = &mats[p.material[i] as usize];
        let s = p.stress[i];
        let z = m.rho0 * m.c0;
        Source {
            pos,
            vel: p.vel[i],
            dev: s.dev(),
            p: -s.trace() / 3.0,
            vol: p.mass[i] / rho,
            z,
            c: m.c0,
            half_inv_z: 0.5 / z,
            inv_c: 1.0 / m.c0,
        }
    }
}

/// Fill `out` from the particle state (positions at the half step, stress σ_n).
pub fn pack<const D: usize>(p: &FineParticles<D>, mats: &[FineMaterial], out: &mut Vec<Source<D>>) {
    out.clear();
    out.par_extend(
        (0..p.len())
            .into_par_iter()
            .with_min_len(CHUNK)
            .map(|i| Source::of(p, mats, i, p.pos[i], p.rho[i])),
    );
}

/// Refresh the velocities (after the momentum sweep).
pub fn update_velocity<const D: usize>(vel: &[Vect<D>], out: &mut [Source<D>]) {
    out.par_iter_mut()
        .zip(vel.par_iter())
        .with_min_len(CHUNK)
        .for_each(|(s, v)| s.vel = *v);
}

/// Eq. (54) fused with [`pack`]: move positions and densities to the half step and fill
/// `out` in the same pass.
pub fn drift_and_pack<const D: usize>(
    p: &mut FineParticles<D>,
    mats: &[FineMaterial],
    half: Real,
    out: &mut Vec<Source<D>>,
) {
    let n = p.len();
    let mut pos = std::mem::take(&mut p.pos);
    let mut rho = std::mem::take(&mut p.rho);
    let state = &*p;
    out.clear();
    out.par_extend(
        pos.par_iter_mut()
            .zip(rho.par_iter_mut())
            .enumerate()
            .with_min_len(CHUNK)
            .map(|(i, (x, r))| {
                *x += state.vel[i] * half;
                *r += state.drho[i] * half;
                Source::of(state, mats, i, *x, *r)
            }),
    );
    debug_assert_eq!(out.len(), n);
    p.pos = pos;
    p.rho = rho;
}
