//! Solids that displace particles at start-up: the build leaves no fine grain or water
//! particle inside a wall, a barrier or a buried boulder, and the load checks measure
//! the water the same way before the build ([`flow_speed`](crate::estimate::flow_speed)).

use crate::geometry::walls::container_faces;
use crate::geometry::Shape;
use crate::numerics::math::{from3, to3, Real, Vect};
use crate::scene::{spec_rotation, Scene, ShapeSpec};
use nalgebra::{Rotation3, Vector3};

/// A body's rotation about a centre.
type Pose = (Vector3<Real>, Rotation3<Real>);

/// Solids that displace particles at start-up: walls and barriers (not planes, whose
/// patch is not a solid; for water not the permeable ones) and bodies (buried
/// boulders), and whether the particles they displace are water's.
pub struct Solids<const D: usize> {
    solids: Vec<(Shape<D>, Option<Pose>)>,
    /// The containers' closed faces: their particles are placed outside the regions,
    /// so they displace nothing, but the water packed against a body meets them
    /// ([`near`](Self::near)).
    faces: Vec<Shape<D>>,
    water: bool,
}

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
        // thick enough that nothing is pushed through a face
        let faces = scene
            .containers
            .iter()
            .flat_map(|c| {
                let size = c
                    .max
                    .iter()
                    .zip(&c.min)
                    .map(|(a, b)| a - b)
                    .fold(0.0, Real::max);
                container_faces::<D>(c, size)
            })
            .map(|f| Shape::Box {
                min: f.min,
                max: f.max,
            })
            .collect();
        Solids {
            solids,
            faces,
            water,
        }
    }

    pub fn is_empty(&self) -> bool {
        self.solids.is_empty()
    }

    /// Whether any solid is a body.
    pub fn has_bodies(&self) -> bool {
        self.solids.iter().any(|(_, pose)| pose.is_some())
    }

    /// A particle at `p` is not created: it lies closer than dp/2 (the lattice
    /// half-spacing) to a solid's surface, or inside it. Water is kept up to a body's
    /// surface: [`water_at_bodies`](crate::world::water_at_bodies) then moves it out to
    /// half a spacing, so that the body displaces its own volume of water.
    pub fn holds(&self, p: &Vect<D>, dp: Real) -> bool {
        self.solids.iter().any(|(shape, pose)| {
            let q = local(pose, p);
            let gap = if self.water && pose.is_some() {
                0.0
            } else {
                0.5 * dp * (1.0 - 1e-6)
            };
            shape.sdf(&q) < gap
        })
    }

    /// The solids and container faces closer to `p` than `reach` (signed distance):
    /// each one's distance and outward normal there (central differences with step
    /// `eps`).
    pub fn near<'a>(
        &'a self,
        p: &'a Vect<D>,
        reach: Real,
        eps: Real,
    ) -> impl Iterator<Item = (Real, Vect<D>)> + 'a {
        let faces = self.faces.iter().map(|f| (f, &None));
        self.solids
            .iter()
            .map(|(shape, pose)| (shape, pose))
            .chain(faces)
            .filter_map(move |(shape, pose)| {
                let q = local(pose, p);
                let s = shape.sdf(&q);
                (s < reach).then(|| {
                    let n = shape.normal(&q, eps);
                    let n = match pose {
                        Some((_, r)) => from3::<D>(&(r * to3(&n))),
                        None => n,
                    };
                    (s, n)
                })
            })
    }

    /// The signed distance from `p` to the nearest body (infinite without bodies).
    pub fn body_distance(&self, p: &Vect<D>) -> Real {
        self.solids
            .iter()
            .filter(|(_, pose)| pose.is_some())
            .map(|(shape, pose)| shape.sdf(&local(pose, p)))
            .fold(Real::INFINITY, Real::min)
    }
}

/// `p` in the frame of a solid's shape: turned back about the body's centre.
fn local<const D: usize>(pose: &Option<Pose>, p: &Vect<D>) -> Vect<D> {
    match pose {
        Some((c, r)) => from3::<D>(&(c + r.inverse() * (to3(p) - c))),
        None => *p,
    }
}
