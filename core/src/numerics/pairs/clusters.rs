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

use crate::numerics::pairs::quad::WIDTH;
use rayon::prelude::*;

/// Clusters per task of the build.
const TASK: usize = 256;

/// The clusters of a family and their pair lists, from one build of its neighbour
/// lists (`NeighborLists::build`), which keeps no half lists of its own.
#[derive(Clone, Debug, Default, serde::Serialize, serde::Deserialize)]
pub struct ClusterPairs {
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
    /// Per cluster, how the passes take it (empty: every cluster whole); set per
    /// step where resting particles sleep ([`sleep::mark_runs`](crate::numerics::sleep::mark_runs)).
    #[serde(skip)]
    pub runs: Vec<Take>,
    /// Per particle, whether it is awake (read by [`Take::AwakePartners`]).
    #[serde(skip)]
    pub awake: Vec<bool>,
}

/// How a pass takes a cluster where resting particles sleep.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Take {
    /// Every pair: a member is awake.
    All,
    /// Only the pairs with an awake partner: the members sleep, some partners do not.
    AwakePartners,
    /// None: the members and their partners all sleep.
    Skip,
}

impl ClusterPairs {
    /// Cut the `n` particles into clusters within each of the slabs `slabs` (particle
    /// `slabs[s]..slabs[s + 1]` in slab s) and build their lists: `half(i, out)` appends
    /// particle i's half list (its neighbours j > i within the list radius) to `out`.
    /// Returns the number of pairs in the half lists.
    pub fn build(
        &mut self,
        slabs: &[u32],
        n: usize,
        half: impl Fn(usize, &mut Vec<u32>) + Sync,
    ) -> usize {
        self.runs.clear();
        self.awake.clear();
        self.start.clear();
        self.slabs.clear();
        for s in 0..slabs.len().saturating_sub(1) {
            self.slabs.push(self.start.len() as u32);
            let (a, b) = (slabs[s] as usize, slabs[s + 1] as usize);
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
        let parts: Vec<(Vec<u32>, Vec<u32>, usize)> = (0..nc.div_ceil(TASK))
            .into_par_iter()
            .map(|t| {
                let (mut counts, mut js, mut pairs) = (Vec::new(), Vec::new(), 0);
                let mut m: [Vec<u32>; WIDTH] = Default::default();
                let (mut row, mut a, mut b) = (Vec::new(), Vec::new(), Vec::new());
                for c in t * TASK..((t + 1) * TASK).min(nc) {
                    m.iter_mut().for_each(Vec::clear);
                    for (k, i) in (start[c]..start[c + 1]).enumerate() {
                        half(i as usize, &mut m[k]);
                        pairs += m[k].len();
                    }
                    if m.iter().all(|l| l.is_sorted()) {
                        // the lists of a cell-sorted family ascend (stencil rows in cell
                        // order): merge them pairwise
                        merge_union(&m[0], &m[1], &mut a);
                        merge_union(&m[2], &m[3], &mut b);
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
                (counts, js, pairs)
            })
            .collect();
        let total: usize = parts.iter().map(|p| p.1.len()).sum();
        self.off.clear();
        self.js.clear();
        if self.js.capacity() < total {
            // room for the lists to grow by a sixteenth before the next reallocation
            self.js.reserve_exact(total + total / 16);
        }
        self.off.reserve_exact(nc + 1);
        self.off.push(0);
        let mut pairs = 0;
        for (counts, js, p) in parts {
            let mut end = self.js.len() as u32;
            self.off.extend(counts.iter().map(|&k| {
                end += k;
                end
            }));
            self.js.extend_from_slice(&js);
            pairs += p;
        }
        pairs
    }

    /// Whether the clusters and their lists are those [`build`](Self::build) makes of
    /// `n` particles in the slabs `slabs`: clusters of at most [`WIDTH`] particles
    /// ascending to `n`, the slabs' first clusters and particles, each particle's
    /// cluster, and compressed rows of particle indices below `n`.
    pub fn fit(&self, slabs: &[u32], n: usize) -> bool {
        use crate::numerics::index_rows::{ascending, below, rows};
        let nc = self.len();
        let clusters = !self.start.is_empty()
            && self.start[0] == 0
            && self.particles() == n
            && self
                .start
                .windows(2)
                .all(|w| w[0] <= w[1] && w[1] - w[0] <= WIDTH as u32);
        if !clusters || self.slabs.len() != slabs.len() || !ascending(&self.slabs) {
            return false;
        }
        let slabs_fit = self.slabs.last().is_some_and(|&l| l as usize == nc)
            && self.particle_slabs.len() == self.slabs.len()
            && self
                .slabs
                .iter()
                .zip(&self.particle_slabs)
                .all(|(&c, &p)| self.start[c as usize] == p);
        slabs_fit
            && self.of.len() == n
            && self
                .of
                .iter()
                .enumerate()
                .all(|(i, &c)| (c as usize) < nc && self.members(c as usize).contains(&i))
            && rows(&self.off, nc, self.js.len())
            && below(&self.js, n)
    }

    /// How the passes take cluster `c`.
    #[inline(always)]
    pub fn take(&self, c: usize) -> Take {
        self.runs.get(c).copied().unwrap_or(Take::All)
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

    #[test]
    fn union_of_ascending_lists() {
        let mut out = Vec::new();
        merge_union(&[1, 4, 5, 9], &[2, 4, 9, 11, 12], &mut out);
        assert_eq!(out, [1, 2, 4, 5, 9, 11, 12]);
        merge_union(&[], &[3], &mut out);
        assert_eq!(out, [3]);
    }
}
