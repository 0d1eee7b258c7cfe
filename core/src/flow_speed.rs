//! The water's expected flow speed and its sound speed, taken from the scene's shapes
//! before any particle exists: for `granmix check`, the time step at rest
//! ([`estimate::rest_dt`](crate::estimate::rest_dt)) and the start checks of
//! [`input`](crate::input). The build ([`world`](crate::world)) takes the same
//! quantities from the particles it places and has the last word.

use crate::geometry::Shape;
use crate::math::Real;
use crate::scene::{Hydrograph, Scene, ShapeSpec, WaterSpec};

/// The water's speeds as the build will choose them.
#[derive(Clone, Debug, PartialEq)]
pub struct WaterSpeed {
    /// The expected flow speed U: `water.speed_scale` if given, else the largest of
    /// √(2 g H) over the water regions, saturated soil regions and inlets (H their
    /// extent along gravity) and of [`initial`](Self::initial).
    pub scale: Real,
    /// The fastest speed the water is given: a region's initial velocity, an inflow's
    /// speed or its hydrograph's peak.
    pub initial: Real,
    /// The sound speed c0: `water.sound_speed` if given, else 10 U (0 when U is 0).
    pub c0: Real,
    /// The key c0 comes from: `water.sound_speed`, `water.speed_scale` or, derived
    /// from the fall height, `simulation.gravity`.
    pub key: &'static str,
}

/// Whether the material named `name` is a saturated soil.
pub fn saturated(scene: &Scene, name: &str) -> bool {
    scene
        .materials
        .iter()
        .any(|m| m.name == name && m.saturated && m.porosity.is_some())
}

/// The water's speeds; `None` without water (neither `[water]` nor a saturated soil,
/// whose pores take `[water]`'s defaults).
pub fn water_speed(scene: &Scene) -> Option<WaterSpeed> {
    let defaults: WaterSpec;
    let pores = scene.regions.iter().any(|r| saturated(scene, &r.material));
    let w = match &scene.water {
        Some(w) => w,
        None if pores => {
            defaults = toml::from_str("").expect("every [water] key has a default");
            &defaults
        }
        None => return None,
    };
    let g = &scene.simulation.gravity;
    let gn = g.iter().map(|x| x * x).sum::<Real>().sqrt();
    let height = |spec: &ShapeSpec| -> Real {
        let (lo, hi) = bounds(scene, spec);
        // the extent along gravity
        (0..lo.len())
            .map(|k| (hi[k] - lo[k]) * g[k].abs() / gn.max(Real::MIN_POSITIVE))
            .sum()
    };
    let norm = |v: &[f64]| v.iter().map(|x| x * x).sum::<Real>().sqrt();
    let initial = w
        .regions
        .iter()
        .filter_map(|r| r.velocity.as_deref().map(norm))
        .chain(w.inflows.iter().map(|f| match (&f.speed, &f.hydrograph) {
            (Some(u), _) => *u,
            // the Gumbel peak is at t = μ: a/(β e)
            (None, Some(Hydrograph::Gumbel { a, beta, .. })) => a / (beta * std::f64::consts::E),
            (None, None) => 0.0,
        }))
        .fold(0.0, Real::max);
    let fall = w
        .regions
        .iter()
        .map(|r| &r.shape)
        .chain(w.inflows.iter().map(|f| &f.shape))
        .chain(
            scene
                .regions
                .iter()
                .filter(|r| saturated(scene, &r.material))
                .map(|r| &r.shape),
        )
        .map(|s| (2.0 * gn * height(s)).sqrt())
        .fold(0.0, Real::max);
    let scale = w.speed_scale.unwrap_or(fall.max(initial));
    let (c0, key) = match (w.sound_speed, w.speed_scale) {
        (Some(c), _) => (c, "water.sound_speed"),
        (None, Some(_)) => (10.0 * scale, "water.speed_scale"),
        (None, None) => (10.0 * scale, "simulation.gravity"),
    };
    Some(WaterSpeed {
        scale,
        initial,
        c0,
        key,
    })
}

/// The bounding box of a shape of the scene, in its dimension.
pub fn bounds(scene: &Scene, spec: &ShapeSpec) -> (Vec<Real>, Vec<Real>) {
    if scene.simulation.dimension == 2 {
        let (lo, hi) = Shape::<2>::from_spec(spec, &scene.assets).bounds();
        (lo.iter().copied().collect(), hi.iter().copied().collect())
    } else {
        let (lo, hi) = Shape::<3>::from_spec(spec, &scene.assets).bounds();
        (lo.iter().copied().collect(), hi.iter().copied().collect())
    }
}
