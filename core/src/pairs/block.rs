//! The geometry of one particle's same-family pairs (fine–fine, water–water), taken a block at a time ahead of
//! the pair terms.
//!
//! A pair term waits on a square root and a division. Inside the long loop body of a
//! sweep the processor overlaps little of that wait with the next pair; taken first,
//! for a block of neighbours in a short loop of independent iterations (two lanes at a
//! time), the square roots and divisions of the block overlap. The block keeps only
//! the pairs within the cut-off, so the sweep's loop has no distance test either.

use crate::math::{Real, Vect};
use crate::periodic::Separation;

/// Neighbours taken per block (a particle's half list holds about 12 in 2D and 50 in
/// 3D).
pub const BLOCK: usize = 32;

/// Pairs of particle i within the cut-off, from one block of its list.
pub struct PairBlock<const D: usize> {
    len: usize,
    j: [u32; BLOCK],
    rij: [Vect<D>; BLOCK],
    r2: [Real; BLOCK],
    r: [Real; BLOCK],
    q: [Real; BLOCK],
}

/// One pair of a [`PairBlock`].
#[derive(Clone, Copy)]
pub struct Pair<const D: usize> {
    pub j: usize,
    /// x_i − x_j.
    pub rij: Vect<D>,
    pub r: Real,
    /// 1/r.
    pub inv_r: Real,
    /// 1/(r (r² + reg)), the weight of Eq. (25) over r².
    pub inv: Real,
}

impl<const D: usize> Default for PairBlock<D> {
    fn default() -> Self {
        PairBlock {
            len: 0,
            j: [0; BLOCK],
            rij: [Vect::<D>::zeros(); BLOCK],
            r2: [0.0; BLOCK],
            r: [0.0; BLOCK],
            q: [0.0; BLOCK],
        }
    }
}

impl<const D: usize> PairBlock<D> {
    /// Take the pairs of `xi` with the particles `js` (at most [`BLOCK`]) closer than
    /// √`cut2`, separated as `sep` has it (minimum images across a periodic seam);
    /// `reg` is the 0.01h² of Eq. (25).
    #[inline(always)]
    pub fn fill(
        &mut self,
        (xi, js, pos): (&Vect<D>, &[u32], &[Vect<D>]),
        cut2: Real,
        reg: Real,
        sep: &impl Separation,
    ) {
        debug_assert!(js.len() <= BLOCK);
        let mut n = 0;
        for &j in js.iter().take(BLOCK) {
            let rij = sep.of(xi - pos[j as usize]);
            let r2 = rij.norm_squared();
            // written always, kept when within the cut-off (no branch to mispredict)
            self.j[n] = j;
            self.rij[n] = rij;
            self.r2[n] = r2;
            n += (r2 < cut2) as usize;
        }
        self.len = n;
        let (r2, r, q) = (&self.r2[..n], &mut self.r[..n], &mut self.q[..n]);
        for k in 0..n {
            r[k] = r2[k].sqrt();
            q[k] = 1.0 / (r2[k] * (r2[k] + reg));
        }
    }

    /// The pairs taken by the last [`fill`](Self::fill), in list order.
    #[inline(always)]
    pub fn pairs(&self, reg: Real) -> impl Iterator<Item = Pair<D>> + '_ {
        (0..self.len).map(move |k| {
            let (r2, r) = (self.r2[k], self.r[k]);
            let inv = r * self.q[k];
            Pair {
                j: self.j[k] as usize,
                rij: self.rij[k],
                r,
                inv_r: (r2 + reg) * inv,
                inv,
            }
        })
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use nalgebra::Vector2;

    #[test]
    fn keeps_the_pairs_within_the_cut_off() {
        let pos: Vec<Vect<2>> = (0..40)
            .map(|k| Vector2::new(0.1 * k as Real, 0.05))
            .collect();
        let js: Vec<u32> = (1..33).collect();
        let mut b = PairBlock::<2>::default();
        let reg = 1e-4;
        b.fill((&pos[0], &js, &pos), 1.0, reg, &crate::periodic::Open);
        let got: Vec<Pair<2>> = b.pairs(reg).collect();
        // r = 0.1 k < 1 for k = 1..9
        assert_eq!(
            got.iter().map(|p| p.j).collect::<Vec<_>>(),
            (1..10).collect::<Vec<_>>()
        );
        for p in &got {
            let r = 0.1 * p.j as Real;
            assert!((p.r - r).abs() < 1e-15);
            assert!((p.inv_r * r - 1.0).abs() < 1e-14);
            assert!((p.inv * r * (r * r + reg) - 1.0).abs() < 1e-14);
            assert!((p.rij[0] + r).abs() < 1e-15);
        }
    }
}
