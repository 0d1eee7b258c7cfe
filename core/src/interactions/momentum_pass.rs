//! The fine grains' momentum sweep: the fine–fine pair law on the clusters' lanes
//! ([`fine::lanes`](crate::fine::lanes), [`fine::momentum`](crate::fine::momentum)), then one particle pass that adds, per
//! fine particle, the walls ([`fine_wall`](super::fine_wall), Eqs. 32–35, with their
//! barrier loads, [`barrier_load`](super::barrier_load)) and the coarse grains
//! ([`fine_coarse`](super::fine_coarse), Eqs. 48–50) to the pair sums and integrates
//! (Eq. 55), with the water's force on a soil ([`soil_water`](super::soil_water),
//! seed 001 Eqs. 8–10) where there is one. The interactions are fused into the one pass so that a particle's record
//! is read once; each interaction's formula lives in its own module.

use super::barrier_load;
use super::fine_coarse::{CoarseSide, FineSide};
use super::fine_wall::{FineAtWall, WallLaw};
use crate::fine::continuity::JumpDiffusion;
use crate::fine::lanes::FinePairs;
use crate::fine::momentum::{integrate, pair_acceleration, MomentumParams};
use crate::fine::pair_sums::{MomentumSums, PairSums};
use crate::fine::source::Source;
use crate::fine::state::FineParticles;
use crate::geometry::walls::Walls;
use crate::numerics::load::Load;
use crate::numerics::math::{Real, Sym, Vect};
use crate::numerics::neighbors::{NeighborLists, CHUNK};
use crate::numerics::sleep::Asleep;
use nalgebra::SVector;
use rayon::prelude::*;

/// What the momentum sweep reads and writes of the step's sleep
/// ([`sleep`](crate::numerics::sleep)): which particles sleep (without a rule none,
/// and no flag is written), which wall objects hold the particles within their reach
/// awake (barriers and walls that can move), and each particle's flags of the step.
pub struct FineSleep<'a> {
    pub asleep: Asleep<'a>,
    pub waking_walls: &'a [bool],
    pub flags: &'a mut [u8],
}

/// Whether a wall particle of the list `wl` belongs to an object that holds its
/// neighbours awake (`waking`, per object).
#[inline(always)]
fn held_by<const D: usize>(waking: &[bool], walls: &Walls<D>, wl: &[u32]) -> bool {
    wl.iter()
        .any(|&w| waking[walls.object[w as usize] as usize])
}

/// Runs over the fine–fine, fine–wall and fine–coarse relations.
///
/// Compute v_{n+1} into `vel_new`, advance the accumulated hourglass acceleration in
/// `hourglass` (in place; each particle reads only its own entry) and per-chunk barrier
/// loads into `loads` (`max(1, barriers)` slots per chunk). `sums` holds one entry per
/// particle, all zero on entry; its momentum part is left zero, its continuity part
/// holds the [`JumpDiffusion`] terms for the continuity sweep. A sleeping particle
/// (`sleep`) keeps v = 0 and its penalty; an awake one is flagged restless or held.
#[allow(clippy::too_many_arguments)]
pub fn momentum_sweep<const D: usize>(
    p: &FineParticles<D>,
    walls: &Walls<D>,
    lists: &NeighborLists,
    art: &[Sym],
    prm: &MomentumParams<'_, D>,
    wall: &WallLaw<D>,
    vel_new: &mut [Vect<D>],
    hourglass: &mut [SVector<f32, D>],
    loads: &mut [Load],
    coarse: CoarseSide<'_, D>,
    jump: &JumpDiffusion<'_, D>,
    sums: &mut [PairSums<D>],
    water: &[Vect<D>],
    (buf, cp, lanes): FinePairs<'_, D>,
    sleep: FineSleep<'_>,
) {
    let (asleep, waking) = (sleep.asleep, sleep.waking_walls);
    let (csrc, coupling, tension) = (coarse.src, coarse.coupling, coarse.tension);
    let nbs = walls.load_slots().max(1);
    // neighbour arrays of one length, so that a neighbour index is bounds-checked once
    let n = p.len();
    let (pos, vel) = (&p.pos[..n], &p.vel[..n]);
    buf.momentum(cp, (p, art), prm, jump, lanes, &mut *sums);
    lists
        .chunks
        .par_iter()
        .zip(sums.par_chunks_mut(CHUNK))
        .zip(vel_new.par_chunks_mut(CHUNK))
        .zip(hourglass.par_chunks_mut(CHUNK))
        .zip(loads.par_chunks_mut(nbs))
        .zip(coarse.reactions.par_iter_mut())
        .zip(sleep.flags.par_chunks_mut(CHUNK))
        .enumerate()
        .for_each(|(c, ((((((cl, sums), vout), hout), lout), react), fl))| {
            for l in lout.iter_mut() {
                *l = Load::default();
            }
            react.clear();
            // one particle's wall pairs at a time, the buffer kept across the chunk
            let mut pairs = Vec::new();
            for (k, vo) in vout.iter_mut().enumerate() {
                let i = c * CHUNK + k;
                let mat = &prm.materials[p.material[i] as usize];
                let (xi, vi, rhoi) = (pos[i], vel[i], p.rho[i]);
                // the pair sums, left zero for the next step
                let sum = std::mem::replace(&mut sums[k].momentum, MomentumSums::zero());
                if asleep.at(i) {
                    *vo = Vect::<D>::zeros();
                    fl[k] = 0;
                    continue;
                }
                let mut acc = pair_acceleration(&sum, rhoi);
                let wl = cl.wall(k);
                // the water's force on a soil (soil_water): buoyancy and seepage
                let lift = water.get(i).map(|f| f / p.mass[i]);
                // held awake by a wall in motion or a barrier, or a coarse grain
                let mut held = asleep.rule.is_some() && held_by(waking, walls, wl);
                if !wl.is_empty() {
                    let (w, s) = (walls, &Source::new(mat, &p.stress[i], p.mass[i], rhoi));
                    let at = FineAtWall::new(wall, w, mat, xi, vi, rhoi, s, wl, lift.as_ref());
                    at.accelerations(wall, walls, wl, &mut pairs);
                    for q in &pairs {
                        acc += q.a;
                        barrier_load::add_reaction(walls, q.w as usize, &q.a, p.mass[i], lout);
                    }
                }
                let near = cl.coarse(k);
                if !near.is_empty() {
                    held = true;
                    let fs = FineSide {
                        pos: xi,
                        vel: vi,
                        rho: rhoi,
                        stress: &p.stress[i],
                        z: mat.rho0 * mat.c0,
                        inv_c: 1.0 / mat.c0,
                        c2: mat.c0 * mat.c0,
                        tension: tension[p.material[i] as usize],
                    };
                    let share = 1.0 / near.len() as Real;
                    for &j in near {
                        if let Some(a) = coupling.acceleration(&fs, &csrc[j as usize], share) {
                            acc += a;
                            react.push((j, a * (-p.mass[i])));
                        }
                    }
                }
                if let Some(a) = lift {
                    acc += a;
                }
                *vo = integrate(p, prm, i, acc, &sum.hourglass, &mut hout[k]);
                if let Some(r) = asleep.rule {
                    fl[k] = r.motion_flags((&vi, vo), prm.dt, held);
                }
            }
        });
}
