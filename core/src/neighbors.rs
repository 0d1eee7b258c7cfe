//! Neighbour search: a cell-linked list over a fixed domain, particles re-sorted by
//! cell for memory locality, and Verlet lists with a skin stored per fixed-size chunk
//! of particles. Lists are built in parallel; every particle's list is in a fixed
//! order (stencil cell order, then index order), so results do not depend on the
//! number of threads.

use crate::math::{Real, Vect};
use rayon::prelude::*;

/// Particles per work chunk. Fixed, so chunking is independent of the thread count.
pub const CHUNK: usize = 256;

/// A uniform grid of cells over a fixed box; positions outside are clamped into the
/// border cells (correct, only slower).
#[derive(Clone, Debug, Default)]
pub struct CellGrid<const D: usize> {
    origin: [Real; 3],
    inv_cell: Real,
    dims: [usize; 3],
    /// `start[c]..start[c+1]` indexes `items` for cell c.
    start: Vec<u32>,
    items: Vec<u32>,
    cell_of: Vec<u32>,
    fill: Vec<u32>,
}

impl<const D: usize> CellGrid<D> {
    /// A grid with cells of size `cell` covering [lo, hi].
    pub fn new(lo: &Vect<D>, hi: &Vect<D>, cell: Real) -> Self {
        let mut origin = [0.0; 3];
        let mut dims = [1usize; 3];
        for k in 0..D {
            origin[k] = lo[k];
            dims[k] = (((hi[k] - lo[k]) / cell).ceil() as usize).max(1);
        }
        CellGrid {
            origin,
            inv_cell: 1.0 / cell,
            dims,
            ..Default::default()
        }
    }

    /// Bytes held by the grid.
    pub fn bytes(&self) -> usize {
        4 * (self.start.capacity()
            + self.items.capacity()
            + self.cell_of.capacity()
            + self.fill.capacity())
    }

    pub fn cell_count(&self) -> usize {
        self.dims[0] * self.dims[1] * self.dims[2]
    }

    #[inline(always)]
    fn coords(&self, x: &Vect<D>) -> [usize; 3] {
        let mut c = [0usize; 3];
        for k in 0..D {
            let f = ((x[k] - self.origin[k]) * self.inv_cell).floor();
            c[k] = if f <= 0.0 {
                0
            } else {
                (f as usize).min(self.dims[k] - 1)
            };
        }
        c
    }

    #[inline(always)]
    fn index(&self, c: [usize; 3]) -> usize {
        (c[2] * self.dims[1] + c[1]) * self.dims[0] + c[0]
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
    }

    /// Particle indices in cell order (valid after [`bin`](Self::bin)).
    pub fn order(&self) -> &[u32] {
        &self.items
    }

    /// Call `f(j)` for every binned particle in the 3^D cells around `x`.
    #[inline(always)]
    pub fn for_each_near(&self, x: &Vect<D>, mut f: impl FnMut(u32)) {
        let c = self.coords(x);
        let lo = |k: usize| if k < D { c[k].saturating_sub(1) } else { 0 };
        let hi = |k: usize| {
            if k < D {
                (c[k] + 1).min(self.dims[k] - 1)
            } else {
                0
            }
        };
        for z in lo(2)..=hi(2) {
            for y in lo(1)..=hi(1) {
                let row = self.index([0, y, z]);
                let a = self.start[row + lo(0)] as usize;
                let b = self.start[row + hi(0) + 1] as usize;
                for &j in &self.items[a..b] {
                    f(j);
                }
            }
        }
    }
}

/// Verlet lists of one chunk of particles: fine–fine, fine–wall and fine–coarse
/// neighbours.
#[derive(Clone, Debug, Default)]
pub struct ChunkList {
    /// `fine[off[k]..off[k+1]]` are the fine neighbours of particle `start + k`.
    pub off: Vec<u32>,
    pub fine: Vec<u32>,
    pub woff: Vec<u32>,
    pub wall: Vec<u32>,
    pub coff: Vec<u32>,
    pub coarse: Vec<u32>,
}

/// Binned positions of a second particle set (walls, coarse grains).
pub struct Binned<'a, const D: usize> {
    pub pos: &'a [Vect<D>],
    pub grid: &'a CellGrid<D>,
}

/// Neighbour lists of all fine particles within the list radius (cut-off + skin).
/// Make room for one more particle's neighbours (at most a few hundred) growing by an
/// eighth instead of doubling: the lists are the solver's largest arrays, and
/// doubling would leave up to half of them unused. Growth only happens while the
/// lists lengthen; a steady run reuses them without allocating.
#[inline]
fn headroom(v: &mut Vec<u32>) {
    const ROOM: usize = 512;
    if v.capacity() - v.len() < ROOM {
        v.reserve_exact((v.len() / 8).max(4 * ROOM));
    }
}

#[derive(Clone, Debug, Default)]
pub struct NeighborLists {
    pub chunks: Vec<ChunkList>,
    pub radius: Real,
    pub builds: usize,
}

impl NeighborLists {
    /// Build the lists from binned grids. `fine_grid` must have been binned on `pos`,
    /// `wall_grid` on `wall_pos`.
    pub fn build<const D: usize>(
        &mut self,
        pos: &[Vect<D>],
        fine_grid: &CellGrid<D>,
        walls: Binned<'_, D>,
        coarse: Binned<'_, D>,
        radius: Real,
    ) {
        let (wall_pos, wall_grid) = (walls.pos, walls.grid);
        let (coarse_pos, coarse_grid) = (coarse.pos, coarse.grid);
        self.radius = radius;
        self.builds += 1;
        let r2 = radius * radius;
        let nchunks = pos.len().div_ceil(CHUNK);
        self.chunks.resize_with(nchunks, ChunkList::default);
        self.chunks.par_iter_mut().enumerate().for_each(|(c, cl)| {
            let start = c * CHUNK;
            let end = (start + CHUNK).min(pos.len());
            cl.off.clear();
            cl.fine.clear();
            cl.woff.clear();
            cl.wall.clear();
            cl.coff.clear();
            cl.coarse.clear();
            cl.off.push(0);
            cl.woff.push(0);
            cl.coff.push(0);
            for i in start..end {
                let xi = pos[i];
                headroom(&mut cl.fine);
                headroom(&mut cl.wall);
                headroom(&mut cl.coarse);
                fine_grid.for_each_near(&xi, |j| {
                    if j as usize != i && (xi - pos[j as usize]).norm_squared() < r2 {
                        cl.fine.push(j);
                    }
                });
                cl.off.push(cl.fine.len() as u32);
                if !wall_pos.is_empty() {
                    wall_grid.for_each_near(&xi, |w| {
                        if (xi - wall_pos[w as usize]).norm_squared() < r2 {
                            cl.wall.push(w);
                        }
                    });
                }
                cl.woff.push(cl.wall.len() as u32);
                if !coarse_pos.is_empty() {
                    coarse_grid.for_each_near(&xi, |w| {
                        if (xi - coarse_pos[w as usize]).norm_squared() < r2 {
                            cl.coarse.push(w);
                        }
                    });
                }
                cl.coff.push(cl.coarse.len() as u32);
            }
        });
    }

    /// Bytes held by the lists.
    pub fn bytes(&self) -> usize {
        self.chunks
            .iter()
            .map(|c| {
                4 * (c.off.capacity()
                    + c.fine.capacity()
                    + c.woff.capacity()
                    + c.wall.capacity()
                    + c.coff.capacity()
                    + c.coarse.capacity())
            })
            .sum()
    }
}

#[cfg(test)]
mod tests {
    use super::*;

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
            pos.push(Vect::<3>::new(rnd(), rnd(), rnd() * 0.5));
        }
        let walls: Vec<Vect<3>> = (0..50)
            .map(|k| Vect::<3>::new(k as f64 / 50.0, 0.5, -0.05))
            .collect();
        let r = 0.13;
        let lo = Vect::<3>::new(0.0, 0.0, -0.1);
        let hi = Vect::<3>::new(1.0, 1.0, 0.5);
        let mut g = CellGrid::new(&lo, &hi, r);
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
        );
        for i in 0..pos.len() {
            let cl = &nl.chunks[i / CHUNK];
            let k = i % CHUNK;
            let mut got: Vec<u32> = cl.fine[cl.off[k] as usize..cl.off[k + 1] as usize].to_vec();
            got.sort();
            let want: Vec<u32> = (0..pos.len() as u32)
                .filter(|&j| j as usize != i && (pos[i] - pos[j as usize]).norm() < r)
                .collect();
            assert_eq!(got, want);
            let gotw = cl.woff[k + 1] - cl.woff[k];
            let wantw = walls.iter().filter(|w| (pos[i] - **w).norm() < r).count() as u32;
            assert_eq!(gotw, wantw);
        }
    }
}
