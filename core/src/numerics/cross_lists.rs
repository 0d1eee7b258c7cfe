//! Neighbour lists between two families: for each particle of family A the particles
//! of family B within a radius, and the transpose (for each of B those of A), both in
//! compressed rows. Built in parallel, in a fixed order: the same lists on any number
//! of threads.

use crate::numerics::math::{Real, Vect};
use crate::numerics::neighbors::CellGrid;
use rayon::prelude::*;

/// Compressed rows: the neighbours of particle i are `idx[off[i]..off[i + 1]]`.
#[derive(Clone, Debug, Default)]
pub struct Rows {
    pub off: Vec<u32>,
    pub idx: Vec<u32>,
}

impl Rows {
    /// The neighbours of particle `i` (none past the rows).
    #[inline(always)]
    pub fn of(&self, i: usize) -> &[u32] {
        match (self.off.get(i), self.off.get(i + 1)) {
            (Some(&a), Some(&b)) => &self.idx[a as usize..b as usize],
            _ => &[],
        }
    }

    /// Number of rows.
    pub fn len(&self) -> usize {
        self.off.len().saturating_sub(1)
    }

    pub fn is_empty(&self) -> bool {
        self.len() == 0
    }

    /// Bytes held.
    pub fn bytes(&self) -> usize {
        (self.off.capacity() + self.idx.capacity()) * 4
    }
}

/// The lists of A against B and of B against A.
#[derive(Clone, Debug, Default)]
pub struct CrossLists {
    /// For each particle of A, its neighbours in B.
    pub a_to_b: Rows,
    /// For each particle of B, its neighbours in A.
    pub b_to_a: Rows,
}

impl CrossLists {
    /// Build the lists of the particles at `a` against those at `b` within `radius`;
    /// `grid` is binned here with `b` (its cells at least `radius` wide).
    pub fn build<const D: usize>(
        &mut self,
        a: &[Vect<D>],
        b: &[Vect<D>],
        grid: &mut CellGrid<D>,
        radius: Real,
    ) {
        grid.bin(b);
        let r2 = radius * radius;
        let grid = &*grid;
        let rows: Vec<Vec<u32>> = a
            .par_iter()
            .map(|x| {
                let mut near = Vec::new();
                grid.for_each_near(x, |j| {
                    if (x - b[j as usize]).norm_squared() < r2 {
                        near.push(j);
                    }
                });
                near.sort_unstable();
                near
            })
            .collect();
        let ab = &mut self.a_to_b;
        ab.off.clear();
        ab.idx.clear();
        ab.off.push(0);
        let mut count = vec![0u32; b.len() + 1];
        for r in &rows {
            ab.idx.extend_from_slice(r);
            ab.off.push(ab.idx.len() as u32);
            for &j in r {
                count[j as usize + 1] += 1;
            }
        }
        // the transpose, each row in ascending order of A
        for j in 0..b.len() {
            count[j + 1] += count[j];
        }
        let ba = &mut self.b_to_a;
        ba.off.clear();
        ba.off.extend_from_slice(&count);
        ba.idx.clear();
        ba.idx.resize(ab.idx.len(), 0);
        let mut fill = count;
        for (i, r) in rows.iter().enumerate() {
            for &j in r {
                let k = &mut fill[j as usize];
                ba.idx[*k as usize] = i as u32;
                *k += 1;
            }
        }
    }

    /// Bytes held.
    pub fn bytes(&self) -> usize {
        self.a_to_b.bytes() + self.b_to_a.bytes()
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use nalgebra::Vector2;

    /// The lists hold exactly the pairs within the radius, and each is the other's
    /// transpose.
    #[test]
    fn lists_match_brute_force_and_transpose() {
        let mut rng = crate::numerics::rng::Rng(7);
        let pts = |n: usize, rng: &mut crate::numerics::rng::Rng| -> Vec<Vect<2>> {
            (0..n)
                .map(|_| Vector2::new(rng.uniform(), rng.uniform()))
                .collect()
        };
        let (a, b) = (pts(300, &mut rng), pts(200, &mut rng));
        let radius = 0.08;
        let mut grid = CellGrid::new(&Vector2::zeros(), &Vector2::new(1.0, 1.0), radius);
        let mut l = CrossLists::default();
        l.build(&a, &b, &mut grid, radius);
        for (i, x) in a.iter().enumerate() {
            let want: Vec<u32> = (0..b.len() as u32)
                .filter(|&j| (x - b[j as usize]).norm() < radius)
                .collect();
            assert_eq!(l.a_to_b.of(i), &want[..]);
        }
        for (j, y) in b.iter().enumerate() {
            let want: Vec<u32> = (0..a.len() as u32)
                .filter(|&i| (a[i as usize] - y).norm() < radius)
                .collect();
            assert_eq!(l.b_to_a.of(j), &want[..]);
        }
    }
}
