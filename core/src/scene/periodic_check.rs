//! Checks on `simulation.periodic`, after the rest of the scene (`scene::validate`):
//! the axis, a period of whole particle spacings and at least three list radii (the
//! wrapped cell stencil of [`neighbors`](crate::numerics::neighbors) needs three distinct cells
//! across it), only water inside, and containers open across the axis.

use super::validate::{fail, Check};
use super::Scene;

/// `simulation.periodic`, if set.
pub(super) fn validate_periodic(s: &Scene) -> Check {
    let Some(p) = &s.simulation.periodic else {
        return Ok(());
    };
    let d = s.simulation.dimension;
    let names = &["x", "y", "z"][..d];
    let Some(axis) = names.iter().position(|&a| a == p.axis) else {
        return fail(
            "simulation.periodic.axis",
            format!(
                "must be one of {names:?} in a {d}D scene, found {:?}",
                p.axis
            ),
        );
    };
    if !(p.min.is_finite() && p.max.is_finite() && p.max > p.min) {
        return fail(
            "simulation.periodic.max",
            format!("must exceed min = {:?}, found {:?}", p.min, p.max),
        );
    }
    let (len, dp) = (p.max - p.min, s.simulation.dp);
    let layers = len / dp;
    if (layers - layers.round()).abs() > 1e-6 * layers.max(1.0) {
        return fail(
            "simulation.periodic.max",
            format!(
                "the period {len:?} m is {layers:.4} particle spacings (dp = {dp:?} m); \
                 make it a whole number so the particle lattice joins across the seam"
            ),
        );
    }
    let n = &s.numerics;
    let radius = (2.0 * n.smoothing_ratio + n.neighbor_skin) * dp;
    if len < 3.0 * radius {
        return fail(
            "simulation.periodic.max",
            format!(
                "the period {len:?} m is under three neighbour-list radii (3 × {radius:.4e} m \
                 = 2h + skin); lengthen it or refine dp"
            ),
        );
    }
    for (key, used) in [
        ("bodies", !s.bodies.is_empty()),
        ("rock_fills", !s.rock_fills.is_empty()),
    ] {
        if used {
            return fail(
                key,
                "periodic boundaries carry soil or water, not boulders, so far: remove \
                 the boulders or `simulation.periodic`",
            );
        }
    }
    if !s.regions.is_empty() && s.water.is_some() {
        return fail(
            "regions",
            "periodic boundaries carry soil or water, not both together, so far: remove \
             the soil, the `[water]` section or `simulation.periodic`",
        );
    }
    for (i, c) in s.containers.iter().enumerate() {
        let open = c.open.clone().unwrap_or_default();
        for side in ["-", "+"] {
            let face = format!("{side}{}", p.axis);
            if !open.contains(&face) {
                return fail(
                    format!("containers[{i}].open"),
                    format!(
                        "a container in a scene periodic along {} must leave its faces \
                         across that axis open: add \"-{0}\" and \"+{0}\"",
                        p.axis
                    ),
                );
            }
        }
        if c.min.get(axis).is_some_and(|&m| m > p.min)
            || c.max.get(axis).is_some_and(|&m| m < p.max)
        {
            return fail(
                format!("containers[{i}].min"),
                format!(
                    "a container in a scene periodic along {} must span the period [{:?}, {:?}] \
                     along it (its faces are cut to the period)",
                    p.axis, p.min, p.max
                ),
            );
        }
    }
    Ok(())
}
