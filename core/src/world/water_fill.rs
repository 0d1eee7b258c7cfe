//! The water of a scene: each `[[water.regions]]` shape filled on the lattice of
//! spacing dp, less what lies inside a solid, at the hydrostatic pressure of its
//! region; and the water's sound speed, chosen from the expected flow speed.

use super::regions::Solids;
use super::v;
use super::Water;
use crate::build_error::BuildError;
use crate::geometry::Shape;
use crate::math::{Real, Vect};
use crate::scene::{Hydrograph, Scene, ShapeSpec, WaterSpec};
use crate::water::boundary::{Inflow, InflowSpeed, Outflow};
use crate::water::material::WaterMaterial;
use crate::water::state::WaterParticles;

/// The pore water of a saturated soil region: its particles' positions, its name and
/// its top (along `up`), below which the pore pressure is hydrostatic.
pub(super) struct PoreWater<const D: usize> {
    pub name: String,
    pub pos: Vec<Vect<D>>,
    pub top: Real,
}

/// Fill the water regions of `scene` at spacing `dp` (particle volume `vol`) under the
/// hydrostatic gravity `g` (the scene's, without its component along a periodic
/// axis), then the pores of its saturated soils (`pores`, one water particle on each
/// soil particle); `reach` is the box of everything else in the scene (walls,
/// grains), which every inlet must meet. `None` without `[water]` or pores to fill;
/// pores without `[water]` take its defaults.
pub(super) fn fill<const D: usize>(
    scene: &Scene,
    g: &Vect<D>,
    (dp, vol): (Real, Real),
    reach: (Vect<D>, Vect<D>),
    pores: &[PoreWater<D>],
) -> Result<Option<Water<D>>, BuildError> {
    let defaults: WaterSpec;
    let spec = match &scene.water {
        Some(s) => s,
        None if pores.is_empty() => return Ok(None),
        None => {
            defaults = toml::from_str("").expect("every [water] key has a default");
            &defaults
        }
    };
    let gnorm = g.norm();
    let up = &if gnorm > 0.0 {
        -g / gnorm
    } else {
        Vect::<D>::zeros()
    };
    let solids = Solids::<D>::of(scene, true);
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
    for r in pores {
        let bottom = r
            .pos
            .iter()
            .map(|p| p.dot(up))
            .fold(Real::INFINITY, Real::min)
            - 0.5 * dp;
        speed = speed.max((2.0 * gnorm * (r.top - bottom)).sqrt());
        let name = format!("pores of {}", r.name);
        regions.push((name, r.pos.clone(), r.top, Vect::<D>::zeros()));
    }
    // the inlets must meet the scene, the water regions included
    let mut reach = reach;
    for x in regions.iter().flat_map(|r| r.1.iter()) {
        reach = (reach.0.inf(x), reach.1.sup(x));
    }
    let inflows = inflows::<D>(scene, reach)?;
    if regions.is_empty() && inflows.is_empty() {
        // a dry soil with pores and no water anywhere: a scene without water
        return Ok(None);
    }
    for f in &inflows {
        let (bottom, top) = f.extent_along(up);
        speed = speed
            .max((2.0 * gnorm * (top - bottom)).sqrt())
            .max(peak_speed(f));
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
    // with pores, the water stands at each column's surface, pores and free water
    // together; without, at each region's top
    let surface = (!pores.is_empty()).then(|| {
        let pts: Vec<&Vect<D>> = regions.iter().flat_map(|r| r.1.iter()).collect();
        column_surfaces(&pts, up, dp)
    });
    let mut at = 0;
    for (name, pts, top, vel) in regions {
        for p in &pts {
            let top = surface.as_ref().map_or(top, |s| s[at]);
            at += 1;
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
    let outflows = spec
        .outflows
        .iter()
        .map(|o| {
            let n = v::<D>(&o.normal);
            Outflow {
                name: o.name.clone(),
                point: v::<D>(&o.point),
                normal: n / n.norm(),
            }
        })
        .collect();
    Ok(Some(Water {
        particles: water,
        material: Some(mat),
        counts,
        inflows,
        outflows,
    }))
}

/// The vertical column of width dp (along `up`) that holds `x`: its horizontal cell.
pub(crate) fn column_key<const D: usize>(x: &Vect<D>, up: &Vect<D>, dp: Real) -> [i64; 3] {
    let h = x - up * x.dot(up);
    let mut k = [0i64; 3];
    for (a, v) in h.iter().enumerate() {
        k[a] = (v / dp).floor() as i64;
    }
    k
}

/// The water surface above each of `pts` (along `up`): the top of the run of water
/// particles, spaced at most 1.5 dp apart, that holds it in its vertical column of
/// width dp, plus dp/2.
fn column_surfaces<const D: usize>(pts: &[&Vect<D>], up: &Vect<D>, dp: Real) -> Vec<Real> {
    use std::collections::HashMap;
    let mut cols: HashMap<[i64; 3], Vec<(Real, usize)>> = HashMap::new();
    for (i, p) in pts.iter().enumerate() {
        cols.entry(column_key(p, up, dp))
            .or_default()
            .push((p.dot(up), i));
    }
    let mut out = vec![0.0; pts.len()];
    for col in cols.values_mut() {
        col.sort_by(|a, b| b.0.total_cmp(&a.0));
        let mut top = col[0].0;
        let mut last = col[0].0;
        for &(z, i) in col.iter() {
            if last - z > 1.5 * dp {
                top = z;
            }
            last = z;
            out[i] = top + 0.5 * dp;
        }
    }
    out
}

/// The largest speed of an inflow: its constant speed, or the hydrograph's peak.
fn peak_speed<const D: usize>(f: &Inflow<D>) -> Real {
    match f.speed {
        InflowSpeed::Constant(u) => u,
        // the Gumbel peak is at t = μ: a/(β e)
        InflowSpeed::Hydrograph(Hydrograph::Gumbel { a, beta, .. }) => {
            a / (beta * std::f64::consts::E)
        }
    }
}

/// The inflows of the scene; an inlet that does not meet `reach` is refused.
fn inflows<const D: usize>(
    scene: &Scene,
    reach: (Vect<D>, Vect<D>),
) -> Result<Vec<Inflow<D>>, BuildError> {
    let Some(spec) = &scene.water else {
        return Ok(Vec::new());
    };
    let mut out = Vec::new();
    for (i, f) in spec.inflows.iter().enumerate() {
        let ShapeSpec::Box { min, max } = &f.shape else {
            unreachable!("validated: an inlet is a box");
        };
        let (lo, hi) = (v::<D>(min), v::<D>(max));
        if (0..D).any(|k| hi[k] < reach.0[k] || lo[k] > reach.1[k]) {
            return Err(BuildError {
                path: format!("water.inflows[{i}].shape"),
                message: format!(
                    "inlet `{}` lies outside the scene: its box {:?}..{:?} meets none of the \
                     walls, barriers, grains or water, which span {:?}..{:?}",
                    f.name,
                    lo.as_slice(),
                    hi.as_slice(),
                    reach.0.as_slice(),
                    reach.1.as_slice()
                ),
            });
        }
        let axis = ["x", "y", "z"]
            .iter()
            .position(|a| f.direction[1..] == **a)
            .expect("validated");
        out.push(Inflow {
            name: f.name.clone(),
            lo,
            hi,
            axis,
            sign: if f.direction.starts_with('-') {
                -1.0
            } else {
                1.0
            },
            speed: match (f.speed, f.hydrograph) {
                (Some(u), _) => InflowSpeed::Constant(u),
                (None, Some(h)) => InflowSpeed::Hydrograph(h),
                (None, None) => unreachable!("validated: a speed or a hydrograph"),
            },
            stop: f.stop.unwrap_or(Real::INFINITY),
            fill: 0.0,
        });
    }
    Ok(out)
}
