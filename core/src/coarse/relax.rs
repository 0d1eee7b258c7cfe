//! Level-set particle relaxation of coarse-grain bodies (the pre-processing seed 000
//! §5.2 applies to its balls, ref. [40]).
//!
//! A lattice cut by a curved or slanted surface leaves its outermost particles anywhere
//! from 0 to one spacing inside the surface, so the body that fine grains and contacts
//! see is ragged and, on average, smaller than the shape. Relaxation moves the
//! particles, keeping their number, until they are evenly spaced and the outer layer
//! lies half a spacing inside the surface everywhere.
//!
//! Each sweep pushes every particle away from its neighbours with the kernel gradient,
//! F_i = −Σ_j ∇W(r_ij) dp^d. Particles within the kernel support of the surface also
//! see the mirror images of their neighbours (and of themselves) across the surface,
//! which stands in for the missing material outside, so a particle half a spacing
//! inside is in balance. Displacements are Jacobi updates (all forces first, then all
//! moves), so the result does not depend on the order of the particles.

use crate::geometry::Shape;
use crate::kernel::WendlandC2;
use crate::math::{Real, Vect};
use std::collections::HashMap;

/// Sweeps of relaxation.
pub const SWEEPS: usize = 120;

/// Bodies with fewer particles than this (2D, 3D) are left as lattices: with hardly
/// any interior, relaxation would spread them over the surface and open gaps.
pub const MIN_PARTICLES: [usize; 2] = [30, 100];

/// Relax `pts` (lattice points inside `shape`) in place.
pub fn relax<const D: usize>(shape: &Shape<D>, pts: &mut [Vect<D>], dp: Real) {
    if matches!(shape, Shape::Box { .. }) || pts.len() < MIN_PARTICLES[D - 2] {
        // a centred lattice already puts every face half a spacing inside
        return;
    }
    let h = 1.15 * dp;
    let kernel = WendlandC2::new(h, D);
    let cut = kernel.cutoff;
    let vol = dp.powi(D as i32);
    let eps = 1e-3 * dp;
    let n = pts.len();
    let mut force = vec![Vect::<D>::zeros(); n];
    let mut images: Vec<Vect<D>> = Vec::with_capacity(n);
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
        let cell = |x: &Vect<D>| -> [i64; 3] {
            let mut c = [0i64; 3];
            for k in 0..D {
                c[k] = (x[k] / cut).floor() as i64;
            }
            c
        };
        let mut grid: HashMap<[i64; 3], Vec<u32>> = HashMap::new();
        for (k, x) in pts.iter().chain(images.iter()).enumerate() {
            grid.entry(cell(x)).or_default().push(k as u32);
        }
        let at = |k: usize| -> &Vect<D> {
            if k < n {
                &pts[k]
            } else {
                &images[k - n]
            }
        };
        for (i, f) in force.iter_mut().enumerate() {
            let xi = pts[i];
            let c = cell(&xi);
            let mut acc = Vect::<D>::zeros();
            let span: i64 = 1;
            let range = |k: usize| if k < D { -span..=span } else { 0..=0 };
            for dx in range(0) {
                for dy in range(1) {
                    for dz in range(2) {
                        let key = [c[0] + dx, c[1] + dy, c[2] + dz];
                        if let Some(list) = grid.get(&key) {
                            for &j in list {
                                let j = j as usize;
                                if j == i {
                                    continue;
                                }
                                let rij = xi - at(j);
                                let r = rij.norm();
                                if r >= cut || r == 0.0 {
                                    continue;
                                }
                                acc -= rij * (kernel.dw(r) / r * vol);
                            }
                        }
                    }
                }
            }
            *f = acc;
        }
        // step: a fraction of h² F, shrinking over the sweeps, capped at dp/10
        let relax = 0.1 * (1.0 - sweep as Real / SWEEPS as Real) + 0.02;
        for (p, f) in pts.iter_mut().zip(&force) {
            let mut dx = f * (relax * h * h);
            let len = dx.norm();
            if len > 0.1 * dp {
                dx *= 0.1 * dp / len;
            }
            *p += dx;
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
