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

/// Fill `out` from the particle state (positions at the half step, stress σ_n).
pub fn pack<const D: usize>(p: &FineParticles<D>, mats: &[FineMaterial], out: &mut Vec<Source<D>>) {
    out.clear();
    out.par_extend((0..p.len()).into_par_iter().with_min_len(CHUNK).map(|i| {
        let m = &mats[p.material[i] as usize];
        let s = p.stress[i];
        Source {
            pos: p.pos[i],
            vel: p.vel[i],
            dev: s.dev(),
            p: -s.trace() / 3.0,
            vol: p.mass[i] / p.rho[i],
            z: m.rho0 * m.c0,
            c: m.c0,
            half_inv_z: 0.5 / (m.rho0 * m.c0),
            inv_c: 1.0 / m.c0,
        }
    }));
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
    out.resize(
        p.len(),
        Source {
            pos: Vect::<D>::zeros(),
            vel: Vect::<D>::zeros(),
            dev: Sym::ZERO,
            p: 0.0,
            vol: 0.0,
            z: 0.0,
            c: 0.0,
            half_inv_z: 0.0,
            inv_c: 0.0,
        },
    );
    let FineParticles {
        pos,
        vel,
        rho,
        drho,
        stress,
        mass,
        material,
        ..
    } = p;
    out.par_chunks_mut(CHUNK)
        .zip(pos.par_chunks_mut(CHUNK))
        .zip(rho.par_chunks_mut(CHUNK))
        .enumerate()
        .for_each(|(c, ((o, x), r))| {
            let base = c * CHUNK;
            for k in 0..o.len() {
                let i = base + k;
                x[k] += vel[i] * half;
                r[k] += drho[i] * half;
                let m = &mats[material[i] as usize];
                let s = stress[i];
                o[k] = Source {
                    pos: x[k],
                    vel: vel[i],
                    dev: s.dev(),
                    p: -s.trace() / 3.0,
                    vol: mass[i] / r[k],
                    z: m.rho0 * m.c0,
                    c: m.c0,
                    half_inv_z: 0.5 / (m.rho0 * m.c0),
                    inv_c: 1.0 / m.c0,
                };
            }
        });
}
