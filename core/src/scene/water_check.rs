//! Checks on the `[water]` table, after the rest of the scene (`scene::validate`).
//! The sound speed against a derived speed scale is checked where the scale is known,
//! when the water is filled ([`world`](crate::world)); a scale given in the scene is
//! checked here.

use super::validate::{fail, positive, validate_solid_shape, vec_len, Check};
use super::Scene;
use std::collections::HashSet;

/// `[water]` and its `[[water.regions]]`.
pub(super) fn validate_water(s: &Scene) -> Check {
    let Some(w) = &s.water else {
        return Ok(());
    };
    let d = s.simulation.dimension;
    positive("water.density", w.density)?;
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
    if let (Some(c), Some(u)) = (w.sound_speed, w.speed_scale) {
        if c < u {
            return fail(
                "water.sound_speed",
                format!(
                    "c0 = {c:?} m/s is below the expected flow speed `water.speed_scale` = {u:?} m/s: \
                     the water would compress by far more than 1 %; take c0 ≥ 10 × {u:?} = {:?} m/s",
                    10.0 * u
                ),
            );
        }
    }
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
    if w.regions.is_empty() {
        return fail(
            "water.regions",
            "[water] needs at least one [[water.regions]] entry saying where the water starts",
        );
    }
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
            vec_len(&format!("{p}.velocity"), v, d)?;
        }
    }
    Ok(())
}
