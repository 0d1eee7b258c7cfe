//! A periodic boundary along one axis: the domain repeats with period L between two
//! planes, and particles leaving through one re-enter through the other (Poiseuille
//! flow between plates, seed 001 §2.1, "periodic in x").
//!
//! Pairs across the seam use the minimum image of x_i − x_j ([`Separation`]); the
//! neighbour grid wraps its stencil along the axis
//! ([`CellGrid`](crate::numerics::neighbors::CellGrid)); the positions are wrapped back into
//! [lo, lo + L) when the lists are rebuilt, and between builds they stray at most a
//! skin beyond, which the minimum image absorbs. The periodic axis is never the
//! grid's slab axis, so the two-phase schedule of [`slabs`](crate::numerics::pairs::slabs) holds across
//! the seam.

use crate::numerics::math::{Real, Vect};

/// Periodic along `axis` with period `len`, the image of the domain starting at `lo`.
#[derive(Clone, Copy, Debug, PartialEq, serde::Serialize, serde::Deserialize)]
pub struct Period {
    pub axis: usize,
    pub lo: Real,
    pub len: Real,
}

impl Period {
    /// `x` moved by whole periods into [lo, lo + L).
    #[inline]
    pub fn wrap_point<const D: usize>(&self, x: &mut Vect<D>) {
        let a = self.axis;
        let s = ((x[a] - self.lo) / self.len).floor();
        if s != 0.0 {
            x[a] -= s * self.len;
            // round-off of the subtraction can land exactly on lo + L
            if x[a] >= self.lo + self.len {
                x[a] -= self.len;
            }
        }
    }
}

/// x_i − x_j as the pair terms see it: the plain difference, or its minimum image
/// across a periodic seam.
pub trait Separation: Sync {
    fn of<const D: usize>(&self, rij: Vect<D>) -> Vect<D>;
}

/// No periodic axis: the plain difference.
#[derive(Clone, Copy, Debug, Default)]
pub struct Open;

impl Separation for Open {
    #[inline(always)]
    fn of<const D: usize>(&self, rij: Vect<D>) -> Vect<D> {
        rij
    }
}

/// A periodic axis or none.
pub type Wrap = Option<Period>;

impl Separation for Period {
    /// Positions lie within a skin of [lo, lo + L), so one period at most separates
    /// a pair from its minimum image.
    #[inline(always)]
    fn of<const D: usize>(&self, mut rij: Vect<D>) -> Vect<D> {
        let (a, half) = (self.axis, 0.5 * self.len);
        if rij[a] > half {
            rij[a] -= self.len;
        } else if rij[a] < -half {
            rij[a] += self.len;
        }
        rij
    }
}

impl Separation for Wrap {
    #[inline(always)]
    fn of<const D: usize>(&self, rij: Vect<D>) -> Vect<D> {
        match self {
            Some(p) => p.of(rij),
            None => rij,
        }
    }
}

/// The gravity of a hydrostatic state: `g` without its component along the periodic
/// axis `axis`, where a body force drives a flow and builds no pressure gradient (seed
/// 001 §2.1). The water's hydrostatic start, its sound speed, wall pressure and
/// potential energy use it.
pub fn hydrostatic<const D: usize>(g: Vect<D>, axis: Option<usize>) -> Vect<D> {
    let mut h = g;
    if let Some(a) = axis {
        h[a] = 0.0;
    }
    h
}

/// Index of axis name `x`, `y` or `z`.
pub fn axis_index(name: &str) -> Option<usize> {
    match name {
        "x" => Some(0),
        "y" => Some(1),
        "z" => Some(2),
        _ => None,
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use nalgebra::Vector2;

    #[test]
    fn minimum_image_and_wrapping() {
        let p = Period {
            axis: 0,
            lo: 0.0,
            len: 0.1,
        };
        let w: Wrap = Some(p);
        let r = w.of(Vector2::new(0.095, 0.01));
        assert!((r[0] + 0.005).abs() < 1e-15 && r[1] == 0.01);
        let r = w.of(Vector2::new(-0.097, 0.0));
        assert!((r[0] - 0.003).abs() < 1e-15);
        assert_eq!(Open.of(Vector2::new(0.095, 0.0))[0], 0.095);
        for (x, want) in [
            (0.1025, 0.0025),
            (-0.0025, 0.0975),
            (0.05, 0.05),
            (0.1, 0.0),
        ] {
            let mut v = Vector2::new(x, 1.0);
            p.wrap_point(&mut v);
            assert!((v[0] - want).abs() < 1e-15, "{x} → {}", v[0]);
            assert!(v[0] >= 0.0 && v[0] < 0.1);
        }
    }
}
