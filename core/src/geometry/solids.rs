//! The wall objects (walls, terrain, barriers, container faces) as solids a viewer
//! draws: one primitive per object in 3D coordinates, at the object's shape at t = 0,
//! with the rigid offset it has moved by since. The wall particles fill the shape's
//! skin (seed 000 §2.4), so the shape is the wall's solid; a plane patch is the slab
//! of its wall layers behind the plane. In 2D every solid is extruded along z into a
//! slab [`SLAB_SPACINGS`] particle spacings thick, centred on z = 0, where the
//! particles lie.

use crate::geometry::tessellate::{self, Triangles};
use crate::geometry::walls::{WallKind, Walls};
use crate::geometry::{tangent_basis, Shape};
use crate::numerics::math::{to3, Real, Vect};
use nalgebra::{Matrix3, Rotation3, UnitQuaternion, Vector3};

/// Thickness of a 2D solid along z, in particle spacings.
pub const SLAB_SPACINGS: Real = 4.0;

/// Sides of a circle drawn as triangles (a 2D ring).
const SEGMENTS: u32 = 64;

/// A solid in 3D coordinates (m).
#[derive(Clone, Debug, PartialEq)]
pub enum Primitive {
    /// A box of edge lengths `size` about `center`, turned by the unit quaternion
    /// `orientation` (w, x, y, z).
    Cube {
        center: [Real; 3],
        size: [Real; 3],
        orientation: [Real; 4],
    },
    /// A cylinder with its axis along z: bounding-box `size` about `center`.
    Cylinder { center: [Real; 3], size: [Real; 3] },
    /// A sphere of diameter `size` about `center`.
    Sphere { center: [Real; 3], size: [Real; 3] },
    /// Triangles: `points` indexed three at a time by `indices`.
    Triangles {
        points: Vec<[Real; 3]>,
        indices: Vec<u32>,
    },
}

/// One wall object as a solid.
#[derive(Clone, Debug, PartialEq)]
pub struct WallSolid {
    /// Index of the object (walls, barriers, container faces in scene order), as the
    /// wall particles' `object`.
    pub object: usize,
    pub name: String,
    pub kind: WallKind,
    /// A prescribed velocity or a co-simulation input can move it.
    pub moving: bool,
    /// The solid at t = 0.
    pub primitive: Primitive,
}

fn a3(v: Vector3<Real>) -> [Real; 3] {
    [v.x, v.y, v.z]
}

/// The rigid offset (m) of every object since t = 0, in 3D coordinates.
pub fn offsets<const D: usize>(walls: &Walls<D>) -> Vec<[Real; 3]> {
    walls
        .objects
        .iter()
        .map(|o| a3(to3(&o.displacement)))
        .collect()
}

/// Every object whose shape is known (a restored state without its scene's shapes
/// has none) as a solid; `dp` is the particle spacing.
pub fn wall_solids<const D: usize>(walls: &Walls<D>, dp: Real) -> Vec<WallSolid> {
    let slab = SLAB_SPACINGS * dp;
    walls
        .objects
        .iter()
        .enumerate()
        .filter_map(|(k, o)| {
            let shape = o.shape.as_ref()?;
            let primitive = solid(shape, slab, || plane_depth(walls, k, shape, dp));
            Some(WallSolid {
                object: k,
                name: o.name.clone(),
                kind: o.kind,
                moving: walls.can_move(k),
                primitive,
            })
        })
        .collect()
}

/// How deep object `k`'s wall layers reach behind its plane: the deepest particle
/// (at t = 0) plus half a spacing, `wall_layers` · dp.
fn plane_depth<const D: usize>(walls: &Walls<D>, k: usize, shape: &Shape<D>, dp: Real) -> Real {
    let Shape::Plane { point, normal, .. } = shape else {
        return 0.0;
    };
    let shift = walls.objects[k].displacement;
    walls
        .pos
        .iter()
        .zip(&walls.object)
        .filter(|(_, &o)| o as usize == k)
        .map(|(x, _)| (point - (x - shift)).dot(normal))
        .fold(0.0, Real::max)
        + 0.5 * dp
}

/// A 2D point at z = 0 or a 3D point.
fn at<const D: usize>(v: &Vect<D>) -> [Real; 3] {
    a3(to3(v))
}

fn triangles((points, indices): Triangles) -> Primitive {
    Primitive::Triangles { points, indices }
}

/// The solid of `shape`; 2D shapes span z ∈ [−slab/2, slab/2]. `depth` gives a
/// plane's depth ([`plane_depth`]).
fn solid<const D: usize>(shape: &Shape<D>, slab: Real, depth: impl FnOnce() -> Real) -> Primitive {
    let flat = D == 2;
    let z = (-0.5 * slab, 0.5 * slab);
    match shape {
        Shape::Box { min, max } => {
            let mut size = a3(to3(&(max - min)));
            if flat {
                size[2] = slab;
            }
            Primitive::Cube {
                center: at(&((min + max) * 0.5)),
                size,
                orientation: [1.0, 0.0, 0.0, 0.0],
            }
        }
        Shape::Sphere { center, radius } if flat => Primitive::Cylinder {
            center: at(center),
            size: [2.0 * radius, 2.0 * radius, slab],
        },
        Shape::Sphere { center, radius } => Primitive::Sphere {
            center: at(center),
            size: [2.0 * radius; 3],
        },
        // a spherical shell is drawn whole: its outer surface
        Shape::Ring { center, radius, .. } if !flat => Primitive::Sphere {
            center: at(center),
            size: [2.0 * radius; 3],
        },
        Shape::Ring {
            center,
            inner,
            radius,
        } => triangles(tessellate::annulus(
            [center[0], center[1]],
            *inner,
            *radius,
            z,
            SEGMENTS,
        )),
        Shape::Cylinder {
            base,
            radius,
            height,
        } => {
            let mut c = at(base);
            c[2] += 0.5 * height;
            Primitive::Cylinder {
                center: c,
                size: [2.0 * radius, 2.0 * radius, *height],
            }
        }
        Shape::Polygon { vertices } => triangles(tessellate::extrude(vertices, z.0, z.1)),
        Shape::Convex { planes, .. } => triangles(tessellate::convex(planes)),
        Shape::Mesh(m) => triangles((
            m.tris
                .iter()
                .flat_map(|t| t.iter().map(|v| a3(*v)))
                .collect(),
            (0..3 * m.tris.len() as u32).collect(),
        )),
        Shape::Terrain { grid, offset } => triangles(tessellate::height_field(grid, offset)),
        Shape::Plane { .. } => plane(shape, depth(), slab),
    }
}

/// A plane patch as the box of its wall layers, `depth` behind the plane and
/// 2 `half_extent` along its tangents (x of the box along the normal, y and z along
/// the tangents of [`tangent_basis`]).
fn plane<const D: usize>(shape: &Shape<D>, depth: Real, slab: Real) -> Primitive {
    let Shape::Plane {
        point,
        normal,
        half_extent,
    } = shape
    else {
        unreachable!("plane() is called on planes")
    };
    let n = to3(normal);
    let t = tangent_basis::<D>(normal);
    let t1 = to3(&t[0]);
    let t2 = t.get(1).map_or_else(Vector3::z, to3);
    let rot = Rotation3::from_matrix_unchecked(Matrix3::from_columns(&[n, t1, t2]));
    let q = UnitQuaternion::from_rotation_matrix(&rot);
    let ext = |k: usize| half_extent.get(k).map_or(slab, |h| 2.0 * h);
    Primitive::Cube {
        center: a3(to3(point) - n * (0.5 * depth)),
        size: [depth, ext(0), ext(1)],
        orientation: [q.w, q.i, q.j, q.k],
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_2d_box_is_a_slab_and_a_3d_plane_a_turned_box() {
        let b = Shape::<2>::Box {
            min: Vect::<2>::new(0.6, 0.0),
            max: Vect::<2>::new(0.63, 0.25),
        };
        let Primitive::Cube { center, size, .. } = solid(&b, 0.03, || 0.0) else {
            panic!()
        };
        assert!((center[0] - 0.615).abs() < 1e-12 && (center[1] - 0.125).abs() < 1e-12);
        assert!((size[0] - 0.03).abs() < 1e-12 && (size[1] - 0.25).abs() < 1e-12);
        assert_eq!((center[2], size[2]), (0.0, 0.03));
        let n = Vect::<3>::new(0.5, 0.0, 0.75f64.sqrt());
        let p = Shape::<3>::Plane {
            point: Vect::<3>::zeros(),
            normal: n,
            half_extent: vec![0.6, 0.2],
        };
        let Primitive::Cube {
            center,
            size,
            orientation: [w, x, y, z],
        } = plane(&p, 0.04, 0.0)
        else {
            panic!()
        };
        // the box's x axis is the normal; the centre half the depth behind the plane
        let q = UnitQuaternion::from_quaternion(nalgebra::Quaternion::new(w, x, y, z));
        assert!((q * Vector3::x() - to3(&n)).norm() < 1e-12);
        assert!((Vector3::from(center) + to3(&n) * 0.02).norm() < 1e-12);
        assert_eq!(size, [0.04, 1.2, 0.4]);
    }
}
