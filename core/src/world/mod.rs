//! The simulated world built from a scene: particles, materials, walls and probes.
//! [`World::build`] delegates to the fine fill ([`regions`]), the walls
//! ([`boundaries`]) and the coarse bodies ([`Coarse::build`]).

use crate::coarse::build::Coarse;
use crate::fine::material::FineMaterial;
use crate::fine::state::FineParticles;
use crate::geometry::walls::Walls;
use crate::numerics::math::{extent, up, Real, Sym, Vect};
use crate::numerics::periodic::{axis_index, hydrostatic, Period, Wrap};
use crate::scene::build_error::BuildError;
use crate::scene::resolution::Resolution;
use crate::scene::Scene;
use crate::water::boundary::{Inflow, Outflow};
use crate::water::material::WaterMaterial;
use crate::water::state::WaterParticles;

mod boundaries;
mod column_fill;
pub mod perturbation;
mod regions;
pub mod water_at_bodies;
mod water_fill;

pub(crate) use water_fill::column_key;

/// A probe point sampled into the time series (or a gauge's base point).
#[derive(Clone, Debug, PartialEq, serde::Serialize, serde::Deserialize)]
pub struct Probe<const D: usize> {
    pub name: String,
    pub position: Vect<D>,
}

/// The water family as the world holds it (seed 001): its particles, its material
/// (None without `[water]`), the particles of each water region, and where water
/// enters and leaves.
#[derive(Clone, Debug, Default, serde::Serialize, serde::Deserialize)]
pub struct Water<const D: usize> {
    pub particles: WaterParticles<D>,
    pub material: Option<WaterMaterial>,
    /// Per water region particle counts, in scene order.
    pub counts: Vec<(String, usize)>,
    pub inflows: Vec<Inflow<D>>,
    pub outflows: Vec<Outflow<D>>,
}

/// Everything that evolves or is looked up during a run.
#[derive(Clone, Debug, serde::Serialize, serde::Deserialize)]
pub struct World<const D: usize> {
    pub fine: FineParticles<D>,
    pub materials: Vec<FineMaterial>,
    pub walls: Walls<D>,
    /// Coarse grains (boulders): bodies, their particles and solids.
    pub coarse: Coarse<D>,
    pub gravity: Vect<D>,
    /// dp, particle volume, h and skin, derived once from the scene.
    pub resolution: Resolution,
    pub time: Real,
    pub steps: u64,
    /// Fixed neighbour-search box (particles outside are clamped into border cells).
    pub domain: (Vect<D>, Vect<D>),
    pub probes: Vec<Probe<D>>,
    /// Water-level gauges: each one's base point (`[[gauges]]`).
    #[serde(default)]
    pub gauges: Vec<Probe<D>>,
    /// Per-region particle counts, in scene order.
    pub region_counts: Vec<(String, usize)>,
    /// The water family: particles, material, counts, inflows and outflows (empty,
    /// without a material, in a scene without `[water]`).
    #[serde(default)]
    pub water: Water<D>,
    /// The periodic axis, if any (`simulation.periodic`).
    #[serde(default)]
    pub periodic: Wrap,
}

fn v<const D: usize>(x: &[f64]) -> Vect<D> {
    Vect::<D>::from_iterator(x.iter().copied())
}

/// Refuse a scene too large for memory before allocating anything, and ask the
/// allocator for the whole estimate at once, fallibly, so that a scene the machine
/// cannot hold is an error here rather than an abort in the middle of filling (the
/// reservation is returned at once, untouched).
fn reserve_memory(scene: &Scene, resolution: &Resolution) -> Result<(), BuildError> {
    let estimate = crate::estimate::budget::enforce(scene, resolution).map_err(|e| BuildError {
        path: "simulation.dp".into(),
        message: e.to_string(),
    })?;
    if Vec::<u8>::new()
        .try_reserve_exact(estimate.bytes as usize)
        .is_err()
    {
        return Err(BuildError {
            path: "simulation.dp".into(),
            message: format!(
                "dp = {} m needs about {} for its {:.3e} particles, which the \
                 allocator refuses; coarsen simulation.dp",
                estimate.dp,
                crate::estimate::budget::human_bytes(estimate.bytes),
                estimate.particles()
            ),
        });
    }
    Ok(())
}

impl<const D: usize> World<D> {
    /// Build from a validated scene at resolution `resolution` (derived once from it,
    /// [`Resolution::of`]).
    pub fn build(scene: &Scene, resolution: Resolution) -> Result<Self, BuildError> {
        reserve_memory(scene, &resolution)?;
        let (dp, vol) = (resolution.dp, resolution.volume);
        let gravity = v::<D>(&scene.simulation.gravity);
        let periodic: Wrap = scene.simulation.periodic.as_ref().map(|p| Period {
            axis: axis_index(&p.axis).unwrap_or(0),
            lo: p.min,
            len: p.max - p.min,
        });
        let g_hyd = hydrostatic(gravity, periodic.map(|p| p.axis));
        // along a periodic slope, normal to the bed
        let up = up(&g_hyd);
        // a dilatant soil's viscous number takes the water's viscosity (dry: none)
        let eta_f = crate::estimate::flow_speed::water_spec(scene).map_or(0.0, |w| w.viscosity);
        let materials: Vec<FineMaterial> = scene
            .materials
            .iter()
            .map(|m| FineMaterial::from_spec(m).immersed(eta_f))
            .collect();
        let (mut fine, region_counts) = regions::fill(scene, &materials, &g_hyd, dp, vol)?;
        let walls = boundaries::build(scene, dp, vol, periodic)?;
        let coarse = Coarse::<D>::build(scene, &resolution)?;

        // Domain: everything, plus a margin for the flow to spread into.
        let mut lo = Vect::<D>::repeat(Real::INFINITY);
        let mut hi = Vect::<D>::repeat(Real::NEG_INFINITY);
        for p in fine
            .pos
            .iter()
            .chain(walls.pos.iter())
            .chain(coarse.particles.pos.iter())
        {
            lo = lo.inf(p);
            hi = hi.sup(p);
        }
        let pores = pore_water(scene, &materials, &fine, &region_counts, &up, dp);
        let filled = water_fill::fill(scene, &g_hyd, (dp, vol), (lo, hi), &pores)?;
        let mut water = filled.unwrap_or_default();
        if let Some(p) = &scene.simulation.perturbation {
            use perturbation::{displace, Family};
            let eps = p.amplitude * dp;
            displace(&mut fine.pos, p.seed, Family::Soil, eps, periodic);
            displace(
                &mut water.particles.pos,
                p.seed,
                Family::Water,
                eps,
                periodic,
            );
        }
        for p in water.particles.pos.iter() {
            lo = lo.inf(p);
            hi = hi.sup(p);
        }
        for f in &water.inflows {
            lo = lo.inf(&f.lo);
            hi = hi.sup(&f.hi);
        }
        let margin = (hi - lo).max() * 0.1 + 8.0 * dp;
        let domain = (lo.add_scalar(-margin), hi.add_scalar(margin));
        let domain = within_period(domain, periodic, (&water.particles.pos, &fine.pos))?;

        let probes = scene
            .probes
            .iter()
            .map(|p| Probe {
                name: p.name.clone(),
                position: v::<D>(&p.position),
            })
            .collect();
        // the arrays grew by doubling while the regions were filled
        fine.shrink_to_fit();
        Ok(World {
            fine,
            materials,
            walls,
            coarse,
            gravity,
            resolution,
            time: 0.0,
            steps: 0,
            domain,
            probes,
            gauges: scene
                .gauges
                .iter()
                .map(|g| Probe {
                    name: g.name.clone(),
                    position: v::<D>(&g.position),
                })
                .collect(),
            region_counts,
            water,
            periodic,
        })
    }

    /// Whether the scene has water (a `[water]` section), whatever its particle count.
    pub fn has_water(&self) -> bool {
        self.water.material.is_some()
    }

    /// The gravity of a hydrostatic state: g without its component along the periodic
    /// axis, where a body force drives a flow and builds no pressure gradient (seed 001
    /// §2.1). The water's hydrostatic start, wall pressure and potential energy use it.
    pub fn hydrostatic_gravity(&self) -> Vect<D> {
        hydrostatic(self.gravity, self.periodic.map(|p| p.axis))
    }

    /// Largest sound speed over fine materials.
    pub fn max_c0(&self) -> Real {
        self.materials.iter().map(|m| m.c0).fold(0.0, Real::max)
    }
}

/// The pore water of the saturated soil regions: one water particle on each of their
/// soil particles, and each region's top.
fn pore_water<const D: usize>(
    scene: &Scene,
    materials: &[FineMaterial],
    fine: &crate::fine::state::FineParticles<D>,
    counts: &[(String, usize)],
    up: &Vect<D>,
    dp: Real,
) -> Vec<water_fill::PoreWater<D>> {
    let mut out = Vec::new();
    let mut start = 0;
    for (r, (name, n)) in scene.regions.iter().zip(counts) {
        let range = start..start + n;
        start += n;
        let m = scene.materials.iter().position(|m| m.name == r.material);
        let saturated = m
            .and_then(|m| materials[m].pores)
            .is_some_and(|p| p.saturated);
        if !saturated {
            continue;
        }
        let pos = fine.pos[range].to_vec();
        let top = extent(&pos, up, dp).1;
        out.push(water_fill::PoreWater {
            name: name.clone(),
            pos,
            top,
        });
    }
    out
}

/// K0 (I − n n) + n n for the vertical unit vector n: the geostatic stress per unit
/// vertical stress (Eq. 26, Jaky's K0 on the horizontal axes, including the
/// out-of-plane axis in plane strain).
pub fn geostatic_tensor<const D: usize>(up: &Vect<D>, k0: Real) -> Sym {
    let mut n = [0.0; 3];
    for k in 0..D {
        n[k] = up[k];
    }
    let mut s = [0.0; 6];
    let idx = [(0, 0), (1, 1), (2, 2), (0, 1), (0, 2), (1, 2)];
    for (c, (a, b)) in idx.iter().enumerate() {
        let delta = if a == b { 1.0 } else { 0.0 };
        s[c] = k0 * (delta - n[*a] * n[*b]) + n[*a] * n[*b];
    }
    Sym(s)
}

/// The domain `(lo, hi)` with exactly one period along the periodic axis, if any; a
/// water or soil particle outside the period is an error naming the key to fix.
fn within_period<const D: usize>(
    mut domain: (Vect<D>, Vect<D>),
    periodic: Wrap,
    (water, soil): (&[Vect<D>], &[Vect<D>]),
) -> Result<(Vect<D>, Vect<D>), BuildError> {
    let Some(p) = periodic else {
        return Ok(domain);
    };
    (domain.0[p.axis], domain.1[p.axis]) = (p.lo, p.lo + p.len);
    let outside = |x: &&Vect<D>| x[p.axis] < p.lo || x[p.axis] >= p.lo + p.len;
    for (family, keys, pos) in [
        ("water", "[[water.regions]]", water),
        ("soil", "[[regions]]", soil),
    ] {
        if let Some(x) = pos.iter().find(outside) {
            return Err(BuildError {
                path: "simulation.periodic".into(),
                message: format!(
                    "a {family} particle at {:?} lies outside the period [{:?}, {:?}) \
                     along its axis: keep {keys} within it",
                    x.as_slice(),
                    p.lo,
                    p.lo + p.len
                ),
            });
        }
    }
    Ok(domain)
}
