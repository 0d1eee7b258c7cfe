//! The `/geometry` topic's `foxglove.SceneUpdate`: each wall object (wall, terrain,
//! barrier, container face) as one `SceneEntity` of solid primitives that Foxglove's
//! 3D panel draws, in the particles' frame `world`. The solids come from
//! [`granmix_core::geometry::solids`]; a moving object's primitives are shifted by its current
//! offset, so that re-sending its entity (same `id`, its name) moves it.

use foxglove::messages::{
    Color, CubePrimitive, CylinderPrimitive, KeyValuePair, Point3, Pose, Quaternion, SceneEntity,
    SceneUpdate, SpherePrimitive, Timestamp, TriangleListPrimitive, Vector3,
};
use granmix_core::geometry::solids::{Primitive, WallSolid};
use granmix_core::geometry::walls::WallKind;

/// Frame id of the simulation's coordinates.
pub const WORLD_FRAME: &str = "world";

/// Colour (RGBA) of a kind of wall object: containers see-through so that what they
/// hold shows.
pub fn colour(kind: WallKind) -> Color {
    let (r, g, b, a) = match kind {
        WallKind::Wall => (0.6, 0.6, 0.6, 0.7),
        WallKind::Terrain => (0.55, 0.45, 0.3, 0.85),
        WallKind::Barrier => (0.95, 0.5, 0.1, 0.85),
        WallKind::Container => (0.5, 0.6, 0.75, 0.3),
    };
    Color { r, g, b, a }
}

fn v3(p: [f64; 3]) -> Vector3 {
    Vector3 {
        x: p[0],
        y: p[1],
        z: p[2],
    }
}

fn plus(a: &[f64; 3], b: &[f64; 3]) -> [f64; 3] {
    [a[0] + b[0], a[1] + b[1], a[2] + b[2]]
}

/// A pose at `position` turned by the unit quaternion `q` (w, x, y, z).
fn pose(position: [f64; 3], q: [f64; 4]) -> Option<Pose> {
    Some(Pose {
        position: Some(v3(position)),
        orientation: Some(Quaternion {
            w: q[0],
            x: q[1],
            y: q[2],
            z: q[3],
        }),
    })
}

const UPRIGHT: [f64; 4] = [1.0, 0.0, 0.0, 0.0];

/// The entity of `solid` shifted by `offset` (m), stamped `time`.
pub fn entity(solid: &WallSolid, offset: &[f64; 3], time: Timestamp) -> SceneEntity {
    let color = Some(colour(solid.kind));
    let mut e = SceneEntity {
        timestamp: Some(time),
        frame_id: WORLD_FRAME.into(),
        id: solid.name.clone(),
        metadata: [
            ("object", solid.object.to_string()),
            ("kind", solid.kind.name().to_string()),
            ("moving", solid.moving.to_string()),
        ]
        .map(|(key, value)| KeyValuePair {
            key: key.into(),
            value,
        })
        .into(),
        ..Default::default()
    };
    match &solid.primitive {
        Primitive::Cube {
            center,
            size,
            orientation,
        } => e.cubes.push(CubePrimitive {
            pose: pose(plus(center, offset), *orientation),
            size: Some(v3(*size)),
            color,
        }),
        Primitive::Cylinder { center, size } => e.cylinders.push(CylinderPrimitive {
            pose: pose(plus(center, offset), UPRIGHT),
            size: Some(v3(*size)),
            bottom_scale: 1.0,
            top_scale: 1.0,
            color,
        }),
        Primitive::Sphere { center, size } => e.spheres.push(SpherePrimitive {
            pose: pose(plus(center, offset), UPRIGHT),
            size: Some(v3(*size)),
            color,
        }),
        Primitive::Triangles { points, indices } => e.triangles.push(TriangleListPrimitive {
            pose: pose(*offset, UPRIGHT),
            points: points
                .iter()
                .map(|p| Point3 {
                    x: p[0],
                    y: p[1],
                    z: p[2],
                })
                .collect(),
            color,
            colors: Vec::new(),
            indices: indices.clone(),
        }),
    }
    e
}

/// The update of `solids`, each shifted by its object's entry of `offsets`.
pub fn update(solids: &[WallSolid], offsets: &[[f64; 3]], time: Timestamp) -> SceneUpdate {
    SceneUpdate {
        deletions: Vec::new(),
        entities: solids
            .iter()
            .map(|s| entity(s, &offsets[s.object], time))
            .collect(),
    }
}
