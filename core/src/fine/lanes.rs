//! The fine–fine pair terms of the momentum and continuity sweeps on cluster pairs
//! ([`clusters`](crate::numerics::pairs::clusters)), a cluster's four particles against one neighbour
//! at a time on [`Quad`] lanes ([`cluster_pass`](crate::numerics::pairs::cluster_pass); issue 45, docs/method.md
//! §Throughput).
//!
//! The momentum pass takes seed 000 Eqs. (16), (18), (20), (23) and (27) (the Riemann
//! P*, σˢ, artificial stress), the hourglass penalty of [`hourglass`](super::hourglass)
//! and, with `numerics.muscl`, the MUSCL reconstruction of the Riemann jump, with the
//! continuity sweep's terms without velocity ([`JumpDiffusion`]: Eq. 19's pressure
//! jump, Eqs. 25–26's diffusion weights); the continuity pass takes Eqs. (15), (19) and
//! (24). Every fine scene runs them: soils of one impedance and sound speed
//! ([`uniform_acoustics`](super::material::uniform_acoustics)) with the one-impedance
//! forms of Eqs. (19)–(20), others with the general ones.
//!
//! Each pair is evaluated once and added to both particles, and the sums run over the
//! cluster slabs in the two-phase schedule ([`slabs`](crate::numerics::pairs::slabs)), so they do not
//! depend on the thread count; the two instruction sets agree bitwise ([`quad`]). The
//! direct evaluation of the equations in `interactions::symmetric_tests` is their
//! reference.
//!
//! [`quad`]: crate::numerics::pairs::quad

// the terms loop over components of several lane arrays at once (x, v, σˢ, L, sums)
#![allow(clippy::needless_range_loop)]

use super::continuity::JumpDiffusion;
use super::momentum::{ArtificialStress, MomentumParams};
use super::pair_sums::{ContinuitySums, PairSums};
use super::source::Source;
use super::state::FineParticles;
use crate::numerics::kernel::WendlandC2;
use crate::numerics::math::{Real, Sym, Vect};
use crate::numerics::pairs::cluster_pass::{
    gather, pack, repack, run_pass, Geometry, PairLaw, Partner, Positioned, FAR,
};
use crate::numerics::pairs::clusters::ClusterPairs;
use crate::numerics::pairs::quad::{Lanes, Quad, WIDTH};
use crate::numerics::periodic::Wrap;
use crate::numerics::riemann::minmod_jump;

/// The fine–fine pair laws' executor for one step: the lane buffers (the state the
/// momentum pass packs serves the continuity pass), the clusters brought up to the last
/// list build, and the instruction set ([`Lanes::detect`]).
pub type FinePairs<'a, const D: usize> = (&'a mut FineLanes<D>, &'a ClusterPairs, Lanes);

/// Components of σˢ the terms read: 2D in-plane xx, yy, the out-of-plane zz and xy;
/// 3D all six ([`Sym::axpy_in`](crate::numerics::math::Sym::axpy_in)).
const fn dev_parts(d: usize) -> usize {
    if d == 2 {
        4
    } else {
        6
    }
}

/// The state the pair terms read, for one particle of a cluster.
#[derive(Clone, Copy, Debug)]
pub struct Rec<const D: usize> {
    x: [Real; D],
    v: [Real; D],
    /// σˢ, in [`Sym`](crate::numerics::math::Sym)'s order.
    dev: [Real; 6],
    p: Real,
    vol: Real,
    /// The pressure of the continuity's jump: K (ρ/ρ0 − 1) by density, P by stress.
    pj: Real,
    /// The geostatic pressure gradient of the particle's soil (the jump by stress).
    pgeo: Real,
    /// Share e of the hourglass penalty kept.
    kept: Real,
    /// ξ G of the particle's soil (0: no penalty).
    g: Real,
    /// The velocity gradient L of the last sweep, by row and column.
    l: [[Real; D]; D],
}

impl<const D: usize> Default for Rec<D> {
    fn default() -> Self {
        Rec {
            x: [FAR; D],
            v: [0.0; D],
            dev: [0.0; 6],
            p: 0.0,
            vol: 0.0,
            pj: 0.0,
            pgeo: 0.0,
            kept: 0.0,
            g: 0.0,
            l: [[0.0; D]; D],
        }
    }
}

impl<const D: usize> Positioned<D> for Rec<D> {
    #[inline(always)]
    fn x(&self) -> &[Real; D] {
        &self.x
    }
}

/// The state of the four particles of a cluster, one record each.
pub type Block<const D: usize> = [Rec<D>; WIDTH];

/// What the general forms read besides [`Rec`], packed only for a scene that needs
/// them (so that the common scene's records stay small).
#[derive(Clone, Copy, Debug)]
pub struct Extra {
    /// Acoustic impedance ρ0 c0 and sound speed c0 of the particle's soil (soils of
    /// several impedances).
    z: Real,
    c: Real,
    /// The artificial stress R of Eq. (27), in [`Sym`]'s order (cohesive soils).
    art: [Real; 6],
}

impl Default for Extra {
    fn default() -> Self {
        Extra {
            z: 1.0,
            c: 1.0,
            art: [0.0; 6],
        }
    }
}

/// The [`Extra`] records of the four particles of a cluster.
pub type ExtraBlock = [Extra; WIDTH];

/// The cluster-pair passes' packed state.
#[derive(Clone, Debug, Default)]
pub struct FineLanes<const D: usize> {
    blocks: Vec<Block<D>>,
    /// Empty for soils of one impedance without artificial stress.
    extra: Vec<ExtraBlock>,
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
    /// Bytes per particle of the packed state and the two passes' lane sums.
    pub fn bytes_per_particle() -> usize {
        use std::mem::size_of;
        size_of::<Block<D>>() / WIDTH
    }

    /// Bytes held.
    pub fn bytes(&self) -> usize {
        use std::mem::size_of;
        self.blocks.capacity() * size_of::<Block<D>>()
            + self.extra.capacity() * size_of::<ExtraBlock>()
    }

    /// Pack the state of every cluster: positions, velocities and [`Source`] records
    /// of `p`, the artificial stresses `art` (empty: none), and per soil ξ G
    /// (`prm.hourglass`), its sound speed and the geostatic pressure gradient of the
    /// jump.
    fn pack(
        &mut self,
        cp: &ClusterPairs,
        (p, art): (&FineParticles<D>, &[Sym]),
        prm: &MomentumParams<'_, D>,
        jump: &JumpDiffusion<'_, D>,
    ) {
        let m = dev_parts(D);
        let by_density = jump.by_density();
        pack(&mut self.blocks, cp, |r, i| {
            let (s, mat) = (Source::of(p, prm.materials, i), p.material[i] as usize);
            for d in 0..D {
                r.x[d] = p.pos[i][d];
                r.v[d] = p.vel[i][d];
                for e in 0..D {
                    r.l[d][e] = p.vel_grad[i][(d, e)] as Real;
                }
            }
            r.dev[..m].copy_from_slice(&s.dev.0[..m]);
            r.p = s.p;
            r.vol = s.vol;
            r.pj = if by_density { s.p_rho } else { s.p };
            r.pgeo = jump.pgeo(mat);
            r.kept = p.hourglass_kept[i] as Real;
            r.g = prm.hourglass.get(mat).copied().unwrap_or(0.0);
        });
        if prm.uniform && art.is_empty() {
            self.extra.clear();
            return;
        }
        pack(&mut self.extra, cp, |r, i| {
            let soil = &prm.materials[p.material[i] as usize];
            (r.z, r.c) = (soil.rho0 * soil.c0, soil.c0);
            if let Some(a) = art.get(i) {
                r.art[..m].copy_from_slice(&a.0[..m]);
            }
        });
    }

    /// The momentum sweep's fine–fine pair terms, with the continuity sweep's terms
    /// without velocity, into `sums` (added), on `lanes`; `art` holds the artificial
    /// stresses with `prm.artificial` (empty without).
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
        self.pack(cp, (p, art), prm, jump);
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
        let blocks = (&self.blocks[..], cp);
        if sc.uniform && !sc.muscl && sc.artificial.is_none() {
            let law = (&Momentum::<D, true>(&sc, &[]), &sc.kernel, &sc.wrap);
            run_pass(law, blocks, lanes, sums);
        } else {
            let law = (
                &Momentum::<D, false>(&sc, &self.extra),
                &sc.kernel,
                &sc.wrap,
            );
            run_pass(law, blocks, lanes, sums);
        }
    }

    /// The continuity sweep's fine–fine pair terms in v_{n+1} (`vel`) into `sums`
    /// (added), on `lanes`, after [`momentum`](Self::momentum) packed the state; with
    /// the one-impedance form of Eq. (19) if `uniform`.
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
        repack(&mut self.blocks, cp, |r, i| {
            r.v.copy_from_slice(vel[i].as_slice())
        });
        let (blocks, extra) = ((&self.blocks[..], cp), &self.extra[..]);
        if uniform {
            run_pass(
                (&Continuity::<D, true>(extra), &kernel, &wrap),
                blocks,
                lanes,
                sums,
            );
        } else {
            run_pass(
                (&Continuity::<D, false>(extra), &kernel, &wrap),
                blocks,
                lanes,
                sums,
            );
        }
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
