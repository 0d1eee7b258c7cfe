//! Shapes and lattice fills. Particles are placed on a cubic lattice of spacing dp and
//! kept where a shape's signed distance says they belong (seed 000 §5.2: particles by
//! lattice fill of a signed-distance shape).

pub mod panels;
pub mod solids;
pub mod start_solids;
pub mod tessellate;
pub mod walls;

use crate::numerics::math::{to3, Real, Vect};
use crate::scene::ShapeSpec;
use crate::shapes::assets::Assets;
use crate::shapes::heightmap::Heightmap;
use crate::shapes::mesh::TriMesh;
use nalgebra::Vector3;
use std::sync::Arc;

/// A shape in `D` dimensions with a signed distance (negative inside).
#[derive(Clone, Debug)]
pub enum Shape<const D: usize> {
    Box {
        min: Vect<D>,
        max: Vect<D>,
    },
    /// Vertical cylinder (axis along the last coordinate), 3D only.
    Cylinder {
        base: Vect<D>,
        radius: Real,
        height: Real,
    },
    Sphere {
        center: Vect<D>,
        radius: Real,
    },
    /// Annulus (2D) or spherical shell (3D).
    Ring {
        center: Vect<D>,
        inner: Real,
        radius: Real,
    },
    /// 2D polygon.
    Polygon {
        vertices: Vec<[Real; 2]>,
    },
    /// Convex polyhedron (3D): intersection of half-spaces n·x ≤ d.
    Convex {
        planes: Vec<(Vector3<Real>, Real)>,
        lo: Vect<D>,
        hi: Vect<D>,
    },
    /// Closed triangle mesh (3D).
    Mesh(Arc<TriMesh>),
    /// Terrain (3D): the ground below a height field is solid.
    Terrain {
        grid: Arc<Heightmap>,
        offset: Vector3<Real>,
    },
    /// Half-space behind `point` with unit `normal`, limited to a patch of `half_extent`.
    Plane {
        point: Vect<D>,
        normal: Vect<D>,
        half_extent: Vec<Real>,
    },
}

fn v<const D: usize>(x: &[f64]) -> Vect<D> {
    Vect::<D>::from_iterator(x.iter().copied())
}

impl<const D: usize> Shape<D> {
    /// Build from a validated scene shape; files come from `assets`.
    pub fn from_spec(s: &ShapeSpec, assets: &Assets) -> Self {
        match s {
            ShapeSpec::Polyhedron { vertices } => {
                let pts: Vec<Vector3<Real>> = vertices
                    .iter()
                    .map(|p| Vector3::new(p[0], p[1], p[2]))
                    .collect();
                let mut lo = Vect::<D>::repeat(Real::INFINITY);
                let mut hi = Vect::<D>::repeat(Real::NEG_INFINITY);
                for p in &pts {
                    for k in 0..D {
                        lo[k] = lo[k].min(p[k]);
                        hi[k] = hi[k].max(p[k]);
                    }
                }
                Shape::Convex {
                    planes: hull_planes(&pts),
                    lo,
                    hi,
                }
            }
            ShapeSpec::Mesh {
                file,
                scale,
                offset,
            } => {
                let m = &assets.meshes[file];
                let o = offset
                    .as_deref()
                    .map(|o| Vector3::new(o[0], o[1], o[2]))
                    .unwrap_or_else(Vector3::zeros);
                Shape::Mesh(Arc::new(m.transformed(*scale, &o)))
            }
            ShapeSpec::Heightmap { file, offset } => Shape::Terrain {
                grid: assets.grids[file].clone(),
                offset: offset
                    .as_deref()
                    .map(|o| Vector3::new(o[0], o[1], o[2]))
                    .unwrap_or_else(Vector3::zeros),
            },
            ShapeSpec::Box { min, max } => Shape::Box {
                min: v(min),
                max: v(max),
            },
            ShapeSpec::Cylinder {
                base,
                radius,
                height,
            } => Shape::Cylinder {
                base: v(base),
                radius: *radius,
                height: *height,
            },
            ShapeSpec::Ring {
                center,
                inner_radius,
                radius,
            } => Shape::Ring {
                center: v(center),
                inner: *inner_radius,
                radius: *radius,
            },
            ShapeSpec::Sphere { center, radius } => Shape::Sphere {
                center: v(center),
                radius: *radius,
            },
            ShapeSpec::Polygon { vertices } => Shape::Polygon {
                vertices: vertices.iter().map(|p| [p[0], p[1]]).collect(),
            },
            ShapeSpec::Plane {
                point,
                normal,
                half_extent,
            } => {
                let n = v::<D>(normal);
                Shape::Plane {
                    point: v(point),
                    normal: n / n.norm(),
                    half_extent: half_extent.clone(),
                }
            }
        }
    }

    /// Signed distance: negative inside. For a plane, "inside" is the wall side (behind
    /// the plane); the patch limits are not part of the distance.
    pub fn sdf(&self, p: &Vect<D>) -> Real {
        match self {
            Shape::Box { min, max } => {
                let c = (min + max) * 0.5;
                let hsz = (max - min) * 0.5;
                let q = (p - c).abs() - hsz;
                let outside = q.map(|x| x.max(0.0)).norm();
                let inside = q.max().min(0.0);
                outside + inside
            }
            Shape::Cylinder {
                base,
                radius,
                height,
            } => {
                let mut r2 = 0.0;
                for k in 0..D - 1 {
                    r2 += (p[k] - base[k]).powi(2);
                }
                let dr = r2.sqrt() - radius;
                let z = p[D - 1] - base[D - 1];
                let dz = (z - height * 0.5).abs() - height * 0.5;
                let out = (dr.max(0.0).powi(2) + dz.max(0.0).powi(2)).sqrt();
                out + dr.max(dz).min(0.0)
            }
            Shape::Sphere { center, radius } => (p - center).norm() - radius,
            Shape::Ring {
                center,
                inner,
                radius,
            } => {
                let r = (p - center).norm();
                (r - radius).max(inner - r)
            }
            Shape::Polygon { vertices } => polygon_sdf(vertices, p[0], p[1]),
            Shape::Plane { point, normal, .. } => (p - point).dot(normal),
            Shape::Convex { planes, .. } => {
                let q = to3(p);
                planes
                    .iter()
                    .map(|(n, d)| n.dot(&q) - d)
                    .fold(Real::NEG_INFINITY, Real::max)
            }
            Shape::Mesh(m) => m.sdf(&to3(p)),
            Shape::Terrain { grid, offset } => {
                let q = to3(p) - offset;
                grid.sdf(q.x, q.y, q.z)
            }
        }
    }

    /// Axis-aligned bounding box.
    pub fn bounds(&self) -> (Vect<D>, Vect<D>) {
        match self {
            Shape::Convex { lo, hi, .. } => (*lo, *hi),
            Shape::Mesh(m) => {
                let mut lo = Vect::<D>::zeros();
                let mut hi = Vect::<D>::zeros();
                for k in 0..D {
                    lo[k] = m.lo[k];
                    hi[k] = m.hi[k];
                }
                (lo, hi)
            }
            Shape::Terrain { grid, offset } => {
                let (x0, x1, y0, y1) = grid.extent();
                let mut lo = Vect::<D>::zeros();
                let mut hi = Vect::<D>::zeros();
                let l = [x0, y0, grid.zmin];
                let h = [x1, y1, grid.zmax];
                for k in 0..D {
                    lo[k] = l[k] + offset[k];
                    hi[k] = h[k] + offset[k];
                }
                (lo, hi)
            }
            Shape::Box { min, max } => (*min, *max),
            Shape::Cylinder {
                base,
                radius,
                height,
            } => {
                let mut lo = *base;
                let mut hi = *base;
                for k in 0..D - 1 {
                    lo[k] -= radius;
                    hi[k] += radius;
                }
                hi[D - 1] += height;
                (lo, hi)
            }
            Shape::Sphere { center, radius } | Shape::Ring { center, radius, .. } => {
                (center.add_scalar(-radius), center.add_scalar(*radius))
            }
            Shape::Polygon { vertices } => {
                let mut lo = Vect::<D>::repeat(Real::INFINITY);
                let mut hi = Vect::<D>::repeat(Real::NEG_INFINITY);
                for p in vertices {
                    for k in 0..2 {
                        lo[k] = lo[k].min(p[k]);
                        hi[k] = hi[k].max(p[k]);
                    }
                }
                (lo, hi)
            }
            Shape::Plane { point, .. } => (*point, *point),
        }
    }

    /// A representative centre (bounding-box centre; the patch centre for a plane).
    pub fn center(&self) -> Vect<D> {
        let (lo, hi) = self.bounds();
        (lo + hi) * 0.5
    }

    /// Lattice points inside the shape (fine-grain fill). Boxes anchor the lattice at
    /// their min corner so that faces fall on half-spacings; other shapes use the
    /// global lattice x = (i + ½) dp.
    pub fn fill(&self, dp: Real) -> Vec<Vect<D>> {
        let (lo, hi) = self.bounds();
        let anchor = match self {
            Shape::Box { min, .. } => *min,
            _ => Vect::<D>::zeros(),
        };
        lattice_in(&lo, &hi, &anchor, dp, |p| self.sdf(p) < 0.0)
    }

    /// Lattice points inside the shape for a coarse-grain body. The lattice is
    /// centred on the shape, at c + k dp or c + (k + ½) dp along each axis; of the
    /// 2^d choices the one whose outermost particles lie closest to half a spacing
    /// inside the surface wins (then the count closest to the volume), so that no
    /// single particle sticks out, symmetric shapes fill symmetrically and a flat face
    /// is a full layer half a spacing inside.
    pub fn body_fill(&self, dp: Real) -> Vec<Vect<D>> {
        let (lo, hi) = self.bounds();
        let c = self.center();
        let target = self.volume().map(|v| v / dp.powi(D as i32));
        let mut best: Option<(Real, Real, Vec<Vect<D>>)> = None;
        for mask in 0..(1usize << D) {
            let mut anchor = c;
            for k in 0..D {
                if mask & (1 << k) != 0 {
                    anchor[k] -= 0.5 * dp;
                }
            }
            let pts = prune_spikes(
                lattice_in(&lo, &hi, &anchor, dp, |p| self.sdf(p) < 0.0),
                &anchor,
                dp,
            );
            if pts.len() < 2 {
                continue;
            }
            let outer = pts
                .iter()
                .map(|p| self.sdf(p))
                .fold(Real::NEG_INFINITY, Real::max);
            let score = ((outer + 0.5 * dp).abs() / dp * 1e6).round();
            let vol = target.map(|n| (pts.len() as Real - n).abs()).unwrap_or(0.0);
            let better = match &best {
                None => true,
                Some((s0, v0, _)) => score < *s0 || (score == *s0 && vol < *v0),
            };
            if better {
                best = Some((score, vol, pts));
            }
        }
        best.map(|b| b.2).unwrap_or_default()
    }

    /// Exact volume (area in 2D) where it is known in closed form.
    pub fn volume(&self) -> Option<Real> {
        use std::f64::consts::PI;
        let d3 = D == 3;
        match self {
            Shape::Box { min, max } => Some((max - min).iter().product()),
            Shape::Sphere { radius, .. } => Some(if d3 {
                4.0 / 3.0 * PI * radius.powi(3)
            } else {
                PI * radius * radius
            }),
            Shape::Ring { inner, radius, .. } => Some(if d3 {
                4.0 / 3.0 * PI * (radius.powi(3) - inner.powi(3))
            } else {
                PI * (radius * radius - inner * inner)
            }),
            Shape::Cylinder { radius, height, .. } => Some(PI * radius * radius * height),
            Shape::Polygon { vertices } => {
                let mut a = 0.0;
                for i in 0..vertices.len() {
                    let (p, q) = (vertices[i], vertices[(i + 1) % vertices.len()]);
                    a += p[0] * q[1] - q[0] * p[1];
                }
                Some(0.5 * a.abs())
            }
            Shape::Mesh(m) => Some(m.volume()),
            Shape::Plane { .. } | Shape::Convex { .. } | Shape::Terrain { .. } => None,
        }
    }

    /// Outward unit normal, the normalised gradient of the signed distance (central
    /// differences with step `eps`); zero where the gradient vanishes.
    pub fn normal(&self, p: &Vect<D>, eps: Real) -> Vect<D> {
        let mut g = Vect::<D>::zeros();
        for k in 0..D {
            let mut a = *p;
            let mut b = *p;
            a[k] += eps;
            b[k] -= eps;
            g[k] = self.sdf(&a) - self.sdf(&b);
        }
        let n = g.norm();
        if n > 0.0 {
            g / n
        } else {
            g
        }
    }

    /// The outward unit normal of the face nearest `p`, as a wall contact takes it
    /// ([`fine_wall`](crate::interactions::fine_wall)): [`normal`](Self::normal), except
    /// on a terrain, whose ground normal under `p` ([`Heightmap::normal`]) is the
    /// gradient's direction at the surface in four height lookups, not thirty.
    ///
    /// [`Heightmap::normal`]: crate::shapes::heightmap::Heightmap::normal
    pub fn face_normal(&self, p: &Vect<D>, eps: Real) -> Vect<D> {
        if let (Shape::Terrain { grid, offset }, 3) = (self, D) {
            let q = to3(p) - offset;
            return Vect::<D>::from_iterator(grid.normal(q.x, q.y));
        }
        self.normal(p, eps)
    }

    /// Wall particles: `layers` lattice layers on the wall side of the surface.
    /// Solid shapes keep the shell −layers·dp < sdf < 0; a plane builds its own
    /// tangential lattice behind the plane.
    pub fn wall_fill(&self, dp: Real, layers: usize) -> Vec<Vect<D>> {
        let depth = layers as Real * dp;
        match self {
            Shape::Plane {
                point,
                normal,
                half_extent,
            } => {
                let tangents = tangent_basis::<D>(normal);
                let mut out = Vec::new();
                let counts: Vec<i64> = half_extent
                    .iter()
                    .map(|h| (h / dp).floor() as i64)
                    .collect();
                let mut idx = vec![0i64; D - 1];
                for k in 0..D - 1 {
                    idx[k] = -counts[k];
                }
                loop {
                    for l in 0..layers {
                        let mut p = point - normal * ((l as Real + 0.5) * dp);
                        for k in 0..D - 1 {
                            p += tangents[k] * ((idx[k] as Real) * dp);
                        }
                        out.push(p);
                    }
                    // odometer increment
                    let mut k = 0;
                    loop {
                        if k == D - 1 {
                            return out;
                        }
                        idx[k] += 1;
                        if idx[k] <= counts[k] {
                            break;
                        }
                        idx[k] = -counts[k];
                        k += 1;
                    }
                }
            }
            _ => {
                let (mut lo, hi) = self.bounds();
                if let Shape::Terrain { .. } = self {
                    // the layers lie below the lowest ground point too
                    lo[D - 1] -= depth + dp;
                }
                let anchor = match self {
                    Shape::Box { min, .. } => *min,
                    _ => Vect::<D>::zeros(),
                };
                lattice_in(&lo, &hi, &anchor, dp, |p| {
                    let d = self.sdf(p);
                    d < 0.0 && d > -depth
                })
            }
        }
    }
}

/// Orthonormal tangents of a unit normal (one in 2D, two in 3D).
pub fn tangent_basis<const D: usize>(n: &Vect<D>) -> Vec<Vect<D>> {
    if D == 2 {
        let mut t = Vect::<D>::zeros();
        t[0] = -n[1];
        t[1] = n[0];
        vec![t]
    } else {
        let n3 = nalgebra::Vector3::new(n[0], n[1], n[2]);
        let a = if n3.x.abs() < 0.9 {
            nalgebra::Vector3::x()
        } else {
            nalgebra::Vector3::y()
        };
        let t1 = n3.cross(&a).normalize();
        let t2 = n3.cross(&t1);
        let c = |t: nalgebra::Vector3<Real>| Vect::<D>::from_iterator(t.iter().copied());
        vec![c(t1), c(t2)]
    }
}

/// Lattice points anchor + (i + ½) dp inside [lo, hi] that satisfy `keep`.
/// Drop lattice points joined to the rest by at most one direct neighbour (spacing dp),
/// repeatedly: the lone particles a lattice leaves in the sharp corners of a slanted
/// shape. A fine particle beside such a spike sees a surface normal that does not face
/// it, so neither the interface nor the penetration barrier holds it off. A body that
/// is nothing but spikes is kept as it is.
fn prune_spikes<const D: usize>(pts: Vec<Vect<D>>, anchor: &Vect<D>, dp: Real) -> Vec<Vect<D>> {
    use std::collections::HashSet;
    let key = |p: &Vect<D>| -> [i64; 3] {
        let mut k = [0i64; 3];
        for a in 0..D {
            k[a] = ((p[a] - anchor[a]) / dp - 0.5).round() as i64;
        }
        k
    };
    let mut alive: HashSet<[i64; 3]> = pts.iter().map(key).collect();
    loop {
        let lone: Vec<[i64; 3]> = pts
            .iter()
            .map(key)
            .filter(|k| alive.contains(k))
            .filter(|k| {
                let mut n = 0;
                for a in 0..D {
                    for s in [-1i64, 1] {
                        let mut q = *k;
                        q[a] += s;
                        n += alive.contains(&q) as usize;
                    }
                }
                n <= 1
            })
            .collect();
        if lone.is_empty() {
            break;
        }
        if lone.len() == alive.len() {
            return pts;
        }
        for k in &lone {
            alive.remove(k);
        }
    }
    pts.into_iter()
        .filter(|p| alive.contains(&key(p)))
        .collect()
}

fn lattice_in<const D: usize>(
    lo: &Vect<D>,
    hi: &Vect<D>,
    anchor: &Vect<D>,
    dp: Real,
    keep: impl Fn(&Vect<D>) -> bool,
) -> Vec<Vect<D>> {
    let mut i0 = [0i64; 3];
    let mut i1 = [0i64; 3];
    for k in 0..D {
        i0[k] = ((lo[k] - anchor[k]) / dp - 0.5).floor() as i64 - 1;
        i1[k] = ((hi[k] - anchor[k]) / dp - 0.5).ceil() as i64 + 1;
    }
    let mut out = Vec::new();
    let (k0, k1) = if D == 3 { (i0[2], i1[2]) } else { (0, 0) };
    for kz in k0..=k1 {
        for ky in i0[1]..=i1[1] {
            for kx in i0[0]..=i1[0] {
                let ids = [kx, ky, kz];
                let mut p = Vect::<D>::zeros();
                for k in 0..D {
                    p[k] = anchor[k] + (ids[k] as Real + 0.5) * dp;
                }
                if keep(&p) {
                    out.push(p);
                }
            }
        }
    }
    out
}

fn polygon_sdf(v: &[[Real; 2]], x: Real, y: Real) -> Real {
    let mut d2 = Real::INFINITY;
    let mut inside = false;
    let n = v.len();
    let mut j = n - 1;
    for i in 0..n {
        let (a, b) = (v[i], v[j]);
        let (ex, ey) = (b[0] - a[0], b[1] - a[1]);
        let (wx, wy) = (x - a[0], y - a[1]);
        let t = ((wx * ex + wy * ey) / (ex * ex + ey * ey)).clamp(0.0, 1.0);
        let (dx, dy) = (wx - ex * t, wy - ey * t);
        d2 = d2.min(dx * dx + dy * dy);
        if (a[1] > y) != (b[1] > y) && x < (b[0] - a[0]) * (y - a[1]) / (b[1] - a[1]) + a[0] {
            inside = !inside;
        }
        j = i;
    }
    let d = d2.sqrt();
    if inside {
        -d
    } else {
        d
    }
}

/// Outward face planes (n, d), n·x ≤ d inside, of the convex hull of `pts`: every
/// plane through three points that has all points on one side.
pub fn hull_planes(pts: &[Vector3<Real>]) -> Vec<(Vector3<Real>, Real)> {
    let scale = pts
        .iter()
        .map(|p| p.norm())
        .fold(0.0, Real::max)
        .max(1e-300);
    let eps = 1e-9 * scale;
    let mut planes: Vec<(Vector3<Real>, Real)> = Vec::new();
    let n = pts.len();
    for i in 0..n {
        for j in i + 1..n {
            for k in j + 1..n {
                let nrm = (pts[j] - pts[i]).cross(&(pts[k] - pts[i]));
                let len = nrm.norm();
                if len < eps * scale {
                    continue;
                }
                let mut nv = nrm / len;
                let mut d = nv.dot(&pts[i]);
                let above = pts.iter().filter(|p| nv.dot(p) - d > eps).count();
                let below = pts.iter().filter(|p| nv.dot(p) - d < -eps).count();
                if above > 0 && below > 0 {
                    continue;
                }
                if above > 0 {
                    nv = -nv;
                    d = -d;
                }
                if !planes
                    .iter()
                    .any(|(m, e)| (m - nv).norm() < 1e-9 && (e - d).abs() < eps)
                {
                    planes.push((nv, d));
                }
            }
        }
    }
    planes
}

#[cfg(test)]
mod tests {
    #[test]
    fn hull_of_cube_corners_has_six_faces_and_exact_distance() {
        let mut pts = Vec::new();
        for &x in &[0.0, 1.0] {
            for &y in &[0.0, 2.0] {
                for &z in &[0.0, 3.0] {
                    pts.push(Vector3::new(x, y, z));
                }
            }
        }
        pts.push(Vector3::new(0.5, 1.0, 1.5)); // interior point is ignored
        let planes = hull_planes(&pts);
        assert_eq!(planes.len(), 6);
        let s = Shape::<3>::Convex {
            planes,
            lo: Vect::<3>::new(0.0, 0.0, 0.0),
            hi: Vect::<3>::new(1.0, 2.0, 3.0),
        };
        assert!((s.sdf(&Vect::<3>::new(0.5, 1.0, 1.5)) + 0.5).abs() < 1e-12);
        assert!((s.sdf(&Vect::<3>::new(0.5, 1.0, 3.25)) - 0.25).abs() < 1e-12);
        // a box body of 10 × 10 × 5 spacings fills with full layers half a spacing in
        let b = Shape::<3>::Box {
            min: Vect::<3>::new(0.0, 0.0, 0.0),
            max: Vect::<3>::new(0.1, 0.1, 0.05),
        };
        let pts = b.body_fill(0.01);
        assert_eq!(pts.len(), 500);
        let zmin = pts.iter().map(|p| p[2]).fold(f64::INFINITY, f64::min);
        assert!((zmin - 0.005).abs() < 1e-12, "{zmin}");
    }

    use super::*;

    #[test]
    fn box_fill_counts_and_volume() {
        let s = Shape::<2>::Box {
            min: Vect::<2>::new(0.0, 0.0),
            max: Vect::<2>::new(0.2, 0.1),
        };
        assert_eq!(s.fill(0.01).len(), 200);
        let c = Shape::<3>::Cylinder {
            base: Vect::<3>::zeros(),
            radius: 0.1,
            height: 0.1,
        };
        let n = c.fill(0.005).len() as f64;
        let vol = std::f64::consts::PI * 0.01 * 0.1;
        assert!((n * 0.005f64.powi(3) / vol - 1.0).abs() < 0.02);
    }

    #[test]
    fn polygon_sdf_sign() {
        let s = Shape::<2>::Polygon {
            vertices: vec![[0.0, 0.0], [1.0, 0.0], [1.0, 1.0], [0.0, 1.0]],
        };
        assert!((s.sdf(&Vect::<2>::new(0.5, 0.25)) + 0.25).abs() < 1e-12);
        assert!((s.sdf(&Vect::<2>::new(2.0, 0.5)) - 1.0).abs() < 1e-12);
    }

    #[test]
    fn wall_shell_has_requested_layers() {
        let s = Shape::<2>::Box {
            min: Vect::<2>::new(-1.0, -0.04),
            max: Vect::<2>::new(1.0, 0.0),
        };
        let w = s.wall_fill(0.01, 4);
        // a 2 m × 0.04 m slab is all shell: 200 × 4 particles
        assert_eq!(w.len(), 800);
        let p = Shape::<2>::Plane {
            point: Vect::<2>::zeros(),
            normal: Vect::<2>::new(0.0, 1.0),
            half_extent: vec![0.1],
        };
        let w = p.wall_fill(0.01, 4);
        assert_eq!(w.len(), 21 * 4);
        assert!(w.iter().all(|q| q[1] < 0.0 && q[1] > -0.04));
    }
}
