//! The lane layout of the water–water pair laws: the state they read, packed per
//! cluster of four particles ([`clusters`](crate::numerics::pairs::clusters)), one record per
//! particle ([`Block`]). Each law's module holds the law and the pass that runs it on
//! the cluster-pair executor ([`cluster_pass`](crate::numerics::pairs::cluster_pass);
//! docs/method.md §Throughput):
//!
//! - [`WaterLanes::correction`]: M of the kernel gradient correction
//!   ([`correction`](super::correction), Bonet & Lok 1999);
//! - [`WaterLanes::moment_and_gradient`]: M and, in the same walk, the velocity
//!   gradient L that the MUSCL reconstruction reads ([`gradient`](super::gradient));
//! - [`WaterLanes::momentum`]: the pressure and viscous forces
//!   ([`momentum`](super::momentum), Zhang, Hu & Adams 2017, Eqs. 7, 16–19);
//! - [`WaterLanes::continuity`]: the density rate with the pressure jump
//!   ([`continuity`](super::continuity), their Eq. 15).
//!
//! Each law is written once, over [`Quad`](crate::numerics::pairs::quad::Quad) lanes. Pairs beyond
//! the cut-off (or with j ≤ i) are masked out, so each pair is evaluated once and added
//! to both particles; the sums run over the cluster slabs in the two-phase schedule
//! ([`slabs`](crate::numerics::pairs::slabs)), so they do not depend on the thread count, and the
//! two instruction sets agree bitwise ([`quad`](crate::numerics::pairs::quad)).

use super::source::WaterSource;
use super::state::WaterParticles;
use crate::numerics::math::{Real, Vect};
use crate::numerics::pairs::cluster_pass::{pack, repack, Positioned, FAR};
use crate::numerics::pairs::clusters::ClusterPairs;
use crate::numerics::pairs::quad::WIDTH;
use nalgebra::SMatrix;

/// The state the pair terms read, for one particle of a cluster.
#[derive(Clone, Copy, Debug)]
pub struct Rec<const D: usize> {
    pub(super) x: [Real; D],
    pub(super) v: [Real; D],
    pub(super) p: Real,
    pub(super) vol: Real,
    pub(super) rho: Real,
    /// The correction B, by row and column.
    pub(super) b: [[Real; D]; D],
    /// The gravity the continuity's jump is taken relative to, with the seepage
    /// acceleration.
    pub(super) g: [Real; D],
    /// The corrected velocity gradient ∇v = L B, by row and column (`water.muscl`;
    /// zero without).
    pub(super) gv: [[Real; D]; D],
}

impl<const D: usize> Default for Rec<D> {
    fn default() -> Self {
        Rec {
            x: [FAR; D],
            v: [0.0; D],
            p: 0.0,
            vol: 0.0,
            rho: 0.0,
            b: [[0.0; D]; D],
            g: [0.0; D],
            gv: [[0.0; D]; D],
        }
    }
}

/// The state of the four particles of a cluster, one record each.
impl<const D: usize> Positioned<D> for Rec<D> {
    #[inline(always)]
    fn x(&self) -> &[Real; D] {
        &self.x
    }
}

pub type Block<const D: usize> = [Rec<D>; WIDTH];

/// The cluster-pair passes' packed state.
#[derive(Clone, Debug, Default)]
pub struct WaterLanes<const D: usize> {
    pub(super) blocks: Vec<Block<D>>,
}

impl<const D: usize> WaterLanes<D> {
    /// Bytes held.
    pub fn bytes(&self) -> usize {
        self.blocks.capacity() * std::mem::size_of::<Block<D>>()
    }

    /// Pack positions, velocities, pressure, volume and density of every cluster.
    pub fn pack(&mut self, cp: &ClusterPairs, w: &WaterParticles<D>, src: &[WaterSource]) {
        pack(&mut self.blocks, cp, |r, i| {
            r.x.copy_from_slice(w.pos[i].as_slice());
            r.v.copy_from_slice(w.vel[i].as_slice());
            r.p = src[i].p;
            r.vol = src[i].vol;
            r.rho = src[i].rho;
        });
    }

    /// Replace the velocities by `vel` and set the continuity's gravity: `hyd`, plus
    /// each particle's seepage acceleration `body` (empty: none).
    pub fn repack_velocity(
        &mut self,
        cp: &ClusterPairs,
        vel: &[Vect<D>],
        (hyd, body): (&Vect<D>, &[Vect<D>]),
    ) {
        repack(&mut self.blocks, cp, |r, i| {
            for d in 0..D {
                r.v[d] = vel[i][d];
                r.g[d] = hyd[d] + body.get(i).map_or(0.0, |a| a[d]);
            }
        });
    }
}

/// A D × D matrix by row and column, as the records hold it.
pub(super) fn rows<const D: usize>(m: &SMatrix<Real, D, D>) -> [[Real; D]; D] {
    std::array::from_fn(|d| std::array::from_fn(|e| m[(d, e)]))
}
