//! The water sweeps: the water–water pair laws on the clusters' lanes
//! ([`WaterLanes`]: [`water::momentum`], [`water::continuity`], the correction and the
//! velocity gradient), then one particle pass each that adds the walls
//! ([`water_wall`](super::water_wall), with their barrier loads,
//! [`barrier_load`](super::barrier_load)) to the pair sums and integrates.
//!
//! [`water::momentum`]: crate::water::momentum
//! [`water::continuity`]: crate::water::continuity

use super::barrier_load;
use super::fine_coarse::CoarseSource;
use super::water_buoyancy::Hydrostatics;
use super::water_coarse;
use super::water_wall::{self, WaterAtWall};

/// Coarse grains seen by the water sweeps: their packed records and one reaction
/// buffer per chunk that receives `(coarse particle, force)` records.
pub struct WaterCoarse<'a, const D: usize> {
    pub src: &'a [CoarseSource<D>],
    pub reactions: &'a mut [Vec<(u32, Vect<D>)>],
    /// The bodies' hydrostatic fields ([`water_buoyancy`](super::water_buoyancy)).
    pub field: &'a Hydrostatics<D>,
    /// One buffer per chunk that receives each pair's share of the field on the
    /// coarse particle, `(coarse particle, force)`.
    pub shares: &'a mut [Vec<(u32, Vect<D>)>],
}
use crate::geometry::walls::Walls;
use crate::numerics::load::Load;
use crate::numerics::math::{Real, Vect};
use crate::numerics::neighbors::{ChunkList, NeighborLists, CHUNK};
use crate::numerics::pairs::clusters::ClusterPairs;
use crate::numerics::pairs::quad::Lanes;
use crate::water::correction::{self, Corr};
use crate::water::lanes::WaterLanes;
use crate::water::momentum::{WaterParams, WaterSums};
use crate::water::source::WaterSource;
use crate::water::state::WaterParticles;
use rayon::prelude::*;

/// The water–water pair laws' executor for one sub-step: the lane buffers holding the
/// state packed at its start ([`WaterLanes::pack`]), the clusters brought up to the
/// last list build, and the instruction set ([`Lanes::detect`]).
pub type WaterPairs<'a, const D: usize> = (&'a mut WaterLanes<D>, &'a ClusterPairs, Lanes);

/// Runs over the water–water relation.
///
/// The momentum sweep's water–water terms into `sums[..].acc` (zero on entry); `corr`
/// holds B, `grad` the velocity gradients with `water.muscl` (empty without).
pub fn momentum_pairs<const D: usize>(
    (corr, grad): (&[Corr<D>], &[Corr<D>]),
    prm: &WaterParams<D>,
    (buf, cp, lanes): WaterPairs<'_, D>,
    sums: &mut [WaterSums<D>],
) {
    buf.pack_corr(cp, corr);
    let muscl = !grad.is_empty();
    if muscl {
        buf.pack_grad(cp, grad);
    }
    buf.momentum(cp, (prm, muscl), lanes, sums);
}

/// Runs over the water–water relation.
///
/// The continuity sweep's water–water terms into `sums[..].drho` (zero on entry), with
/// the velocities v_{n+1} in `w`; `body` holds each particle's seepage acceleration
/// (empty: none). It reads the state the momentum pass packed, with the velocities
/// packed anew.
pub fn continuity_pairs<const D: usize>(
    w: &WaterParticles<D>,
    prm: &WaterParams<D>,
    body: &[Vect<D>],
    (buf, cp, lanes): WaterPairs<'_, D>,
    sums: &mut [WaterSums<D>],
) {
    buf.repack_velocity(cp, &w.vel, (&prm.hydrostatic, body));
    buf.continuity(cp, prm, lanes, sums);
}

/// Runs over the water–water, water–wall and water–coarse relations.
///
/// The kernel gradient correction B of every particle into `corr`: M from the
/// water–water pairs and the walls, then inverted ([`correction`]); the identity where
/// `on` is false.
#[allow(clippy::too_many_arguments)]
pub fn correction_sweep<const D: usize>(
    w: &WaterParticles<D>,
    walls: &Walls<D>,
    csrc: &[CoarseSource<D>],
    lists: &NeighborLists,
    prm: &WaterParams<D>,
    (on, (buf, cp, lanes)): (bool, WaterPairs<'_, D>),
    corr: &mut [Corr<D>],
) {
    if !on {
        corr.par_iter_mut().for_each(|b| *b = Corr::<D>::identity());
        return;
    }
    corr.par_iter_mut().for_each(|b| *b = Corr::<D>::zeros());
    buf.correction(cp, prm, lanes, corr);
    lists
        .chunks
        .par_iter()
        .zip(corr.par_chunks_mut(CHUNK))
        .enumerate()
        .for_each(|(c, (cl, out))| {
            for (k, b) in out.iter_mut().enumerate() {
                let xi = w.pos[c * CHUNK + k];
                boundary_moment(b, (prm, walls, csrc), (cl, k), &xi);
                *b = correction::invert(b);
            }
        });
}

/// Add the walls' and the coarse particles' share of M to `m`, for particle `k` of a
/// chunk's lists `cl` at `xi`.
#[inline]
fn boundary_moment<const D: usize>(
    m: &mut Corr<D>,
    (prm, walls, csrc): (&WaterParams<D>, &Walls<D>, &[CoarseSource<D>]),
    (cl, k): (&ChunkList, usize),
    xi: &Vect<D>,
) {
    for &wp in cl.wall(k) {
        *m += water_wall::moment(prm, walls, xi, wp as usize);
    }
    for &j in cl.coarse(k) {
        *m += water_coarse::moment(prm, &csrc[j as usize], xi);
    }
}

/// The correction and the velocity gradient (`water.muscl`) in one walk over the water
/// pairs: their sums M and L together into `ml`
/// ([`WaterLanes::moment_and_gradient`]), then per particle B into `corr` (with the
/// correction `on`, M⁻¹ with the walls' and bodies' M; the identity without) and
/// ∇v = L B into `grad` ([`gradient`](crate::water::gradient)). Wall and coarse
/// neighbours do not enter L: the gradient of a particle by a wall is that of its
/// water neighbours, under-estimated where B is not blended to I, which only leaves
/// more dissipation there.
#[allow(clippy::too_many_arguments)]
pub fn correction_and_gradient_sweep<const D: usize>(
    w: &WaterParticles<D>,
    walls: &Walls<D>,
    csrc: &[CoarseSource<D>],
    lists: &NeighborLists,
    prm: &WaterParams<D>,
    (on, (buf, cp, lanes)): (bool, WaterPairs<'_, D>),
    ml: &mut [[Corr<D>; 2]],
    (corr, grad): (&mut [Corr<D>], &mut [Corr<D>]),
) {
    ml.par_iter_mut().for_each(|s| *s = [Corr::<D>::zeros(); 2]);
    buf.moment_and_gradient(cp, prm, lanes, ml);
    lists
        .chunks
        .par_iter()
        .zip(ml.par_chunks(CHUNK))
        .zip(corr.par_chunks_mut(CHUNK))
        .zip(grad.par_chunks_mut(CHUNK))
        .enumerate()
        .for_each(|(c, (((cl, ml), corr), grad))| {
            for (k, (b, g)) in corr.iter_mut().zip(grad.iter_mut()).enumerate() {
                *b = if on {
                    let mut m = ml[k][0];
                    let xi = w.pos[c * CHUNK + k];
                    boundary_moment(&mut m, (prm, walls, csrc), (cl, k), &xi);
                    correction::invert(&m)
                } else {
                    Corr::<D>::identity()
                };
                *g = ml[k][1] * *b;
            }
        });
}

#[allow(clippy::too_many_arguments)]
pub fn momentum_sweep<const D: usize>(
    w: &WaterParticles<D>,
    src: &[WaterSource],
    corr: &[Corr<D>],
    walls: &Walls<D>,
    coarse: WaterCoarse<'_, D>,
    lists: &NeighborLists,
    prm: &WaterParams<D>,
    (no_slip, body): (bool, &[Vect<D>]),
    vel_new: &mut [Vect<D>],
    loads: &mut [Load],
    sums: &mut [WaterSums<D>],
) {
    let (csrc, field) = (coarse.src, coarse.field);
    let nbs = walls.load_slots().max(1);
    lists
        .chunks
        .par_iter()
        .zip(sums.par_chunks_mut(CHUNK))
        .zip(vel_new.par_chunks_mut(CHUNK))
        .zip(loads.par_chunks_mut(nbs))
        .zip(coarse.reactions.par_iter_mut())
        .zip(coarse.shares.par_iter_mut())
        .enumerate()
        .for_each(|(c, (((((cl, sums), vout), lout), react), shares))| {
            for l in lout.iter_mut() {
                *l = Load::default();
            }
            react.clear();
            shares.clear();
            for (k, vo) in vout.iter_mut().enumerate() {
                let i = c * CHUNK + k;
                let (xi, vi, rho) = (w.pos[i], w.vel[i], w.rho[i]);
                let scale = 2.0 / rho;
                let mut acc = std::mem::replace(&mut sums[k].acc, Vect::<D>::zeros()) * scale;
                let wl = cl.wall(k);
                if !wl.is_empty() {
                    let mut at =
                        WaterAtWall::new(prm, walls, (xi, vi, rho, src[i].p), wl, no_slip, corr[i]);
                    if let Some(b) = body.get(i) {
                        // the seepage drag of the last sub-step joins gravity
                        at.hyd += b;
                    }
                    for &wp in wl {
                        if let Some(t) = at.momentum(prm, walls, wp as usize) {
                            let a = t * scale;
                            acc += a;
                            barrier_load::add_reaction(walls, wp as usize, &a, w.mass[i], lout);
                        }
                    }
                }
                let state = (&xi, &vi, rho, src[i].p);
                // water in the film between a body and what it lies on (module notes of
                // water_buoyancy): within the kernel of a wall or of a second body
                let film = field.film(prm, (walls, csrc), &xi, cl.coarse(k));
                for &j in cl.coarse(k) {
                    let cj = &csrc[j as usize];
                    if let Some(t) = water_coarse::momentum(prm, cj, state, &corr[i], no_slip) {
                        let a = t * scale;
                        acc += a;
                        react.push((j, a * (-w.mass[i])));
                        let pc = field.p[j as usize];
                        if film && field.in_gap(j as usize) {
                            // the film's pressure is the field's: the body gets none of
                            // this pair but its share of Archimedes' force
                            shares.push((j, a * (-w.mass[i])));
                        } else if pc.is_finite() {
                            let f = (pc, field.rho_g(j as usize));
                            if let Some(h) =
                                water_coarse::hydrostatic_share(prm, cj, &xi, &corr[i], f)
                            {
                                shares.push((j, h * (-scale * w.mass[i])));
                            }
                        }
                    }
                }
                *vo = (vi + (acc + prm.gravity) * prm.dt) * prm.keep;
            }
        });
}

/// Runs over the water–water, water–wall and water–coarse relations.
///
/// dρ/dt with v_{n+1} into `drho`; `sums[..].drho` holds the water–water terms on
/// entry ([`continuity_pairs`]) and is left zero.
#[allow(clippy::too_many_arguments)]
pub fn continuity_sweep<const D: usize>(
    w: &WaterParticles<D>,
    walls: &Walls<D>,
    csrc: &[CoarseSource<D>],
    lists: &NeighborLists,
    prm: &WaterParams<D>,
    drho: &mut [Real],
    sums: &mut [WaterSums<D>],
) {
    lists
        .chunks
        .par_iter()
        .zip(sums.par_chunks_mut(CHUNK))
        .zip(drho.par_chunks_mut(CHUNK))
        .enumerate()
        .for_each(|(c, ((cl, sums), dout))| {
            for (k, d) in dout.iter_mut().enumerate() {
                let i = c * CHUNK + k;
                let mut rate = std::mem::replace(&mut sums[k].drho, 0.0);
                for &wp in cl.wall(k) {
                    rate += water_wall::continuity(prm, walls, &w.pos[i], &w.vel[i], wp as usize);
                }
                for &j in cl.coarse(k) {
                    rate += water_coarse::continuity(prm, &csrc[j as usize], &w.pos[i], &w.vel[i]);
                }
                *d = w.rho[i] * rate;
            }
        });
}
