//! Where bodies start: a body that starts inside a wall, barrier or closed container
//! face is refused at load. Its particles would sit among the wall's, and the contact
//! would throw it out at thousands of m/s within the first step, where the speed guard
//! stops the run; plain `check` refuses it first.
//!
//! Each body is sampled on a grid of points over its bounding ball (its pose applied);
//! a point deeper than dp/2 inside both the body and a wall's particle layers is an
//! overlap. Bodies only touching a wall (resting on a floor) pass. Two bodies that
//! start overlapping each other are refused alike, with both names.

use super::grid_probe;
use crate::geometry::{tangent_basis, Shape};
use crate::numerics::math::{from3, to3, Real, Vect};
use crate::scene::{spec_rotation, BodySpec, ContainerSpec, KeyError, Scene};

/// Refuse the first body that starts inside a wall, barrier or container face.
pub fn check_bodies(scene: &Scene, dp: Real) -> Result<(), KeyError> {
    match scene.simulation.dimension {
        2 => check_in::<2>(scene, dp),
        _ => check_in::<3>(scene, dp),
    }
}

/// A wall as the overlap test sees it: its name and whether a point lies in its
/// particle layers (deeper than the margin).
struct Wall<'a, const D: usize> {
    name: &'a str,
    inside: Box<dyn Fn(&Vect<D>) -> bool + 'a>,
    /// Bounding box (padded by the layers), to skip bodies far away.
    lo: Vect<D>,
    hi: Vect<D>,
}

/// Refuse the first body of `scene` that starts inside a wall, barrier or container
/// face, at particle spacing `dp`.
fn check_in<const D: usize>(scene: &Scene, dp: Real) -> Result<(), KeyError> {
    if scene.bodies.is_empty() {
        return Ok(());
    }
    let margin = 0.5 * dp;
    let depth = scene.numerics.wall_layers as Real * dp;
    let walls = walls::<D>(scene, depth, margin);
    for (i, b) in scene.bodies.iter().enumerate() {
        check_body(scene, (i, b), &walls, margin)?;
    }
    check_pairs::<D>(scene, margin)
}

/// A body as the overlap tests see it: its signed distance with its pose applied, and
/// the box around its bounding ball.
struct Posed<const D: usize> {
    sdf: Box<dyn Fn(&Vect<D>) -> Real>,
    lo: Vect<D>,
    hi: Vect<D>,
}

impl<const D: usize> Posed<D> {
    fn of(scene: &Scene, b: &BodySpec) -> Self {
        let shape = Shape::<D>::from_spec(&b.shape, &scene.assets);
        let (lo, hi) = shape.bounds();
        let c = shape.center();
        let r = (hi - lo).norm() * 0.5;
        // the body's own frame: the pose undone about its centre
        let rot = spec_rotation(b, D).inverse();
        let c3 = to3(&c);
        Posed {
            sdf: Box::new(move |p: &Vect<D>| shape.sdf(&from3::<D>(&(c3 + rot * (to3(p) - c3))))),
            lo: c.add_scalar(-r),
            hi: c.add_scalar(r),
        }
    }
}

/// Refuse the first two bodies that start overlapping: a point of a grid over the
/// overlap of their bounding boxes deeper than `margin` inside both. Their particles
/// would interpenetrate, and two rigid bodies would stay glued as one (issue 74).
/// Bodies that only touch pass.
fn check_pairs<const D: usize>(scene: &Scene, margin: Real) -> Result<(), KeyError> {
    let posed: Vec<Posed<D>> = scene.bodies.iter().map(|b| Posed::of(scene, b)).collect();
    for i in 0..posed.len() {
        for j in i + 1..posed.len() {
            let (a, b) = (&posed[i], &posed[j]);
            let (lo, hi) = (a.lo.sup(&b.lo), a.hi.inf(&b.hi));
            if (0..D).any(|k| hi[k] - lo[k] <= 2.0 * margin) {
                continue;
            }
            let hit = grid_probe::first((lo, hi), |p| (a.sdf)(p) < -margin && (b.sdf)(p) < -margin);
            if let Some(p) = hit {
                let (bi, bj) = (&scene.bodies[i], &scene.bodies[j]);
                return Err(KeyError::new(
                    format!("bodies[{j}].shape"),
                    format!(
                        "bodies `{}` and `{}` start overlapping (at {:?}): their particles \
                         would interpenetrate, and rigid bodies would move glued together; \
                         move them apart",
                        bi.name,
                        bj.name,
                        p.as_slice()
                    ),
                ));
            }
        }
    }
    Ok(())
}

/// The walls, barriers and containers of `scene` as the overlap test sees them: their
/// particle layers `depth` thick, a point inside deeper than `margin`.
fn walls<const D: usize>(scene: &Scene, depth: Real, margin: Real) -> Vec<Wall<'_, D>> {
    let mut walls: Vec<Wall<D>> = Vec::new();
    for w in scene.walls.iter().chain(&scene.barriers) {
        let shape = Shape::<D>::from_spec(&w.shape, &scene.assets);
        walls.push(Wall::of_shape(&w.name, shape, depth, margin));
    }
    for c in &scene.containers {
        let (lo, hi) = (
            Vect::<D>::from_iterator(c.min.iter().copied()),
            Vect::<D>::from_iterator(c.max.iter().copied()),
        );
        walls.push(Wall {
            name: &c.name,
            inside: Box::new(move |p: &Vect<D>| in_face(c, p, depth, margin)),
            lo: lo.add_scalar(-depth),
            hi: hi.add_scalar(depth),
        });
    }
    walls
}

impl<'a, const D: usize> Wall<'a, D> {
    /// The wall or barrier `name` of `shape`: a plane's patch holds its layers,
    /// `depth` thick, behind its point; another shape, its inside. A point is in it
    /// deeper than `margin`.
    fn of_shape(name: &'a str, shape: Shape<D>, depth: Real, margin: Real) -> Self {
        let (lo, hi) = match &shape {
            // a plane's patch: its layers behind the point, its half extents across
            Shape::Plane {
                point, half_extent, ..
            } => {
                let r = half_extent.iter().fold(depth, |a, h| a.max(*h));
                (point.add_scalar(-r), point.add_scalar(r))
            }
            s => {
                let (lo, hi) = s.bounds();
                (lo.add_scalar(-depth), hi.add_scalar(depth))
            }
        };
        let inside: Box<dyn Fn(&Vect<D>) -> bool> = match shape {
            Shape::Plane {
                point,
                normal,
                half_extent,
            } => {
                let tangents = tangent_basis::<D>(&normal);
                Box::new(move |p: &Vect<D>| {
                    let d = (p - point).dot(&normal);
                    d < -margin
                        && d > -depth
                        && tangents
                            .iter()
                            .zip(&half_extent)
                            .all(|(t, h)| (p - point).dot(t).abs() <= *h)
                })
            }
            s => Box::new(move |p: &Vect<D>| s.sdf(p) < -margin),
        };
        Wall {
            name,
            inside,
            lo,
            hi,
        }
    }
}

/// Refuse body `b` (number `i`) if a point of the grid over its bounding ball lies
/// deeper than `margin` inside both the body (its pose applied) and one of `walls`.
fn check_body<const D: usize>(
    scene: &Scene,
    (i, b): (usize, &BodySpec),
    walls: &[Wall<D>],
    margin: Real,
) -> Result<(), KeyError> {
    let body = Posed::<D>::of(scene, b);
    for w in walls {
        if (0..D).any(|k| body.hi[k] < w.lo[k] || body.lo[k] > w.hi[k]) {
            continue;
        }
        let hit = grid_probe::first((body.lo, body.hi), |p| {
            (body.sdf)(p) < -margin && (w.inside)(p)
        });
        if let Some(p) = hit {
            return Err(KeyError::new(
                format!("bodies[{i}].shape"),
                format!(
                    "body `{}` starts inside wall `{}` (at {:?}): its particles would sit \
                     among the wall's and the contact would throw it out within the first \
                     step; move it clear of the wall",
                    b.name,
                    w.name,
                    p.as_slice()
                ),
            ));
        }
    }
    Ok(())
}

/// Whether `p` lies in a closed face of container `c` (a slab `depth` thick outside
/// its interior box), deeper than `margin`.
fn in_face<const D: usize>(c: &ContainerSpec, p: &Vect<D>, depth: Real, margin: Real) -> bool {
    let default_open = [if D == 2 { "+y" } else { "+z" }.to_string()];
    let open = c.open.as_deref().unwrap_or(&default_open);
    let within = (0..D).all(|k| p[k] > c.min[k] - depth && p[k] < c.max[k] + depth);
    within
        && (0..D).any(|a| {
            let axis = ["x", "y", "z"][a];
            (p[a] < c.min[a] - margin && !open.contains(&format!("-{axis}")))
                || (p[a] > c.max[a] + margin && !open.contains(&format!("+{axis}")))
        })
}
