//! Momentum sweep, Eqs. (16), (20), (27) and the wall terms of Eqs. (32)–(35).
//!
//! For each fine particle i:
//!   dv_i/dt = 2/ρ_i Σ_j (σ̄ˢ_ij − P* I + f_ijⁿ R̄_ij)·∇_i W_ij V_j + g
//!           + 2/ρ_i Σ_w (σˢ_i − P*_w I)·∇_i W_iw V_w
//! and v_{n+1} = v_n + Δt dv/dt (Eq. 55). Wall particles take the stress of i
//! (σ_w = σ_i, no-slip); P*_w solves the one-sided Riemann problem along the wall
//! normal of Eq. (33). The wall pair's interface stress is cut at the soil's tensile
//! strength, the apex of its Drucker–Prager cone ([`wall_contact`]): a contact that
//! would pull harder opens. The reaction on barrier particles is summed per chunk.
//!
//! The sweep has two passes. The pair pass evaluates each fine–fine pair once and adds
//! its terms to both particles' [`MomentumSums`] (two-phase slab schedule,
//! [`slabs`](crate::slabs)): σ̄ˢ_ij, P* and the hourglass weight are symmetric in the
//! pair and e_ji = −e_ij, so j receives the negated traction weighted by V_i. The same
//! pass takes the continuity sweep's terms without velocity
//! ([`JumpDiffusion`], [`pair_sums`](super::pair_sums)). The particle pass adds the wall
//! and coarse-grain terms and integrates.

use super::continuity::JumpDiffusion;
use super::hourglass::{non_affine, pair_weight};
use super::material::FineMaterial;
use super::pair_block::{Pair, PairBlock, BLOCK};
use super::pair_sums::PairSums;
use super::source::Source;
use super::state::FineParticles;
use super::wall_contact;
use crate::coarse::coupling::{CoarseSource, Coupling, FineSide};
use crate::kernel::WendlandC2;
use crate::load::Load;
use crate::math::{to3, Real, Sym, Vect};
use crate::neighbors::{NeighborLists, CHUNK};
use crate::riemann::{pair_reciprocals, Riemann, Side};
use crate::scene::WallStress;
use crate::slabs::two_phase;
use crate::walls::Walls;
use nalgebra::SVector;
use rayon::prelude::*;

/// Artificial-stress settings (cohesive materials only).
#[derive(Clone, Copy, Debug)]
pub struct ArtificialStress {
    /// Exponent n of Eq. (27).
    pub exponent: Real,
    /// W(dp, h).
    pub w_dp: Real,
}

/// Inputs of the momentum sweep that are not particle arrays.
pub struct MomentumParams<'a, const D: usize> {
    pub kernel: WendlandC2,
    pub riemann: Riemann,
    pub gravity: Vect<D>,
    pub dt: Real,
    pub artificial: Option<ArtificialStress>,
    /// Coulomb coefficient of fine grains on walls (0: off).
    pub wall_friction: Real,
    /// Deviatoric stress of the dummy wall particles.
    pub wall_stress: WallStress,
    /// Per material: ξ G of the hourglass penalty (empty: off).
    pub hourglass: &'a [Real],
    /// Per material: share of the stored penalty kept over the step, exp(−Δt c0/(N h)).
    pub hourglass_leak: &'a [f32],
    /// Per material: whether the grain–boulder interface carries the soil's tension
    /// (cohesive soils, c > 0).
    pub tension: &'a [bool],
    /// The fine materials (sound speed of a pair of different soils).
    pub materials: &'a [FineMaterial],
    /// All materials share one impedance and sound speed
    /// ([`uniform_acoustics`](super::material::uniform_acoustics)).
    pub uniform: bool,
}

/// Fine–fine pair sums of one particle, added from both sides of each pair.
#[derive(Clone, Copy, Debug)]
pub struct MomentumSums<const D: usize> {
    /// Σ_j (σ̄ˢ_ij − P* I + f_ijⁿ R̄_ij)·e_ij ∂W/∂r V_j of Eq. (16) (times 2/ρ_i gives
    /// the acceleration).
    pub acc: Vect<D>,
    /// Σ_j s_ij ξḠ_ij ṽ_ij ∂W/∂r V_j / r_ij, the hourglass increment (times Δt/ρ_i).
    pub hourglass: Vect<D>,
}

impl<const D: usize> MomentumSums<D> {
    pub fn zero() -> Self {
        MomentumSums {
            acc: Vect::<D>::zeros(),
            hourglass: Vect::<D>::zeros(),
        }
    }
}

/// Coarse grains seen by the fine sweep: their packed records, the coupling law, and
/// one reaction buffer per chunk that receives `(coarse particle, force)` records.
pub struct CoarseSide<'a, const D: usize> {
    pub src: &'a [CoarseSource<D>],
    pub coupling: Coupling,
    pub reactions: &'a mut [Vec<(u32, Vect<D>)>],
}

/// Compute v_{n+1} into `vel_new`, advance the accumulated hourglass acceleration in
/// `hourglass` (in place; each particle reads only its own entry) and per-chunk barrier
/// loads into `loads` (`max(1, barriers)` slots per chunk). `sums` holds one entry per
/// particle, all zero on entry; its momentum part is left zero, its continuity part
/// holds the [`JumpDiffusion`] terms for the continuity sweep.
#[allow(clippy::too_many_arguments)]
pub fn momentum_sweep<const D: usize>(
    p: &FineParticles<D>,
    src: &[Source],
    walls: &Walls<D>,
    lists: &NeighborLists,
    art: &[Sym],
    prm: &MomentumParams<'_, D>,
    vel_new: &mut [Vect<D>],
    hourglass: &mut [SVector<f32, D>],
    loads: &mut [Load],
    coarse: CoarseSide<'_, D>,
    jump: &JumpDiffusion<'_, D>,
    sums: &mut [PairSums<D>],
) {
    let (csrc, coupling) = (coarse.src, coarse.coupling);
    let nbs = walls.load_slots().max(1);
    let cut2 = prm.kernel.cutoff * prm.kernel.cutoff;
    let vw = walls.volume;
    // neighbour arrays of one length, so that a neighbour index is bounds-checked once
    let n = p.len();
    let (pos, vel, src) = (&p.pos[..n], &p.vel[..n], &src[..n]);
    pair_pass(p, src, lists, art, prm, jump, &mut *sums);
    lists
        .chunks
        .par_iter()
        .zip(sums.par_chunks_mut(CHUNK))
        .zip(vel_new.par_chunks_mut(CHUNK))
        .zip(hourglass.par_chunks_mut(CHUNK))
        .zip(loads.par_chunks_mut(nbs))
        .zip(coarse.reactions.par_iter_mut())
        .enumerate()
        .for_each(|(c, (((((cl, sums), vout), hout), lout), react))| {
            for l in lout.iter_mut() {
                *l = Load::default();
            }
            react.clear();
            for (k, vo) in vout.iter_mut().enumerate() {
                let i = c * CHUNK + k;
                let si = &src[i];
                let ci = prm.materials[p.material[i] as usize].c0;
                let inv_ci = 1.0 / ci;
                let (xi, vi) = (pos[i], vel[i]);
                let rhoi = p.rho[i];
                let inv_rho2 = 2.0 / rhoi;
                // hourglass penalty: ξ G_i while some of it is kept (0: off, or released
                // by plastic flow)
                let kept_i = p.hourglass_kept[i];
                let gi = if kept_i > 0.0 {
                    prm.hourglass
                        .get(p.material[i] as usize)
                        .copied()
                        .unwrap_or(0.0)
                } else {
                    0.0
                };
                // the pair sums, left zero for the next step
                let sum = std::mem::replace(&mut sums[k].momentum, MomentumSums::zero());
                let mut acc = sum.acc * inv_rho2;
                let (w0, w1) = (cl.woff[k] as usize, cl.woff[k + 1] as usize);
                if w1 > w0 {
                    let wl = &cl.wall[w0..w1];
                    // Wall normal at i, Eq. (33): Φ = −Σ_w ∇_i W_iw V_w.
                    let mut phi = Vect::<D>::zeros();
                    for &w in wl {
                        let rij = xi - walls.pos[w as usize];
                        let r2 = rij.norm_squared();
                        if r2 >= cut2 || r2 == 0.0 {
                            continue;
                        }
                        let r = r2.sqrt();
                        phi -= rij * (prm.kernel.dw(r) / r * vw);
                    }
                    let nrm = phi.norm();
                    let n = if nrm > 0.0 { phi / nrm } else { phi };
                    let ul = -n.dot(&vi); // Eq. (32)
                    let share = 1.0 / wl.len() as Real;
                    let strength = match prm.wall_stress {
                        WallStress::Extrapolated => {
                            WallStrength::new(&prm.materials[p.material[i] as usize], si)
                        }
                        WallStress::Mirrored => WallStrength::MIRROR,
                    };
                    let tensile =
                        wall_contact::tensile_strength(&prm.materials[p.material[i] as usize]);
                    for &w in wl {
                        let w = w as usize;
                        let rij = xi - walls.pos[w];
                        let r2 = rij.norm_squared();
                        if r2 >= cut2 || r2 == 0.0 {
                            continue;
                        }
                        let r = r2.sqrt();
                        let e = rij * (1.0 / r);
                        let dw = prm.kernel.dw(r);
                        let uw = -n.dot(&walls.velocity(w));
                        // Eq. (34): U_R = −U_L + 2u_w, so U_L − U_R = 2(U_L − u_w).
                        let du = 2.0 * (ul - uw);
                        // Eq. (35): hydrostatic increase towards the wall.
                        let pr = si.p + rhoi * r * prm.gravity.dot(&(-e)).max(0.0);
                        let beta = prm.riemann.limiter(du, inv_ci);
                        let pstar = 0.5 * (si.p + pr) + 0.5 * beta * si.z * du;
                        let mut sstar = si.dev.scale(0.5 * (1.0 + strength.ratio(pr)));
                        sstar.0[0] -= pstar;
                        sstar.0[1] -= pstar;
                        sstar.0[2] -= pstar;
                        // the contact opens beyond the soil's tensile strength
                        let sstar = wall_contact::cut(sstar, &n, tensile);
                        let mut a = sstar.dot_vec(&e) * (inv_rho2 * dw * vw);
                        if prm.wall_friction > 0.0 {
                            let an = a.dot(&n);
                            if an > 0.0 {
                                let vrel = vi - walls.velocity(w);
                                let vt = vrel - n * vrel.dot(&n);
                                let s = vt.norm();
                                if s > 0.0 {
                                    let mag = (prm.wall_friction * an).min(s / prm.dt * share);
                                    a -= vt * (mag / s);
                                }
                            }
                        }
                        acc += a;
                        if let Some(b) = walls.objects[walls.object[w] as usize].barrier {
                            let f = to3(&a) * (-p.mass[i]);
                            let arm = to3(&(walls.pos[w] - walls.barriers[b].reference));
                            let s = walls.load_slot(b, w);
                            lout[s].force += f;
                            lout[s].moment += arm.cross(&f);
                        }
                    }
                }
                let (c0, c1) = (cl.coff[k] as usize, cl.coff[k + 1] as usize);
                if c1 > c0 {
                    let fs = FineSide {
                        pos: xi,
                        vel: vi,
                        rho: rhoi,
                        stress: &p.stress[i],
                        z: si.z,
                        inv_c: inv_ci,
                        c2: ci * ci,
                        tension: prm.tension[p.material[i] as usize],
                    };
                    let share = 1.0 / (c1 - c0) as Real;
                    for &j in &cl.coarse[c0..c1] {
                        if let Some(a) = coupling.acceleration(&fs, &csrc[j as usize], share) {
                            acc += a;
                            react.push((j, a * (-p.mass[i])));
                        }
                    }
                }
                // Δa_i = Δt/ρ_i Σ_j ..., accumulated on the share of the old one kept through
                // plastic flow (e_i) and over the step's relaxation
                let hg = &mut hout[k];
                *hg = if gi > 0.0 {
                    *hg * (kept_i * prm.hourglass_leak[p.material[i] as usize])
                        + (sum.hourglass * (prm.dt / rhoi)).cast::<f32>()
                } else {
                    SVector::zeros()
                };
                acc += hg.cast::<Real>();
                *vo = vi + (acc + prm.gravity) * prm.dt;
            }
        });
}

/// The fine–fine terms of the sweep, each pair evaluated once and added to both of its
/// particles, and the continuity sweep's terms without velocity.
fn pair_pass<const D: usize>(
    p: &FineParticles<D>,
    src: &[Source],
    lists: &NeighborLists,
    art: &[Sym],
    prm: &MomentumParams<'_, D>,
    jump: &JumpDiffusion<'_, D>,
    sums: &mut [PairSums<D>],
) {
    let cut2 = prm.kernel.cutoff * prm.kernel.cutoff;
    let n = p.len();
    let (pos, vel, src) = (&p.pos[..n], &p.vel[..n], &src[..n]);
    let (material, kept, vel_grad) = (&p.material[..n], &p.hourglass_kept[..n], &p.vel_grad[..n]);
    let hourglass = !prm.hourglass.is_empty();
    let slabs = &lists.slabs;
    two_phase(
        slabs,
        &mut sums[..n],
        &|s, win: &mut [PairSums<D>], base| {
            let mut block = PairBlock::<D>::default();
            for i in slabs[s] as usize..slabs[s + 1] as usize {
                let si = &src[i];
                let mat_i = material[i] as usize;
                let ci = prm.materials[mat_i].c0;
                let (half_inv_z, inv_ci) = si.reciprocals(ci);
                let (xi, vi) = (pos[i], vel[i]);
                let left = |u: Real| Side::new(si.z, u, si.p);
                let (half_z, inv_z_uniform) = (0.5 * si.z, 2.0 * half_inv_z);
                let kept_i = kept[i];
                let g_i = if hourglass { prm.hourglass[mat_i] } else { 0.0 };
                let li = &vel_grad[i];
                let mut own = PairSums::<D>::zero();
                for js in lists.fine_of(i).chunks(BLOCK) {
                    block.fill(&xi, js, pos, cut2, jump.reg);
                    for Pair {
                        j,
                        rij,
                        r,
                        inv_r,
                        inv,
                    } in block.pairs(jump.reg)
                    {
                        let (sj, vj) = (&src[j], vel[j]);
                        let e = rij * inv_r;
                        let dw = prm.kernel.dw_within(r);
                        let (ul, ur) = (-vi.dot(&e), -vj.dot(&e));
                        let mat_j = material[j] as usize;
                        // P* of Eq. (20), the same seen from either side
                        let (pstar, two_inv_z) = if prm.uniform {
                            let beta = prm.riemann.limiter(ul - ur, inv_ci);
                            (
                                Riemann::p_star_uniform(si.p, sj.p, beta, half_z, ul - ur),
                                inv_z_uniform,
                            )
                        } else {
                            let cj = prm.materials[mat_j].c0;
                            let (inv_z, inv_c) =
                                pair_reciprocals(si.z, sj.z, ci, cj, half_inv_z, inv_ci);
                            let right = Side::new(sj.z, ur, sj.p);
                            (
                                prm.riemann.p_star(left(ul), right, inv_z, inv_c),
                                2.0 * inv_z,
                            )
                        };
                        // σ*·e = (σ̄ˢ − P* I)·e, Eq. (18)
                        let mut t = si.dev.add(&sj.dev).dot_vec(&e) * 0.5 - e * pstar;
                        if let Some(a) = &prm.artificial {
                            let fa = (prm.kernel.w(r) / a.w_dp).powf(a.exponent);
                            t += art[i].add(&art[j]).dot_vec(&e) * (0.5 * fa);
                        }
                        let aj = &mut win[j - base];
                        jump.pair(
                            (si, mat_i),
                            (sj, mat_j),
                            &rij,
                            (r, dw, inv),
                            two_inv_z,
                            &mut own.continuity,
                            &mut aj.continuity,
                        );
                        let (own, aj) = (&mut own.momentum, &mut aj.momentum);
                        own.acc += t * (dw * sj.vol);
                        aj.acc -= t * (dw * si.vol);
                        if hourglass {
                            let kept_j = kept[j];
                            if kept_i > 0.0 || kept_j > 0.0 {
                                let g = 0.5 * (g_i + prm.hourglass[mat_j]);
                                let s = pair_weight(kept_i, kept_j) * g;
                                let vc = non_affine(&(vi - vj), &rij, li, &vel_grad[j]);
                                let q = s * dw * inv_r;
                                if kept_i > 0.0 {
                                    own.hourglass += vc * (q * sj.vol);
                                }
                                // ṽ_ji = −ṽ_ij
                                if kept_j > 0.0 {
                                    aj.hourglass -= vc * (q * si.vol);
                                }
                            }
                        }
                    }
                }
                let a = &mut win[i - base];
                a.momentum.acc += own.momentum.acc;
                a.momentum.hourglass += own.momentum.hourglass;
                a.continuity.add(&own.continuity);
            }
        },
    );
}

/// The deviatoric stress a dummy wall particle carries against particle i: the
/// particle's σˢ_i at the same share of the Drucker–Prager strength √J2 ≤ 3α_φ P + k_c
/// (Eqs. 4, 6) at the wall's pressure P_w of Eq. (35) as it uses at its own pressure,
/// σˢ_w = m σˢ_i with m = (3α_φ P_w + k_c)/max(3α_φ P_i + k_c, √J2(σˢ_i)). In a
/// frictional layer shear and pressure both grow with depth, so this extrapolates the
/// stress to the wall as Eq. (35) extrapolates the pressure (for c = 0, m = P_w/P_i
/// exactly); seed 000's mirror σˢ_w = σˢ_i gives a particle lying on the wall only the
/// shear at its own centre, half the basal shear of a one-particle-thick layer. The
/// pair term takes the mean ½(σˢ_i + σˢ_w), as Eq. (34) takes ½(P_L + P_R); m never
/// lets the wall exceed the strength at its pressure, and is 1 where neither side
/// has strength (a particle in tension without cohesion carries no shear).
#[derive(Clone, Copy, Debug)]
struct WallStrength {
    /// 3α_φ, or 0 for the mirror.
    three_alpha: Real,
    k_c: Real,
    /// 1 / max(3α_φ P_i + k_c, √J2(σˢ_i)), or 0 where that vanishes.
    inv_used: Real,
}

impl WallStrength {
    /// m = 1 everywhere.
    const MIRROR: WallStrength = WallStrength {
        three_alpha: 0.0,
        k_c: 0.0,
        inv_used: 0.0,
    };

    fn new(m: &FineMaterial, si: &Source) -> Self {
        let three_alpha = 3.0 * m.alpha_phi;
        let used = (three_alpha * si.p + m.k_c).max(si.dev.j2().sqrt());
        WallStrength {
            three_alpha,
            k_c: m.k_c,
            inv_used: if used > 0.0 { 1.0 / used } else { 0.0 },
        }
    }

    /// m at the wall pressure `pw`.
    #[inline(always)]
    fn ratio(&self, pw: Real) -> Real {
        if self.inv_used > 0.0 {
            (self.three_alpha * pw + self.k_c).max(0.0) * self.inv_used
        } else {
            1.0
        }
    }
}
