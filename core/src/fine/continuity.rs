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
//! The pair law ([`FineLanes::continuity`]) is written once, on the lanes of the clusters that
//! [`lanes`](super::lanes) packs: it evaluates each
//! fine–fine pair once and adds its terms in v_{n+1} to both particles'
//! [`ContinuitySums`]; the terms without velocity ([`JumpDiffusion`]) are already
//! there, from the momentum sweep's pair pass. The particle pass
//! ([`interactions::continuity_pass`](crate::interactions::continuity_pass)) takes the
//! sums as [`Rates`], adds the interactions and [`Rates::update`]s the stress.

// the terms loop over components of several lane arrays at once (v, sums)
#![allow(clippy::needless_range_loop)]

use super::hourglass::penalty_kept;
use super::lanes::{Block, Extra, ExtraBlock, FineLanes, Rec};
use super::material::FineMaterial;
use super::pair_sums::{ContinuitySums, PairSums};
use super::plasticity::constitutive_step;
use crate::numerics::kernel::WendlandC2;
use crate::numerics::math::{Real, Sym, Vect};
use crate::numerics::pairs::cluster_pass::{gather, run_pass, Geometry, PairLaw, Partner};
use crate::numerics::pairs::clusters::ClusterPairs;
use crate::numerics::pairs::quad::{Lanes, Quad};
use crate::numerics::periodic::Wrap;
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
    /// The rates of particle i (stress σ_n `stress`, material index `mat`, factor
    /// `weight` of [`ContinuityParams::weight`]) from its fine–fine pair sums.
    #[inline(always)]
    pub fn from_sums(
        prm: &ContinuityParams<'_, D>,
        stress: &Sym,
        (mat, weight): (usize, Real),
        sum: &ContinuitySums<D>,
    ) -> Self {
        let geo = prm.geostatic[mat].scale(prm.geostatic_scale * weight);
        // Ψ of Eq. (26) summed: σ_i − σ_j (σ = σˢ − P I) minus the geostatic gradient
        // −(r_ij·up) geo
        let mut diff = stress.dev().scale(sum.w).sub(&sum.wdev);
        let dp = sum.wp - (-stress.trace() / 3.0) * sum.w;
        diff.0[0] += dp;
        diff.0[1] += dp;
        diff.0[2] += dp;
        diff.axpy(-sum.wz, &geo);
        Rates {
            drho: sum.drho + sum.drho_v,
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
}

impl<const D: usize> FineLanes<D> {
    /// The continuity sweep's fine–fine pair terms in v_{n+1} (`vel`) into `sums`
    /// (added), on `lanes`, after [`momentum`](FineLanes::momentum) packed the state;
    /// with the one-impedance form of Eq. (19) if `uniform`.
    pub fn continuity(
        &mut self,
        cp: &ClusterPairs,
        (vel, kernel, wrap, uniform): (&[Vect<D>], WendlandC2, Wrap, bool),
        lanes: Lanes,
        sums: &mut [PairSums<D>],
    ) {
        if cp.is_empty() {
            return;
        }
        self.repack_velocities(cp, vel);
        let (blocks, extra) = self.packed();
        let blocks = (blocks, cp);
        if uniform {
            let law = (&Continuity::<D, true>(extra), &kernel, &wrap);
            run_pass(law, blocks, lanes, sums);
        } else {
            let law = (&Continuity::<D, false>(extra), &kernel, &wrap);
            run_pass(law, blocks, lanes, sums);
        }
    }
}

/// The continuity terms of the four lanes against partner j: what the lanes gain
/// (drho, then −v_ij ⊗ e ∂W/∂r V_j by row) into `own`, and what j gains from each
/// into `tj`, to be summed over the lanes (drho added, the gradient subtracted).
#[inline(always)]
fn continuity_term<Q: Quad, const D: usize, const UNIFORM: bool>(
    q: Q,
    i: &ContinuityLanes<Q, D>,
    (
        Partner {
            rij, g, rec: rj, ..
        },
        xj,
    ): (Partner<'_, Q, Rec<D>, D>, Option<&Extra>),
    own: &mut [Q::V; 10],
    tj: &mut [Q::V; 10],
) {
    let zero = q.splat(0.0);
    let (v, vol) = (&i.v, i.vol);
    let Geometry { m, inv_r, dw, .. } = g;
    let dw = q.select(m, dw, zero);
    let volj = q.splat(rj.vol);
    let mut e = [zero; D];
    let mut g = [zero; D];
    let mut s = zero;
    for d in 0..D {
        e[d] = q.mul(rij[d], inv_r);
        // g = v_ij ∂W/∂r, s = g·e: 2 (U* − U_L) of Eq. (15) without the jump
        g[d] = q.mul(q.sub(v[d], q.splat(rj.v[d])), dw);
        s = q.add(s, q.mul(g[d], e[d]));
    }
    if UNIFORM {
        own[0] = q.add(own[0], q.mul(s, volj));
        tj[0] = q.mul(s, vol);
    } else {
        // 2 Z_j (U_R − U_L)/(Z_i + Z_j), and Z_i for j (Eq. 19)
        let zj = q.splat(xj.expect("the extra records of several impedances").z);
        let t = q.div(q.mul(q.splat(2.0), s), q.add(i.z, zj));
        own[0] = q.add(own[0], q.mul(q.mul(t, zj), volj));
        tj[0] = q.mul(q.mul(t, i.z), vol);
    }
    for a in 0..D {
        let (gi, gj) = (q.mul(g[a], volj), q.mul(g[a], vol));
        for b in 0..D {
            let k = 1 + a * D + b;
            own[k] = q.add(own[k], q.mul(gi, e[b]));
            tj[k] = q.mul(gj, e[b]);
        }
    }
}

/// The lanes of a cluster as the continuity terms read them.
struct ContinuityLanes<Q: Quad, const D: usize> {
    v: [Q::V; D],
    vol: Q::V,
    z: Q::V,
}

/// The continuity pass, with the one-impedance form of Eq. (19) if `UNIFORM`, and the
/// clusters' [`Extra`] records (the impedances without `UNIFORM`).
struct Continuity<'a, const D: usize, const UNIFORM: bool>(&'a [ExtraBlock]);

impl<const D: usize, const UNIFORM: bool> PairLaw<D, 10> for Continuity<'_, D, UNIFORM> {
    type Rec = Rec<D>;
    type Sums = PairSums<D>;
    type Lanes<Q: Quad> = ContinuityLanes<Q, D>;
    const USED: usize = 1 + D * D;

    #[inline(always)]
    fn lanes<Q: Quad>(&self, q: Q, c: usize, recs: &Block<D>) -> ContinuityLanes<Q, D> {
        ContinuityLanes {
            v: std::array::from_fn(|d| gather(q, recs, |r| r.v[d])),
            vol: gather(q, recs, |r| r.vol),
            z: match (UNIFORM, self.0.get(c)) {
                (false, Some(xi)) => gather(q, xi, |r| r.z),
                _ => q.splat(0.0),
            },
        }
    }

    #[inline(always)]
    fn pair<Q: Quad>(
        &self,
        q: Q,
        i: &ContinuityLanes<Q, D>,
        j: Partner<'_, Q, Rec<D>, D>,
        own: &mut [Q::V; 10],
        tj: &mut [Q::V; 10],
    ) {
        let xj = if UNIFORM {
            None
        } else {
            self.0.get(j.c).map(|x| &x[j.l])
        };
        continuity_term::<Q, D, UNIFORM>(q, i, (j, xj), own, tj);
    }

    #[inline(always)]
    fn own(s: &mut PairSums<D>, t: &[Real; 10]) {
        let s = &mut s.continuity;
        s.drho_v += t[0];
        for a in 0..D {
            for b in 0..D {
                // −v_ij ⊗ e_ij ∂W/∂r V_j, Eq. (24)
                s.grad[(a, b)] -= t[1 + a * D + b];
            }
        }
    }
}
