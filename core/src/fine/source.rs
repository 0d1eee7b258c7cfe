//! The per-particle data that neighbours read in the sweeps, packed into one record so
//! that a neighbour costs two cache lines (its position, read first for the distance
//! test, its velocity and this record) instead of one per array. Positions and
//! velocities are read from the particle state itself: the distance test then scans a
//! compact array, and the state is not held twice.

use super::material::{DensityFloor, FineMaterial};
use super::state::FineParticles;
use crate::numerics::math::{Real, Sym};
use crate::numerics::neighbors::CHUNK;
use rayon::prelude::*;

/// Neighbour-side view of a fine particle for one step.
#[derive(Clone, Copy, Debug)]
pub struct Source {
    /// Deviatoric stress σˢ.
    pub dev: Sym,
    /// Pressure P = −tr(σ)/3.
    pub p: Real,
    /// Volume m/ρ.
    pub vol: Real,
    /// Acoustic impedance ρ0 c0 (Eq. 21, reference density).
    pub z: Real,
    /// Pressure from density, K (ρ/ρ0 − 1): the jump of Eq. (19) in the continuity
    /// sweep (`numerics.continuity_jump = "density"`), taken once per particle
    /// rather than once per pair.
    pub p_rho: Real,
}

impl Source {
    /// 1/(2 z) and 1/c for sound speed `c`: the pair reciprocals when both particles
    /// share a material ([`pair_reciprocals`](crate::numerics::riemann::pair_reciprocals)).
    /// Taken once per particle in the sweeps rather than stored, so that a record is
    /// 80 bytes.
    #[inline(always)]
    pub fn reciprocals(&self, c: Real) -> (Real, Real) {
        (0.5 / self.z, 1.0 / c)
    }
}

impl Source {
    /// The record of particle `i` at density `rho`.
    #[inline(always)]
    fn of<const D: usize>(
        p: &FineParticles<D>,
        mats: &[FineMaterial],
        i: usize,
        rho: Real,
    ) -> Self {
        let m = &mats[p.material[i] as usize];
        let s = p.stress[i];
        let z = m.rho0 * m.c0;
        Source {
            dev: s.dev(),
            p: -s.trace() / 3.0,
            vol: p.mass[i] / rho,
            z,
            p_rho: m.bulk * (rho / m.rho0 - 1.0),
        }
    }
}

/// Fill `out` from the particle state (positions at the half step, stress σ_n).
pub fn pack<const D: usize>(p: &FineParticles<D>, mats: &[FineMaterial], out: &mut Vec<Source>) {
    out.clear();
    out.par_extend(
        (0..p.len())
            .into_par_iter()
            .with_min_len(CHUNK)
            .map(|i| Source::of(p, mats, i, p.rho[i])),
    );
}

/// Eq. (54) fused with [`pack`]: move positions and densities to the half step and fill
/// `out` in the same pass.
pub fn drift_and_pack<const D: usize>(
    p: &mut FineParticles<D>,
    mats: &[FineMaterial],
    (half, floor): (Real, &[Real]),
    out: &mut Vec<Source>,
) {
    let n = p.len();
    let mut pos = std::mem::take(&mut p.pos);
    let mut rho = std::mem::take(&mut p.rho);
    let state = &*p;
    // an empty `floor`: no floor
    let floor = (!floor.is_empty()).then_some(DensityFloor {
        material: &state.material,
        floor,
    });
    out.clear();
    out.par_extend(
        pos.par_iter_mut()
            .zip(rho.par_iter_mut())
            .enumerate()
            .with_min_len(CHUNK)
            .map(|(i, (x, r))| {
                *x += state.vel[i] * half;
                *r += state.drho[i] * half;
                if let Some(f) = &floor {
                    f.hold(i, r);
                }
                Source::of(state, mats, i, *r)
            }),
    );
    debug_assert_eq!(out.len(), n);
    p.pos = pos;
    p.rho = rho;
}

#[cfg(test)]
mod tests {
    /// A neighbour record holds 10 numbers.
    #[test]
    fn a_record_is_80_bytes() {
        assert_eq!(std::mem::size_of::<super::Source>(), 80);
    }
}
