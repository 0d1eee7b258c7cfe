//! Momentum of the water, water–water terms (Zhang, Hu & Adams 2017, Eqs. 7, 16–19;
//! seed 001 Eq. 2 with the Riemann solver in place of Monaghan's viscosity):
//!
//!   dv_i/dt = (2/ρ_i) Σ_j ( −P*_ij ∇_i W_ij + μ v_ij (x_ij·∇_i W_ij)/(r² + 0.01h²) ) V_j + g
//!
//! P* = ½(P_i + P_j) + ½ β ρ_w c0 (U_L − U_R), U = −v·e_ij (the linearised Riemann
//! problem along the pair, seed 000 Eqs. 19–21): dissipation under compression only,
//! as in Zhang et al. (2017). Their limiter β = min(η max(U_L − U_R, 0)/c0, 1) (η = 3)
//! is optional (`water.limiter`); by default β = 1 under compression, which the resting
//! tank and the dam break of docs/method.md §Water measured as the better choice.
//! With `water.muscl` the jump U_L − U_R is taken between the velocities reconstructed
//! to the pair's midpoint ([`momentum_term`]), so that the dissipation vanishes
//! for a linear velocity field: a standing wave's log decrement falls from 0.63 to 0.12
//! per period at h/50, and a resting tank still settles (docs/method.md §Water).
//! The viscous term is Morris et al. (1997) Eq. (8).
//! The law is written once, on [`Quad`] lanes, and run by the cluster-pair executor
//! ([`WaterLanes::momentum`](super::lanes::WaterLanes::momentum)). Each pair is
//! evaluated once and added to both particles with opposite signs, so Σ m_i dv_i/dt of
//! the pair terms is zero to round-off.

// the terms loop over components of several lane arrays at once (x, v, B, ∇v)
#![allow(clippy::needless_range_loop)]

use super::lanes::{Block, Rec, WaterLanes};
use crate::numerics::kernel::WendlandC2;
use crate::numerics::math::{Real, Vect};
use crate::numerics::pairs::cluster_pass::{gather, run_pass, Geometry, PairLaw, Partner};
use crate::numerics::pairs::clusters::ClusterPairs;
use crate::numerics::pairs::quad::{Lanes, Quad};
use crate::numerics::periodic::Wrap;
use crate::numerics::riemann::minmod_jump;

/// Constants of the water sweeps for one step.
#[derive(Clone, Copy, Debug)]
pub struct WaterParams<const D: usize> {
    pub kernel: WendlandC2,
    pub gravity: Vect<D>,
    /// The gravity of the hydrostatic state: g without its component along a
    /// periodic axis, where no hydrostatic gradient can build (a body force there
    /// drives a flow, seed 001 §2.1).
    pub hydrostatic: Vect<D>,
    /// The periodic axis, if any: pairs across it take the minimum image.
    pub wrap: Wrap,
    pub dt: Real,
    /// Acoustic impedance ρ_w c0.
    pub z: Real,
    /// 1/c0.
    pub inv_c: Real,
    /// Limiter coefficient η (∞: none).
    pub eta: Real,
    /// Dynamic viscosity μ.
    pub mu: Real,
    /// Share of the velocity kept over the step: exp(−Δt/τ) while the settling
    /// damping is on, 1 otherwise.
    pub keep: Real,
    /// Walls and barriers push and never pull (P* ≥ 0 at them): free water has no
    /// tensile strength. False with a saturated soil, whose pore water keeps the
    /// suction it builds ([`WaterMaterial::walls_push_only`]), and for water without a
    /// free surface (a closed channel), whose pressure has no reference level: there
    /// the clamp would turn its fluctuations about zero into a net push.
    ///
    /// [`WaterMaterial::walls_push_only`]: super::material::WaterMaterial::walls_push_only
    pub push_only: bool,
}

/// Per-particle sums of the pair passes.
#[derive(Clone, Copy, Debug)]
pub struct WaterSums<const D: usize> {
    /// Σ (−P* e dW + μ v_ij r² dW/(r (r² + 0.01h²))) V_j; times 2/ρ_i is dv_i/dt.
    pub acc: Vect<D>,
    /// Σ (v_ij·e + ΔP/Z) dW V_j; times ρ_i is dρ_i/dt.
    pub drho: Real,
}

impl<const D: usize> WaterSums<D> {
    pub fn zero() -> Self {
        WaterSums {
            acc: Vect::<D>::zeros(),
            drho: 0.0,
        }
    }
}

/// P* of the pair (i, j) along e = e_ij: ½(P_i + P_j) + ½ β Z (U_L − U_R).
#[inline(always)]
pub fn p_star<const D: usize>(prm: &WaterParams<D>, pi: Real, pj: Real, du: Real) -> Real {
    // β = 0 in expansion; η = ∞ (no limiter) gives β = 1 in compression
    let beta = if du > 0.0 {
        (prm.eta * du * prm.inv_c).min(1.0)
    } else {
        0.0
    };
    0.5 * (pi + pj) + 0.5 * beta * prm.z * du
}

/// The lanes of a cluster as its momentum terms read them.
pub(super) struct MomentumLanes<Q: Quad, const D: usize> {
    v: [Q::V; D],
    b: [[Q::V; D]; D],
    /// ∇v, with `MUSCL` only.
    gv: [[Q::V; D]; D],
    p: Q::V,
    vol: Q::V,
}

/// The momentum pass, with the jump reconstructed if `MUSCL`.
pub(super) struct Momentum<'a, const D: usize, const MUSCL: bool>(pub(super) &'a WaterParams<D>);

impl<const D: usize, const MUSCL: bool> PairLaw<D, D> for Momentum<'_, D, MUSCL> {
    type Rec = Rec<D>;
    type Sums = WaterSums<D>;
    type Lanes<Q: Quad> = MomentumLanes<Q, D>;

    #[inline(always)]
    fn lanes<Q: Quad>(&self, q: Q, _: usize, recs: &Block<D>) -> MomentumLanes<Q, D> {
        let zero = q.splat(0.0);
        let mut lanes = MomentumLanes {
            v: std::array::from_fn(|d| gather(q, recs, |r| r.v[d])),
            b: [[zero; D]; D],
            gv: [[zero; D]; D],
            p: gather(q, recs, |r| r.p),
            vol: gather(q, recs, |r| r.vol),
        };
        for d in 0..D {
            for c in 0..D {
                lanes.b[d][c] = gather(q, recs, |r| r.b[d][c]);
                if MUSCL {
                    lanes.gv[d][c] = gather(q, recs, |r| r.gv[d][c]);
                }
            }
        }
        lanes
    }

    /// The momentum terms of the four lanes against partner j: what the lanes gain
    /// (times V_j) and what j gains from each (times V_i, subtracted after the lane
    /// sums); zero outside the cut-off. With `MUSCL` the jump U_L − U_R is taken between the
    /// velocities reconstructed to the pair's midpoint, v_i − ½ ∇v_i r e and
    /// v_j + ½ ∇v_j r e (van Leer 1979, as Vila (1999) brings it to SPH), limited by
    /// minmod against the raw jump ([`minmod_jump`]): zero for a linear velocity field.
    #[inline(always)]
    fn pair<Q: Quad>(
        &self,
        q: Q,
        i: &MomentumLanes<Q, D>,
        Partner { rij, g, rec, .. }: Partner<'_, Q, Rec<D>, D>,
        own: &mut [Q::V; D],
        tj: &mut [Q::V; D],
    ) {
        let prm = self.0;
        let zero = q.splat(0.0);
        let (half, one) = (q.splat(0.5), q.splat(1.0));
        let Geometry {
            m, r, inv_r, dw, ..
        } = g;
        let mut e = [zero; D];
        let mut vij = [zero; D];
        // U_L − U_R = −v_ij·e
        let mut vie = zero;
        for d in 0..D {
            e[d] = q.mul(rij[d], inv_r);
            vij[d] = q.sub(i.v[d], q.splat(rec.v[d]));
            vie = q.add(vie, q.mul(vij[d], e[d]));
        }
        let mut du = q.sub(zero, vie);
        if MUSCL {
            // U_L − U_R of the reconstructed velocities: du + ½ r e·(∇v_i + ∇v_j) e
            let mut ege = zero;
            for d in 0..D {
                let mut s = zero;
                for c in 0..D {
                    let g = q.add(i.gv[d][c], q.splat(rec.gv[d][c]));
                    s = q.add(s, q.mul(g, e[c]));
                }
                ege = q.add(ege, q.mul(e[d], s));
            }
            let rec = q.add(du, q.mul(q.mul(half, r), ege));
            du = minmod_jump(q, du, rec);
        }
        // β = min(η du/c0, 1) under compression, 0 in expansion (p_star)
        let eta_c = q.splat(prm.eta * prm.inv_c);
        let beta = q.select(q.lt(zero, du), q.min(q.mul(eta_c, du), one), zero);
        let mean = q.mul(half, q.add(i.p, q.splat(rec.p)));
        let ps = q.add(mean, q.mul(q.mul(q.mul(half, beta), q.splat(prm.z)), du));
        // B̄e = ½ (B_i + B_j) e
        let mut eh = [zero; D];
        for d in 0..D {
            eh[d] = q.mul(e[d], half);
        }
        let mut be = [zero; D];
        let mut ebe = zero;
        for d in 0..D {
            let mut s = zero;
            for c in 0..D {
                let bsum = q.add(i.b[d][c], q.splat(rec.b[d][c]));
                s = q.add(s, q.mul(bsum, eh[c]));
            }
            be[d] = s;
            ebe = q.add(ebe, q.mul(e[d], s));
        }
        // Morris' term with the corrected gradient: μ ∂W/∂r e·B̄e / r
        let visc = q.mul(q.mul(q.mul(q.splat(prm.mu), dw), inv_r), ebe);
        let pd = q.mul(q.sub(zero, ps), dw);
        let volj = q.splat(rec.vol);
        for d in 0..D {
            let t = q.add(q.mul(be[d], pd), q.mul(vij[d], visc));
            let t = q.select(m, t, zero);
            own[d] = q.add(own[d], q.mul(t, volj));
            tj[d] = q.mul(t, i.vol);
        }
    }

    #[inline(always)]
    fn own(s: &mut WaterSums<D>, t: &[Real; D]) {
        for d in 0..D {
            s.acc[d] += t[d];
        }
    }

    #[inline(always)]
    fn partner(s: &mut WaterSums<D>, t: &[Real; D]) {
        for d in 0..D {
            s.acc[d] -= t[d];
        }
    }
}

impl<const D: usize> WaterLanes<D> {
    /// The momentum pass's water–water sums into `sums[..].acc` (added), on `lanes`,
    /// after [`pack_corr`](Self::pack_corr); with the Riemann jump reconstructed
    /// (`muscl`) after [`pack_grad`](Self::pack_grad) too.
    pub fn momentum(
        &mut self,
        cp: &ClusterPairs,
        (prm, muscl): (&WaterParams<D>, bool),
        lanes: Lanes,
        sums: &mut [WaterSums<D>],
    ) {
        let blocks = (&self.blocks[..], cp);
        if muscl {
            run_pass(
                (&Momentum::<D, true>(prm), &prm.kernel, &prm.wrap),
                blocks,
                lanes,
                sums,
            );
        } else {
            run_pass(
                (&Momentum::<D, false>(prm), &prm.kernel, &prm.wrap),
                blocks,
                lanes,
                sums,
            );
        }
    }
}
