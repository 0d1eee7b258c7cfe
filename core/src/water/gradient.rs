//! The water's velocity gradient, corrected (Bonet & Lok 1999):
//!
//!   L_i = −Σ_j v_ij ⊗ ∇_i W_ij V_j,   ∇v_i = L_i B_i
//!
//! with B_i the pressure force's correction ([`correction`](super::correction)):
//! exact for a linear velocity field wherever B is (a full neighbourhood). With
//! `water.muscl` the momentum sweep reconstructs each pair's velocities to its midpoint
//! with it, so that the Riemann dissipation acts only on what a linear field does not
//! explain ([`momentum`](super::momentum)).
//!
//! The water–water sums of L are written once, on [`Quad`] lanes, and taken in the
//! same walk over the pairs as the correction's M ([`MomentGradient`], run by
//! [`WaterLanes::moment_and_gradient`]), so the reconstruction costs no pass of its
//! own.

// the terms loop over the rows and columns of L
#![allow(clippy::needless_range_loop)]

use super::correction::{add_upper, moment_terms, Corr};
use super::lanes::{rows, Block, Rec, WaterLanes};
use super::momentum::WaterParams;
use crate::numerics::math::Real;
use crate::numerics::pairs::cluster_pass::{gather, repack, run_pass, Geometry, PairLaw, Partner};
use crate::numerics::pairs::clusters::ClusterPairs;
use crate::numerics::pairs::quad::{Lanes, Quad};

/// The lanes as [`MomentGradient`] reads them: velocities and volumes.
pub(super) struct GradientLanes<Q: Quad, const D: usize> {
    v: [Q::V; D],
    vol: Q::V,
}

/// The terms of L of the four lanes against partner j: L_i = −Σ_j v_ij ⊗ e_ij ∂W/∂r V_j
/// by row (for j, −v_ji ⊗ ∇_j W is the same tensor, times V_i), what the
/// lanes gain (times V_j) into `own` and what j gains (times V_i) into `tj`, from their
/// first entries on.
#[inline(always)]
fn gradient_terms<Q: Quad, const D: usize>(
    q: Q,
    i: &GradientLanes<Q, D>,
    (rij, g, rec): (&[Q::V; D], &Geometry<Q>, &Rec<D>),
    own: &mut [Q::V],
    tj: &mut [Q::V],
) {
    let zero = q.splat(0.0);
    let f = q.select(g.m, q.sub(zero, g.dw), zero);
    let volj = q.splat(rec.vol);
    for a in 0..D {
        let ga = q.mul(q.sub(i.v[a], q.splat(rec.v[a])), f);
        for b in 0..D {
            let t = q.mul(ga, q.mul(rij[b], g.inv_r));
            own[a * D + b] = q.add(own[a * D + b], q.mul(t, volj));
            tj[a * D + b] = q.mul(t, i.vol);
        }
    }
}

/// M and L in one walk over the pairs (`water.muscl`): the terms of
/// [`Moment`](super::correction::Moment) then those of L, so that the reconstruction's
/// gradient costs no pass of its own. M takes its terms in the same order as
/// [`Moment`](super::correction::Moment)'s own pass, so it is bitwise the same.
pub(super) struct MomentGradient;

impl<const D: usize> PairLaw<D, 15> for MomentGradient {
    type Rec = Rec<D>;
    type Sums = [Corr<D>; 2];
    type Lanes<Q: Quad> = GradientLanes<Q, D>;
    const USED: usize = D * (D + 1) / 2 + D * D;

    #[inline(always)]
    fn lanes<Q: Quad>(&self, q: Q, _: usize, recs: &Block<D>) -> GradientLanes<Q, D> {
        GradientLanes {
            v: std::array::from_fn(|d| gather(q, recs, |r| r.v[d])),
            vol: gather(q, recs, |r| r.vol),
        }
    }

    #[inline(always)]
    fn pair<Q: Quad>(
        &self,
        q: Q,
        i: &GradientLanes<Q, D>,
        Partner { rij, g, rec, .. }: Partner<'_, Q, Rec<D>, D>,
        own: &mut [Q::V; 15],
        tj: &mut [Q::V; 15],
    ) {
        let k = D * (D + 1) / 2;
        let (om, ol) = own.split_at_mut(k);
        let (tm, tl) = tj.split_at_mut(k);
        moment_terms(q, i.vol, (&rij, &g, rec), om, tm);
        gradient_terms(q, i, (&rij, &g, rec), ol, tl);
    }

    #[inline(always)]
    fn own(s: &mut [Corr<D>; 2], t: &[Real; 15]) {
        let k = D * (D + 1) / 2;
        add_upper(&mut s[0], &t[..k]);
        add_rows(&mut s[1], &t[k..]);
    }
}

/// Add `t` (D × D, by row) to `l`.
#[inline(always)]
fn add_rows<const D: usize>(l: &mut Corr<D>, t: &[Real]) {
    for a in 0..D {
        for b in 0..D {
            l[(a, b)] += t[a * D + b];
        }
    }
}

impl<const D: usize> WaterLanes<D> {
    /// Pack each particle's corrected velocity gradient ∇v (`water.muscl`), after
    /// [`pack`](Self::pack).
    pub fn pack_grad(&mut self, cp: &ClusterPairs, grad: &[Corr<D>]) {
        repack(&mut self.blocks, cp, |r, i| r.gv = rows(&grad[i]));
    }

    /// The correction's and the velocity gradient's water–water sums, M and L, into
    /// `ml` (added), on `lanes`, after [`pack`](Self::pack): one walk over the pairs
    /// ([`MomentGradient`]).
    pub fn moment_and_gradient(
        &mut self,
        cp: &ClusterPairs,
        prm: &WaterParams<D>,
        lanes: Lanes,
        ml: &mut [[Corr<D>; 2]],
    ) {
        run_pass(
            (&MomentGradient, &prm.kernel, &prm.wrap),
            (&self.blocks, cp),
            lanes,
            ml,
        );
    }
}
