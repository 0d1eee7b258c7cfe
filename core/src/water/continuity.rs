//! Continuity of the water, water–water terms (Zhang, Hu & Adams 2017, Eq. 15), with
//! the new velocities v_{n+1}:
//!
//!   dρ_i/dt = 2ρ_i Σ_j (v_i − v*)·∇_i W_ij V_j = ρ_i Σ_j (v_ij·e_ij + ΔP_ij/Z) ∂W/∂r V_j
//!
//! with U* = ½(U_L + U_R) + (P_L − P_R)/(2Z) along the pair. The pressure jump acts as
//! a density diffusion (the Riemann counterpart of seed 001 Eq. 1's δ-term). granmix
//! takes it relative to the hydrostatic state, ΔP_ij = P_i − P_j − ρ̄_ij g·x_ij, as
//! Fourtakas et al. (2019) do for δ-SPH and seed 000 Eq. (26) does for the stress:
//! with the plain jump the diffusion does not vanish at hydrostatic rest near the free
//! surface and the floor, and keeps a resting tank moving.
//!
//! The law is written once, on [`Quad`] lanes, and run by the cluster-pair executor
//! ([`WaterLanes::continuity`](super::lanes::WaterLanes::continuity)).

// the terms loop over components of several lane arrays at once (x, v, g)
#![allow(clippy::needless_range_loop)]

use super::lanes::{Block, Rec, WaterLanes};
use super::momentum::{WaterParams, WaterSums};
use crate::numerics::math::Real;
use crate::numerics::pairs::cluster_pass::{gather, run_pass, PairLaw, Partner};
use crate::numerics::pairs::clusters::ClusterPairs;
use crate::numerics::pairs::quad::{Lanes, Quad};

/// The lanes of a cluster as its continuity terms read them.
pub(super) struct ContinuityLanes<Q: Quad, const D: usize> {
    v: [Q::V; D],
    g: [Q::V; D],
    p: Q::V,
    vol: Q::V,
    rho: Q::V,
}

/// The continuity pass: dρ/dt's water–water terms (module notes).
pub(super) struct Continuity<'a, const D: usize>(pub(super) &'a WaterParams<D>);

impl<const D: usize> PairLaw<D, 1> for Continuity<'_, D> {
    type Rec = Rec<D>;
    type Sums = WaterSums<D>;
    type Lanes<Q: Quad> = ContinuityLanes<Q, D>;

    #[inline(always)]
    fn lanes<Q: Quad>(&self, q: Q, _: usize, recs: &Block<D>) -> ContinuityLanes<Q, D> {
        ContinuityLanes {
            v: std::array::from_fn(|d| gather(q, recs, |r| r.v[d])),
            g: std::array::from_fn(|d| gather(q, recs, |r| r.g[d])),
            p: gather(q, recs, |r| r.p),
            vol: gather(q, recs, |r| r.vol),
            rho: gather(q, recs, |r| r.rho),
        }
    }

    /// (v_ij·e + ΔP_ij/Z) ∂W/∂r V_j for the lanes, (v_ij·e − ΔP_ij/Z) ∂W/∂r V_i for j
    /// (v_ji·e_ji = v_ij·e_ij, ΔP_ji = −ΔP_ij), with ΔP_ij = P_i − P_j − ρ̄ ḡ·x_ij
    /// (module notes).
    #[inline(always)]
    fn pair<Q: Quad>(
        &self,
        q: Q,
        i: &ContinuityLanes<Q, D>,
        Partner { rij, g, rec, .. }: Partner<'_, Q, Rec<D>, D>,
        own: &mut [Q::V; 1],
        tj: &mut [Q::V; 1],
    ) {
        let zero = q.splat(0.0);
        let half = q.splat(0.5);
        let (mut vx, mut gx) = (zero, zero);
        for d in 0..D {
            let vij = q.sub(i.v[d], q.splat(rec.v[d]));
            vx = q.add(vx, q.mul(vij, rij[d]));
            let gd = q.mul(half, q.add(i.g[d], q.splat(rec.g[d])));
            gx = q.add(gx, q.mul(gd, rij[d]));
        }
        let u = q.mul(vx, g.inv_r);
        let rho = q.mul(half, q.add(i.rho, q.splat(rec.rho)));
        let dp = q.sub(i.p, q.splat(rec.p));
        let jump = q.mul(q.sub(dp, q.mul(rho, gx)), q.splat(1.0 / self.0.z));
        let dw = q.select(g.m, g.dw, zero);
        own[0] = q.add(own[0], q.mul(q.mul(q.add(u, jump), dw), q.splat(rec.vol)));
        tj[0] = q.mul(q.mul(q.sub(u, jump), dw), i.vol);
    }

    #[inline(always)]
    fn own(s: &mut WaterSums<D>, t: &[Real; 1]) {
        s.drho += t[0];
    }
}

impl<const D: usize> WaterLanes<D> {
    /// The continuity pass's water–water sums into `sums[..].drho` (added), on
    /// `lanes`, after [`repack_velocity`](Self::repack_velocity).
    pub fn continuity(
        &mut self,
        cp: &ClusterPairs,
        prm: &WaterParams<D>,
        lanes: Lanes,
        sums: &mut [WaterSums<D>],
    ) {
        run_pass(
            (&Continuity(prm), &prm.kernel, &prm.wrap),
            (&self.blocks, cp),
            lanes,
            sums,
        );
    }
}
