//! Clusters of four consecutive particles and, for each, the particles its members
//! pair with: the lists of the lane passes (a cluster of four against one particle at a
//! time, after GROMACS' NxM scheme, Páll & Hess 2013; issue 45, docs/method.md
//! §Throughput).
//!
//! Within each slab of the lists ([`slabs`](crate::numerics::pairs::slabs)) the particles are cut into
//! clusters of [`WIDTH`] in index order, the last of a slab holding what is left, so
//! that no cluster straddles two slabs. A cluster's list is the union of its members'
//! half lists, ascending. The half lists hold each pair once under its lower index, so
//! a pass takes the pair (i, j) of a member i and a listed j only where j > i (and
//! within the cut-off), and every pair within the cut-off exactly once. A listed j lies
//! in the cluster's slab or the next: the two-phase schedule runs over clusters as it
//! does over particles.

use crate::numerics::neighbors::NeighborLists;
use crate::numerics::pairs::quad::WIDTH;
use rayon::prelude::*;

/// Clusters per task of the build.
const TASK: usize = 256;

/// The clusters of a family and their pair lists, derived from one build of its
/// neighbour lists.
#[derive(Clone, Debug, Default)]
pub struct ClusterPairs {
    /// The list build (`NeighborLists::builds`) and particle count these come from.
    from: Option<(usize, usize)>,
    /// Cluster c holds particles `start[c]..start[c + 1]` (at most [`WIDTH`]).
    pub start: Vec<u32>,
    /// Slab s holds clusters `slabs[s]..slabs[s + 1]`.
    pub slabs: Vec<u32>,
    /// Slab s holds particles `particle_slabs[s]..particle_slabs[s + 1]`.
    pub particle_slabs: Vec<u32>,
    /// The cluster of each particle.
    pub of: Vec<u32>,
    /// `js[off[c]..off[c + 1]]`: the particles the members of c pair with, ascending.
    off: Vec<u32>,
    js: Vec<u32>,
}

impl ClusterPairs {
    /// Derive the clusters from `lists` over `n` particles, unless they already are.
    pub fn update(&mut self, lists: &NeighborLists, n: usize) {
        let key = (lists.builds, n);
        if self.from == Some(key) && lists.builds > 0 {
            return;
        }
        self.from = Some(key);
        self.start.clear();
        self.slabs.clear();
        for s in 0..lists.slabs.len().saturating_sub(1) {
            self.slabs.push(self.start.len() as u32);
            let (a, b) = (lists.slabs[s] as usize, lists.slabs[s + 1] as usize);
            self.start.extend((a..b).step_by(WIDTH).map(|k| k as u32));
        }
        self.slabs.push(self.start.len() as u32);
        self.start.push(n as u32);
        self.particle_slabs.clear();
        let start = &self.start;
        self.particle_slabs
            .extend(self.slabs.iter().map(|&c| start[c as usize]));
        let nc = self.start.len() - 1;
        self.of.clear();
        self.of.resize(n, 0);
        for c in 0..nc {
            for i in self.start[c]..self.start[c + 1] {
                self.of[i as usize] = c as u32;
            }
        }
        let start = &self.start;
        let parts: Vec<(Vec<u32>, Vec<u32>)> = (0..nc.div_ceil(TASK))
            .into_par_iter()
            .map(|t| {
                let (mut counts, mut js) = (Vec::new(), Vec::new());
                let (mut row, mut a, mut b) = (Vec::new(), Vec::new(), Vec::new());
                for c in t * TASK..((t + 1) * TASK).min(nc) {
                    let mut m: [&[u32]; WIDTH] = [&[]; WIDTH];
                    for (k, i) in (start[c]..start[c + 1]).enumerate() {
                        m[k] = lists.inner_of(i as usize);
                    }
                    if m.iter().all(|l| l.is_sorted()) {
                        // the lists of a cell-sorted family ascend (stencil rows in cell
                        // order): merge them pairwise
                        merge_union(m[0], m[1], &mut a);
                        merge_union(m[2], m[3], &mut b);
                        merge_union(&a, &b, &mut row);
                    } else {
                        // a list that wraps across a periodic seam
                        row.clear();
                        m.iter().for_each(|l| row.extend_from_slice(l));
                        row.sort_unstable();
                        row.dedup();
                    }
                    counts.push(row.len() as u32);
                    js.extend_from_slice(&row);
                }
                (counts, js)
            })
            .collect();
        self.off.clear();
        self.js.clear();
        self.off.push(0);
        for (counts, js) in parts {
            let mut end = self.js.len() as u32;
            self.off.extend(counts.iter().map(|&k| {
                end += k;
                end
            }));
            self.js.extend_from_slice(&js);
        }
    }

    /// Particles in the clusters.
    pub fn particles(&self) -> usize {
        self.start.last().map_or(0, |&n| n as usize)
    }

    /// Number of clusters.
    pub fn len(&self) -> usize {
        self.start.len().saturating_sub(1)
    }

    pub fn is_empty(&self) -> bool {
        self.len() == 0
    }

    /// The particles the members of cluster `c` pair with (j > i of some member i).
    #[inline]
    pub fn of(&self, c: usize) -> &[u32] {
        &self.js[self.off[c] as usize..self.off[c + 1] as usize]
    }

    /// The particles of cluster `c`.
    #[inline]
    pub fn members(&self, c: usize) -> std::ops::Range<usize> {
        self.start[c] as usize..self.start[c + 1] as usize
    }

    /// Cluster–particle pairs held.
    pub fn pairs(&self) -> usize {
        self.js.len()
    }

    /// Bytes held.
    pub fn bytes(&self) -> usize {
        4 * (self.start.capacity()
            + self.slabs.capacity()
            + self.particle_slabs.capacity()
            + self.of.capacity()
            + self.off.capacity()
            + self.js.capacity())
    }

    /// Forget the lists they were derived from (the next [`update`](Self::update)
    /// derives them again).
    pub fn invalidate(&mut self) {
        self.from = None;
    }
}

/// The ascending union of two ascending lists into `out`.
fn merge_union(a: &[u32], b: &[u32], out: &mut Vec<u32>) {
    out.clear();
    let (mut i, mut j) = (0, 0);
    while i < a.len() && j < b.len() {
        let (x, y) = (a[i], b[j]);
        out.push(x.min(y));
        i += (x <= y) as usize;
        j += (y <= x) as usize;
    }
    out.extend_from_slice(&a[i..]);
    out.extend_from_slice(&b[j..]);
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::numerics::math::Vect;
    use crate::numerics::neighbors::{Binned, CellGrid};
    use crate::numerics::periodic::Open;
    use crate::numerics::rng::Rng;
    use nalgebra::Vector2;

    #[test]
    fn union_of_ascending_lists() {
        let mut out = Vec::new();
        merge_union(&[1, 4, 5, 9], &[2, 4, 9, 11, 12], &mut out);
        assert_eq!(out, [1, 2, 4, 5, 9, 11, 12]);
        merge_union(&[], &[3], &mut out);
        assert_eq!(out, [3]);
    }

    /// Every listed pair (i, j) has j in the list of i's cluster; no cluster straddles a
    /// slab; each listed particle lies in its cluster's slab or the next, after the
    /// cluster's first member.
    #[test]
    fn cluster_pairs_cover_the_lists() {
        let mut rng = Rng(7);
        let pos: Vec<Vect<2>> = (0..900)
            .map(|k| {
                let (a, b) = ((k % 45) as f64, (k / 45) as f64);
                Vector2::new(
                    a * 0.01 + 0.003 * rng.uniform(),
                    b * 0.01 + 0.003 * rng.uniform(),
                )
            })
            .collect();
        let (lo, hi) = (Vector2::new(0.0, 0.0), Vector2::new(0.46, 0.21));
        let mut g = CellGrid::periodic(&lo, &hi, 0.026, None);
        g.bin(&pos);
        let pos: Vec<Vect<2>> = g.order().iter().map(|&i| pos[i as usize]).collect();
        g.bin(&pos);
        let none = CellGrid::periodic(&lo, &hi, 0.026, None);
        let empty: Vec<Vect<2>> = Vec::new();
        let mut nl = NeighborLists::default();
        let nb = |grid| Binned { pos: &empty, grid };
        nl.build(&pos, &g, nb(&none), nb(&none), 0.026, &Open);
        let mut cp = ClusterPairs::default();
        cp.update(&nl, pos.len());
        assert_eq!(cp.start[0], 0);
        assert_eq!(*cp.start.last().unwrap() as usize, pos.len());
        let cluster = |i: usize| cp.start.partition_point(|&b| b as usize <= i) - 1;
        let slab_of = |c: usize| cp.slabs.partition_point(|&b| b as usize <= c) - 1;
        for s in 0..nl.slabs.len() - 1 {
            // the slab's clusters hold exactly its particles
            let (a, b) = (cp.slabs[s] as usize, cp.slabs[s + 1] as usize);
            assert_eq!(cp.start[a], nl.slabs[s]);
            assert_eq!(cp.start[b], nl.slabs[s + 1]);
        }
        let mut listed = 0;
        for i in 0..pos.len() {
            let ci = cluster(i);
            assert!(cp.members(ci).len() <= WIDTH);
            assert_eq!(cp.of[i] as usize, ci);
            for &j in nl.inner_of(i) {
                assert!(cp.of(ci).contains(&j), "pair {i}-{j}");
                listed += 1;
            }
            let js = cp.of(ci);
            assert!(js.windows(2).all(|w| w[0] < w[1]), "ascending, once each");
            for &j in js {
                let (a, b) = (slab_of(ci), slab_of(cluster(j as usize)));
                assert!(j > cp.start[ci] && (b == a || b == a + 1));
            }
        }
        assert!(listed > 0);
        // the lanes hold every listed pair, plus the ones masked out
        assert!(cp.pairs() * WIDTH >= listed);
    }
}
