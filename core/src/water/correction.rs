//! Kernel gradient correction of the water's pressure force (Bonet & Lok 1999; the
//! corrected configuration of SPHinXsys):
//!
//!   M_i = −Σ_j x_ij ⊗ ∇_i W_ij V_j,   B_i = M_i⁻¹
//!
//! summed over water and wall neighbours. On a full, regular neighbourhood
//! M = κ I with κ = 0.974 for the Wendland C2 kernel at h = 1.3 dp in 2D, so the
//! uncorrected pressure force of a linear (hydrostatic) field is 2.6 % short: a
//! resting tank settles 2.6 % above ρ_w g (H − z), and along its side walls, whose
//! dummy particles carry the exact hydrostatic gradient, the water sinks, driving a
//! circulation that never stops (0.1 m/s in a 0.5 m tank). With B_i the pressure
//! force is exact for linear fields wherever the neighbourhood is full.
//!
//! Near the free surface M loses rank and its inverse would multiply the few
//! remaining terms; B_i is blended towards the identity there: with s = det(M)^{1/D}
//! (0.97 inside, about 0.7 on the surface row), B = w M⁻¹ + (1 − w) I with
//! w = clamp((s − 0.75)/0.15, 0, 1).
//!
//! The water–water sum of M is written once, on [`Quad`] lanes ([`Moment`]), and run
//! by the cluster-pair executor
//! ([`WaterLanes::correction`](super::lanes::WaterLanes::correction)).

// the terms loop over the rows and columns of M
#![allow(clippy::needless_range_loop)]

use super::lanes::{rows, Block, Rec, WaterLanes};
use super::momentum::WaterParams;
use crate::numerics::math::{Real, Vect};
use crate::numerics::pairs::cluster_pass::{gather, repack, run_pass, Geometry, PairLaw, Partner};
use crate::numerics::pairs::clusters::ClusterPairs;
use crate::numerics::pairs::quad::{Lanes, Quad};
use nalgebra::SMatrix;

/// D × D correction matrix.
pub type Corr<const D: usize> = SMatrix<Real, D, D>;

/// −r ∂W/∂r V e⊗e, one neighbour's share of M_i (for either particle of the pair).
#[inline(always)]
pub fn share<const D: usize>(e: &Vect<D>, r: Real, dw: Real, vol: Real) -> Corr<D> {
    e * e.transpose() * (-r * dw * vol)
}

/// B from M, blended towards I where the neighbourhood is not full (module notes).
#[inline]
pub fn invert<const D: usize>(m: &Corr<D>) -> Corr<D> {
    // M in the top-left block of a 3 × 3 identity: the same determinant and inverse
    let mut m3 = nalgebra::Matrix3::<Real>::identity();
    for a in 0..D {
        for b in 0..D {
            m3[(a, b)] = m[(a, b)];
        }
    }
    let det = m3.determinant();
    let s = if det > 0.0 {
        det.powf(1.0 / D as Real)
    } else {
        0.0
    };
    let w = ((s - 0.75) / 0.15).clamp(0.0, 1.0);
    let id = Corr::<D>::identity();
    if w == 0.0 {
        return id;
    }
    match m3.try_inverse() {
        Some(b3) => {
            let b = Corr::<D>::from_fn(|a, c| b3[(a, c)]);
            b * w + id * (1.0 - w)
        }
        None => id,
    }
}

/// The correction's pass: M_i = −Σ_j r ∂W/∂r e⊗e V_j
/// ([`correction`](super::correction)), its upper triangle row by row.
pub(super) struct Moment;

/// The lanes as [`Moment`] reads them: the volumes.
pub(super) struct Volumes<Q: Quad>(Q::V);

impl<const D: usize> PairLaw<D, 6> for Moment {
    type Rec = Rec<D>;
    type Sums = Corr<D>;
    type Lanes<Q: Quad> = Volumes<Q>;
    const USED: usize = D * (D + 1) / 2;

    #[inline(always)]
    fn lanes<Q: Quad>(&self, q: Q, _: usize, recs: &Block<D>) -> Volumes<Q> {
        Volumes(gather(q, recs, |r| r.vol))
    }

    #[inline(always)]
    fn pair<Q: Quad>(
        &self,
        q: Q,
        voli: &Volumes<Q>,
        Partner { rij, g, rec, .. }: Partner<'_, Q, Rec<D>, D>,
        own: &mut [Q::V; 6],
        tj: &mut [Q::V; 6],
    ) {
        moment_terms(q, voli.0, (&rij, &g, rec), own, tj);
    }

    #[inline(always)]
    fn own(m: &mut Corr<D>, t: &[Real; 6]) {
        add_upper(m, t);
    }
}

/// The terms of M of the four lanes (volumes `voli`) against partner j: the upper
/// triangle of −x_ij ⊗ ∇W V row by row, what the lanes gain (times V_j) into `own` and
/// what j gains (times V_i) into `tj`, from their first entries on.
#[inline(always)]
pub(super) fn moment_terms<Q: Quad, const D: usize>(
    q: Q,
    voli: Q::V,
    (rij, g, rec): (&[Q::V; D], &Geometry<Q>, &Rec<D>),
    own: &mut [Q::V],
    tj: &mut [Q::V],
) {
    let zero = q.splat(0.0);
    let f = q.select(g.m, q.sub(zero, q.mul(g.r, g.dw)), zero);
    let volj = q.splat(rec.vol);
    let e: [Q::V; D] = std::array::from_fn(|d| q.mul(rij[d], g.inv_r));
    let mut k = 0;
    for d in 0..D {
        for c in d..D {
            let t = q.mul(q.mul(e[d], e[c]), f);
            own[k] = q.add(own[k], q.mul(t, volj));
            tj[k] = q.mul(t, voli);
            k += 1;
        }
    }
}

/// Add the upper triangle `t` (row by row) to both triangles of `m`.
#[inline(always)]
pub(super) fn add_upper<const D: usize>(m: &mut Corr<D>, t: &[Real]) {
    let mut k = 0;
    for d in 0..D {
        for c in d..D {
            m[(d, c)] += t[k];
            if c != d {
                m[(c, d)] += t[k];
            }
            k += 1;
        }
    }
}

impl<const D: usize> WaterLanes<D> {
    /// Pack each particle's correction B, after [`pack`](Self::pack).
    pub fn pack_corr(&mut self, cp: &ClusterPairs, corr: &[Corr<D>]) {
        repack(&mut self.blocks, cp, |r, i| r.b = rows(&corr[i]));
    }

    /// The correction's water–water sums of M into `m` (added), on `lanes`, after
    /// [`pack`](Self::pack).
    pub fn correction(
        &mut self,
        cp: &ClusterPairs,
        prm: &WaterParams<D>,
        lanes: Lanes,
        m: &mut [Corr<D>],
    ) {
        run_pass(
            (&Moment, &prm.kernel, &prm.wrap),
            (&self.blocks, cp),
            lanes,
            m,
        );
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::numerics::kernel::WendlandC2;

    /// On a regular 2D lattice at h = 1.3 dp, M = κ I with κ = 0.9739 (the lattice
    /// sum of the Wendland C2 kernel), and B M = I.
    #[test]
    fn regular_lattice_moment_and_its_inverse() {
        let dp = 0.01;
        let k = WendlandC2::new(1.3 * dp, 2);
        let mut m = Corr::<2>::zeros();
        for a in -4i32..=4 {
            for b in -4i32..=4 {
                let x = Vect::<2>::new(a as Real * dp, b as Real * dp);
                let r = x.norm();
                if r > 0.0 && r < k.cutoff {
                    m += share(&(x / r), r, k.dw(r), dp * dp);
                }
            }
        }
        assert!((m[(0, 0)] - 0.973921).abs() < 1e-5, "{m}");
        assert!((m[(1, 1)] - m[(0, 0)]).abs() < 1e-12 && m[(0, 1)].abs() < 1e-12);
        let b = invert(&m);
        assert!((b * m - Corr::<2>::identity()).norm() < 1e-12);
        // half a neighbourhood (a free surface): B = I
        let mut half = Corr::<2>::zeros();
        for a in -4i32..=4 {
            for b in -4i32..=0 {
                let x = Vect::<2>::new(a as Real * dp, b as Real * dp);
                let r = x.norm();
                if r > 0.0 && r < k.cutoff {
                    half += share(&(x / r), r, k.dw(r), dp * dp);
                }
            }
        }
        assert_eq!(invert(&half), Corr::<2>::identity());
    }
}
