//! Momentum sweep of the fine grains, Eqs. (16), (20), (27) and (55).
//!
//! For each fine particle i:
//!   dv_i/dt = 2/ρ_i Σ_j (σ̄ˢ_ij − P* I + f_ijⁿ R̄_ij)·∇_i W_ij V_j + g + (interactions)
//! and v_{n+1} = v_n + Δt dv/dt (Eq. 55). The terms of walls and coarse grains are
//! interactions ([`interactions`](crate::interactions)); this module holds the
//! fine–fine terms and the update.
//!
//! The pair law ([`FineLanes::momentum`]) is written once, on the lanes of the clusters that
//! [`lanes`](super::lanes) packs: it evaluates each
//! fine–fine pair once and adds its terms to both particles' [`MomentumSums`]: σ̄ˢ_ij,
//! P* and the hourglass weight are symmetric in the pair and e_ji = −e_ij, so j
//! receives the negated traction weighted by V_i. The same pass takes the continuity
//! sweep's terms without velocity ([`JumpDiffusion`](super::continuity::JumpDiffusion),
//! [`pair_sums`](super::pair_sums)). The particle pass
//! ([`interactions::momentum_pass`](crate::interactions::momentum_pass)) turns the sums
//! into an acceleration ([`pair_acceleration`]), adds the interactions and
//! [`integrate`]s. The pair terms take the Riemann P* with its limiter (Eqs. 20, 23),
//! σˢ (Eq. 18), the artificial stress (Eq. 27), the hourglass penalty of
//! [`hourglass`](super::hourglass) and, with `numerics.muscl`, the MUSCL
//! reconstruction of the Riemann jump; the one-impedance forms of Eqs. (19)–(20) for
//! soils of one impedance and sound speed
//! ([`uniform_acoustics`](super::material::uniform_acoustics)), the general ones
//! otherwise. Each pair is evaluated once and added to both particles; the sums run
//! over the cluster slabs in the two-phase schedule
//! ([`slabs`](crate::numerics::pairs::slabs)), so they do not depend on the thread
//! count, and the instruction sets agree bitwise.

// the terms loop over components of several lane arrays at once (x, v, σˢ, L, sums)
#![allow(clippy::needless_range_loop)]

use super::continuity::JumpDiffusion;
use super::lanes::{dev_parts, Block, Extra, ExtraBlock, FineLanes, Rec};
use super::material::FineMaterial;
use super::pair_sums::{ContinuitySums, MomentumSums, PairSums};
use super::state::FineParticles;
use crate::numerics::kernel::WendlandC2;
use crate::numerics::math::{Real, Sym, Vect};
use crate::numerics::pairs::cluster_pass::{gather, run_pass, Geometry, PairLaw, Partner};
use crate::numerics::pairs::clusters::ClusterPairs;
use crate::numerics::pairs::quad::{Lanes, Quad, WIDTH};
use crate::numerics::periodic::Wrap;
use crate::numerics::riemann::minmod_jump;
use crate::numerics::riemann::Riemann;
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

/// The scalars of the momentum pass on lanes.
struct MomentumScalars<const D: usize> {
    kernel: WendlandC2,
    wrap: Wrap,
    /// Every soil has one impedance and sound speed: the one-impedance forms of
    /// Eqs. (19)–(20), with the three constants below.
    uniform: bool,
    /// η of the limiter (Eq. 23), and η/c0 with one sound speed.
    eta: Real,
    eta_c: Real,
    /// Z/2 of P* (Eq. 20) and 2/(Z + Z) of U* (Eq. 19), with one impedance.
    half_z: Real,
    inv_z: Real,
    /// The MUSCL reconstruction of the Riemann jump (`numerics.muscl`).
    muscl: bool,
    /// Artificial stress (cohesive soils).
    artificial: Option<ArtificialStress>,
    hourglass: bool,
    by_density: bool,
    diffusion: bool,
    up: Vect<D>,
    /// 0.01 h² of Eq. (25).
    reg: Real,
}

impl<const D: usize> FineLanes<D> {
    /// The momentum sweep's fine–fine pair terms, with the continuity sweep's terms
    /// without velocity, into `sums` (added), on `lanes`; `art` holds the artificial
    /// stresses with `prm.artificial` (empty without). Packs the clusters' state first
    /// ([`FineLanes::pack`]).
    #[allow(clippy::too_many_arguments)]
    pub fn momentum(
        &mut self,
        cp: &ClusterPairs,
        (p, art): (&FineParticles<D>, &[Sym]),
        prm: &MomentumParams<'_, D>,
        jump: &JumpDiffusion<'_, D>,
        lanes: Lanes,
        sums: &mut [PairSums<D>],
    ) {
        let art = if prm.artificial.is_some() { art } else { &[] };
        let soils = (prm.materials, prm.hourglass, prm.uniform);
        self.pack(cp, (p, art), soils, (jump.by_density(), |m| jump.pgeo(m)));
        pair_pass((self.packed(), cp), prm, jump, lanes, sums);
    }
}

/// The momentum pass on the packed clusters (their records, the [`Extra`] records,
/// empty where not needed, and the cluster pairs) into `sums` (added), on `lanes`.
fn pair_pass<const D: usize>(
    ((blocks, extra), cp): ((&[Block<D>], &[ExtraBlock]), &ClusterPairs),
    prm: &MomentumParams<'_, D>,
    jump: &JumpDiffusion<'_, D>,
    lanes: Lanes,
    sums: &mut [PairSums<D>],
) {
    // with one impedance and sound speed, those of any soil (none: no fine grains)
    let Some(mat) = prm.materials.first() else {
        return;
    };
    let z = mat.rho0 * mat.c0;
    let sc = MomentumScalars {
        kernel: prm.kernel,
        wrap: prm.wrap,
        uniform: prm.uniform,
        eta: prm.riemann.eta,
        eta_c: prm.riemann.eta / mat.c0,
        half_z: 0.5 * z,
        inv_z: 2.0 * (0.5 / z),
        muscl: prm.muscl,
        artificial: prm.artificial,
        hourglass: !prm.hourglass.is_empty(),
        by_density: jump.by_density(),
        diffusion: jump.diffusion(),
        up: jump.up(),
        reg: jump.reg,
    };
    let blocks = (blocks, cp);
    if sc.uniform && !sc.muscl && sc.artificial.is_none() {
        let law = (&Momentum::<D, true>(&sc, &[]), &sc.kernel, &sc.wrap);
        run_pass(law, blocks, lanes, sums);
    } else {
        let law = (&Momentum::<D, false>(&sc, extra), &sc.kernel, &sc.wrap);
        run_pass(law, blocks, lanes, sums);
    }
}

/// The lanes of a cluster as the momentum terms read them.
struct MomentumLanes<Q: Quad, const D: usize> {
    v: [Q::V; D],
    dev: [Q::V; 6],
    p: Q::V,
    vol: Q::V,
    pj: Q::V,
    pgeo: Q::V,
    kept: Q::V,
    g: Q::V,
    l: [[Q::V; D]; D],
    z: Q::V,
    c: Q::V,
    art: [Q::V; 6],
}

/// The momentum terms of the four lanes of a cluster against particle `j` (lane `l`
/// of block `bj`): what the lanes gain, added into `own` (the acceleration (D), the hourglass
/// increment (D), then the continuity's drho, w, wz, wp and σˢ weights),
/// and what j gains from each lane, to be summed over the lanes, into `tj`. False,
/// with neither touched, if no lane pairs with j (a list entry beyond the cut-off of
/// every member, in the lists' skin).
#[inline(always)]
fn momentum_term<Q: Quad, const D: usize, const PLAIN: bool>(
    q: Q,
    sc: &MomentumScalars<D>,
    i: &MomentumLanes<Q, D>,
    (
        Partner {
            rij, g, rec: rj, ..
        },
        xj,
    ): (Partner<'_, Q, Rec<D>, D>, Option<&Extra>),
    own: &mut [Q::V; 16],
    tj: &mut [Q::V; 16],
) {
    let zero = q.splat(0.0);
    let half = q.splat(0.5);
    let Geometry {
        m,
        r2,
        r,
        inv_r,
        dw,
    } = g;
    // the pairs beyond the cut-off (or with j ≤ i) add nothing: every term is ∝ ∂W/∂r
    let dw = q.select(m, dw, zero);
    let volj = q.splat(rj.vol);
    let mut e = [zero; D];
    let mut vij = [zero; D];
    // v_ij·e = U_R − U_L (U = −v·e)
    let mut vie = zero;
    let mut up_r = zero;
    for d in 0..D {
        e[d] = q.mul(rij[d], inv_r);
        vij[d] = q.sub(i.v[d], q.splat(rj.v[d]));
        vie = q.add(vie, q.mul(vij[d], e[d]));
        up_r = q.add(up_r, q.mul(rij[d], q.splat(sc.up[d])));
    }
    let (ps, two_inv_z) = p_star::<Q, D, PLAIN>(q, sc, i, (rj, xj), (&e, r, vie));
    // σ*·e = ½ (σˢ_i + σˢ_j)·e − P* e, Eq. (18)
    let mut a = [zero; 6];
    for k in 0..dev_parts(D) {
        a[k] = q.add(i.dev[k], q.splat(rj.dev[k]));
    }
    let t = sym_dot(q, &a, &e);
    let ra =
        (!PLAIN && sc.artificial.is_some()).then(|| artificial_traction(q, sc, i, xj, (r, &e)));
    let (dvj, dvi) = (q.mul(dw, volj), q.mul(dw, i.vol));
    for d in 0..D {
        let mut td = q.sub(q.mul(t[d], half), q.mul(e[d], ps));
        if let Some(ra) = &ra {
            td = q.add(td, ra[d]);
        }
        own[d] = q.add(own[d], q.mul(td, dvj));
        // j takes −t (e_ji = −e_ij): subtracted after the lane sum
        tj[d] = q.mul(td, dvi);
    }
    if sc.hourglass {
        hourglass_terms(q, i, rj, (&rij, &vij), (dw, inv_r, volj), own, tj);
    }
    let geo = [r, r2, dw, up_r, two_inv_z];
    jump_and_weights(q, sc, i, rj, geo, own, tj);
}

/// P* of Eq. (20) for the four lanes against `rj` (the one-impedance form, or the
/// general one with the [`Extra`] records `xj`), with the jump U_L − U_R reconstructed
/// by MUSCL where the scene asks; and 2/(Z_i + Z_j) of Eq. (19).
#[inline(always)]
fn p_star<Q: Quad, const D: usize, const PLAIN: bool>(
    q: Q,
    sc: &MomentumScalars<D>,
    i: &MomentumLanes<Q, D>,
    (rj, xj): (&Rec<D>, Option<&Extra>),
    (e, r, vie): (&[Q::V; D], Q::V, Q::V),
) -> (Q::V, Q::V) {
    let zero = q.splat(0.0);
    let (half, one) = (q.splat(0.5), q.splat(1.0));
    let pj = q.splat(rj.p);
    // U_L − U_R, and U_R − U_L for the limiter
    let mut du = q.sub(zero, vie);
    let mut sep = vie;
    if !PLAIN && sc.muscl {
        // between v_i − ½ L_i r e and v_j + ½ L_j r e: du + ½ r e·(L_i + L_j) e,
        // limited by minmod against du
        let mut ele = zero;
        for d in 0..D {
            let mut s = zero;
            for c in 0..D {
                s = q.add(s, q.mul(q.add(i.l[d][c], q.splat(rj.l[d][c])), e[c]));
            }
            ele = q.add(ele, q.mul(e[d], s));
        }
        du = minmod_jump(q, du, q.add(du, q.mul(q.mul(half, r), ele)));
        sep = q.sub(zero, du);
    }
    let comp = q.select(q.lt(zero, sep), sep, zero);
    if PLAIN || sc.uniform {
        // P* = ½ (P_i + P_j) + ½ β Z (U_L − U_R), β = min(η max(U_R − U_L, 0)/c0, 1)
        // (Riemann::limiter, p_star_uniform)
        let beta = q.min(q.mul(q.splat(sc.eta_c), comp), one);
        let mean = q.mul(half, q.add(i.p, pj));
        let ps = q.add(mean, q.mul(q.mul(beta, q.splat(sc.half_z)), du));
        (ps, q.splat(sc.inv_z))
    } else {
        // Eq. (20), (Z_L P_R + Z_R P_L + β Z_L Z_R (U_L − U_R))/(Z_L + Z_R), with
        // c̄ = ½ (c_i + c_j) in β (Riemann::p_star)
        let xj = xj.expect("the extra records of several impedances");
        let zj = q.splat(xj.z);
        let inv_zsum = q.div(one, q.add(i.z, zj));
        let inv_c = q.div(q.splat(2.0), q.add(i.c, q.splat(xj.c)));
        let beta = q.min(q.mul(q.mul(q.splat(sc.eta), comp), inv_c), one);
        let zz = q.mul(q.mul(beta, i.z), zj);
        let num = q.add(q.add(q.mul(i.z, pj), q.mul(zj, i.p)), q.mul(zz, du));
        (q.mul(num, inv_zsum), q.mul(q.splat(2.0), inv_zsum))
    }
}

/// The artificial stress of Eq. (27) along `e`, ½ f^n (R_i + R_j)·e with
/// f = W(r)/W(dp), for the four lanes against lane `l` of the [`Extra`] records `xj`.
#[inline(always)]
fn artificial_traction<Q: Quad, const D: usize>(
    q: Q,
    sc: &MomentumScalars<D>,
    i: &MomentumLanes<Q, D>,
    xj: Option<&Extra>,
    (r, e): (Q::V, &[Q::V; D]),
) -> [Q::V; D] {
    let (zero, half) = (q.splat(0.0), q.splat(0.5));
    let a = sc.artificial.expect("artificial stress is on");
    let mut rr = [0.0; WIDTH];
    q.store(&mut rr, r);
    let fa = q.mul(
        half,
        q.load(&rr.map(|r| (sc.kernel.w(r) / a.w_dp).powf(a.exponent))),
    );
    let mut b = [zero; 6];
    for k in 0..dev_parts(D) {
        let art_j = xj.expect("the extra records of artificial stress").art[k];
        b[k] = q.mul(q.add(i.art[k], q.splat(art_j)), fa);
    }
    sym_dot(q, &b, e)
}

/// The hourglass penalty s_ij ξḠ_ij ṽ_ij ∂W/∂r V / r ([`hourglass`](super::hourglass))
/// of the four lanes against `rj`, for both sides of every pair (`momentum::integrate`
/// drops the increment of a particle whose share e is 0): what the lanes gain into
/// `own[D..2D]`, what `rj` gains from each into `tj[D..2D]`.
#[inline(always)]
fn hourglass_terms<Q: Quad, const D: usize>(
    q: Q,
    i: &MomentumLanes<Q, D>,
    rj: &Rec<D>,
    (rij, vij): (&[Q::V; D], &[Q::V; D]),
    (dw, inv_r, volj): (Q::V, Q::V, Q::V),
    own: &mut [Q::V; 16],
    tj: &mut [Q::V; 16],
) {
    let (zero, half) = (q.splat(0.0), q.splat(0.5));
    let gp = q.mul(half, q.add(i.g, q.splat(rj.g)));
    let s = q.mul(q.mul(half, q.add(i.kept, q.splat(rj.kept))), gp);
    let qq = q.mul(q.mul(s, dw), inv_r);
    for d in 0..D {
        // ṽ_ij = v_ij − ½ (L_i + L_j) r_ij
        let mut lr = zero;
        for c in 0..D {
            let lsum = q.add(i.l[d][c], q.splat(rj.l[d][c]));
            lr = q.add(lr, q.mul(lsum, rij[c]));
        }
        let vc = q.sub(vij[d], q.mul(lr, half));
        own[D + d] = q.add(own[D + d], q.mul(vc, q.mul(qq, volj)));
        tj[D + d] = q.mul(vc, q.mul(qq, i.vol));
    }
}

/// The continuity sweep's terms without velocity for the four lanes against `rj`: the
/// jump of Eq. (19), P_L − P_R, into U* − U_L (`own[2D]`, `tj[2D]`), and the weights of
/// Eqs. (25)–(26), w = r_ij·∇_i W V/(r² + 0.01h²) (`own[2D + 1..]`, `tj[2D + 1..]`).
#[inline(always)]
fn jump_and_weights<Q: Quad, const D: usize>(
    q: Q,
    sc: &MomentumScalars<D>,
    i: &MomentumLanes<Q, D>,
    rj: &Rec<D>,
    [r, r2, dw, up_r, two_inv_z]: [Q::V; 5],
    own: &mut [Q::V; 16],
    tj: &mut [Q::V; 16],
) {
    let zero = q.splat(0.0);
    let (volj, pj) = (q.splat(rj.vol), q.splat(rj.p));
    // the jump of Eq. (19), P_L − P_R, into U* − U_L (JumpDiffusion::pair)
    let k = q.mul(dw, two_inv_z);
    let pjj = q.splat(rj.pj);
    let (jump_i, jump_j) = if sc.by_density {
        (q.sub(i.pj, pjj), q.sub(pjj, i.pj))
    } else {
        (
            q.sub(i.pj, q.sub(pjj, q.mul(up_r, i.pgeo))),
            q.sub(pjj, q.add(i.pj, q.mul(up_r, q.splat(rj.pgeo)))),
        )
    };
    let o = 2 * D;
    own[o] = q.add(own[o], q.mul(q.mul(jump_i, k), volj));
    tj[o] = q.mul(q.mul(jump_j, k), i.vol);
    // the weights of Eqs. (25)–(26), w = r_ij·∇_i W V/(r² + 0.01h²)
    if sc.diffusion {
        let w = q.div(q.mul(r, dw), q.add(r2, q.splat(sc.reg)));
        let (wi, wj) = (q.mul(w, volj), q.mul(w, i.vol));
        own[o + 1] = q.add(own[o + 1], wi);
        own[o + 2] = q.add(own[o + 2], q.mul(wi, up_r));
        own[o + 3] = q.add(own[o + 3], q.mul(wi, pj));
        tj[o + 1] = wj;
        tj[o + 2] = q.sub(zero, q.mul(wj, up_r));
        tj[o + 3] = q.mul(wj, i.p);
        for k in 0..dev_parts(D) {
            own[o + 4 + k] = q.add(own[o + 4 + k], q.mul(wi, q.splat(rj.dev[k])));
            tj[o + 4 + k] = q.mul(wj, i.dev[k]);
        }
    }
}

/// A symmetric tensor `a` (in [`Sym`]'s order, the in-plane part in 2D) times `e`.
#[inline(always)]
fn sym_dot<Q: Quad, const D: usize>(q: Q, a: &[Q::V; 6], e: &[Q::V; D]) -> [Q::V; D] {
    let mut t = [q.splat(0.0); D];
    if D == 2 {
        t[0] = q.add(q.mul(a[0], e[0]), q.mul(a[3], e[1]));
        t[1] = q.add(q.mul(a[3], e[0]), q.mul(a[1], e[1]));
    } else {
        t[0] = q.add(
            q.add(q.mul(a[0], e[0]), q.mul(a[3], e[1])),
            q.mul(a[4], e[2]),
        );
        t[1] = q.add(
            q.add(q.mul(a[3], e[0]), q.mul(a[1], e[1])),
            q.mul(a[5], e[2]),
        );
        t[2] = q.add(
            q.add(q.mul(a[4], e[0]), q.mul(a[5], e[1])),
            q.mul(a[2], e[2]),
        );
    }
    t
}

/// The momentum pass, with the clusters' [`Extra`] records (empty: not needed);
/// `PLAIN` for soils of one impedance without MUSCL or artificial stress (the common
/// scene), whose terms then carry no test for the others.
struct Momentum<'a, const D: usize, const PLAIN: bool>(&'a MomentumScalars<D>, &'a [ExtraBlock]);

impl<const D: usize, const PLAIN: bool> PairLaw<D, 16> for Momentum<'_, D, PLAIN> {
    type Rec = Rec<D>;
    type Sums = PairSums<D>;
    type Lanes<Q: Quad> = MomentumLanes<Q, D>;
    /// The acceleration and the hourglass increment (D each), the continuity's drho,
    /// w, wz and wp, and the σˢ weights.
    const USED: usize = 2 * D + 4 + dev_parts(D);

    #[inline(always)]
    fn lanes<Q: Quad>(&self, q: Q, c: usize, bi: &Block<D>) -> MomentumLanes<Q, D> {
        let zero = q.splat(0.0);
        let mut lanes = MomentumLanes::<Q, D> {
            v: std::array::from_fn(|d| gather(q, bi, |r| r.v[d])),
            dev: [zero; 6],
            p: gather(q, bi, |r| r.p),
            vol: gather(q, bi, |r| r.vol),
            pj: gather(q, bi, |r| r.pj),
            pgeo: gather(q, bi, |r| r.pgeo),
            kept: gather(q, bi, |r| r.kept),
            g: gather(q, bi, |r| r.g),
            l: [[zero; D]; D],
            z: zero,
            c: zero,
            art: [zero; 6],
        };
        let xi = if PLAIN { None } else { self.1.get(c) };
        if let Some(xi) = xi {
            lanes.z = gather(q, xi, |r| r.z);
            lanes.c = gather(q, xi, |r| r.c);
        }
        for d in 0..D {
            for e in 0..D {
                lanes.l[d][e] = gather(q, bi, |r| r.l[d][e]);
            }
        }
        for k in 0..dev_parts(D) {
            lanes.dev[k] = gather(q, bi, |r| r.dev[k]);
            if let (Some(xi), Some(_)) = (xi, &self.0.artificial) {
                lanes.art[k] = gather(q, xi, |r| r.art[k]);
            }
        }
        lanes
    }

    #[inline(always)]
    fn pair<Q: Quad>(
        &self,
        q: Q,
        i: &MomentumLanes<Q, D>,
        j: Partner<'_, Q, Rec<D>, D>,
        own: &mut [Q::V; 16],
        tj: &mut [Q::V; 16],
    ) {
        let xj = if PLAIN {
            None
        } else {
            self.1.get(j.c).map(|x| &x[j.l])
        };
        momentum_term::<Q, D, PLAIN>(q, self.0, i, (j, xj), own, tj);
    }

    #[inline(always)]
    fn own(s: &mut PairSums<D>, t: &[Real; 16]) {
        for d in 0..D {
            s.momentum.acc[d] += t[d];
            s.momentum.hourglass[d] += t[D + d];
        }
        add_weights::<D>(&mut s.continuity, t);
    }

    #[inline(always)]
    fn partner(s: &mut PairSums<D>, t: &[Real; 16]) {
        // j takes −t of the acceleration and the hourglass increment (e_ji = −e_ij)
        for d in 0..D {
            s.momentum.acc[d] -= t[d];
            s.momentum.hourglass[d] -= t[D + d];
        }
        add_weights::<D>(&mut s.continuity, t);
    }
}

/// Add the continuity's terms of the momentum pass, `t[2D..]`, to `s`.
#[inline(always)]
fn add_weights<const D: usize>(s: &mut ContinuitySums<D>, t: &[Real; 16]) {
    let o = 2 * D;
    s.drho += t[o];
    s.w += t[o + 1];
    s.wz += t[o + 2];
    s.wp += t[o + 3];
    for k in 0..dev_parts(D) {
        s.wdev.0[k] += t[o + 4 + k];
    }
}
