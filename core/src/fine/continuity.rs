//! Continuity, velocity gradient, stress diffusion and the constitutive update,
//! in one sweep with the new velocities v_{n+1}.
//!
//! dρ_i/dt = 2ρ_i Σ_j (v_i − v*)·∇_i W_ij V_j              Eq. (15), v* from Eq. (19)
//! ∇v_i    = −Σ_j (v_i − v_j) ⊗ ∇_i W_ij V_j                Eq. (24) (sign so that a
//!           linear field v = A x gives ∇v = A with ∇_i W = W' e_ij, e_ij from j to i)
//! D_i     = 2ζ h c0 Σ_j Ψ_ij (r_ij·∇_i W_ij)/(r² + 0.01h²) V_j      Eqs. (25)–(26)
//! The pressure jump of v* is taken from density by default, K (ρ/ρ0 − 1), or from the
//! stress relative to the geostatic state (`numerics.continuity_jump`; see the pair loop).
//! The terms of walls and coarse grains are interactions
//! ([`interactions`](crate::interactions)); this module holds the fine–fine terms and
//! the constitutive update.
//!
//! The pair pass evaluates each fine–fine pair once and adds its terms in v_{n+1} to
//! both particles' [`ContinuitySums`] (two-phase slab schedule, [`slabs`](crate::pairs::slabs));
//! the terms without velocity ([`JumpDiffusion`]) are already there, from the momentum
//! sweep's pair pass. The particle pass
//! ([`interactions::continuity_pass`](crate::interactions::continuity_pass)) takes the
//! sums as [`Rates`], adds the interactions and [`Rates::update`]s the stress.

use super::hourglass::penalty_kept;
use super::material::FineMaterial;
use super::pair_sums::{ContinuitySums, PairSums};
use super::plasticity::constitutive_step;
use super::source::Source;
use super::state::FineParticles;
use crate::kernel::WendlandC2;
use crate::math::{sub_outer, Real, Sym, Vect};
use crate::neighbors::NeighborLists;
use crate::pairs::block::{Pair, PairBlock, BLOCK};
use crate::pairs::slabs::two_phase;
use crate::periodic::{Open, Separation, Wrap};
use crate::riemann::pair_reciprocals;
use crate::scene::ContinuityJump;
use nalgebra::{Matrix3, SMatrix};

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
    /// Per particle: the factor on `geostatic` of a soil the water pushes, its weight
    /// less the water's vertical force over the weight `geostatic` holds (seepage
    /// changes the gradient a soil rests at); empty: 1 for all.
    pub weight: &'a [Real],
    /// Unit vector opposite to the hydrostatic gravity (zero without gravity; along a
    /// periodic slope, normal to the bed).
    pub up: Vect<D>,
    /// Pressure of the jump term of Eq. (19).
    pub jump: ContinuityJump,
    /// All materials share one impedance and sound speed
    /// ([`uniform_acoustics`](super::material::uniform_acoustics)).
    pub uniform: bool,
    /// The periodic axis, if any: pairs across it take the minimum image.
    pub wrap: Wrap,
}

/// Output buffers of the sweep.
pub struct ContinuityOut<'a, const D: usize> {
    /// Pair sums, one per particle: the continuity part holds the momentum sweep's
    /// [`JumpDiffusion`] terms on entry, and is left zero.
    pub sums: &'a mut [PairSums<D>],
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

/// One particle's rates from its pair sums, to which the interactions add their terms
/// before [`Rates::update`].
pub struct Rates<const D: usize> {
    /// Σ 2 (U* − U_L) ∂W/∂r V of Eq. (15) (times ρ_i gives dρ_i/dt).
    pub drho: Real,
    /// The velocity gradient of Eq. (24).
    pub grad: SMatrix<Real, D, D>,
    /// Ψ of Eq. (26) summed.
    diff: Sym,
}

impl<const D: usize> Rates<D> {
    /// The rates of particle i (record `si`, material index `mat`, factor `weight` of
    /// [`ContinuityParams::weight`]) from its fine–fine pair sums.
    #[inline(always)]
    pub fn from_sums(
        prm: &ContinuityParams<'_, D>,
        si: &Source,
        (mat, weight): (usize, Real),
        sum: &ContinuitySums<D>,
    ) -> Self {
        let geo = prm.geostatic[mat].scale(prm.geostatic_scale * weight);
        // Ψ of Eq. (26) summed: σ_i − σ_j (σ = σˢ − P I) minus the geostatic gradient
        // −(r_ij·up) geo
        let mut diff = si.dev.scale(sum.w).sub(&sum.wdev);
        let dp = sum.wp - si.p * sum.w;
        diff.0[0] += dp;
        diff.0[1] += dp;
        diff.0[2] += dp;
        diff.axpy(-sum.wz, &geo);
        Rates {
            drho: sum.drho,
            grad: sum.grad,
            diff,
        }
    }

    /// The constitutive update of particle i (material `mi`, density `rho`) over the
    /// step, Eqs. (7)–(12) with the diffusion of Eq. (25): `stress` and
    /// `plastic_strain` advanced in place, L_i in single precision into `vel_grad` and
    /// the share of the hourglass penalty kept into `kept`. Returns dρ_i/dt.
    #[inline(always)]
    pub fn update(
        &self,
        prm: &ContinuityParams<'_, D>,
        mi: &FineMaterial,
        rho: Real,
        out: ParticleOut<'_, D>,
    ) -> Real {
        let grad = self.grad;
        let mut l = Matrix3::<Real>::zeros();
        for a in 0..D {
            for b in 0..D {
                l[(a, b)] = grad[(a, b)];
            }
        }
        let d = self.diff.scale(2.0 * prm.zeta * prm.kernel.h * mi.c0);
        let u = constitutive_step(mi, &l, out.stress, *out.plastic_strain, &d, prm.dt, rho);
        *out.stress = u.stress;
        *out.plastic_strain += u.plastic_strain;
        *out.vel_grad = grad.cast::<f32>();
        *out.kept = penalty_kept(&u.stress, mi.shear, u.plastic_strain);
        rho * self.drho
    }
}

/// One particle's entries of [`ContinuityOut`].
pub struct ParticleOut<'a, const D: usize> {
    pub stress: &'a mut Sym,
    pub plastic_strain: &'a mut Real,
    pub vel_grad: &'a mut SMatrix<f32, D, D>,
    pub kept: &'a mut f32,
}

/// The continuity sweep's pair terms that need no velocity: the pressure jump of
/// Eq. (19) in U* − U_L, and the weights of the stress diffusion of Eqs. (25)–(26).
/// Positions and σ_n are the same in both sweeps, so the momentum sweep's pair pass
/// takes these with the pair's distance and kernel gradient it has at hand
/// ([`pair_sums`](super::pair_sums)).
pub struct JumpDiffusion<'a, const D: usize> {
    by_density: bool,
    pgeo: &'a [Real],
    up: Vect<D>,
    diffusion: bool,
    /// 0.01 h² of Eq. (25).
    pub reg: Real,
}

impl<'a, const D: usize> JumpDiffusion<'a, D> {
    pub fn new(prm: &ContinuityParams<'a, D>) -> Self {
        JumpDiffusion {
            by_density: prm.jump == ContinuityJump::Density,
            pgeo: prm.geostatic_pressure,
            up: prm.up,
            diffusion: prm.zeta > 0.0,
            reg: 0.01 * prm.kernel.h * prm.kernel.h,
        }
    }

    /// The jump is taken from density (`numerics.continuity_jump`).
    pub fn by_density(&self) -> bool {
        self.by_density
    }

    /// The geostatic pressure gradient of soil `mat` (the jump by stress).
    pub fn pgeo(&self, mat: usize) -> Real {
        self.pgeo.get(mat).copied().unwrap_or(0.0)
    }

    /// Stress diffusion is on (ζ > 0).
    pub fn diffusion(&self) -> bool {
        self.diffusion
    }

    /// The unit vector the geostatic state is taken along.
    pub fn up(&self) -> Vect<D> {
        self.up
    }

    /// Add the terms of pair (i, j) to both particles' sums: `dw` = ∂W/∂r at `r`,
    /// `inv` = 1/(r (r² + 0.01h²)), `two_inv_z` = 2/(Z_i + Z_j).
    ///
    /// Eq. (19) splits U* − U_L into a velocity part, Z_j (U_R − U_L)/(Z_i + Z_j),
    /// added by the continuity pair pass, and the pressure part (P_L − P_R)/(Z_i + Z_j)
    /// taken here; for j the states swap (P_L = P_j, P_R = P_i as seen from j).
    #[allow(clippy::too_many_arguments)]
    #[inline(always)]
    pub fn pair(
        &self,
        (si, mat_i): (&Source, usize),
        (sj, mat_j): (&Source, usize),
        rij: &Vect<D>,
        (r, dw, inv): (Real, Real, Real),
        two_inv_z: Real,
        own: &mut ContinuitySums<D>,
        aj: &mut ContinuitySums<D>,
    ) {
        let up_r = rij.dot(&self.up);
        // The jump P_L − P_R of Eq. (19) acts here as a pressure Laplacian. granmix
        // integrates the pressure from the stress, not from the density, so with the
        // stress's jump (seed 000) nothing feeds a density change back: where the
        // Laplacian does not vanish at rest (a free surface, a floor, a deposit off the
        // geostatic state) the density drifts for as long as the run lasts. From the
        // density, K (ρ/ρ0 − 1), the jump diffuses density towards uniform and vanishes
        // in a uniform deposit at rest. The stress's jump is taken relative to the
        // geostatic state, as Eq. (26) does for the stress: seen from i,
        // P_j + (P^H_i − P^H_j) = P_j − (r_ij·up) pgeo_i.
        let (jump_i, jump_j) = if self.by_density {
            (si.p_rho - sj.p_rho, sj.p_rho - si.p_rho)
        } else {
            (
                si.p - (sj.p - up_r * self.pgeo[mat_i]),
                sj.p - (si.p + up_r * self.pgeo[mat_j]),
            )
        };
        let k = dw * two_inv_z;
        own.drho += jump_i * k * sj.vol;
        aj.drho += jump_j * k * si.vol;
        if self.diffusion {
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
}

/// Runs over the fine–fine relation (`NeighborLists::inner_of`).
///
/// The fine–fine terms of the sweep in v_{n+1}, each pair evaluated once and added to
/// both of its particles: the velocity part of 2 (U* − U_L) in Eq. (15),
/// 2 Z_j (U_R − U_L)/(Z_i + Z_j) with U_R − U_L = v_ij·e_ij (Z_i for j), and
/// −v_ij ⊗ e_ij of Eq. (24), the same for j (v_ji ⊗ e_ji = v_ij ⊗ e_ij).
#[inline]
pub fn pair_pass<const D: usize>(
    p: &FineParticles<D>,
    src: &[Source],
    mats: &[FineMaterial],
    lists: &NeighborLists,
    prm: &ContinuityParams<'_, D>,
    sums: &mut [PairSums<D>],
) {
    // one pass per separation, so that the open scene's pair loop has no branch on it
    match &prm.wrap {
        None => separated_pair_pass(p, src, mats, lists, prm, sums, &Open),
        Some(period) => separated_pair_pass(p, src, mats, lists, prm, sums, period),
    }
}

#[inline(always)]
fn separated_pair_pass<const D: usize>(
    p: &FineParticles<D>,
    src: &[Source],
    mats: &[FineMaterial],
    lists: &NeighborLists,
    prm: &ContinuityParams<'_, D>,
    sums: &mut [PairSums<D>],
    sep: &impl Separation,
) {
    let cut2 = prm.kernel.cutoff * prm.kernel.cutoff;
    let n = p.len();
    let (pos, vel, src, material) = (&p.pos[..n], &p.vel[..n], &src[..n], &p.material[..n]);
    let slabs = &lists.slabs;
    two_phase(
        slabs,
        &mut sums[..n],
        &|s, win: &mut [PairSums<D>], base| {
            let mut block = PairBlock::<D>::default();
            for i in slabs[s] as usize..slabs[s + 1] as usize {
                let mi = &mats[material[i] as usize];
                let si = &src[i];
                let (half_inv_z, inv_ci) = si.reciprocals(mi.c0);
                let (xi, vi, vol_i) = (pos[i], vel[i], si.vol);
                let mut own = ContinuitySums::<D>::zero();
                for js in lists.inner_of(i).chunks(BLOCK) {
                    block.fill((&xi, js, pos), cut2, 0.0, sep);
                    for Pair {
                        j, rij, r, inv_r, ..
                    } in block.pairs(0.0)
                    {
                        let e = rij * inv_r;
                        let dw = prm.kernel.dw_within(r);
                        let (vol_j, vij) = (src[j].vol, vi - vel[j]);
                        let g = vij * dw;
                        let s = g.dot(&e);
                        let (si_w, sj_w) = if prm.uniform {
                            (s, s)
                        } else {
                            let sj = &src[j];
                            let cj = mats[material[j] as usize].c0;
                            let (inv_z, _) =
                                pair_reciprocals(si.z, sj.z, mi.c0, cj, half_inv_z, inv_ci);
                            let t = 2.0 * s * inv_z;
                            (t * sj.z, t * si.z)
                        };
                        let aj = &mut win[j - base].continuity;
                        own.drho += si_w * vol_j;
                        aj.drho += sj_w * vol_i;
                        sub_outer(&mut own.grad, &(g * vol_j), &e);
                        sub_outer(&mut aj.grad, &(g * vol_i), &e);
                    }
                }
                let a = &mut win[i - base].continuity;
                a.drho += own.drho;
                a.grad += own.grad;
            }
        },
    );
}
