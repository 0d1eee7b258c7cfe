//! Momentum sweep of the fine grains, Eqs. (16), (20), (27) and (55).
//!
//! For each fine particle i:
//!   dv_i/dt = 2/ρ_i Σ_j (σ̄ˢ_ij − P* I + f_ijⁿ R̄_ij)·∇_i W_ij V_j + g + (interactions)
//! and v_{n+1} = v_n + Δt dv/dt (Eq. 55). The terms of walls and coarse grains are
//! interactions ([`interactions`](crate::interactions)); this module holds the
//! fine–fine terms and the update.
//!
//! The pair pass evaluates each fine–fine pair once and adds its terms to both
//! particles' [`MomentumSums`] (two-phase slab schedule, [`slabs`](crate::pairs::slabs)):
//! σ̄ˢ_ij, P* and the hourglass weight are symmetric in the pair and e_ji = −e_ij, so j
//! receives the negated traction weighted by V_i. The same pass takes the continuity
//! sweep's terms without velocity ([`JumpDiffusion`], [`pair_sums`](super::pair_sums)).
//! The particle pass ([`interactions::momentum_pass`](crate::interactions::momentum_pass))
//! turns the sums into an acceleration ([`pair_acceleration`]), adds the interactions
//! and [`integrate`]s.

use super::continuity::JumpDiffusion;
use super::hourglass::{non_affine, pair_weight};
use super::material::FineMaterial;
use super::pair_sums::{MomentumSums, PairSums};
use super::source::Source;
use super::state::FineParticles;
use crate::kernel::WendlandC2;
use crate::math::{Real, Sym, Vect};
use crate::neighbors::NeighborLists;
use crate::pairs::block::{Pair, PairBlock, BLOCK};
use crate::pairs::quad::Portable;
use crate::pairs::slabs::two_phase;
use crate::periodic::{Open, Separation, Wrap};
use crate::riemann::{minmod_jump, pair_reciprocals, Riemann, Side};
use nalgebra::SVector;

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
    /// Per material: ξ G of the hourglass penalty (empty: off).
    pub hourglass: &'a [Real],
    /// Per material: share of the stored penalty kept over the step, exp(−Δt c0/(N h)).
    pub hourglass_leak: &'a [f32],
    /// The fine materials (sound speed of a pair of different soils).
    pub materials: &'a [FineMaterial],
    /// All materials share one impedance and sound speed
    /// ([`uniform_acoustics`](super::material::uniform_acoustics)).
    pub uniform: bool,
    /// The periodic axis, if any: pairs across it take the minimum image.
    pub wrap: Wrap,
    /// MUSCL reconstruction of the Riemann jump (`numerics.muscl`).
    pub muscl: bool,
}

/// The acceleration of particle i from its fine–fine pair sums: (2/ρ_i) times the sum
/// of Eq. (16).
#[inline(always)]
pub fn pair_acceleration<const D: usize>(sum: &MomentumSums<D>, rho: Real) -> Vect<D> {
    sum.acc * (2.0 / rho)
}

/// Eq. (55) for particle i: v_{n+1} = v_n + Δt (a + a_hg + g), with `acc` the
/// acceleration of its pair sums and interactions, and the hourglass acceleration
/// `hg` advanced in place from the pair sums' increment `sum_hourglass`:
/// Δa_i = Δt/ρ_i Σ_j ..., accumulated on the share of the old one kept through
/// plastic flow (e_i) and over the step's relaxation.
#[inline(always)]
pub fn integrate<const D: usize>(
    p: &FineParticles<D>,
    prm: &MomentumParams<'_, D>,
    i: usize,
    acc: Vect<D>,
    sum_hourglass: &Vect<D>,
    hg: &mut SVector<f32, D>,
) -> Vect<D> {
    let mat = p.material[i] as usize;
    // hourglass penalty: ξ G_i while some of it is kept (0: off, or released by
    // plastic flow)
    let kept_i = p.hourglass_kept[i];
    let gi = if kept_i > 0.0 {
        prm.hourglass.get(mat).copied().unwrap_or(0.0)
    } else {
        0.0
    };
    *hg = if gi > 0.0 {
        *hg * (kept_i * prm.hourglass_leak[mat])
            + (sum_hourglass * (prm.dt / p.rho[i])).cast::<f32>()
    } else {
        SVector::zeros()
    };
    let acc = acc + hg.cast::<Real>();
    p.vel[i] + (acc + prm.gravity) * prm.dt
}

/// Particle i's side of the Riemann problems of its pairs (Eq. 20), with the
/// reciprocals it shares between them.
struct StarSide<'a> {
    si: &'a Source,
    ci: Real,
    half_inv_z: Real,
    inv_ci: Real,
    half_z: Real,
    inv_z_uniform: Real,
}

impl<'a> StarSide<'a> {
    #[inline(always)]
    fn new(si: &'a Source, ci: Real) -> Self {
        let (half_inv_z, inv_ci) = si.reciprocals(ci);
        StarSide {
            si,
            ci,
            half_inv_z,
            inv_ci,
            half_z: 0.5 * si.z,
            inv_z_uniform: 2.0 * half_inv_z,
        }
    }

    /// P* of Eq. (20), the same seen from either side, for the velocities `ul`, `ur`
    /// along the pair's normal and neighbour `sj` of material `mat_j`; and 2/(Z_i + Z_j).
    #[inline(always)]
    fn p_star<const D: usize>(
        &self,
        prm: &MomentumParams<'_, D>,
        (ul, ur): (Real, Real),
        sj: &Source,
        mat_j: usize,
    ) -> (Real, Real) {
        let si = self.si;
        if prm.uniform {
            let beta = prm.riemann.limiter(ul - ur, self.inv_ci);
            (
                Riemann::p_star_uniform(si.p, sj.p, beta, self.half_z, ul - ur),
                self.inv_z_uniform,
            )
        } else {
            let cj = prm.materials[mat_j].c0;
            let (inv_z, inv_c) =
                pair_reciprocals(si.z, sj.z, self.ci, cj, self.half_inv_z, self.inv_ci);
            let left = Side::new(si.z, ul, si.p);
            let right = Side::new(sj.z, ur, sj.p);
            (prm.riemann.p_star(left, right, inv_z, inv_c), 2.0 * inv_z)
        }
    }
}

/// Runs over the fine–fine relation (`NeighborLists::inner_of`).
///
/// The fine–fine terms of the sweep, each pair evaluated once and added to both of its
/// particles, and the continuity sweep's terms without velocity.
#[inline]
pub fn pair_pass<const D: usize>(
    p: &FineParticles<D>,
    src: &[Source],
    lists: &NeighborLists,
    art: &[Sym],
    prm: &MomentumParams<'_, D>,
    jump: &JumpDiffusion<'_, D>,
    sums: &mut [PairSums<D>],
) {
    // one pass per separation and reconstruction, so that the common scene's pair loop
    // branches on neither
    let a = (p, src, lists, art);
    match (&prm.wrap, prm.muscl) {
        (None, false) => separated_pair_pass::<D, false>(a, prm, jump, sums, &Open),
        (None, true) => separated_pair_pass::<D, true>(a, prm, jump, sums, &Open),
        (Some(period), false) => separated_pair_pass::<D, false>(a, prm, jump, sums, period),
        (Some(period), true) => separated_pair_pass::<D, true>(a, prm, jump, sums, period),
    }
}

/// [`pair_pass`] with pairs separated by `sep`, the Riemann jump reconstructed if
/// `MUSCL`.
#[inline(always)]
fn separated_pair_pass<const D: usize, const MUSCL: bool>(
    (p, src, lists, art): (&FineParticles<D>, &[Source], &NeighborLists, &[Sym]),
    prm: &MomentumParams<'_, D>,
    jump: &JumpDiffusion<'_, D>,
    sums: &mut [PairSums<D>],
    sep: &impl Separation,
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
                let star = StarSide::new(si, prm.materials[mat_i].c0);
                let (xi, vi) = (pos[i], vel[i]);
                let kept_i = kept[i];
                let g_i = if hourglass { prm.hourglass[mat_i] } else { 0.0 };
                let li = &vel_grad[i];
                let mut own = PairSums::<D>::zero();
                for js in lists.inner_of(i).chunks(BLOCK) {
                    block.fill((&xi, js, pos), cut2, jump.reg, sep);
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
                        let (mut ul, ur) = (-vi.dot(&e), -vj.dot(&e));
                        if MUSCL {
                            // the jump between v_i − ½L_i r e and v_j + ½L_j r e
                            let l = (li + vel_grad[j]).cast::<Real>();
                            let du = ul - ur;
                            let rec = du + 0.5 * r * e.dot(&(l * e));
                            ul = ur + minmod_jump(Portable, [du; 4], [rec; 4])[0];
                        }
                        let mat_j = material[j] as usize;
                        let (pstar, two_inv_z) = star.p_star(prm, (ul, ur), sj, mat_j);
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
