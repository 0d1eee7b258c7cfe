//! The fine grains' continuity and stress sweep with v_{n+1}: the fine–fine pair law on
//! the clusters' lanes ([`fine::lanes`](crate::fine::lanes),
//! [`fine::continuity`](crate::fine::continuity)), then one particle pass that adds,
//! per fine particle, the walls as no-slip mirrors ([`fine_wall`](super::fine_wall),
//! Eqs. 32–34) and the coarse grains as free-slip mirrors moving with v̄
//! ([`fine_coarse`](super::fine_coarse), Eqs. 48, 60) to the pair sums, and updates the
//! stress (Eqs. 7–12, 15, 24–26).

use super::fine_coarse::{self, CoarseSource};
use super::fine_wall;
use crate::fine::continuity::{ContinuityOut, ContinuityParams, ParticleOut, Rates};
use crate::fine::lanes::FinePairs;
use crate::fine::material::FineMaterial;
use crate::fine::pair_sums::ContinuitySums;
use crate::fine::state::FineParticles;
use crate::geometry::walls::Walls;
use crate::numerics::neighbors::{NeighborLists, CHUNK};
use crate::numerics::sleep::{Asleep, RESTLESS};
use rayon::prelude::*;

/// Runs over the fine–fine, fine–wall and fine–coarse relations.
///
/// Sweep with v_{n+1} already in `p.vel`. A sleeping particle (`asleep`) keeps its
/// stress and dρ/dt = 0; an awake one whose velocity gradient is restless is flagged
/// in `flags`.
#[allow(clippy::too_many_arguments)]
pub fn continuity_sweep<const D: usize>(
    p: &FineParticles<D>,
    mats: &[FineMaterial],
    walls: &Walls<D>,
    lists: &NeighborLists,
    prm: &ContinuityParams<'_, D>,
    coarse: &[CoarseSource<D>],
    out: ContinuityOut<'_, D>,
    (buf, cp, lanes): FinePairs<'_, D>,
    (asleep, flags): (Asleep<'_>, &mut [u8]),
) {
    // neighbour arrays of one length, so that a neighbour index is bounds-checked once
    let n = p.len();
    let (pos, vel, material) = (&p.pos[..n], &p.vel[..n], &p.material[..n]);
    let terms = (vel, prm.kernel, prm.wrap, prm.uniform);
    buf.continuity(cp, terms, lanes, &mut *out.sums);
    lists
        .chunks
        .par_iter()
        .zip(out.sums.par_chunks_mut(CHUNK))
        .zip(out.drho.par_chunks_mut(CHUNK))
        .zip(out.stress.par_chunks_mut(CHUNK))
        .zip(out.plastic_strain.par_chunks_mut(CHUNK))
        .zip(out.vel_grad.par_chunks_mut(CHUNK))
        .zip(out.hourglass_kept.par_chunks_mut(CHUNK))
        .zip(flags.par_chunks_mut(CHUNK))
        .enumerate()
        .for_each(
            |(c, (((((((cl, sums), drho_out), stress_out), eps_out), lg_out), kept_out), fl))| {
                for k in 0..drho_out.len() {
                    let i = c * CHUNK + k;
                    let mat = material[i] as usize;
                    let (xi, vi) = (pos[i], vel[i]);
                    // the pair sums, left zero for the next step
                    let sum = std::mem::replace(&mut sums[k].continuity, ContinuitySums::zero());
                    if asleep.at(i) {
                        drho_out[k] = 0.0;
                        continue;
                    }
                    let weight = prm.weight.get(i).copied().unwrap_or(1.0);
                    let mut rates = Rates::from_sums(prm, &stress_out[k], (mat, weight), &sum);
                    let (drho, grad) = (&mut rates.drho, &mut rates.grad);
                    for &w in cl.wall(k) {
                        let (k, wrap) = (&prm.kernel, &prm.wrap);
                        fine_wall::continuity(k, walls, wrap, &xi, &vi, w as usize, drho, grad);
                    }
                    for &j in cl.coarse(k) {
                        let cj = &coarse[j as usize];
                        fine_coarse::continuity(&prm.kernel, cj, &xi, &vi, drho, grad);
                    }
                    let out = ParticleOut {
                        stress: &mut stress_out[k],
                        plastic_strain: &mut eps_out[k],
                        vel_grad: &mut lg_out[k],
                        kept: &mut kept_out[k],
                    };
                    drho_out[k] = rates.update(prm, &mats[mat], p.rho[i], out);
                    if let Some(r) = asleep.rule {
                        let l2 = lg_out[k].norm_squared() as crate::numerics::math::Real;
                        if r.restless_strain(l2) {
                            fl[k] |= RESTLESS;
                        }
                    }
                }
            },
        );
}
