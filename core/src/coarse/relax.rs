//! Level-set particle relaxation of coarse-grain bodies (the pre-processing seed 000
//! §5.2 applies to its balls, ref. [40]).
//!
//! A lattice cut by a curved or slanted surface leaves its outermost particles anywhere
//! from 0 to one spacing inside the surface, so the body that fine grains and contacts
//! see is ragged and, on average, smaller than the shape. Relaxation moves the
//! particles, keeping their number, until they are evenly spaced and the outer layer
//! lies half a spacing inside the surface everywhere.
//!
//! The sweeps are [`packing`](crate::numerics::packing)'s. Particles within the kernel support of
//! the surface also see the mirror images of their neighbours (and of themselves)
//! across the surface, which stands in for the missing material outside, so a particle
//! half a spacing inside is in balance.

use crate::geometry::Shape;
use crate::numerics::math::{Real, Vect};
use crate::numerics::packing::{Packing, SWEEPS};

/// Bodies with fewer particles than this (2D, 3D) are left as lattices: with hardly
/// any interior, relaxation would spread them over the surface and open gaps.
pub const MIN_PARTICLES: [usize; 2] = [30, 100];

/// Relax `pts` (lattice points inside `shape`) in place.
pub fn relax<const D: usize>(shape: &Shape<D>, pts: &mut [Vect<D>], dp: Real) {
    if matches!(shape, Shape::Box { .. }) || pts.len() < MIN_PARTICLES[D - 2] {
        // a centred lattice already puts every face half a spacing inside
        return;
    }
    let packing = Packing::new(dp, D);
    let cut = packing.cutoff();
    let eps = 1e-3 * dp;
    let mut images: Vec<Vect<D>> = Vec::with_capacity(pts.len());
    for sweep in 0..SWEEPS {
        // mirror images across the surface of particles near it
        images.clear();
        for p in pts.iter() {
            let s = shape.sdf(p);
            if s > -cut {
                let nrm = shape.normal(p, eps);
                images.push(p - nrm * (2.0 * s));
            }
        }
        let force = packing.forces(pts, &images);
        for (p, f) in pts.iter_mut().zip(&force) {
            *p += packing.step((sweep, SWEEPS), f);
            // never closer than 0.4 dp to the surface
            let s = shape.sdf(p);
            if s > -0.4 * dp {
                let nrm = shape.normal(p, eps);
                *p -= nrm * (s + 0.4 * dp);
            }
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Smallest distance between two particles, and the band of signed distance the
    /// outermost particles (one per direction) lie in.
    fn check<const D: usize>(shape: &Shape<D>, pts: &[Vect<D>], dp: Real) -> (Real, Real, Real) {
        let mut dmin = Real::INFINITY;
        for i in 0..pts.len() {
            for j in i + 1..pts.len() {
                dmin = dmin.min((pts[i] - pts[j]).norm());
            }
        }
        // outer layer: particles with no neighbour further out along their normal
        let (mut lo, mut hi) = (Real::INFINITY, Real::NEG_INFINITY);
        for p in pts {
            let s = shape.sdf(p);
            if s > -0.8 * dp {
                lo = lo.min(s);
                hi = hi.max(s);
            }
        }
        (dmin / dp, lo / dp, hi / dp)
    }

    #[test]
    fn relaxed_disc_and_polygon_have_an_even_outer_layer_half_a_spacing_inside() {
        let dp = 1.0;
        let shapes: Vec<Shape<2>> = vec![
            Shape::Sphere {
                center: Vect::<2>::new(0.0, 0.0),
                radius: 4.3,
            },
            Shape::Polygon {
                vertices: vec![[0.0, 0.0], [7.3, 0.7], [8.1, 5.9], [1.2, 6.4]],
            },
        ];
        for shape in shapes {
            let mut pts = shape.body_fill(dp);
            let before = check(&shape, &pts, dp);
            relax(&shape, &mut pts, dp);
            let (dmin, lo, hi) = check(&shape, &pts, dp);
            assert!(
                dmin > 0.75,
                "particles {dmin} dp apart (lattice: {before:?})"
            );
            assert!(
                lo > -0.85 && hi < -0.35,
                "outer layer between {lo} and {hi} dp (lattice: {before:?})"
            );
        }
    }
}
