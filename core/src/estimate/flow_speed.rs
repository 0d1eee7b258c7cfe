//! The water's expected flow speed U and its sound speed c0, chosen by one rule
//! ([`choose`]) for the build and for what runs before it.
//!
//! The build ([`world`](crate::world)) measures the speeds on the particles it places.
//! The load checks of [`input`](crate::input) and the time step at rest
//! ([`estimate::rest_dt`](crate::estimate::rest_dt)) measure them on the scene's shapes
//! before any particle exists ([`water_speed`]): on the same lattice, less the same
//! solids, so that both choose the same c0.

use crate::geometry::start_solids::Solids;
use crate::geometry::Shape;
use crate::numerics::math::{box_extent, extent, up, Real, Vect};
use crate::numerics::periodic::{axis_index, hydrostatic};
use crate::scene::resolution::Resolution;
use crate::scene::{KeyError, Scene, ShapeSpec, WaterSpec};
use std::borrow::Cow;

/// The water's speeds as the build chooses them.
#[derive(Clone, Debug, PartialEq)]
pub struct WaterSpeed {
    /// The expected flow speed U: `water.speed_scale` if given, else the fastest of
    /// the [`Measured`] speeds.
    pub scale: Real,
    /// The fastest speed the water is given ([`Measured::initial`]).
    pub initial: Real,
    /// The sound speed c0: `water.sound_speed` if given, else 10 U.
    pub c0: Real,
    /// The key c0 comes from: `water.sound_speed`, `water.speed_scale` or, derived
    /// from the fall height, `simulation.gravity`.
    pub key: &'static str,
}

/// What the water does before it moves, measured on its particles (or on the lattice
/// they will take).
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct Measured {
    /// The fastest fall √(2 g H) over the water regions, the pores of the saturated
    /// soils and the inlets, H being each one's extent along gravity.
    pub fall: Real,
    /// The fastest speed the water is given: a region's initial velocity, an inflow's
    /// speed or its hydrograph's peak.
    pub initial: Real,
}

impl Measured {
    /// Take the fall through `(bottom, top)`, an extent along gravity of magnitude `g`.
    pub fn fall(&mut self, g: Real, (bottom, top): (Real, Real)) {
        self.fall = self.fall.max((2.0 * g * (top - bottom)).sqrt());
    }

    /// Take a speed the water is given.
    pub fn given(&mut self, u: Real) {
        self.initial = self.initial.max(u);
    }
}

/// The one rule: U is `water.speed_scale` if given, else the fastest measured speed;
/// c0 is `water.sound_speed` if given, else 10 U, which keeps the water's density
/// within 1 % of ρ_w. Refused, with the key to change: a speed scale below a speed the
/// water is given, a sound speed below U (the water would compress by far more than
/// 1 %), and no sound speed at all (the water neither falls nor moves).
pub fn choose(spec: &WaterSpec, m: Measured) -> Result<WaterSpeed, KeyError> {
    let scale = spec.speed_scale.unwrap_or(m.fall.max(m.initial));
    if let Some(u) = spec.speed_scale.filter(|u| *u < m.initial) {
        return Err(KeyError::new(
            "water.speed_scale",
            format!(
                "speed_scale = {u:?} m/s is below the speed {:?} m/s the water is given (a \
                 region's initial velocity or an inflow); c0 = 10 × speed_scale would let the \
                 water compress by far more than 1 %: take speed_scale ≥ {:?} m/s",
                m.initial, m.initial
            ),
        ));
    }
    let (c0, key) = match (spec.sound_speed, spec.speed_scale) {
        (Some(c), Some(u)) if c < scale => {
            return Err(KeyError::new(
                "water.sound_speed",
                format!(
                    "c0 = {c:?} m/s is below the expected flow speed `water.speed_scale` = \
                     {u:?} m/s: the water would compress by far more than 1 %; take c0 ≥ 10 × \
                     {u:?} = {:?} m/s",
                    10.0 * u
                ),
            ))
        }
        (Some(c), None) if c < scale => {
            return Err(KeyError::new(
                "water.sound_speed",
                format!(
                    "c0 = {c:?} m/s is below the expected flow speed {scale:?} m/s (√(2 g H) \
                     over the tallest water region, or its initial speed): the water would \
                     compress by far more than 1 %; take c0 ≥ {:?} m/s, or set \
                     `water.speed_scale`",
                    10.0 * scale
                ),
            ))
        }
        (Some(c), _) => (c, "water.sound_speed"),
        (None, _) if scale.is_nan() || scale <= 0.0 => {
            return Err(KeyError::new(
                "water.sound_speed",
                "the water neither falls (no gravity) nor moves, so no flow speed can be \
                 derived: give `water.sound_speed` or `water.speed_scale`",
            ))
        }
        (None, Some(_)) => (10.0 * scale, "water.speed_scale"),
        (None, None) => (10.0 * scale, "simulation.gravity"),
    };
    Ok(WaterSpeed {
        scale,
        initial: m.initial,
        c0,
        key,
    })
}

/// Whether the material named `name` is a saturated soil.
pub fn saturated(scene: &Scene, name: &str) -> bool {
    scene
        .materials
        .iter()
        .any(|m| m.name == name && m.saturated && m.porosity.is_some())
}

/// The `[water]` of a scene's water: its own, or every key's default for the pores of a
/// saturated soil in a scene without one; `None` without either.
pub fn water_spec(scene: &Scene) -> Option<Cow<'_, WaterSpec>> {
    match &scene.water {
        Some(w) => Some(Cow::Borrowed(w)),
        None if scene.regions.iter().any(|r| saturated(scene, &r.material)) => Some(Cow::Owned(
            toml::from_str("").expect("every [water] key has a default"),
        )),
        None => None,
    }
}

/// The water's speeds, measured on the scene's shapes as the build will measure them
/// on its particles ([`measure`]); `None` when the scene holds no water (no water
/// region, inlet or saturated soil). Refused as [`choose`] refuses.
pub fn water_speed(scene: &Scene, res: &Resolution) -> Result<Option<WaterSpeed>, KeyError> {
    let Some(spec) = water_spec(scene) else {
        return Ok(None);
    };
    let m = match scene.simulation.dimension {
        2 => measure::<2>(scene, &spec, res),
        _ => measure::<3>(scene, &spec, res),
    };
    m.map(|m| choose(&spec, m)).transpose()
}

/// Most lattice points the bounding box of a shape may hold for [`measure`] to fill it
/// as the build does (a few milliseconds); a larger shape is measured by its bounding
/// box, which reaches at most a spacing or so further.
const MEASURED_POINTS: Real = (1u64 << 20) as Real;

/// The water's speeds from the scene's shapes: each water region and saturated soil
/// filled on the build's lattice less the build's solids, as long as it is small
/// enough ([`MEASURED_POINTS`]), each inlet by its box; `None` without any of them. A
/// jittered soil's pores are measured unjittered.
fn measure<const D: usize>(scene: &Scene, spec: &WaterSpec, res: &Resolution) -> Option<Measured> {
    let sim = &scene.simulation;
    let axis = sim.periodic.as_ref().and_then(|p| axis_index(&p.axis));
    let g = hydrostatic(Vect::<D>::from_iterator(sim.gravity.iter().copied()), axis);
    let (gn, up) = (g.norm(), up(&g));
    let mut m = Measured::default();
    let mut any = false;
    let water = Solids::<D>::of(scene, true);
    for r in &spec.regions {
        m.fall(gn, lattice_extent(scene, &r.shape, &water, res.dp, &up));
        if let Some(v) = &r.velocity {
            m.given(Vect::<D>::from_iterator(v.iter().copied()).norm());
        }
        any = true;
    }
    let soil = Solids::<D>::of(scene, false);
    for r in scene
        .regions
        .iter()
        .filter(|r| saturated(scene, &r.material))
    {
        m.fall(gn, lattice_extent(scene, &r.shape, &soil, res.dp, &up));
        any = true;
    }
    for f in &spec.inflows {
        if let ShapeSpec::Box { min, max } = &f.shape {
            let v = |x: &[Real]| Vect::<D>::from_iterator(x.iter().copied());
            m.fall(gn, box_extent(&v(min), &v(max), &up));
        }
        m.given(match (f.speed, &f.hydrograph) {
            (Some(u), _) => u,
            (None, Some(h)) => h.peak(),
            (None, None) => 0.0,
        });
        any = true;
    }
    any.then_some(m)
}

/// The extent along `up` of the particles the build places in `shape` at spacing `dp`
/// (its lattice less what `solids` hold), or of its bounding box where that holds more
/// than [`MEASURED_POINTS`] lattice points or none is left.
fn lattice_extent<const D: usize>(
    scene: &Scene,
    spec: &ShapeSpec,
    solids: &Solids<D>,
    dp: Real,
    up: &Vect<D>,
) -> (Real, Real) {
    let shape = Shape::<D>::from_spec(spec, &scene.assets);
    let (lo, hi) = shape.bounds();
    let points: Real = (0..D).map(|k| (hi[k] - lo[k]) / dp + 3.0).product();
    if points <= MEASURED_POINTS {
        let mut pts = shape.fill(dp);
        pts.retain(|p| !solids.holds(p, dp));
        if !pts.is_empty() {
            return extent(&pts, up, dp);
        }
    }
    box_extent(&lo, &hi, up)
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

#[cfg(test)]
mod tests {
    use super::*;
    use crate::input::bundled_scenes;
    use crate::water::material::WaterMaterial;
    use crate::world::World;

    fn built_water<const D: usize>(scene: &Scene) -> Option<WaterMaterial> {
        let world = World::<D>::build(scene, Resolution::of::<D>(scene)).expect("builds");
        world.water.material
    }

    /// The sound speed and speed scale that the load checks and the time step at rest
    /// take are the ones the build gives the water, bit for bit, in every bundled scene
    /// with water.
    #[test]
    fn the_estimate_chooses_the_built_sound_speed() {
        let mut checked = Vec::new();
        for (name, loaded) in bundled_scenes() {
            let scene = &loaded.scene;
            let speed = water_speed(scene, &Resolution::of_scene(scene)).expect("loaded");
            let built = match scene.simulation.dimension {
                2 => built_water::<2>(scene),
                _ => built_water::<3>(scene),
            };
            match (speed, built) {
                (Some(s), Some(m)) => {
                    assert_eq!((s.c0, s.scale), (m.c0, m.speed_scale), "{name}");
                    checked.push(name);
                }
                (None, None) => {}
                (s, m) => panic!("{name}: estimated {s:?}, built {m:?}"),
            }
        }
        assert!(checked.len() >= 11, "{checked:?}");
    }

    /// A scene whose soil has pores but no water (the dry counterpart of a saturated
    /// one) holds no water, before the build as in it.
    #[test]
    fn dry_pores_hold_no_water() {
        let (_, loaded) = bundled_scenes()
            .into_iter()
            .find(|(n, _)| n == "saturated_collapse_2d.toml")
            .expect("bundled");
        let mut scene = loaded.scene;
        scene.materials[0].saturated = false;
        let res = Resolution::of_scene(&scene);
        assert_eq!(water_speed(&scene, &res), Ok(None));
        assert!(built_water::<2>(&scene).is_none());
    }

    /// The one rule's refusals name the key to change.
    #[test]
    fn choose_refuses_with_the_key() {
        let spec = |extra: &str| -> WaterSpec { toml::from_str(extra).expect("a [water] table") };
        let m = Measured {
            fall: 3.0,
            initial: 1.0,
        };
        let key = |s: &str| choose(&spec(s), m).map_err(|e| e.path);
        assert_eq!(choose(&spec(""), m).map(|w| w.c0), Ok(30.0));
        assert_eq!(key("sound_speed = 2.0"), Err("water.sound_speed".into()));
        assert_eq!(
            key("sound_speed = 20.0\nspeed_scale = 30.0"),
            Err("water.sound_speed".into())
        );
        assert_eq!(key("speed_scale = 0.5"), Err("water.speed_scale".into()));
        let still = Measured::default();
        assert_eq!(
            choose(&spec(""), still).map_err(|e| e.path),
            Err("water.sound_speed".into())
        );
        assert_eq!(
            choose(&spec("sound_speed = 5.0"), still).map(|w| w.c0),
            Ok(5.0)
        );
    }
}
