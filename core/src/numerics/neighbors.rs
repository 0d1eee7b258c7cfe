//! Neighbour search: a cell-linked list over a fixed domain, particles re-sorted by
//! cell for memory locality, and Verlet lists with a skin stored per fixed-size chunk
//! of particles. Lists are built in parallel; every particle's list is in a fixed
//! order (stencil cell order, then index order), so results do not depend on the
//! number of threads.
//!
//! Cells are numbered with one axis, the *slab axis* (the domain's longest), varying
//! slowest. After re-sorting, the particles of one layer of cells across that axis (a
//! slab, one list radius thick) are a contiguous index range, and a pair within the
//! list radius lies in one slab or two neighbouring ones. The fine–fine lists hold
//! each pair once, under its lower index (j > i), so a neighbour j of a particle i in
//! slab s lies in slab s or s + 1: the symmetric sweeps rely on this
//! ([`slabs`](crate::numerics::pairs::slabs)).

use crate::numerics::math::{Real, Vect};
use crate::numerics::pairs::clusters::ClusterPairs;
use crate::numerics::periodic::{Period, Separation};
use rayon::prelude::*;

/// Particles per work chunk. Fixed, so chunking is independent of the thread count.
pub const CHUNK: usize = 256;

/// Bytes a binned grid holds per cell: `start` and the scratch `fill`, one `u32` each
/// ([`CellGrid::bin`]); the memory estimate prices grids with it.
pub const BYTES_PER_CELL: usize = 8;

/// Most cells a grid may have: a cell index is a `u32`.
pub const MAX_CELLS: usize = u32::MAX as usize;

/// A uniform grid of cells over a fixed box; positions outside are clamped into the
/// border cells (correct, only slower). Along a periodic axis the cells tile the
/// period, positions are taken modulo the period and the stencil wraps
/// ([`periodic`](crate::numerics::periodic)).
#[derive(Clone, Debug, Default, serde::Serialize, serde::Deserialize)]
pub struct CellGrid<const D: usize> {
    origin: [Real; 3],
    /// 1 / cell size per axis (the periodic axis' cells are stretched to tile the
    /// period).
    inv_cell: [Real; 3],
    dims: [usize; 3],
    /// Axes from the slowest varying in the cell index to the fastest: the slab axis
    /// first, the longest other axis last (so a stencil row is three adjacent cells).
    axes: [usize; 3],
    /// The periodic axis, if any (never the slab axis).
    wrap: Option<usize>,
    /// `start[c]..start[c+1]` indexes `items` for cell c.
    start: Vec<u32>,
    items: Vec<u32>,
    /// Whether `items` is the identity (the positions were binned already in cell
    /// order): a stencil row's particles are then a contiguous index range.
    #[serde(default)]
    sorted: bool,
    /// Scratch of [`CellGrid::bin`] (refilled there before it is read).
    #[serde(skip)]
    cell_of: Vec<u32>,
    #[serde(skip)]
    fill: Vec<u32>,
}

impl<const D: usize> CellGrid<D> {
    /// A grid with cells of size `cell` covering [lo, hi].
    pub fn new(lo: &Vect<D>, hi: &Vect<D>, cell: Real) -> Self {
        Self::periodic(lo, hi, cell, None)
    }

    /// A grid with cells of at least `cell` covering [lo, hi], and along the axis of
    /// `period` (if any) exactly the period, with at least three cells across it.
    pub fn periodic(lo: &Vect<D>, hi: &Vect<D>, cell: Real, period: Option<Period>) -> Self {
        let mut origin = [0.0; 3];
        let mut dims = [1usize; 3];
        let mut inv_cell = [1.0 / cell; 3];
        for k in 0..D {
            origin[k] = lo[k];
            dims[k] = (((hi[k] - lo[k]) / cell).ceil() as usize).max(1);
        }
        let wrap = period.map(|p| {
            let a = p.axis;
            origin[a] = p.lo;
            dims[a] = ((p.len / cell).floor() as usize).max(1);
            // three distinct cells in every wrapped stencil (the scene checks the period)
            assert!(
                dims[a] >= 3,
                "period {} under three list radii {cell}",
                p.len
            );
            inv_cell[a] = dims[a] as Real / p.len;
            a
        });
        // longest axis first (ties: the lower axis), the periodic axis never first, then
        // the longer of the others last; in 2D the unused third axis (one cell) sits in
        // the middle
        let mut by_len: Vec<usize> = (0..D).collect();
        by_len.sort_by(|&a, &b| {
            (wrap == Some(a))
                .cmp(&(wrap == Some(b)))
                .then(dims[b].cmp(&dims[a]))
                .then(a.cmp(&b))
        });
        let axes = if D == 3 {
            [by_len[0], by_len[2], by_len[1]]
        } else {
            [by_len[0], 2, by_len.get(1).copied().unwrap_or(1)]
        };
        CellGrid {
            origin,
            inv_cell,
            dims,
            axes,
            wrap,
            ..Default::default()
        }
    }

    /// Number of slabs: cells along the slab axis.
    pub fn slab_count(&self) -> usize {
        self.dims[self.axes[0]]
    }

    /// `out[s]..out[s+1]` is the range, in cell order, of the particles binned in slab
    /// s (valid after [`bin`](Self::bin)).
    pub fn slab_starts(&self, out: &mut Vec<u32>) {
        let per_slab = self.dims[self.axes[1]] * self.dims[self.axes[2]];
        out.clear();
        out.extend((0..=self.slab_count()).map(|s| self.start[s * per_slab]));
    }

    /// Bytes held by the grid.
    pub fn bytes(&self) -> usize {
        4 * (self.start.capacity()
            + self.items.capacity()
            + self.cell_of.capacity()
            + self.fill.capacity())
    }

    /// Whether `other` has this grid's geometry (origin, cells, axis order, periodic
    /// axis), bit for bit: a restored grid against the one the scene builds.
    pub fn same_geometry(&self, other: &Self) -> bool {
        let bits = |v: &[Real; 3]| v.map(Real::to_bits);
        bits(&self.origin) == bits(&other.origin)
            && bits(&self.inv_cell) == bits(&other.inv_cell)
            && self.dims == other.dims
            && self.axes == other.axes
            && self.wrap == other.wrap
    }

    /// Whether the binned contents are consistent for `n` binned items: none (never
    /// binned or released), or one start per cell and one more, ascending to the item
    /// count, every item below `n`, and `sorted` only where the items are the identity.
    pub fn contents_fit(&self, n: usize) -> bool {
        use crate::numerics::index_rows::{below, rows};
        if self.start.is_empty() {
            return self.items.is_empty() && !self.sorted;
        }
        rows(&self.start, self.cell_count(), self.items.len())
            && self.items.len() == n
            && below(&self.items, n)
            && (!self.sorted || self.items.iter().enumerate().all(|(k, &i)| i as usize == k))
    }

    pub fn cell_count(&self) -> usize {
        self.dims[0] * self.dims[1] * self.dims[2]
    }

    #[inline(always)]
    fn coords(&self, x: &Vect<D>) -> [usize; 3] {
        let mut c = [0usize; 3];
        for k in 0..D {
            let f = ((x[k] - self.origin[k]) * self.inv_cell[k]).floor();
            c[k] = if self.wrap == Some(k) {
                (f as i64).rem_euclid(self.dims[k] as i64) as usize
            } else if f <= 0.0 {
                0
            } else {
                (f as usize).min(self.dims[k] - 1)
            };
        }
        c
    }

    #[inline(always)]
    fn index(&self, c: [usize; 3]) -> usize {
        let [a, b, f] = self.axes;
        (c[a] * self.dims[b] + c[b]) * self.dims[f] + c[f]
    }

    /// Bin `pos` by cell (counting sort). Afterwards `order()` lists particles cell by cell.
    pub fn bin(&mut self, pos: &[Vect<D>]) {
        let n = pos.len();
        let nc = self.cell_count();
        let mut cell_of = std::mem::take(&mut self.cell_of);
        cell_of.clear();
        cell_of.par_extend(pos.par_iter().map(|x| self.index(self.coords(x)) as u32));
        self.cell_of = cell_of;
        self.start.clear();
        self.start.resize(nc + 1, 0);
        for &c in &self.cell_of {
            self.start[c as usize + 1] += 1;
        }
        for c in 0..nc {
            self.start[c + 1] += self.start[c];
        }
        self.items.clear();
        self.items.resize(n, 0);
        self.fill.clear();
        self.fill.extend_from_slice(&self.start);
        for (i, &c) in self.cell_of.iter().enumerate() {
            let slot = &mut self.fill[c as usize];
            self.items[*slot as usize] = i as u32;
            *slot += 1;
        }
        self.sorted = self.cell_of.windows(2).all(|w| w[0] <= w[1]);
    }

    /// Free the binned arrays, keeping the geometry: the grid holds no particles and
    /// no cells until it is binned again (looking anything up in it before then is a
    /// bug).
    pub fn release(&mut self) {
        for v in [
            &mut self.start,
            &mut self.items,
            &mut self.cell_of,
            &mut self.fill,
        ] {
            *v = Vec::new();
        }
        self.sorted = false;
    }

    /// Particle indices in cell order (valid after [`bin`](Self::bin)).
    pub fn order(&self) -> &[u32] {
        &self.items
    }

    /// Call `f(j)` for every binned particle in the 3^D cells around `x`.
    #[inline(always)]
    pub fn for_each_near(&self, x: &Vect<D>, mut f: impl FnMut(u32)) {
        self.stencil(x, false, |a, b| {
            for &j in &self.items[a..b] {
                f(j);
            }
        })
    }

    /// Call `f(a, b)` for each run `order()[a..b]` of binned particles around `x`, in
    /// the stencil's order: a row of adjacent cells (only the cells from the cell of
    /// `x` on, in cell order, if `forward`), or one cell of a periodic grid.
    #[inline(always)]
    fn stencil(&self, x: &Vect<D>, forward: bool, mut f: impl FnMut(usize, usize)) {
        if self.wrap.is_some() {
            return self.wrapped_stencil(x, f);
        }
        let c = self.coords(x);
        let [a0, a1, a2] = self.axes;
        let lo = |k: usize| if k < D { c[k].saturating_sub(1) } else { 0 };
        let hi = |k: usize| {
            if k < D {
                (c[k] + 1).min(self.dims[k] - 1)
            } else {
                0
            }
        };
        let own = self.index(c);
        for s in lo(a0)..=hi(a0) {
            for m in lo(a1)..=hi(a1) {
                let mut cc = [0usize; 3];
                cc[a0] = s;
                cc[a1] = m;
                let row = self.index(cc);
                let (mut first, last) = (row + lo(a2), row + hi(a2));
                if forward {
                    if last < own {
                        continue;
                    }
                    first = first.max(own);
                }
                let a = self.start[first] as usize;
                let b = self.start[last + 1] as usize;
                if a < b {
                    f(a, b);
                }
            }
        }
    }

    /// The stencil of a periodic grid: every one of the 3^D cells around `x`, the
    /// periodic axis' neighbours taken modulo the period (the forward half is not
    /// contiguous across the seam, so the lists filter j > i themselves).
    fn wrapped_stencil(&self, x: &Vect<D>, mut f: impl FnMut(usize, usize)) {
        let c = self.coords(x);
        // the cells along axis k around c[k]: (cells, count)
        let around = |k: usize| -> ([usize; 3], usize) {
            if k >= D {
                ([0; 3], 1)
            } else if self.wrap == Some(k) {
                let n = self.dims[k];
                ([(c[k] + n - 1) % n, c[k], (c[k] + 1) % n], 3)
            } else {
                let (lo, hi) = (c[k].saturating_sub(1), (c[k] + 1).min(self.dims[k] - 1));
                let mut out = [0; 3];
                for (m, v) in (lo..=hi).enumerate() {
                    out[m] = v;
                }
                (out, hi - lo + 1)
            }
        };
        let [a0, a1, a2] = self.axes;
        let (s0, n0) = around(a0);
        let (s1, n1) = around(a1);
        let (s2, n2) = around(a2);
        for &p in &s0[..n0] {
            for &q in &s1[..n1] {
                for &r in &s2[..n2] {
                    let mut cc = [0usize; 3];
                    cc[a0] = p;
                    cc[a1] = q;
                    cc[a2] = r;
                    let k = self.index(cc);
                    let (a, b) = (self.start[k] as usize, self.start[k + 1] as usize);
                    if a < b {
                        f(a, b);
                    }
                }
            }
        }
    }

    /// Append to `out`, in stencil order, the binned particles j around `x` whose
    /// separation from `x` is shorter than the square root of `r2` (`pos`: the binned
    /// positions), only those with j > `above` if it is given (with the grid sorted by
    /// cell, only the stencil's forward half is searched then). Where the positions were
    /// binned in cell order, a stencil row's candidates are read as one index range,
    /// without the indirection through [`order`](Self::order); the lists are the same.
    #[inline(always)]
    pub fn collect_near(
        &self,
        x: &Vect<D>,
        pos: &[Vect<D>],
        r2: Real,
        above: Option<usize>,
        sep: &impl Separation,
        out: &mut Vec<u32>,
    ) {
        let forward = above.is_some() && self.wrap.is_none();
        let above = above.map_or(0, |i| i + 1);
        let contiguous = self.sorted && self.items.len() == pos.len();
        self.stencil(x, forward, |a, b| {
            if contiguous {
                // the row's particles are the index range a..b itself
                let a = a.max(above).min(b);
                for (k, y) in pos[a..b].iter().enumerate() {
                    if sep.of(x - y).norm_squared() < r2 {
                        out.push((a + k) as u32);
                    }
                }
            } else {
                for &j in &self.items[a..b] {
                    if j as usize >= above && sep.of(x - pos[j as usize]).norm_squared() < r2 {
                        out.push(j);
                    }
                }
            }
        })
    }
}

/// Serialise a [`CellGrid`] as its geometry only (origin, cell size, dimensions, axis
/// order), for grids that are binned afresh before every read: they come back empty.
pub mod geometry_only {
    use super::CellGrid;
    use crate::numerics::math::Real;
    use serde::{Deserialize, Deserializer, Serialize, Serializer};

    type Geometry = ([Real; 3], [Real; 3], [usize; 3], [usize; 3], Option<usize>);

    pub fn serialize<S: Serializer, const D: usize>(
        g: &CellGrid<D>,
        s: S,
    ) -> Result<S::Ok, S::Error> {
        (g.origin, g.inv_cell, g.dims, g.axes, g.wrap).serialize(s)
    }

    pub fn deserialize<'de, De: Deserializer<'de>, const D: usize>(
        d: De,
    ) -> Result<CellGrid<D>, De::Error> {
        let (origin, inv_cell, dims, axes, wrap) = Geometry::deserialize(d)?;
        Ok(CellGrid {
            origin,
            inv_cell,
            dims,
            axes,
            wrap,
            ..Default::default()
        })
    }
}

/// Verlet lists of one chunk of particles, fused: a family's relations with the walls
/// (fine–wall or water–wall) and the coarse grains (fine–coarse or water–coarse) are
/// stored side by side so that a pass reads a particle's record once. Each relation is
/// read through its own accessor; the inner relation (fine–fine or water–water) is
/// kept as cluster lists only ([`NeighborLists::clusters`]).
#[derive(Clone, Debug, Default, serde::Serialize, serde::Deserialize)]
pub struct ChunkList {
    pub wall_off: Vec<u32>,
    pub wall: Vec<u32>,
    pub coarse_off: Vec<u32>,
    pub coarse: Vec<u32>,
}

impl ChunkList {
    /// Whether the chunk's rows are those of `len` particles, with wall indices below
    /// `walls` and coarse indices below `coarse`.
    pub fn fits(&self, len: usize, walls: usize, coarse: usize) -> bool {
        use crate::numerics::index_rows::{below, rows};
        rows(&self.wall_off, len, self.wall.len())
            && rows(&self.coarse_off, len, self.coarse.len())
            && below(&self.wall, walls)
            && below(&self.coarse, coarse)
    }

    /// The wall relation: the wall particles near the chunk's k-th particle.
    #[inline(always)]
    pub fn wall(&self, k: usize) -> &[u32] {
        &self.wall[self.wall_off[k] as usize..self.wall_off[k + 1] as usize]
    }

    /// The coarse relation: the coarse particles near the chunk's k-th particle.
    #[inline(always)]
    pub fn coarse(&self, k: usize) -> &[u32] {
        &self.coarse[self.coarse_off[k] as usize..self.coarse_off[k + 1] as usize]
    }
}

/// Binned positions of a second particle set (walls, coarse grains).
pub struct Binned<'a, const D: usize> {
    pub pos: &'a [Vect<D>],
    pub grid: &'a CellGrid<D>,
}

/// Neighbour lists of all fine particles within the list radius (cut-off + skin).
#[derive(Clone, Debug, Default, serde::Serialize, serde::Deserialize)]
pub struct NeighborLists {
    pub chunks: Vec<ChunkList>,
    /// The inner relation: the family's clusters of four and, for each, the union of
    /// its members' half lists (each pair once, under its lower index). The half lists
    /// themselves are not kept: a cluster's list holds them in about a quarter of the
    /// memory.
    pub clusters: ClusterPairs,
    /// Pairs in the half lists (summary.json `relations`).
    inner_pairs: usize,
    /// `slabs[s]..slabs[s+1]`: the particles of slab s (see the module notes).
    pub slabs: Vec<u32>,
    pub radius: Real,
    pub builds: usize,
}

impl NeighborLists {
    /// Build the lists from binned grids. `fine_grid` must have been binned on `pos`,
    /// `wall_grid` on `wall_pos`; `sep` gives the pair separations (minimum images
    /// across a periodic seam).
    pub fn build<const D: usize>(
        &mut self,
        pos: &[Vect<D>],
        fine_grid: &CellGrid<D>,
        walls: Binned<'_, D>,
        coarse: Binned<'_, D>,
        radius: Real,
        sep: &impl Separation,
    ) {
        let (wall_pos, wall_grid) = (walls.pos, walls.grid);
        let (coarse_pos, coarse_grid) = (coarse.pos, coarse.grid);
        self.radius = radius;
        self.builds += 1;
        fine_grid.slab_starts(&mut self.slabs);
        let r2 = radius * radius;
        let nchunks = pos.len().div_ceil(CHUNK);
        self.chunks.resize_with(nchunks, ChunkList::default);
        self.chunks.par_iter_mut().enumerate().for_each(|(c, cl)| {
            let start = c * CHUNK;
            let end = (start + CHUNK).min(pos.len());
            cl.wall_off.clear();
            cl.wall.clear();
            cl.coarse_off.clear();
            cl.coarse.clear();
            cl.wall_off.reserve_exact(end - start + 1);
            cl.coarse_off.reserve_exact(end - start + 1);
            cl.wall_off.push(0);
            cl.coarse_off.push(0);
            for xi in &pos[start..end] {
                if !wall_pos.is_empty() {
                    wall_grid.collect_near(xi, wall_pos, r2, None, sep, &mut cl.wall);
                }
                cl.wall_off.push(cl.wall.len() as u32);
                if !coarse_pos.is_empty() {
                    coarse_grid.collect_near(xi, coarse_pos, r2, None, sep, &mut cl.coarse);
                }
                cl.coarse_off.push(cl.coarse.len() as u32);
            }
        });
        self.inner_pairs = self.clusters.build(&self.slabs, pos.len(), |i, out| {
            fine_grid.collect_near(&pos[i], pos, r2, Some(i), sep, out)
        });
    }

    /// Whether the lists are those of `n` particles (as [`build`](Self::build) makes
    /// them): a chunk per [`CHUNK`] particles, each fitting its walls' and coarse
    /// particles' counts, slabs ascending to `n`, and the cluster lists of `n`.
    pub fn fit(&self, n: usize, walls: usize, coarse: usize) -> bool {
        let chunks = n.div_ceil(CHUNK);
        self.chunks.len() == chunks
            && self.chunks.iter().enumerate().all(|(c, cl)| {
                let len = CHUNK.min(n - c * CHUNK);
                cl.fits(len, walls, coarse)
            })
            && self.slabs.first() == Some(&0)
            && self.slabs.last().is_some_and(|&l| l as usize == n)
            && crate::numerics::index_rows::ascending(&self.slabs)
            && self.clusters.fit(&self.slabs, n)
    }

    /// Pairs held by each of the fused relations: inner, wall and coarse.
    pub fn pairs(&self) -> [usize; 3] {
        self.chunks
            .iter()
            .fold([self.inner_pairs, 0, 0], |[i, w, c], cl| {
                [i, w + cl.wall.len(), c + cl.coarse.len()]
            })
    }

    /// Bytes held by the lists.
    pub fn bytes(&self) -> usize {
        self.chunks
            .iter()
            .map(|c| {
                4 * (c.wall_off.capacity()
                    + c.wall.capacity()
                    + c.coarse_off.capacity()
                    + c.coarse.capacity())
            })
            .sum::<usize>()
            + 4 * self.slabs.capacity()
            + self.clusters.bytes()
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::numerics::pairs::quad::WIDTH;
    use crate::numerics::periodic::Open;
    use crate::numerics::rng::Rng;
    use nalgebra::Vector2;

    /// Particle i's half list as the cluster lists hold it: the entries j > i of its
    /// cluster's list within `r`; every entry of the cluster's list lies within `r` of
    /// a member below it.
    fn half_list<const D: usize>(
        nl: &NeighborLists,
        pos: &[Vect<D>],
        i: usize,
        r: Real,
        sep: &impl Separation,
    ) -> Vec<u32> {
        let (cp, near) = (&nl.clusters, |a: usize, b: usize| {
            sep.of(pos[a] - pos[b]).norm() < r
        });
        let ci = cp.of[i] as usize;
        for &j in cp.of(ci) {
            let j = j as usize;
            assert!(
                cp.members(ci).any(|m| m < j && near(m, j)),
                "{j} in {ci}'s list"
            );
        }
        let js = cp.of(ci).iter().copied();
        js.filter(|&j| j as usize > i && near(i, j as usize))
            .collect()
    }

    #[test]
    fn lists_match_brute_force() {
        let mut pos = Vec::new();
        let mut s = 12345u64;
        let mut rnd = || {
            s = s
                .wrapping_mul(6364136223846793005)
                .wrapping_add(1442695040888963407);
            (s >> 11) as f64 / (1u64 << 53) as f64
        };
        for _ in 0..700 {
            pos.push(Vect::<3>::new(rnd(), rnd() * 1.4, rnd() * 0.5));
        }
        let walls: Vec<Vect<3>> = (0..50)
            .map(|k| Vect::<3>::new(k as f64 / 50.0, 0.5, -0.05))
            .collect();
        let r = 0.13;
        let lo = Vect::<3>::new(0.0, 0.0, -0.1);
        let hi = Vect::<3>::new(1.0, 1.4, 0.5);
        let mut g = CellGrid::new(&lo, &hi, r);
        // slab axis: the longest (y), then z, x fastest (the longer of the others)
        assert_eq!(g.axes, [1, 2, 0]);
        // sorted by cell, as the stepper keeps them
        g.bin(&pos);
        let pos: Vec<Vect<3>> = g.order().iter().map(|&i| pos[i as usize]).collect();
        g.bin(&pos);
        let mut gw = CellGrid::new(&lo, &hi, r);
        gw.bin(&walls);
        let mut nl = NeighborLists::default();
        let gc = CellGrid::new(&lo, &hi, r);
        nl.build(
            &pos,
            &g,
            Binned {
                pos: &walls,
                grid: &gw,
            },
            Binned {
                pos: &[],
                grid: &gc,
            },
            r,
            &crate::numerics::periodic::Open,
        );
        assert_eq!(nl.slabs.len(), g.slab_count() + 1);
        assert_eq!(*nl.slabs.last().unwrap() as usize, pos.len());
        let slab = |i: usize| nl.slabs.partition_point(|&b| b as usize <= i) - 1;
        // the relations' pair counts (summary.json `relations`)
        let (n, pos, walls) = (pos.len(), &pos, &walls);
        let inner = (0..n)
            .flat_map(|i| (i + 1..n).map(move |j| (i, j)))
            .filter(|&(i, j)| (pos[i] - pos[j]).norm() < r)
            .count();
        let wall = (0..n)
            .flat_map(|i| walls.iter().map(move |w| (pos[i] - w).norm()))
            .filter(|&d| d < r)
            .count();
        assert_eq!(nl.pairs(), [inner, wall, 0]);
        for i in 0..pos.len() {
            let (cl, k) = (&nl.chunks[i / CHUNK], i % CHUNK);
            let got = half_list(&nl, pos, i, r, &crate::numerics::periodic::Open);
            let want: Vec<u32> = (i as u32 + 1..pos.len() as u32)
                .filter(|&j| (pos[i] - pos[j as usize]).norm() < r)
                .collect();
            assert_eq!(got, want);
            // a neighbour lies in the particle's slab or the next
            for &j in &got {
                let (si, sj) = (slab(i), slab(j as usize));
                assert!(sj == si || sj == si + 1, "pair {i}-{j} in slabs {si}, {sj}");
            }
            let gotw = cl.wall(k).len() as u32;
            let wantw = walls.iter().filter(|w| (pos[i] - **w).norm() < r).count() as u32;
            assert_eq!(gotw, wantw);
        }
    }

    /// Across a periodic seam the lists hold the minimum-image pairs, each once, and a
    /// neighbour still lies in its particle's slab or the next.
    #[test]
    fn periodic_lists_match_brute_force_minimum_image() {
        use crate::numerics::periodic::{Period, Separation, Wrap};
        let mut s = 777u64;
        let mut rnd = || {
            s = s
                .wrapping_mul(6364136223846793005)
                .wrapping_add(1442695040888963407);
            (s >> 11) as f64 / (1u64 << 53) as f64
        };
        // periodic along x (the longest axis, so the slab axis must become y)
        let wrap: Wrap = Some(Period {
            axis: 0,
            lo: 0.0,
            len: 1.0,
        });
        let mut pos: Vec<Vect<2>> = (0..900)
            .map(|_| Vect::<2>::new(rnd() * 1.02 - 0.01, rnd() * 0.6))
            .collect();
        let walls: Vec<Vect<2>> = (0..40)
            .map(|k| Vect::<2>::new(0.0125 + k as f64 / 40.0, -0.02))
            .collect();
        let r = 0.13;
        let (lo, hi) = (Vect::<2>::new(-0.2, -0.1), Vect::<2>::new(1.2, 0.7));
        let mut g = CellGrid::periodic(&lo, &hi, r, wrap);
        assert_eq!(g.axes, [1, 2, 0]);
        assert_eq!(g.dims[0], 7);
        g.bin(&pos);
        pos = g.order().iter().map(|&i| pos[i as usize]).collect();
        g.bin(&pos);
        let mut gw = CellGrid::periodic(&lo, &hi, r, wrap);
        gw.bin(&walls);
        let gc = CellGrid::periodic(&lo, &hi, r, wrap);
        let mut nl = NeighborLists::default();
        let binned = |p, g| Binned { pos: p, grid: g };
        nl.build(&pos, &g, binned(&walls, &gw), binned(&[], &gc), r, &wrap);
        let slab = |i: usize| nl.slabs.partition_point(|&b| b as usize <= i) - 1;
        let mut across = 0;
        for i in 0..pos.len() {
            let (cl, k) = (&nl.chunks[i / CHUNK], i % CHUNK);
            let got = half_list(&nl, &pos, i, r, &wrap);
            let want: Vec<u32> = (i as u32 + 1..pos.len() as u32)
                .filter(|&j| wrap.of(pos[i] - pos[j as usize]).norm() < r)
                .collect();
            assert_eq!(got, want, "particle {i}");
            across += want
                .iter()
                .filter(|&&j| (pos[i] - pos[j as usize]).norm() >= r)
                .count();
            for &j in &got {
                let (si, sj) = (slab(i), slab(j as usize));
                assert!(sj == si || sj == si + 1, "pair {i}-{j} in slabs {si}, {sj}");
            }
            let gotw = cl.wall(k).len() as u32;
            let wantw = walls
                .iter()
                .filter(|w| wrap.of(pos[i] - **w).norm() < r)
                .count();
            assert_eq!(gotw as usize, wantw);
        }
        assert!(across > 50, "only {across} pairs across the seam");
    }

    #[test]
    fn two_dimensional_grid_orders_the_long_axis_first() {
        let g = CellGrid::<2>::new(&Vect::<2>::new(0.0, 0.0), &Vect::<2>::new(0.3, 1.0), 0.1);
        assert_eq!(g.axes, [1, 2, 0]);
        assert_eq!(g.slab_count(), 10);
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
        let cp = &nl.clusters;
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
            for j in (i + 1..pos.len()).filter(|&j| (pos[i] - pos[j]).norm() < 0.026) {
                assert!(cp.of(ci).contains(&(j as u32)), "pair {i}-{j}");
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
