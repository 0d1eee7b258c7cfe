//! The water of a scene: each `[[water.regions]]` shape filled on the lattice of
//! spacing dp, less what lies inside a solid, at the hydrostatic pressure of its
//! region; and the water's sound speed, chosen by [`flow_speed::choose`] from the
//! speeds measured on these particles.
//!
//! [`flow_speed::choose`]: crate::estimate::flow_speed::choose

use super::column_fill::column_fill;
use super::v;
use super::water_at_bodies::conform;
use super::Water;
use crate::estimate::flow_speed::{choose, water_spec, Measured};
use crate::geometry::start_solids::Solids;
use crate::geometry::Shape;
use crate::numerics::math::{extent, up, Real, Vect};
use crate::scene::build_error::{empty_region_message, BuildError};
use crate::scene::{OutflowSpec, Scene, ShapeSpec, WaterFill, WaterRegionSpec};
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
    let Some(spec) = water_spec(scene) else {
        return Ok(None);
    };
    let gnorm = g.norm();
    let up = &up(g);
    let solids = Solids::<D>::of(scene, true);
    // every region's lattice points, its top (along `up`) and velocity
    let mut regions = Vec::new();
    let mut speed = Measured::default();
    for (ri, r) in spec.regions.iter().enumerate() {
        let (region, (bottom, top)) = region_points::<D>(scene, (ri, r), &solids, (dp, up))?;
        speed.fall(gnorm, (bottom, top));
        speed.given(region.vel.norm());
        regions.push(region);
    }
    for r in pores {
        let bottom = extent(&r.pos, up, dp).0;
        speed.fall(gnorm, (bottom, r.top));
        regions.push(Region {
            name: format!("pores of {}", r.name),
            pts: r.pos.clone(),
            top: r.top,
            vel: Vect::<D>::zeros(),
            columns: None,
        });
    }
    // the inlets must meet the scene, the water regions included
    let mut reach = reach;
    for x in regions.iter().flat_map(|r| r.pts.iter()) {
        reach = (reach.0.inf(x), reach.1.sup(x));
    }
    let inflows = inflows::<D>(scene, reach)?;
    if regions.is_empty() && inflows.is_empty() {
        // a dry soil with pores and no water anywhere: a scene without water
        return Ok(None);
    }
    for f in &inflows {
        speed.fall(gnorm, f.extent_along(up));
        speed.given(f.peak_speed());
    }
    let chosen = choose(&spec, speed).map_err(|e| BuildError {
        path: e.path,
        message: e.message,
    })?;
    let mut mat = WaterMaterial::from_spec(&spec, chosen.c0, chosen.scale);
    match (
        spec.incompressible_start,
        spec.hydrostatic_start,
        pores.is_empty(),
    ) {
        (Some(true), false, _) => {
            return Err(BuildError {
                path: "water.incompressible_start".into(),
                message: "the incompressible start needs the hydrostatic one (it replaces \
                          the hydrostatic pressure where the water is free to move): drop \
                          water.hydrostatic_start = false or this key"
                    .into(),
            })
        }
        (Some(true), _, false) => {
            return Err(BuildError {
                path: "water.incompressible_start".into(),
                message: "a saturated soil's pore water starts hydrostatic (the soil \
                          holds it, which the start's Laplace problem does not know): \
                          drop this key or set it false"
                    .into(),
            })
        }
        (_, _, false) => {
            // pore water starts hydrostatic and keeps its suction at walls
            // (docs/method.md §Water, "A wall never pulls")
            mat.incompressible_start = false;
            mat.walls_push_only = false;
        }
        _ => {}
    }
    let at_rest = Rest {
        mat: &mat,
        hydrostatic: spec.hydrostatic_start,
        g: gnorm,
        up,
        vol,
        solids: &solids,
    };
    let (particles, counts) = at_rest.particles(regions, !pores.is_empty(), dp);
    Ok(Some(Water {
        particles,
        material: Some(mat),
        counts,
        inflows,
        outflows: outflows::<D>(&spec.outflows),
    }))
}

/// One water region to place, less the points inside a solid (refused if none is
/// left): the lattice points of spacing `dp` in its shape, or with `fill = "columns"`
/// its column fill along the vertical `up`, with each particle's surface and volume;
/// and the extent along `up` of its lattice points, from which the sound speed is
/// chosen (as `flow_speed` estimates it before the build, whichever the fill).
fn region_points<const D: usize>(
    scene: &Scene,
    (ri, r): (usize, &WaterRegionSpec),
    solids: &Solids<D>,
    (dp, up): (Real, &Vect<D>),
) -> Result<(Region<D>, (Real, Real)), BuildError> {
    let empty = || BuildError {
        path: format!("water.regions[{ri}].shape"),
        message: empty_region_message("water region", &r.name, dp),
    };
    let shape = Shape::<D>::from_spec(&r.shape, &scene.assets);
    let mut lattice = shape.fill(dp);
    if !solids.is_empty() {
        lattice.retain(|p| !solids.holds(p, dp));
    }
    if lattice.is_empty() {
        return Err(empty());
    }
    // the extent the sound speed is chosen from: the lattice less the solids, as
    // `flow_speed` measures it before the build; conforming the water to a body
    // (below) moves points near it by up to half a spacing, which can take the gap's
    // water under a body resting on the floor below the lattice's lowest row
    let reach = extent(&lattice, up, dp);
    if !solids.is_empty() {
        let kept = conform(&mut lattice, solids, dp);
        let mut k = kept.iter();
        lattice.retain(|_| *k.next().expect("one flag per point"));
    }
    if lattice.is_empty() {
        return Err(empty());
    }
    let (pts, columns) = match r.fill {
        WaterFill::Lattice => (lattice, None),
        WaterFill::Columns => {
            let axis = (0..D)
                .find(|&k| up[k].abs() == 1.0)
                .ok_or_else(|| BuildError {
                    path: format!("water.regions[{ri}].fill"),
                    message: format!(
                        "water region `{}`: fill = \"columns\" stacks particles along the \
                     vertical, so the gravity must point along an axis (it is {:?}); use \
                     fill = \"lattice\" or a gravity along −y (2D) or −z (3D)",
                        r.name,
                        (-up).as_slice()
                    ),
                })?;
            let mut c = column_fill(&shape, dp, axis);
            if !solids.is_empty() {
                c.retain(|p| !solids.holds(&p.pos, dp));
                let mut pos: Vec<Vect<D>> = c.iter().map(|p| p.pos).collect();
                let kept = conform(&mut pos, solids, dp);
                for (p, x) in c.iter_mut().zip(pos) {
                    p.pos = x;
                }
                let mut k = kept.iter();
                c.retain(|_| *k.next().expect("one flag per point"));
            }
            if c.is_empty() {
                return Err(empty());
            }
            let columns: Columns = c.iter().map(|p| (p.surface, p.volume)).collect();
            (c.into_iter().map(|p| p.pos).collect(), Some(columns))
        }
    };
    let vel = r
        .velocity
        .as_deref()
        .map(v::<D>)
        .unwrap_or_else(Vect::<D>::zeros);
    let region = Region {
        name: r.name.clone(),
        pts,
        top: reach.1,
        vel,
        columns,
    };
    Ok((region, reach))
}

/// Each particle's column surface and volume, for a column fill.
type Columns = Vec<(Real, Real)>;

/// One region of water to place: its name, its particles, its top (along `up`), its
/// velocity and, for a column fill, each particle's surface and volume.
struct Region<const D: usize> {
    name: String,
    pts: Vec<Vect<D>>,
    top: Real,
    vel: Vect<D>,
    columns: Option<Columns>,
}

/// How the water starts: its material, whether at the hydrostatic pressure (under
/// gravity `g` along `up`) or at ρ_w, the particle volume `vol`, and the solids whose
/// bodies the water's columns run through.
struct Rest<'a, const D: usize> {
    mat: &'a WaterMaterial,
    hydrostatic: bool,
    g: Real,
    up: &'a Vect<D>,
    vol: Real,
    solids: &'a Solids<D>,
}

impl<const D: usize> Rest<'_, D> {
    /// The water particles of `regions`, in order, and each region's name and count.
    /// With pores, the water stands at each column's surface, pores and free water
    /// together, through the bodies that sit in it; without, at each region's top.
    fn particles(
        &self,
        regions: Vec<Region<D>>,
        with_pores: bool,
        dp: Real,
    ) -> (WaterParticles<D>, Vec<(String, usize)>) {
        let (mat, up) = (self.mat, self.up);
        let mut water = WaterParticles::<D>::default();
        let mut counts = Vec::new();
        let surface = with_pores.then(|| {
            let pts: Vec<&Vect<D>> = regions.iter().flat_map(|r| r.pts.iter()).collect();
            let through_body = |x: &Vect<D>| self.solids.body_distance(x) < dp;
            column_surfaces(&pts, up, dp, through_body)
        });
        let mut at = 0;
        for r in regions {
            for (i, p) in r.pts.iter().enumerate() {
                let column = r.columns.as_ref().map(|c| c[i]);
                let top = surface
                    .as_ref()
                    .map(|s| s[at])
                    .or(column.map(|c| c.0))
                    .unwrap_or(r.top);
                at += 1;
                let rho = if self.hydrostatic {
                    mat.density(mat.hydrostatic_pressure(self.g, top - p.dot(up)))
                } else {
                    mat.rho0
                };
                water.push(*p, r.vel, rho, rho * column.map_or(self.vol, |c| c.1));
            }
            counts.push((r.name, r.pts.len()));
        }
        water.shrink_to_fit();
        (water, counts)
    }
}

/// The outflow planes of the scene, each normal made a unit vector.
fn outflows<const D: usize>(specs: &[OutflowSpec]) -> Vec<Outflow<D>> {
    specs
        .iter()
        .map(|o| {
            let n = v::<D>(&o.normal);
            Outflow {
                name: o.name.clone(),
                point: v::<D>(&o.point),
                normal: n / n.norm(),
            }
        })
        .collect()
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
/// particles that holds it in its vertical column of width dp, plus dp/2. A run is
/// broken where the column has no water for more than 1.5 dp, unless every point of
/// the gap (on the lower particle's vertical, every dp/2) is `solid`: a body sitting in
/// the water (a boulder in saturated soil) leaves a gap of its chord plus about dp in
/// the column, and the water under it stands at the surface above it (issue 44: it
/// started at the body's underside, about 100 Pa instead of 2.5 kPa, under the debris
/// flow's boulders).
fn column_surfaces<const D: usize>(
    pts: &[&Vect<D>],
    up: &Vect<D>,
    dp: Real,
    solid: impl Fn(&Vect<D>) -> bool,
) -> Vec<Real> {
    use std::collections::HashMap;
    let mut cols: HashMap<[i64; 3], Vec<(Real, usize)>> = HashMap::new();
    for (i, p) in pts.iter().enumerate() {
        cols.entry(column_key(p, up, dp))
            .or_default()
            .push((p.dot(up), i));
    }
    let bridged = |p: &Vect<D>, (low, high): (Real, Real)| {
        let n = ((high - low) / (0.5 * dp)).floor() as usize;
        (1..n).all(|k| solid(&(p + up * (0.5 * dp * k as Real))))
    };
    let mut out = vec![0.0; pts.len()];
    for col in cols.values_mut() {
        col.sort_by(|a, b| b.0.total_cmp(&a.0));
        let mut top = col[0].0;
        let mut last = col[0].0;
        for &(z, i) in col.iter() {
            if last - z > 1.5 * dp && !bridged(pts[i], (z, last)) {
                top = z;
            }
            last = z;
            out[i] = top + 0.5 * dp;
        }
    }
    out
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
