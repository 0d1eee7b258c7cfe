//! Solids that displace particles at start-up: the build leaves no fine grain or water
//! particle inside a wall, a barrier or a buried boulder, and the load checks measure
//! the water the same way before the build ([`flow_speed`](crate::flow_speed)).

use crate::geometry::Shape;
use crate::math::{from3, to3, Real, Vect};
use crate::scene::{spec_rotation, Scene, ShapeSpec};
use nalgebra::{Rotation3, Vector3};

/// A body's rotation about a centre.
type Pose = (Vector3<Real>, Rotation3<Real>);

/// Solids that displace particles at start-up: walls and barriers (not planes, whose
/// patch is not a solid; for water not the permeable ones) and bodies (buried
/// boulders).
pub struct Solids<const D: usize>(Vec<(Shape<D>, Option<Pose>)>);

impl<const D: usize> Solids<D> {
    pub fn of(scene: &Scene, water: bool) -> Self {
        let mut solids: Vec<(Shape<D>, Option<Pose>)> = Vec::new();
        for w in scene.walls.iter().chain(&scene.barriers) {
            let passes = water && w.permeable;
            if !matches!(w.shape, ShapeSpec::Plane { .. }) && !passes {
                solids.push((Shape::<D>::from_spec(&w.shape, &scene.assets), None));
            }
        }
        for b in &scene.bodies {
            let shape = Shape::<D>::from_spec(&b.shape, &scene.assets);
            let c = to3(&shape.center());
            solids.push((shape, Some((c, spec_rotation(b, D)))));
        }
        Solids(solids)
    }

    pub fn is_empty(&self) -> bool {
        self.0.is_empty()
    }

    /// A particle at `p` is not created: it lies closer than dp/2 (the lattice
    /// half-spacing) to a solid's surface, or inside it.
    pub fn holds(&self, p: &Vect<D>, dp: Real) -> bool {
        self.0.iter().any(|(shape, pose)| {
            let q = match pose {
                Some((c, r)) => from3::<D>(&(c + r.inverse() * (to3(p) - c))),
                None => *p,
            };
            shape.sdf(&q) < 0.5 * dp * (1.0 - 1e-6)
        })
    }
}
