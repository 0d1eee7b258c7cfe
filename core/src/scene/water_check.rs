//! Checks on the `[water]` table, after the rest of the scene (`scene::validate`).
//! The sound speed against a derived speed scale is checked where the scale is known,
//! when the water is filled ([`world`](crate::world)); a scale given in the scene is
//! checked here.

use super::validate::{
    density, direction, fail, initial_velocity, positive, validate_solid_shape, vec_len, Check,
};
use super::{validate_shape, Scene, ShapeSpec};
use std::collections::HashSet;

/// `[[water.inflows]]` and `[[water.outflows]]`.
fn validate_open_boundaries(s: &Scene) -> Check {
    let Some(w) = &s.water else {
        return Ok(());
    };
    let d = s.simulation.dimension;
    let mut names = HashSet::new();
    for (i, f) in w.inflows.iter().enumerate() {
        let p = format!("water.inflows[{i}]");
        if !names.insert(f.name.as_str()) {
            return fail(
                format!("{p}.name"),
                format!("duplicate inflow name `{}`", f.name),
            );
        }
        let ShapeSpec::Box { min, max } = &f.shape else {
            return fail(format!("{p}.shape.type"), "an inlet must be a box");
        };
        validate_shape(&format!("{p}.shape"), &f.shape, d)?;
        let axes = ["x", "y", "z"];
        let axis = f
            .direction
            .strip_prefix(['+', '-'])
            .and_then(|a| axes[..d].iter().position(|x| *x == a))
            .filter(|_| f.direction.len() == 2);
        let Some(axis) = axis else {
            let allowed: Vec<String> = axes[..d]
                .iter()
                .flat_map(|a| [format!("\"+{a}\""), format!("\"-{a}\"")])
                .collect();
            return fail(
                format!("{p}.direction"),
                format!(
                    "must be one of {}, found {:?}",
                    allowed.join(", "),
                    f.direction
                ),
            );
        };
        let length = max[axis] - min[axis];
        if length < 3.0 * s.simulation.dp {
            return fail(
                format!("{p}.shape"),
                format!(
                    "the inlet is {length:?} m long along {}, less than three particle \
                     spacings (3 dp = {:?} m)",
                    f.direction,
                    3.0 * s.simulation.dp
                ),
            );
        }
        match (f.speed, &f.hydrograph) {
            (Some(u), None) => positive(&format!("{p}.speed"), u)?,
            (None, Some(crate::scene::Hydrograph::Gumbel { a, beta, .. })) => {
                positive(&format!("{p}.hydrograph.a"), *a)?;
                positive(&format!("{p}.hydrograph.beta"), *beta)?;
            }
            _ => return fail(
                p,
                "give the inflow either `speed` (m/s) or `hydrograph`, not both and not neither",
            ),
        }
        if let Some(t) = f.stop {
            positive(&format!("{p}.stop"), t)?;
        }
    }
    for (i, o) in w.outflows.iter().enumerate() {
        let p = format!("water.outflows[{i}]");
        vec_len(&format!("{p}.point"), &o.point, d)?;
        direction(&format!("{p}.normal"), &o.normal, d)?;
    }
    Ok(())
}

/// `[water]` and its `[[water.regions]]`.
pub(super) fn validate_water(s: &Scene) -> Check {
    let Some(w) = &s.water else {
        return Ok(());
    };
    let d = s.simulation.dimension;
    density("water.density", w.density)?;
    if !(w.viscosity.is_finite() && w.viscosity >= 0.0) {
        return fail(
            "water.viscosity",
            format!(
                "the dynamic viscosity must be ≥ 0 Pa·s (water at 20 °C: 1.0e-3), found {:?}",
                w.viscosity
            ),
        );
    }
    if let Some(c) = w.sound_speed {
        positive("water.sound_speed", c)?;
    }
    if let Some(u) = w.speed_scale {
        positive("water.speed_scale", u)?;
    }
    // c0 against the expected flow speed: flow_speed::choose, at load and in the build
    if let Some(eta) = w.limiter {
        if !(eta.is_finite() && eta >= 0.0) {
            return fail(
                "water.limiter",
                format!("must be ≥ 0 (leave it out for no limiter), found {eta:?}"),
            );
        }
    }
    if !(w.settle_time.is_finite() && w.settle_time >= 0.0) {
        return fail(
            "water.settle_time",
            format!(
                "must be ≥ 0 s (0: no settling phase), found {:?}",
                w.settle_time
            ),
        );
    }
    // a soil with pores may hold the water (saturated) or be its dry counterpart
    let pores = s
        .materials
        .iter()
        .any(|m| m.saturated || m.porosity.is_some());
    if w.regions.is_empty() && w.inflows.is_empty() && !pores {
        return fail(
            "water.regions",
            "[water] needs at least one [[water.regions]] entry saying where the water \
             starts, a [[water.inflows]] entry letting it in, or a soil with pores \
             (`porosity`, `saturated = true` in [[materials]])",
        );
    }
    validate_open_boundaries(s)?;
    let mut names = HashSet::new();
    for (i, r) in w.regions.iter().enumerate() {
        let p = format!("water.regions[{i}]");
        if !names.insert(r.name.as_str()) {
            return fail(
                format!("{p}.name"),
                format!("duplicate water region name `{}`", r.name),
            );
        }
        validate_solid_shape(&format!("{p}.shape"), &r.shape, d, "hold water")?;
        if let Some(v) = &r.velocity {
            initial_velocity(&format!("{p}.velocity"), v, s)?;
        }
    }
    Ok(())
}
