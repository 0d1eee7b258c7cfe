//! The per-particle data that neighbours read in the water sweeps: pressure and
//! volume at the half step, packed once per step.

use super::material::WaterMaterial;
use super::state::WaterParticles;
use crate::numerics::math::Real;
use crate::numerics::neighbors::CHUNK;
use rayon::prelude::*;

/// Neighbour-side view of a water particle for one step.
#[derive(Clone, Copy, Debug, Default)]
pub struct WaterSource {
    /// Pressure from the equation of state.
    pub p: Real,
    /// Volume m/ρ.
    pub vol: Real,
    /// Density ρ.
    pub rho: Real,
}

/// Drift positions and density by `half` (x += v Δt/2, ρ += dρ/dt Δt/2, as seed 000
/// Eq. 54 does for the fine grains) and pack the sources at the new density.
pub fn drift_and_pack<const D: usize>(
    w: &mut WaterParticles<D>,
    m: &WaterMaterial,
    half: Real,
    src: &mut Vec<WaterSource>,
) {
    src.resize(w.len(), WaterSource::default());
    w.pos
        .par_chunks_mut(CHUNK)
        .zip(w.rho.par_chunks_mut(CHUNK))
        .zip(w.vel.par_chunks(CHUNK))
        .zip(w.drho.par_chunks(CHUNK))
        .zip(w.mass.par_chunks(CHUNK))
        .zip(src.par_chunks_mut(CHUNK))
        .for_each(|(((((x, r), v), d), mass), s)| {
            for k in 0..x.len() {
                x[k] += v[k] * half;
                r[k] += d[k] * half;
                s[k] = WaterSource {
                    p: m.pressure(r[k]),
                    vol: mass[k] / r[k],
                    rho: r[k],
                };
            }
        });
}

/// Pack the sources at the current density, without moving (after a re-sort).
pub fn pack<const D: usize>(w: &WaterParticles<D>, m: &WaterMaterial, src: &mut Vec<WaterSource>) {
    src.clear();
    src.par_extend(
        w.rho
            .par_iter()
            .zip(&w.mass)
            .map(|(&r, &mass)| WaterSource {
                p: m.pressure(r),
                vol: mass / r,
                rho: r,
            }),
    );
}
