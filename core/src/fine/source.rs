//! What a fine particle's partners read of it in the sweeps, derived from its state
//! when it is read rather than stored: the pair passes pack it into their cluster
//! records ([`lanes`](super::lanes)), the wall and coarse terms take it per particle.
//! The drift of Eq. (54), which moves the state these derive from to the half step.

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
    /// Taken once per particle in the sweeps rather than stored.
    #[inline(always)]
    pub fn reciprocals(&self, c: Real) -> (Real, Real) {
        (0.5 / self.z, 1.0 / c)
    }
}

impl Source {
    /// The record of a particle of soil `m`, stress `s`, mass `mass` and density `rho`.
    #[inline(always)]
    pub fn new(m: &FineMaterial, s: &Sym, mass: Real, rho: Real) -> Self {
        Source {
            dev: s.dev(),
            p: -s.trace() / 3.0,
            vol: mass / rho,
            z: m.rho0 * m.c0,
            p_rho: m.bulk * (rho / m.rho0 - 1.0),
        }
    }

    /// The record of particle `i` of `p` (positions and densities at the half step
    /// after [`drift`], stress σ_n).
    #[inline(always)]
    pub fn of<const D: usize>(p: &FineParticles<D>, mats: &[FineMaterial], i: usize) -> Self {
        let m = &mats[p.material[i] as usize];
        Source::new(m, &p.stress[i], p.mass[i], p.rho[i])
    }
}

/// Eq. (54): move positions and densities to the half step (densities held at their
/// floor, `floor` per soil; empty: no floor).
pub fn drift<const D: usize>(p: &mut FineParticles<D>, (half, floor): (Real, &[Real])) {
    let mut pos = std::mem::take(&mut p.pos);
    let mut rho = std::mem::take(&mut p.rho);
    let state = &*p;
    let floor = (!floor.is_empty()).then_some(DensityFloor {
        material: &state.material,
        floor,
    });
    pos.par_iter_mut()
        .zip(rho.par_iter_mut())
        .enumerate()
        .with_min_len(CHUNK)
        .for_each(|(i, (x, r))| {
            *x += state.vel[i] * half;
            *r += state.drho[i] * half;
            if let Some(f) = &floor {
                f.hold(i, r);
            }
        });
    p.pos = pos;
    p.rho = rho;
}
