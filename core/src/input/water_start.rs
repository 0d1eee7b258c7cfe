//! The water's start, checked from the shapes before any particle is placed, so that
//! plain `check` refuses what the build would: a sound speed below the expected flow
//! speed or none that can be derived, a speed scale below a speed the water is given
//! (the build's own rule, [`flow_speed::choose`]), an inlet that meets nothing of the
//! scene, and an outflow that removes a whole water region at t = 0. The build repeats
//! the first checks on its particles.
//!
//! [`flow_speed::choose`]: crate::estimate::flow_speed::choose

use crate::estimate::flow_speed::{bounds, water_speed, WaterSpeed};
use crate::numerics::math::Real;
use crate::scene::resolution::Resolution;
use crate::scene::{KeyError, Scene, ShapeSpec};

/// Refuse a water start that the build or the first step would refuse; the water's
/// speeds otherwise (`None` without water).
pub fn check_water_start(scene: &Scene, res: &Resolution) -> Result<Option<WaterSpeed>, KeyError> {
    let speed = water_speed(scene, res)?;
    let Some(w) = &scene.water else {
        return Ok(speed);
    };
    let fail = |key: String, msg: String| Err(KeyError::new(key, msg));
    let (lo, hi) = reach(scene, res.dp);
    for (i, f) in w.inflows.iter().enumerate() {
        let ShapeSpec::Box { min, max } = &f.shape else {
            continue;
        };
        if (0..lo.len()).any(|k| max[k] < lo[k] || min[k] > hi[k]) {
            return fail(
                format!("water.inflows[{i}].shape"),
                format!(
                    "inlet `{}` lies outside the scene: its box {min:?}..{max:?} meets none of \
                     the walls, barriers, grains or water, which span {lo:?}..{hi:?}",
                    f.name
                ),
            );
        }
    }
    for (i, o) in w.outflows.iter().enumerate() {
        for r in &w.regions {
            let (rlo, rhi) = bounds(scene, &r.shape);
            if beyond(&o.point, &o.normal, &rlo, &rhi) {
                return fail(
                    format!("water.outflows[{i}]"),
                    format!(
                        "outflow `{}` removes the whole water region `{}` at t = 0: the region \
                         lies on the side its normal points to; turn the normal or move the \
                         plane",
                        o.name, r.name
                    ),
                );
            }
        }
    }
    Ok(speed)
}

/// Whether the box [lo, hi] lies wholly on the side of the plane (point, normal) that
/// the normal points to, where an outflow removes water.
fn beyond(point: &[Real], normal: &[Real], lo: &[Real], hi: &[Real]) -> bool {
    // the box corner nearest the plane's inner side
    let nearest: Real = (0..lo.len())
        .map(|k| {
            let c = if normal[k] >= 0.0 { lo[k] } else { hi[k] };
            normal[k] * (c - point[k])
        })
        .sum();
    nearest > 0.0
}

/// The box spanned by the scene's walls (their layers included), barriers, containers,
/// grains, bodies and water regions.
fn reach(scene: &Scene, dp: Real) -> (Vec<Real>, Vec<Real>) {
    let d = scene.simulation.dimension;
    let depth = scene.numerics.wall_layers as Real * dp;
    let (mut lo, mut hi) = (vec![Real::INFINITY; d], vec![Real::NEG_INFINITY; d]);
    let mut grow = |a: &[Real], b: &[Real], pad: Real| {
        for k in 0..d {
            lo[k] = lo[k].min(a[k] - pad);
            hi[k] = hi[k].max(b[k] + pad);
        }
    };
    for w in scene.walls.iter().chain(&scene.barriers) {
        let (a, b) = bounds(scene, &w.shape);
        grow(&a, &b, depth);
    }
    for c in &scene.containers {
        grow(&c.min, &c.max, depth);
    }
    let shapes = scene
        .regions
        .iter()
        .map(|r| &r.shape)
        .chain(scene.bodies.iter().map(|b| &b.shape))
        .chain(
            scene
                .water
                .iter()
                .flat_map(|w| w.regions.iter().map(|r| &r.shape)),
        );
    for s in shapes {
        let (a, b) = bounds(scene, s);
        grow(&a, &b, 0.0);
    }
    (lo, hi)
}
