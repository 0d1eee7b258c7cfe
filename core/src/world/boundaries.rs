//! The walls of a scene: wall and barrier shapes as layers of wall particles (seed 000
//! §2.5), container faces, and the barriers' load panels.

use super::v;
use crate::geometry::walls::{
    container_faces, Barrier, ContainerFace, WallKind, WallObject, Walls,
};
use crate::geometry::Shape;
use crate::numerics::math::{Real, Vect};
use crate::numerics::periodic::Wrap;
use crate::scene::build_error::BuildError;
use crate::scene::{ContainerSpec, Scene, ShapeSpec};

/// The wall particles of every wall, barrier and container face, barriers split into
/// their panels.
pub(super) fn build<const D: usize>(
    scene: &Scene,
    dp: Real,
    vol: Real,
    periodic: Wrap,
) -> Result<Walls<D>, BuildError> {
    let layers = scene.numerics.wall_layers;
    let mut walls = Walls::<D> {
        volume: vol,
        ..Default::default()
    };
    for (list, key, is_barrier) in [
        (&scene.walls, "walls", false),
        (&scene.barriers, "barriers", true),
    ] {
        for (wi, w) in list.iter().enumerate() {
            let shape = Shape::<D>::from_spec(&w.shape, &scene.assets);
            let pts = shape.wall_fill(dp, layers);
            if pts.is_empty() {
                return Err(BuildError {
                    path: format!("{key}[{wi}].shape"),
                    message: format!("`{}` holds no wall particle at dp = {dp:?} m", w.name),
                });
            }
            let vel = w
                .velocity
                .as_deref()
                .map(v::<D>)
                .unwrap_or_else(Vect::<D>::zeros);
            let reference =
                w.reference_point
                    .as_deref()
                    .map(v::<D>)
                    .unwrap_or_else(|| match &w.shape {
                        ShapeSpec::Plane { point, .. } => v::<D>(point),
                        _ => shape.center(),
                    });
            let window = match w.move_between.as_deref() {
                Some([t0, t1]) => (*t0, *t1),
                _ => (Real::NEG_INFINITY, Real::INFINITY),
            };
            add_object(
                &mut walls,
                &w.name,
                pts,
                vel,
                window,
                is_barrier.then_some(reference),
                shape,
            );
            if let Some(o) = walls.objects.last_mut() {
                o.driven = w.input.is_some();
                o.permeable = w.permeable;
                o.kind = match (&w.shape, is_barrier) {
                    (_, true) => WallKind::Barrier,
                    (ShapeSpec::Heightmap { .. }, false) => WallKind::Terrain,
                    _ => WallKind::Wall,
                };
            }
        }
    }
    for c in &scene.containers {
        container(&mut walls, c, layers as Real * dp, dp, periodic);
    }
    crate::geometry::panels::split_scene_panels(&mut walls, scene);
    Ok(walls)
}

/// The closed faces of container `c` as boxes of wall particles `t` thick; along a
/// periodic axis the faces are cut to the period, so that they join across the seam.
fn container<const D: usize>(
    walls: &mut Walls<D>,
    c: &ContainerSpec,
    t: Real,
    dp: Real,
    periodic: Wrap,
) {
    let (lo, hi) = (v::<D>(&c.min), v::<D>(&c.max));
    for ContainerFace {
        face,
        axis: a,
        sign,
        min: mut fmin,
        max: mut fmax,
    } in container_faces::<D>(c, t)
    {
        if let Some(p) = periodic {
            (fmin[p.axis], fmax[p.axis]) = (p.lo, p.lo + p.len);
        }
        let shape = Shape::<D>::Box {
            min: fmin,
            max: fmax,
        };
        let pts = shape.fill(dp);
        let name = format!("{}.{}", c.name, face_name(&face, D));
        let solid = shape.clone();
        let mut reference = (lo + hi) * 0.5;
        reference[a] = if sign < 0.0 { lo[a] } else { hi[a] };
        add_object(
            walls,
            &name,
            pts,
            Vect::<D>::zeros(),
            (Real::NEG_INFINITY, Real::INFINITY),
            c.report_loads.then_some(reference),
            solid,
        );
        if let Some(o) = walls.objects.last_mut() {
            o.kind = WallKind::Container;
        }
    }
}

/// Append one wall object (a barrier when `barrier` holds its reference point) and its
/// particles.
fn add_object<const D: usize>(
    walls: &mut Walls<D>,
    name: &str,
    pts: Vec<Vect<D>>,
    vel: Vect<D>,
    window: (Real, Real),
    barrier: Option<Vect<D>>,
    shape: Shape<D>,
) {
    let o = walls.objects.len() as u16;
    let b = barrier.map(|reference| {
        walls.barriers.push(Barrier {
            name: name.to_string(),
            object: o as usize,
            reference,
            panels: Vec::new(),
            slot0: walls.barriers.len(),
            panel_axes: Vec::new(),
            panel_lo: Vect::<D>::zeros(),
            panel_hi: Vect::<D>::zeros(),
        });
        walls.barriers.len() - 1
    });
    walls.objects.push(WallObject {
        name: name.to_string(),
        kind: WallKind::Wall,
        velocity: vel,
        prescribed: vel,
        window,
        barrier: b,
        displacement: Vect::<D>::zeros(),
        shape: Some(shape),
        driven: false,
        permeable: false,
    });
    for p in pts {
        walls.pos.push(p);
        walls.object.push(o);
    }
}

/// Human name of a container face: the vertical axis gives bottom/top.
fn face_name(face: &str, dim: usize) -> &'static str {
    match (face, dim) {
        ("-x", _) => "left",
        ("+x", _) => "right",
        ("-y", 2) | ("-z", 3) => "bottom",
        ("+y", 2) | ("+z", 3) => "top",
        ("-y", _) => "front",
        _ => "back",
    }
}
