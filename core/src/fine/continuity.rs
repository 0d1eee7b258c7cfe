//! Continuity, velocity gradient, stress diffusion and the constitutive update,
//! in one sweep with the new velocities v_{n+1}.
//!
//! dρ_i/dt = 2ρ_i Σ_j (v_i − v*)·∇_i W_ij V_j              Eq. (15), v* from Eq. (19)
//! ∇v_i    = −Σ_j (v_i − v_j) ⊗ ∇_i W_ij V_j                Eq. (24) (sign so that a
//!           linear field v = A x gives ∇v = A with ∇_i W = W' e_ij, e_ij from j to i)
//! D_i     = 2ζ h c0 Σ_j Ψ_ij (r_ij·∇_i W_ij)/(r² + 0.01h²) V_j      Eqs. (25)–(26)
//! The pressure jump of v* is taken from density by default, K (ρ/ρ0 − 1), or from the
//! stress relative to the geostatic state (`numerics.continuity_jump`; see the pair loop).
//! Walls are no-slip mirrors, v_w,dummy = 2 v_wall − v_i; the wall pressure of Eq. (35)
//! acts in the momentum equation only.
//!
//! The sweep has two passes. The pair pass evaluates each fine–fine pair once and adds
//! its terms to both particles' [`ContinuitySums`] (two-phase slab schedule,
//! [`slabs`](crate::slabs)); the particle pass adds the wall and coarse-grain terms and
//! updates the stress.

use super::hourglass::penalty_kept;
use super::material::FineMaterial;
use super::plasticity::update_stress;
use super::riemann::{pair_reciprocals, Riemann, Side};
use super::source::Source;
use super::state::FineParticles;
use crate::coarse::coupling::CoarseSource;
use crate::kernel::WendlandC2;
use crate::math::{sub_outer, Real, Sym, Vect};
use crate::neighbors::{NeighborLists, CHUNK};
use crate::scene::ContinuityJump;
use crate::slabs::two_phase;
use crate::walls::Walls;
use nalgebra::{Matrix3, SMatrix};
use rayon::prelude::*;

/// Inputs of the continuity/stress sweep that are not particle arrays.
pub struct ContinuityParams<'a, const D: usize> {
    pub kernel: WendlandC2,
    pub gravity: Vect<D>,
    pub dt: Real,
    /// ζ of Eq. (25); 0 disables stress diffusion.
    pub zeta: Real,
    /// Per material: ρ0 |g| (K0 (I − n n) + n n), the geostatic gradient of Eq. (26).
    pub geostatic: &'a [Sym],
    /// Per material: the mean of `geostatic` (times `geostatic_scale`), the gradient
    /// of the geostatic pressure along `up`.
    pub geostatic_pressure: &'a [Real],
    /// Factor on `geostatic` while gravity is ramped up (1 otherwise).
    pub geostatic_scale: Real,
    /// Unit vector opposite to gravity (zero without gravity).
    pub up: Vect<D>,
    /// Pressure of the jump term of Eq. (19).
    pub jump: ContinuityJump,
    /// All materials share one impedance and sound speed
    /// ([`uniform_acoustics`](super::riemann::uniform_acoustics)).
    pub uniform: bool,
}

/// Fine–fine pair sums of one particle, added from both sides of each pair.
#[derive(Clone, Copy, Debug)]
pub struct ContinuitySums<const D: usize> {
    /// Σ_j 2 (U* − U_L) ∂W/∂r V_j of Eq. (15) (times ρ_i gives dρ_i/dt).
    pub drho: Real,
    /// Σ_j −v_ij ⊗ e_ij ∂W/∂r V_j, Eq. (24).
    pub grad: SMatrix<Real, D, D>,
    /// Σ w, Σ w (r_ij·up), Σ w P_j and Σ w σˢ_j of Eq. (26), with
    /// w = r_ij·∇_i W_ij V_j/(r² + 0.01h²).
    pub w: Real,
    pub wz: Real,
    pub wp: Real,
    pub wdev: Sym,
}

impl<const D: usize> ContinuitySums<D> {
    pub fn zero() -> Self {
        ContinuitySums {
            drho: 0.0,
            grad: SMatrix::zeros(),
            w: 0.0,
            wz: 0.0,
            wp: 0.0,
            wdev: Sym::ZERO,
        }
    }

    #[inline(always)]
    fn add(&mut self, o: &Self) {
        self.drho += o.drho;
        self.grad += o.grad;
        self.w += o.w;
        self.wz += o.wz;
        self.wp += o.wp;
        self.wdev.axpy_in::<D>(1.0, &o.wdev);
    }
}

/// Output buffers of the sweep.
pub struct ContinuityOut<'a, const D: usize> {
    /// Pair sums (scratch, one per particle): all zero on entry, and left zero.
    pub sums: &'a mut [ContinuitySums<D>],
    pub drho: &'a mut [Real],
    /// Stress, advanced in place (neighbours are read from the sources).
    pub stress: &'a mut [Sym],
    /// Accumulated plastic strain, advanced in place.
    pub plastic_strain: &'a mut [Real],
    /// L_i in single precision, for the hourglass penalty.
    pub vel_grad: &'a mut [SMatrix<f32, D, D>],
    /// Share of the hourglass penalty kept through the stress update (1: elastic).
    pub hourglass_kept: &'a mut [f32],
}

/// Sweep with v_{n+1} already in `p.vel`.
#[allow(clippy::too_many_arguments)]
pub fn continuity_sweep<const D: usize>(
    p: &FineParticles<D>,
    src: &[Source],
    mats: &[FineMaterial],
    walls: &Walls<D>,
    lists: &NeighborLists,
    prm: &ContinuityParams<'_, D>,
    coarse: &[CoarseSource<D>],
    out: ContinuityOut<'_, D>,
) {
    let cut2 = prm.kernel.cutoff * prm.kernel.cutoff;
    let h = prm.kernel.h;
    let vw = walls.volume;
    // neighbour arrays of one length, so that a neighbour index is bounds-checked once
    let n = p.len();
    let (pos, vel, src, material) = (&p.pos[..n], &p.vel[..n], &src[..n], &p.material[..n]);
    pair_pass(p, src, mats, lists, prm, &mut *out.sums);
    lists
        .chunks
        .par_iter()
        .zip(out.sums.par_chunks_mut(CHUNK))
        .zip(out.drho.par_chunks_mut(CHUNK))
        .zip(out.stress.par_chunks_mut(CHUNK))
        .zip(out.plastic_strain.par_chunks_mut(CHUNK))
        .zip(out.vel_grad.par_chunks_mut(CHUNK))
        .zip(out.hourglass_kept.par_chunks_mut(CHUNK))
        .enumerate()
        .for_each(
            |(c, ((((((cl, sums), drho_out), stress_out), eps_out), lg_out), kept_out))| {
                for k in 0..drho_out.len() {
                    let i = c * CHUNK + k;
                    let mi = &mats[material[i] as usize];
                    let si = &src[i];
                    let (xi, vi) = (pos[i], vel[i]);
                    let rhoi = p.rho[i];
                    let sig_i = stress_out[k];
                    let geo = prm.geostatic[material[i] as usize].scale(prm.geostatic_scale);
                    // the pair sums, left zero for the next step
                    let sum = std::mem::replace(&mut sums[k], ContinuitySums::zero());
                    let mut drho = sum.drho;
                    let mut grad = sum.grad;
                    // Ψ of Eq. (26) summed: σ_i − σ_j (σ = σˢ − P I) minus the geostatic
                    // gradient −(r_ij·up) geo
                    let mut diff = si.dev.scale(sum.w).sub(&sum.wdev);
                    let dp = sum.wp - si.p * sum.w;
                    diff.0[0] += dp;
                    diff.0[1] += dp;
                    diff.0[2] += dp;
                    diff.axpy(-sum.wz, &geo);
                    let (w0, w1) = (cl.woff[k] as usize, cl.woff[k + 1] as usize);
                    for &w in &cl.wall[w0..w1] {
                        let w = w as usize;
                        let rij = xi - walls.pos[w];
                        let r2 = rij.norm_squared();
                        if r2 >= cut2 || r2 == 0.0 {
                            continue;
                        }
                        let r = r2.sqrt();
                        let e = rij * (1.0 / r);
                        let dwv = prm.kernel.dw(r) * vw;
                        // Eqs. (32)–(34): U* = u_w, so only the mirrored velocity enters.
                        // The hydrostatic jump of Eq. (35) is the geostatic state itself,
                        // which the fine–fine pair terms subtract too; it acts in the
                        // momentum equation only (kept here, it made every grain resting on
                        // a floor gain density exponentially).
                        let rel = (vi - walls.velocity(w)) * 2.0;
                        drho += rel.dot(&e) * dwv;
                        sub_outer(&mut grad, &(rel * dwv), &e);
                    }
                    // coarse grains: free-slip mirrors moving with v̄ (Eqs. 48, 60): only the
                    // normal relative velocity is reflected (no coarse–fine friction here;
                    // μ_cf acts in the momentum sweep). The mirror plane is the coarse
                    // particle's tangent plane, which holds for a fine particle in front of
                    // it (n_j·e_ij > 0); one beside or behind it (at a corner or tip of a
                    // body resolved by few particles) is reflected along e_ij instead, as
                    // by an interior particle. Reflected across n_j, such a particle would
                    // be compressed while it moves away from the body (n_j·e_ij < 0 flips
                    // the sign of the approach rate).
                    for &j in &cl.coarse[cl.coff[k] as usize..cl.coff[k + 1] as usize] {
                        let cj = &coarse[j as usize];
                        let rij = xi - cj.pos;
                        let r2 = rij.norm_squared();
                        if r2 >= cut2 || r2 == 0.0 {
                            continue;
                        }
                        let r = r2.sqrt();
                        let e = rij * (1.0 / r);
                        let dwv = prm.kernel.dw(r) * cj.vol;
                        let n = if cj.normal.dot(&e) > 0.0 {
                            cj.normal
                        } else {
                            e
                        };
                        let rel = n * (2.0 * (vi - cj.vel).dot(&n));
                        drho += rel.dot(&e) * dwv;
                        sub_outer(&mut grad, &(rel * dwv), &e);
                    }
                    drho_out[k] = rhoi * drho;
                    let mut l = Matrix3::<Real>::zeros();
                    for a in 0..D {
                        for b in 0..D {
                            l[(a, b)] = grad[(a, b)];
                        }
                    }
                    let d = diff.scale(2.0 * prm.zeta * h * mi.c0);
                    let u = update_stress(mi, &l, &sig_i, &d, prm.dt);
                    stress_out[k] = u.stress;
                    eps_out[k] += u.plastic_strain;
                    lg_out[k] = grad.cast::<f32>();
                    kept_out[k] = penalty_kept(&u.stress, mi.shear, u.plastic_strain);
                }
            },
        );
}

/// The fine–fine terms of the sweep, each pair evaluated once and added to both of its
/// particles (for j the pair is seen with e_ji = −e_ij: U_L and U_R swap and change
/// sign, and its own pressures enter Eq. (19)).
fn pair_pass<const D: usize>(
    p: &FineParticles<D>,
    src: &[Source],
    mats: &[FineMaterial],
    lists: &NeighborLists,
    prm: &ContinuityParams<'_, D>,
    sums: &mut [ContinuitySums<D>],
) {
    let cut2 = prm.kernel.cutoff * prm.kernel.cutoff;
    let reg = 0.01 * prm.kernel.h * prm.kernel.h;
    let n = p.len();
    let (pos, vel, src, material) = (&p.pos[..n], &p.vel[..n], &src[..n], &p.material[..n]);
    let by_density = prm.jump == ContinuityJump::Density;
    let pgeo = prm.geostatic_pressure;
    let slabs = &lists.slabs;
    two_phase(
        slabs,
        &mut sums[..n],
        &|s, win: &mut [ContinuitySums<D>], base| {
            for i in slabs[s] as usize..slabs[s + 1] as usize {
                let cl = &lists.chunks[i / CHUNK];
                let k = i % CHUNK;
                let mi = &mats[material[i] as usize];
                let si = &src[i];
                let (half_inv_z, inv_ci) = si.reciprocals(mi.c0);
                let (xi, vi) = (pos[i], vel[i]);
                let pgeo_i = pgeo[material[i] as usize];
                let pi = if by_density { si.p_rho } else { si.p };
                let mut own = ContinuitySums::<D>::zero();
                for &j in &cl.fine[cl.off[k] as usize..cl.off[k + 1] as usize] {
                    let j = j as usize;
                    let rij = xi - pos[j];
                    let r2 = rij.norm_squared();
                    if r2 >= cut2 {
                        continue;
                    }
                    let (sj, vj) = (&src[j], vel[j]);
                    let r = r2.sqrt();
                    // one division for both 1/r and 1/(r² + 0.01h²) of Eq. (25)
                    let den = r2 + reg;
                    let inv = 1.0 / (r * den);
                    let e = rij * (den * inv);
                    let dw = prm.kernel.dw_within(r);
                    let (dwv_i, dwv_j) = (dw * si.vol, dw * sj.vol);
                    let (ul, ur) = (-vi.dot(&e), -vj.dot(&e));
                    let up_r = rij.dot(&prm.up);
                    // The jump P_L − P_R of Eq. (19) acts here as a pressure Laplacian.
                    // granmix integrates the pressure from the stress, not from the
                    // density, so with the stress's jump (seed 000) nothing feeds a
                    // density change back: where the Laplacian does not vanish at rest
                    // (a free surface, a floor, a deposit off the geostatic state) the
                    // density drifts for as long as the run lasts. From the density,
                    // K (ρ/ρ0 − 1), the jump diffuses density towards uniform and
                    // vanishes in a uniform deposit at rest. The stress's jump is taken
                    // relative to the geostatic state, as Eq. (26) does for the stress:
                    // seen from i, P_j + (P^H_i − P^H_j) = P_j − (r_ij·up) pgeo_i.
                    let (pj, pj_seen, pi_seen) = if by_density {
                        (sj.p_rho, sj.p_rho, si.p_rho)
                    } else {
                        (
                            sj.p,
                            sj.p - up_r * pgeo_i,
                            si.p + up_r * pgeo[material[j] as usize],
                        )
                    };
                    // U* seen from i and from j (U_L, U_R → −U_R, −U_L)
                    let (us_i, us_j) = if prm.uniform {
                        (
                            Riemann::u_star_uniform(ul, ur, pi, pj_seen, half_inv_z),
                            Riemann::u_star_uniform(-ur, -ul, pj, pi_seen, half_inv_z),
                        )
                    } else {
                        let cj = mats[material[j] as usize].c0;
                        let (inv_z, _) =
                            pair_reciprocals(si.z, sj.z, mi.c0, cj, half_inv_z, inv_ci);
                        (
                            Riemann::u_star(
                                Side::new(si.z, ul, pi),
                                Side::new(sj.z, ur, pj_seen),
                                inv_z,
                            ),
                            Riemann::u_star(
                                Side::new(sj.z, -ur, pj),
                                Side::new(si.z, -ul, pi_seen),
                                inv_z,
                            ),
                        )
                    };
                    let vij = vi - vj;
                    let aj = &mut win[j - base];
                    // (v_i − v*)·e_ij = U* − U_L (U measured along −e_ij)
                    own.drho += 2.0 * (us_i - ul) * dwv_j;
                    aj.drho += 2.0 * (us_j + ur) * dwv_i;
                    // −v_ij ⊗ e_ij for both: v_ji ⊗ e_ji = v_ij ⊗ e_ij
                    sub_outer(&mut own.grad, &(vij * dwv_j), &e);
                    sub_outer(&mut aj.grad, &(vij * dwv_i), &e);
                    if prm.zeta > 0.0 {
                        let w = r * r * dw * inv;
                        let (wi, wj) = (w * sj.vol, w * si.vol);
                        own.w += wi;
                        own.wz += wi * up_r;
                        own.wp += wi * sj.p;
                        own.wdev.axpy_in::<D>(wi, &sj.dev);
                        aj.w += wj;
                        aj.wz -= wj * up_r;
                        aj.wp += wj * si.p;
                        aj.wdev.axpy_in::<D>(wj, &si.dev);
                    }
                }
                win[i - base].add(&own);
            }
        },
    );
}
