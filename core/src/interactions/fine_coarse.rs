//! Fine ↔ coarse coupling, Eqs. (48)–(50) and (60).
//!
//! A fine particle sees a coarse particle as a solid boundary particle whose stress is
//! its own (σ_j^c = σ_i^f), moving with the time-averaged coarse velocity v̄ of Eq.
//! (60). Per pair, the acceleration of fine particle i is
//!   a_ij = (2/ρ_i) (σ_i·e_ij − P*_diss n_j) ∂W/∂r V_j                     (Eq. 48)
//! with P*_diss of Eq. (49) taken on the coarse normal n_j (Z_R = ρ_c c_c, infinite for
//! a rigid body; the limiter sees the mirrored jump, as at walls). Coulomb friction
//! μ_cf acts against the tangential slip, bounded by μ_cf times the normal part.
//! The coarse particle receives exactly −m_i a_ij (Eq. 50 with σ_i^c = σ_j^f), so the
//! momentum exchanged over each fine step balances to round-off.
//! A cohesionless soil's interface carries no tension: an attractive normal part of
//! a_ij (a separating fine particle pulled by P*_diss, or by a tensile stress) is
//! dropped, and the contact is frictional (μ_cf) without adhesion, as the contacts of
//! the MPM–DEM of seed 004. A cohesive soil (c > 0) is bonded to the boulders as
//! Eq. (48) has it: the mirrored stress σ_i carries the soil's tension, bounded by its
//! own Drucker–Prager surface, so the interface is as strong as the soil.
//!
//! In the continuity equation a coarse particle is a free-slip mirror moving with v̄
//! ([`continuity`]).

use crate::coarse::{Body, CoarseParticles, SolidMaterial};
use crate::numerics::kernel::WendlandC2;
use crate::numerics::math::{sub_outer, Real, Sym, Vect};
use crate::numerics::riemann::Riemann;
use nalgebra::SMatrix;
use rayon::prelude::*;

/// The coarse-particle data the fine sweeps read.
#[derive(Clone, Copy, Debug, serde::Serialize, serde::Deserialize)]
pub struct CoarseSource<const D: usize> {
    /// Position at the middle of the fine step.
    pub pos: Vect<D>,
    /// Time-averaged velocity v̄ of Eq. (60).
    pub vel: Vect<D>,
    /// Outward unit normal n^c (zero inside).
    pub normal: Vect<D>,
    /// 1/(ρ_c c_c); 0 for rigid bodies.
    pub inv_z: Real,
    /// Reference volume V⁰ = dp^d.
    pub vol: Real,
    /// Depth below the body surface (m).
    pub depth: Real,
    /// The body's acceleration over the last fine step, F/m + g (translation only;
    /// zero for a fixed body):
    /// the water's dummy pressure takes it (Adami et al. 2012); the fine coupling does
    /// not.
    pub acc: Vect<D>,
}

/// Pack the coarse particles for a fine step of length `dt`: positions predicted to
/// its middle with the current velocity; `gravity` for the bodies' accelerations.
pub fn pack<const D: usize>(
    p: &CoarseParticles<D>,
    bodies: &[Body<D>],
    solids: &[SolidMaterial],
    (dt, vol): (Real, Real),
    gravity: &Vect<D>,
    out: &mut Vec<CoarseSource<D>>,
) {
    out.clear();
    out.par_extend((0..p.len()).into_par_iter().with_min_len(256).map(|i| {
        let b = &bodies[p.body[i] as usize];
        let m = &solids[b.material];
        CoarseSource {
            pos: p.pos[i] + p.vel[i] * (0.5 * dt),
            vel: p.vbar[i],
            normal: p.normal[i],
            inv_z: if b.is_rigid() {
                0.0
            } else {
                1.0 / (m.rho0 * m.c0)
            },
            vol,
            depth: p.depth[i],
            acc: if b.fixed {
                Vect::<D>::zeros()
            } else {
                crate::numerics::math::from3::<D>(&b.force) / b.mass + gravity
            },
        }
    }));
}

/// Fine-particle inputs of one coupling pair.
pub struct FineSide<'a, const D: usize> {
    pub pos: Vect<D>,
    pub vel: Vect<D>,
    pub rho: Real,
    pub stress: &'a Sym,
    /// ρ0 c0 of the fine material and 1/c0.
    pub z: Real,
    pub inv_c: Real,
    /// c0² of the fine material (penetration barrier).
    pub c2: Real,
    /// The interface carries the soil's tension (cohesive soil).
    pub tension: bool,
}

/// Coupling settings.
#[derive(Clone, Copy, Debug)]
pub struct Coupling {
    pub kernel: WendlandC2,
    pub riemann: Riemann,
    /// μ_cf.
    pub mu_cf: Real,
    pub dt: Real,
    /// Particle spacing dp.
    pub dp: Real,
}

impl Coupling {
    /// Acceleration of the fine particle from one coarse particle (zero outside the
    /// kernel). `share` divides the friction bound among the coarse neighbours.
    #[inline]
    pub fn acceleration<const D: usize>(
        &self,
        f: &FineSide<'_, D>,
        c: &CoarseSource<D>,
        share: Real,
    ) -> Option<Vect<D>> {
        let rij = f.pos - c.pos;
        let r2 = rij.norm_squared();
        let cut = self.kernel.cutoff;
        if r2 >= cut * cut || r2 == 0.0 {
            return None;
        }
        let r = r2.sqrt();
        let e = rij / r;
        let dwv = self.kernel.dw(r) * c.vol;
        let n = c.normal;
        let vrel = f.vel - c.vel;
        // approach speed along n (U_L − U_R of Eq. 49 with U along −n)
        let w = -vrel.dot(&n);
        let beta = self.riemann.limiter(2.0 * w, f.inv_c);
        // Z_L Z_R / (Z_L + Z_R) = Z_f / (1 + Z_f / Z_c)
        let zeff = f.z / (1.0 + f.z * c.inv_z);
        let p_diss = beta * zeff * w;
        let k = 2.0 / f.rho * dwv;
        let mut a = (f.stress.dot_vec(&e) - n * p_diss) * k;
        // a cohesionless soil's interface carries no tension: an attractive normal
        // part (a separating fine particle, or one in tension) is dropped; a cohesive
        // soil keeps Eq. (48) whole
        let an = a.dot(&n);
        if an < 0.0 && !f.tension {
            a -= n * an;
        }
        // penetration barrier (not in seed 000): coarse particle j, at depth d_j below
        // the body surface, is a ball of radius R_j = (d_j² + dp²/4)^½. The ball of
        // radius d_j lies inside the body, so a fine particle outside it penetrates
        // R_j by at most R_j − d_j ≤ dp/2, and one at its rest distance (d_j + dp/2
        // along the normal) is untouched; on a flat face the balls of the surface
        // layer meet at the surface midway between particles. Inside a ball the fine
        // particle is pushed out radially by a spring of frequency c0/dp weighted by
        // W_ij V_j. The push is continuous in position, at corners and tips too, and
        // inactive while the interface holds. It stops a fine particle in tension
        // (which the no-tension interface does not hold back) from being pressed into
        // a boulder by its neighbours, and pushes out one that got in.
        let radius2 = c.depth * c.depth + 0.25 * self.dp * self.dp;
        if r2 < radius2 {
            let w = self.kernel.w(r) * c.vol;
            a += e * (f.c2 / (self.dp * self.dp) * (radius2.sqrt() - r) * w);
        }
        if self.mu_cf > 0.0 && n.norm_squared() > 0.0 {
            let an = a.dot(&n);
            if an > 0.0 {
                let vt = vrel - n * vrel.dot(&n);
                let s = vt.norm();
                if s > 0.0 {
                    let mag = (self.mu_cf * an).min(s / self.dt * share);
                    a -= vt * (mag / s);
                }
            }
        }
        Some(a)
    }
}

/// Coarse grains seen by the fine sweeps: their packed records, the coupling law, per
/// fine material whether the interface carries the soil's tension (cohesive soils,
/// c > 0), and one reaction buffer per chunk that receives `(coarse particle, force)`
/// records.
pub struct CoarseSide<'a, const D: usize> {
    pub src: &'a [CoarseSource<D>],
    pub coupling: Coupling,
    pub tension: &'a [bool],
    pub reactions: &'a mut [Vec<(u32, Vect<D>)>],
}

/// The continuity terms of coarse particle `c` on fine particle i at `xi` moving with
/// `vi` (Eqs. 48, 60), added to `drho` (Eq. 15) and `grad` (Eq. 24). The coarse
/// particle is a free-slip mirror moving with v̄: only the normal relative velocity is
/// reflected (no coarse–fine friction here; μ_cf acts in the momentum sweep). The
/// mirror plane is the coarse particle's tangent plane, which holds for a fine particle
/// in front of it (n_j·e_ij > 0); one beside or behind it (at a corner or tip of a body
/// resolved by few particles) is reflected along e_ij instead, as by an interior
/// particle. Reflected across n_j, such a particle would be compressed while it moves
/// away from the body (n_j·e_ij < 0 flips the sign of the approach rate).
#[inline(always)]
pub fn continuity<const D: usize>(
    kernel: &WendlandC2,
    c: &CoarseSource<D>,
    xi: &Vect<D>,
    vi: &Vect<D>,
    drho: &mut Real,
    grad: &mut SMatrix<Real, D, D>,
) {
    let cut2 = kernel.cutoff * kernel.cutoff;
    let rij = xi - c.pos;
    let r2 = rij.norm_squared();
    if r2 >= cut2 || r2 == 0.0 {
        return;
    }
    let r = r2.sqrt();
    let e = rij * (1.0 / r);
    let dwv = kernel.dw(r) * c.vol;
    let n = if c.normal.dot(&e) > 0.0 { c.normal } else { e };
    let rel = n * (2.0 * (vi - c.vel).dot(&n));
    *drho += rel.dot(&e) * dwv;
    sub_outer(grad, &(rel * dwv), &e);
}

/// Scatter the per-chunk coarse reactions (`(particle, force)` records in chunk order)
/// into `f_fine`, in a fixed order.
pub fn gather_reactions<const D: usize>(chunks: &[Vec<(u32, Vect<D>)>], f_fine: &mut [Vect<D>]) {
    for f in f_fine.iter_mut() {
        *f = Vect::<D>::zeros();
    }
    add_reactions(chunks, f_fine, 1.0);
}

/// Add the per-chunk `(coarse particle, force)` records of `chunks`, times `scale`, to
/// `out` (the water's mean force over its sub-steps).
pub fn add_reactions<const D: usize>(
    chunks: &[Vec<(u32, Vect<D>)>],
    out: &mut [Vect<D>],
    scale: Real,
) {
    for c in chunks {
        for (j, f) in c {
            out[*j as usize] += *f * scale;
        }
    }
}
