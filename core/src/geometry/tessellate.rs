//! Triangles of the shapes that no viewer primitive draws: a 2D polygon or annulus
//! extruded into a slab, a convex polyhedron from its face planes, and a terrain's
//! height field. Every list is indexed (three indices a triangle) and wound
//! counter-clockwise seen from outside, so that the faces' normals point out.

use crate::numerics::math::Real;
use crate::shapes::heightmap::Heightmap;
use nalgebra::Vector3;

/// Vertices and triangle indices (three a triangle).
pub type Triangles = (Vec<[Real; 3]>, Vec<u32>);

/// Twice the signed area of `v` (positive counter-clockwise).
fn signed_area2(v: &[[Real; 2]]) -> Real {
    (0..v.len())
        .map(|i| {
            let (p, q) = (v[i], v[(i + 1) % v.len()]);
            p[0] * q[1] - q[0] * p[1]
        })
        .sum()
}

/// z of (b − a) × (c − a).
fn cross(a: [Real; 2], b: [Real; 2], c: [Real; 2]) -> Real {
    (b[0] - a[0]) * (c[1] - a[1]) - (b[1] - a[1]) * (c[0] - a[0])
}

/// Triangles of a simple polygon given counter-clockwise, by ear clipping; a corner
/// left with no ear (collinear leftovers) is closed as a fan.
fn ear_clip(v: &[[Real; 2]]) -> Vec<[usize; 3]> {
    let mut idx: Vec<usize> = (0..v.len()).collect();
    let mut out = Vec::with_capacity(v.len().saturating_sub(2));
    while idx.len() > 3 {
        let n = idx.len();
        let ear = (0..n).find(|&k| {
            let (a, b, c) = (idx[(k + n - 1) % n], idx[k], idx[(k + 1) % n]);
            cross(v[a], v[b], v[c]) > 0.0
                && idx.iter().all(|&p| {
                    p == a
                        || p == b
                        || p == c
                        || cross(v[a], v[b], v[p]) < 0.0
                        || cross(v[b], v[c], v[p]) < 0.0
                        || cross(v[c], v[a], v[p]) < 0.0
                })
        });
        let Some(k) = ear else { break };
        out.push([idx[(k + n - 1) % n], idx[k], idx[(k + 1) % n]]);
        idx.remove(k);
    }
    for k in 1..idx.len().saturating_sub(1) {
        out.push([idx[0], idx[k], idx[k + 1]]);
    }
    out
}

/// The polygon `v` (either orientation) extruded from z0 to z1 > z0: both caps and
/// one quad a side.
pub fn extrude(v: &[[Real; 2]], z0: Real, z1: Real) -> Triangles {
    let mut ring: Vec<[Real; 2]> = v.to_vec();
    if signed_area2(&ring) < 0.0 {
        ring.reverse();
    }
    let n = ring.len() as u32;
    // 0..n the bottom ring, n..2n the top one
    let points: Vec<[Real; 3]> = [z0, z1]
        .iter()
        .flat_map(|&z| ring.iter().map(move |p| [p[0], p[1], z]))
        .collect();
    let mut idx = Vec::new();
    for [a, b, c] in ear_clip(&ring) {
        let (a, b, c) = (a as u32, b as u32, c as u32);
        idx.extend([n + a, n + b, n + c]);
        idx.extend([c, b, a]);
    }
    for a in 0..n {
        let b = (a + 1) % n;
        idx.extend([a, b, n + b, a, n + b, n + a]);
    }
    (points, idx)
}

/// An annulus about `c` (radii `inner` < `outer`) extruded from z0 to z1 with
/// `segments` sides on each circle.
pub fn annulus(
    c: [Real; 2],
    inner: Real,
    outer: Real,
    z: (Real, Real),
    segments: u32,
) -> Triangles {
    let angle = |k: u32| std::f64::consts::TAU * k as Real / segments as Real;
    // vertex 4k + (bottom outer, top outer, bottom inner, top inner)
    let mut points = Vec::with_capacity(4 * segments as usize);
    for k in 0..segments {
        let (s, co) = angle(k).sin_cos();
        for (r, zz) in [(outer, z.0), (outer, z.1), (inner, z.0), (inner, z.1)] {
            points.push([c[0] + r * co, c[1] + r * s, zz]);
        }
    }
    let mut idx = Vec::with_capacity(24 * segments as usize);
    for k in 0..segments {
        let (a, b) = (4 * k, 4 * ((k + 1) % segments));
        // outer side, inner side (facing the centre), top and bottom caps
        idx.extend([a, b, b + 1, a, b + 1, a + 1]);
        idx.extend([a + 2, a + 3, b + 3, a + 2, b + 3, b + 2]);
        idx.extend([a + 1, b + 1, b + 3, a + 1, b + 3, a + 3]);
        idx.extend([a, a + 2, b + 2, a, b + 2, b]);
    }
    (points, idx)
}

/// The convex polyhedron n·x ≤ d of `planes`: its corners (where three planes meet
/// inside all others) and each face as a fan of its corners in counter-clockwise
/// order about the outward normal.
pub fn convex(planes: &[(Vector3<Real>, Real)]) -> Triangles {
    let scale = planes.iter().map(|p| p.1.abs()).fold(1.0, Real::max);
    let eps = 1e-9 * scale;
    let mut corners: Vec<Vector3<Real>> = Vec::new();
    for (i, a) in planes.iter().enumerate() {
        for (j, b) in planes.iter().enumerate().skip(i + 1) {
            for c in planes.iter().skip(j + 1) {
                let m = nalgebra::Matrix3::from_rows(&[
                    a.0.transpose(),
                    b.0.transpose(),
                    c.0.transpose(),
                ]);
                let Some(x) = m.try_inverse().map(|inv| inv * Vector3::new(a.1, b.1, c.1)) else {
                    continue;
                };
                let inside = planes.iter().all(|(n, d)| n.dot(&x) - d <= eps);
                if inside && !corners.iter().any(|y| (y - x).norm() <= eps) {
                    corners.push(x);
                }
            }
        }
    }
    let points: Vec<[Real; 3]> = corners.iter().map(|p| [p.x, p.y, p.z]).collect();
    let mut idx = Vec::new();
    for (n, d) in planes {
        let mut face: Vec<usize> = (0..corners.len())
            .filter(|&k| (n.dot(&corners[k]) - d).abs() <= eps)
            .collect();
        if face.len() < 3 {
            continue;
        }
        let centre = face.iter().map(|&k| corners[k]).sum::<Vector3<Real>>() / face.len() as Real;
        let u = (corners[face[0]] - centre).normalize();
        let w = n.cross(&u);
        let at = |k: usize| {
            let r = corners[k] - centre;
            r.dot(&w).atan2(r.dot(&u))
        };
        face.sort_by(|&p, &q| at(p).total_cmp(&at(q)));
        for k in 1..face.len() - 1 {
            idx.extend([face[0], face[k], face[k + 1]].map(|x| x as u32));
        }
    }
    (points, idx)
}

/// Most vertices of a drawn terrain: a finer grid is drawn at every s-th node.
const TERRAIN_VERTICES: usize = 1 << 18;

/// The terrain's surface through its grid nodes (shifted by `offset`), two triangles
/// a cell, facing up; grids of more than 2¹⁸ nodes are drawn at every s-th node.
pub fn height_field(grid: &Heightmap, offset: &Vector3<Real>) -> Triangles {
    let n = grid.ncols * grid.nrows;
    let s = ((n as Real / TERRAIN_VERTICES as Real).sqrt().ceil() as usize).max(1);
    let along = |m: usize| -> Vec<usize> {
        let mut v: Vec<usize> = (0..m).step_by(s).collect();
        if v.last() != Some(&(m - 1)) {
            v.push(m - 1);
        }
        v
    };
    let (cols, rows) = (along(grid.ncols), along(grid.nrows));
    let mut points = Vec::with_capacity(cols.len() * rows.len());
    for &j in &rows {
        for &i in &cols {
            points.push([
                grid.x0 + i as Real * grid.cell + offset.x,
                grid.y0 + j as Real * grid.cell + offset.y,
                grid.z[j * grid.ncols + i] + offset.z,
            ]);
        }
    }
    let nc = cols.len() as u32;
    let mut idx = Vec::new();
    for j in 0..rows.len() as u32 - 1 {
        for i in 0..nc - 1 {
            let a = j * nc + i;
            idx.extend([a, a + 1, a + nc + 1, a, a + nc + 1, a + nc]);
        }
    }
    (points, idx)
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Σ over triangles of (a × b)·c / 6: the enclosed volume when every face points
    /// out.
    fn volume((p, idx): &Triangles) -> Real {
        idx.chunks(3)
            .map(|t| {
                let v = |k: u32| Vector3::from(p[k as usize]);
                v(t[0]).cross(&v(t[1])).dot(&v(t[2])) / 6.0
            })
            .sum()
    }

    #[test]
    fn extruded_l_shape_and_clockwise_polygon_enclose_their_volume() {
        // an L of area 3 given clockwise, 0.5 thick
        let l = [
            [0.0, 0.0],
            [0.0, 2.0],
            [1.0, 2.0],
            [1.0, 1.0],
            [2.0, 1.0],
            [2.0, 0.0],
        ];
        let t = extrude(&l, -0.25, 0.25);
        assert_eq!(t.1.len(), 3 * (2 * 4 + 2 * 6));
        assert!((volume(&t) - 1.5).abs() < 1e-12, "{}", volume(&t));
    }

    #[test]
    fn annulus_encloses_the_ring_volume() {
        let t = annulus([1.0, 2.0], 0.5, 1.0, (0.0, 2.0), 256);
        let exact = std::f64::consts::PI * (1.0 - 0.25) * 2.0;
        assert!((volume(&t) / exact - 1.0).abs() < 1e-3, "{}", volume(&t));
    }

    #[test]
    fn convex_box_has_twelve_outward_triangles() {
        let pts: Vec<Vector3<Real>> = (0..8)
            .map(|k| {
                Vector3::new(
                    (k & 1) as Real,
                    ((k >> 1) & 1) as Real * 2.0,
                    (k >> 2) as Real * 3.0,
                )
            })
            .collect();
        let t = convex(&crate::geometry::hull_planes(&pts));
        assert_eq!(t.0.len(), 8);
        assert_eq!(t.1.len(), 36);
        assert!((volume(&t) - 6.0).abs() < 1e-12, "{}", volume(&t));
    }
}
