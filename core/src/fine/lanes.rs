//! The fine grains' lane layout: the record of each particle that the fine–fine pair
//! laws read ([`Rec`], and [`Extra`] where a scene needs the general forms), packed by
//! cluster ([`clusters`](crate::numerics::pairs::clusters)) for the executor
//! ([`cluster_pass`](crate::numerics::pairs::cluster_pass)), which runs a cluster's
//! four particles against one neighbour at a time on [`Quad`] lanes (issue 45,
//! docs/method.md §Throughput).
//!
//! The laws themselves are written once, in their modules: the momentum pass
//! ([`momentum::pair_pass`](super::momentum::pair_pass): seed 000 Eqs. 16, 18, 20, 23
//! and 27, the hourglass penalty, MUSCL, and the continuity's terms without velocity)
//! and the continuity pass ([`continuity::pair_pass`](super::continuity::pair_pass):
//! Eqs. 15, 19 and 24). Every fine scene runs them. The direct evaluation of the
//! equations in `interactions::symmetric_tests` is their reference.
//!
//! [`Quad`]: crate::numerics::pairs::quad::Quad

use super::material::FineMaterial;
use super::source::Source;
use super::state::FineParticles;
use crate::numerics::math::{Real, Sym, Vect};
use crate::numerics::pairs::cluster_pass::{pack, repack, Positioned, FAR};
use crate::numerics::pairs::clusters::ClusterPairs;
use crate::numerics::pairs::quad::{Lanes, WIDTH};

/// The fine–fine pair laws' executor for one step: the lane buffers (the state the
/// momentum pass packs serves the continuity pass), the clusters brought up to the last
/// list build, and the instruction set ([`Lanes::detect`]).
pub type FinePairs<'a, const D: usize> = (&'a mut FineLanes<D>, &'a ClusterPairs, Lanes);

/// Components of σˢ the terms read: 2D in-plane xx, yy, the out-of-plane zz and xy;
/// 3D all six ([`Sym::axpy_in`](crate::numerics::math::Sym::axpy_in)).
pub(super) const fn dev_parts(d: usize) -> usize {
    if d == 2 {
        4
    } else {
        6
    }
}

/// The state the pair terms read, for one particle of a cluster.
#[derive(Clone, Copy, Debug)]
pub struct Rec<const D: usize> {
    pub(super) x: [Real; D],
    pub(super) v: [Real; D],
    /// σˢ, in [`Sym`](crate::numerics::math::Sym)'s order.
    pub(super) dev: [Real; 6],
    pub(super) p: Real,
    pub(super) vol: Real,
    /// The pressure of the continuity's jump: K (ρ/ρ0 − 1) by density, P by stress.
    pub(super) pj: Real,
    /// The geostatic pressure gradient of the particle's soil (the jump by stress).
    pub(super) pgeo: Real,
    /// Share e of the hourglass penalty kept.
    pub(super) kept: Real,
    /// ξ G of the particle's soil (0: no penalty).
    pub(super) g: Real,
    /// The velocity gradient L of the last sweep, by row and column.
    pub(super) l: [[Real; D]; D],
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
    pub(super) z: Real,
    pub(super) c: Real,
    /// The artificial stress R of Eq. (27), in [`Sym`]'s order (cohesive soils).
    pub(super) art: [Real; 6],
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
    /// of `p`, the artificial stresses `art` (empty: none), and per soil of
    /// `materials` ξ G (`hourglass`, empty: no penalty), its sound speed and the
    /// geostatic pressure gradient `pgeo` of the continuity's jump, taken from the
    /// density if `by_density`. The [`Extra`] records only for soils of several
    /// impedances (not `uniform`) or with artificial stress.
    pub(super) fn pack(
        &mut self,
        cp: &ClusterPairs,
        (p, art): (&FineParticles<D>, &[Sym]),
        (materials, hourglass, uniform): (&[FineMaterial], &[Real], bool),
        (by_density, pgeo): (bool, impl Fn(usize) -> Real + Sync),
    ) {
        let m = dev_parts(D);
        pack(&mut self.blocks, cp, |r, i| {
            let (s, mat) = (Source::of(p, materials, i), p.material[i] as usize);
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
            r.pgeo = pgeo(mat);
            r.kept = p.hourglass_kept[i] as Real;
            r.g = hourglass.get(mat).copied().unwrap_or(0.0);
        });
        if uniform && art.is_empty() {
            self.extra.clear();
            return;
        }
        pack(&mut self.extra, cp, |r, i| {
            let soil = &materials[p.material[i] as usize];
            (r.z, r.c) = (soil.rho0 * soil.c0, soil.c0);
            if let Some(a) = art.get(i) {
                r.art[..m].copy_from_slice(&a.0[..m]);
            }
        });
    }

    /// Bring the packed velocities to `vel` (v_{n+1}, for the continuity pass).
    pub(super) fn repack_velocities(&mut self, cp: &ClusterPairs, vel: &[Vect<D>]) {
        repack(&mut self.blocks, cp, |r, i| {
            r.v.copy_from_slice(vel[i].as_slice())
        });
    }

    /// The packed records and [`Extra`] records (empty where not needed).
    pub(super) fn packed(&self) -> (&[Block<D>], &[ExtraBlock]) {
        (&self.blocks, &self.extra)
    }
}
