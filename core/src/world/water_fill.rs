//! The water of a scene: each `[[water.regions]]` shape filled on the lattice of
//! spacing dp, less what lies inside a solid, at the hydrostatic pressure of its
//! region; and the water's sound speed, chosen from the expected flow speed.

use super::regions::Solids;
use super::v;
use crate::build_error::BuildError;
use crate::geometry::Shape;
use crate::math::{Real, Vect};
use crate::scene::Scene;
use crate::water::material::WaterMaterial;
use crate::water::state::WaterParticles;

/// The water particles, their material and the particle count of each region (scene
/// order); `None` without `[water]`.
pub(super) type Filled<const D: usize> = (WaterParticles<D>, WaterMaterial, Vec<(String, usize)>);

/// Fill the water regions of `scene` at spacing `dp` (particle volume `vol`).
pub(super) fn fill<const D: usize>(
    scene: &Scene,
    up: &Vect<D>,
    dp: Real,
    vol: Real,
) -> Result<Option<Filled<D>>, BuildError> {
    let Some(spec) = &scene.water else {
        return Ok(None);
    };
    let gnorm = v::<D>(&scene.simulation.gravity).norm();
    let solids = Solids::<D>::of(scene);
    // every region's lattice points, its top (along `up`) and velocity
    let mut regions = Vec::new();
    let mut speed: Real = 0.0;
    for (ri, r) in spec.regions.iter().enumerate() {
        let shape = Shape::<D>::from_spec(&r.shape, &scene.assets);
        let mut pts = shape.fill(dp);
        if !solids.is_empty() {
            pts.retain(|p| !solids.holds(p, dp));
        }
        if pts.is_empty() {
            return Err(BuildError {
                path: format!("water.regions[{ri}].shape"),
                message: format!(
                    "water region `{}` holds no particle at dp = {dp:?} m; enlarge it or refine dp",
                    r.name
                ),
            });
        }
        let height = |p: &Vect<D>| p.dot(up);
        let top = pts.iter().map(height).fold(Real::NEG_INFINITY, Real::max) + 0.5 * dp;
        let bottom = pts.iter().map(height).fold(Real::INFINITY, Real::min) - 0.5 * dp;
        let vel = r
            .velocity
            .as_deref()
            .map(v::<D>)
            .unwrap_or_else(Vect::<D>::zeros);
        speed = speed
            .max((2.0 * gnorm * (top - bottom)).sqrt())
            .max(vel.norm());
        regions.push((r.name.clone(), pts, top, vel));
    }
    let scale = spec.speed_scale.unwrap_or(speed);
    let c0 = match spec.sound_speed {
        Some(c) if c < scale => {
            return Err(BuildError {
                path: "water.sound_speed".into(),
                message: format!(
                    "c0 = {c:?} m/s is below the expected flow speed {scale:.4} m/s (√(2 g H) over \
                     the tallest water region, or its initial speed): the water would compress by \
                     far more than 1 %; take c0 ≥ {:.4} m/s, or set `water.speed_scale`",
                    10.0 * scale
                ),
            })
        }
        Some(c) => c,
        None if scale > 0.0 => 10.0 * scale,
        None => {
            return Err(BuildError {
                path: "water.sound_speed".into(),
                message: "the water neither falls (no gravity) nor moves, so no flow speed can be \
                          derived: give `water.sound_speed` or `water.speed_scale`"
                    .into(),
            })
        }
    };
    let mat = WaterMaterial::from_spec(spec, c0, scale);
    let mut water = WaterParticles::<D>::default();
    let mut counts = Vec::new();
    for (name, pts, top, vel) in regions {
        for p in &pts {
            let rho = if spec.hydrostatic_start {
                mat.density(mat.hydrostatic_pressure(gnorm, top - p.dot(up)))
            } else {
                mat.rho0
            };
            water.push(*p, vel, rho, rho * vol);
        }
        counts.push((name, pts.len()));
    }
    water.shrink_to_fit();
    Ok(Some((water, mat, counts)))
}
