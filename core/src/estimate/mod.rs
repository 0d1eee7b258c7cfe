//! Particle counts and memory of a scene, estimated from its shapes without building a
//! particle, so that any spacing dp can be vetted in a fraction of a second.
//!
//! The builder ([`World::build`](crate::world::World::build)) places particles on a
//! lattice of spacing dp (seed 000 §5.2), so a shape of volume V (area in 2D) holds
//! about V / dp^D of them. Boxes, planes and container faces are counted exactly from
//! the lattice; other shapes, the fine grains a solid displaces (closer than dp/2 to
//! its surface) and the wall and rigid-body shells are measured by stratified random
//! sampling of the shape's bounding box at a resolution independent of dp. Shells
//! thinner than the sampling resolution are the band −w < sdf < 0 scaled to their
//! depth (coarea formula: the shell volume is the surface area times the depth).

pub mod budget;
pub mod flow_speed;

use crate::estimate::flow_speed::{saturated, water_spec, water_speed, WaterSpeed};
use crate::fine::lanes::FineLanes;
use crate::fine::pair_sums::PairSums;
use crate::fine::pores::Pores;
use crate::geometry::Shape;
use crate::numerics::math::{from3, to3, Real, Sym, Vect};
use crate::numerics::neighbors::BYTES_PER_CELL;
use crate::numerics::pairs::quad::WIDTH;
use crate::numerics::rng::Rng;
use crate::scene::build_error::empty_region_message;
use crate::scene::resolution::Resolution;
use crate::scene::spec_rotation;
use crate::scene::KeyError;
use crate::scene::{BodyModel, Scene, ShapeSpec};
use nalgebra::{Rotation3, SMatrix, SVector, Vector3};
use std::mem::size_of;

/// Samples per region or wall; per body (rock fills hold hundreds of small bodies).
const SAMPLES: usize = 1 << 15;
const BODY_SAMPLES: usize = 1 << 11;

/// What a scene will hold at its dp, estimated.
#[derive(Clone, Debug)]
pub struct Estimate {
    pub dimension: usize,
    pub dp: Real,
    /// Fine particles per region, in scene order.
    pub regions: Vec<(String, Real)>,
    /// Water particles per water region at the start (inflows add more), in scene
    /// order; counted at the fine grains' bytes per particle (a bound).
    pub water: Vec<(String, Real)>,
    /// Water particles each inflow lets in by `simulation.end_time`, in scene order:
    /// the length let in (the speed's integral up to its stop) in layers of dp, each
    /// layer the inlet's cross-section at spacing dp, as the inflow emits them
    /// ([`Inflow::emit`](crate::water::boundary::Inflow::emit)). Outflows may take some
    /// out again: for memory this is a bound.
    pub inflows: Vec<(String, Real)>,
    /// Dummy wall particles of every wall, barrier and container face.
    pub walls: Real,
    /// Coarse particles per body, after rigid interiors are trimmed.
    pub bodies: Vec<(String, Real)>,
    /// Coarse particles of the largest body before trimming (held while it is built).
    pub largest_body_fill: Real,
    /// Cells of one neighbour-search grid over the domain.
    pub cells: Real,
    /// Bytes of the dense cell grids of the steppers ([`CellGrid`](crate::numerics::neighbors::CellGrid)):
    /// [`BYTES_PER_CELL`] for each cell of each grid binned, which in a sparse domain
    /// (parts far apart) outweighs the particles.
    pub grid_bytes: Real,
    /// Bytes per particle of each kind: fine, wall, coarse.
    pub per_particle: [Real; 3],
    /// Estimated bytes held by a running simulation (the peak of its build included).
    pub bytes: Real,
}

impl Estimate {
    pub fn fine(&self) -> Real {
        self.regions.iter().map(|r| r.1).sum::<Real>() + 0.0
    }
    pub fn coarse(&self) -> Real {
        // + 0.0: an empty sum is −0
        self.bodies.iter().map(|b| b.1).sum::<Real>() + 0.0
    }
    /// Water particles at the start.
    pub fn water(&self) -> Real {
        self.water.iter().map(|r| r.1).sum::<Real>() + 0.0
    }
    /// Water particles the inflows let in over the run.
    pub fn inflow(&self) -> Real {
        self.inflows.iter().map(|r| r.1).sum::<Real>() + 0.0
    }
    /// Every particle: fine, wall, coarse and water, with what the inflows let in.
    pub fn particles(&self) -> Real {
        self.fine() + self.walls + self.coarse() + self.water() + self.inflow()
    }
    /// Fine and water particles stepped on average over the run: those at the start
    /// and half of what the inflows let in (a steady inflow lets them in at an even
    /// rate), for the cost in particle-steps.
    pub fn mean_stepped(&self) -> Real {
        self.fine() + self.water() + 0.5 * self.inflow()
    }
}

/// Estimate a validated scene (its assets loaded) at its resolution `res`
/// ([`Resolution::of_scene`]).
pub fn estimate(scene: &Scene, res: &Resolution) -> Estimate {
    match scene.simulation.dimension {
        2 => estimate_in::<2>(scene, res),
        _ => estimate_in::<3>(scene, res),
    }
}

/// A solid that displaces fine grains: its shape and, for a body, its pose.
struct Solid<const D: usize> {
    shape: Shape<D>,
    pose: Option<(Vector3<Real>, Rotation3<Real>)>,
    /// Bounding box in the scene frame.
    lo: Vect<D>,
    hi: Vect<D>,
}

impl<const D: usize> Solid<D> {
    fn sdf(&self, p: &Vect<D>) -> Real {
        match &self.pose {
            Some((c, r)) => self
                .shape
                .sdf(&from3::<D>(&(c + r.inverse() * (to3(p) - c)))),
            None => self.shape.sdf(p),
        }
    }
}

fn estimate_in<const D: usize>(scene: &Scene, res: &Resolution) -> Estimate {
    let dp = res.dp;
    let n = &scene.numerics;
    // one stream of samples, drawn by regions, walls and bodies in that order
    let mut rng = Rng(0x5EED_0FB0_D6E7);
    let mut bounds = Bounds::<D>::new();
    let solids = solids::<D>(scene);
    let fine: Vec<(&str, &ShapeSpec)> = scene
        .regions
        .iter()
        .map(|r| (r.name.as_str(), &r.shape))
        .collect();
    let regions = count_regions(scene, &fine, res, &solids, &mut rng, &mut bounds);
    let water: Vec<(&str, &ShapeSpec)> = scene
        .water
        .iter()
        .flat_map(|w| w.regions.iter().map(|r| (r.name.as_str(), &r.shape)))
        .collect();
    let mut water = count_regions(scene, &water, res, &solids, &mut rng, &mut bounds);
    // a saturated soil's pores hold one water particle per soil particle
    for (r, (_, n)) in scene.regions.iter().zip(&regions) {
        if saturated(scene, &r.material) {
            water.push((format!("pores of {}", r.name), *n));
        }
    }
    let inflows = count_inflows::<D>(scene, dp);
    let walls = count_walls(scene, dp, &mut rng, &mut bounds);
    let (bodies, largest_body_fill) = count_bodies(scene, res, &solids, &mut rng, &mut bounds);
    let (lo_all, hi_all) = (bounds.lo, bounds.hi);

    // the domain: everything plus the builder's margin; one cell per list radius
    let radius = (2.0 * n.smoothing_ratio + n.neighbor_skin) * dp;
    let cells = if lo_all[0].is_finite() {
        let margin = (hi_all - lo_all).max() * 0.1 + 8.0 * dp;
        (0..D)
            .map(|k| {
                ((hi_all[k] - lo_all[k] + 2.0 * margin) / radius)
                    .ceil()
                    .max(1.0)
            })
            .product()
    } else {
        1.0
    };

    let per_particle = [
        fine_bytes_per_particle::<D>(n.smoothing_ratio, n.neighbor_skin),
        wall_bytes_per_particle::<D>(),
        coarse_bytes_per_particle::<D>(),
    ];
    let mut e = Estimate {
        dimension: D,
        dp,
        regions,
        water,
        inflows,
        walls,
        bodies,
        largest_body_fill,
        cells,
        grid_bytes: 0.0,
        per_particle,
        bytes: 0.0,
    };
    let water = water_spec(scene).is_some() && (e.water() > 0.0 || has_inflows(scene));
    let seepage = water && scene.materials.iter().any(|m| Pores::of(m).is_some());
    // the soil–water lists' cells are 2h + 1.5 skin wide (one kept grid and one built
    // for the outputs)
    let sw_radius = (2.0 * n.smoothing_ratio + 1.5 * n.neighbor_skin) * dp;
    let sw_cells = cells * (radius / sw_radius).powi(D as i32);
    // per family: its own grid and the walls', and the coarse particles' if any
    let grids = 2.0 + (e.coarse() > 0.0) as u8 as Real;
    e.grid_bytes = BYTES_PER_CELL as Real
        * (cells * (grids * (e.fine() > 0.0) as u8 as Real)
            + cells * (grids * water as u8 as Real)
            + sw_cells * 2.0 * seepage as u8 as Real);
    e.bytes = (e.fine() + e.water() + e.inflow()) * per_particle[0]
        + e.walls * per_particle[1]
        + e.coarse() * per_particle[2]
        + largest_body_fill * BODY_FILL_BYTES_PER_DIM * D as Real
        + e.grid_bytes;
    e
}

/// The water particles each inflow lets in by the end time (see [`Estimate::inflows`]).
fn count_inflows<const D: usize>(scene: &Scene, dp: Real) -> Vec<(String, Real)> {
    let Some(w) = &scene.water else {
        return Vec::new();
    };
    let end = scene.simulation.end_time;
    w.inflows
        .iter()
        .map(|f| {
            let ShapeSpec::Box { min, max } = &f.shape else {
                // validated: an inlet is a box
                return (f.name.clone(), 0.0);
            };
            let axis = ["x", "y", "z"]
                .iter()
                .position(|a| f.direction.get(1..) == Some(*a))
                .unwrap_or(0);
            let cross: Real = (0..D)
                .filter(|&k| k != axis)
                .map(|k| ((max[k] - min[k]) / dp).round().max(1.0))
                .product();
            let t = f.stop.map_or(end, |s| s.min(end)).max(0.0);
            let length = match (f.speed, &f.hydrograph) {
                (Some(u), _) => u * t,
                (None, Some(h)) => h.length(t),
                (None, None) => 0.0,
            };
            (f.name.clone(), (length / dp).floor().max(0.0) * cross)
        })
        .collect()
}

fn has_inflows(scene: &Scene) -> bool {
    scene.water.as_ref().is_some_and(|w| !w.inflows.is_empty())
}

/// The part of the scene that would hold no particle at its dp, by the estimate: the
/// first region or water region whose count is below one, or body that holds fewer
/// than two particles, with the build's message.
pub fn empty_part(scene: &Scene, e: &Estimate) -> Option<KeyError> {
    let regions = scene.regions.iter().map(|r| ("regions", "region", &r.name));
    let water = scene
        .water
        .iter()
        .flat_map(|w| w.regions.iter())
        .map(|r| ("water.regions", "water region", &r.name));
    let mut index = std::collections::HashMap::new();
    for ((key, what, name), (_, n)) in regions.chain(water).zip(e.regions.iter().chain(&e.water)) {
        let i = index.entry(key).or_insert(0usize);
        if n.is_nan() || *n < 1.0 {
            return Some(KeyError::new(
                format!("{key}[{i}].shape"),
                empty_region_message(what, name, e.dp),
            ));
        }
        *i += 1;
    }
    match scene.simulation.dimension {
        2 => empty_body::<2>(scene, e),
        _ => empty_body::<3>(scene, e),
    }
}

/// The first body whose lattice fill at spacing `dp` holds fewer than the two
/// particles a body needs (the build's test, [`Shape::body_fill`]), with the build's
/// message. Only the bodies the estimate `e` puts under 64 particles are filled: the
/// others hold particles.
fn empty_body<const D: usize>(scene: &Scene, e: &Estimate) -> Option<KeyError> {
    let dp = e.dp;
    for ((i, b), (_, n)) in scene.bodies.iter().enumerate().zip(&e.bodies) {
        if *n >= 64.0 {
            continue;
        }
        let shape = Shape::<D>::from_spec(&b.shape, &scene.assets);
        let n = shape.body_fill(dp).len();
        if n < 2 {
            return Some(KeyError::new(
                format!("bodies[{i}].shape"),
                format!(
                    "body `{}` holds {n} particle(s) at dp = {dp} m; it needs at least 2 \
                     (enlarge it or refine dp)",
                    b.name
                ),
            ));
        }
    }
    None
}

/// The box around everything counted so far.
struct Bounds<const D: usize> {
    lo: Vect<D>,
    hi: Vect<D>,
}

impl<const D: usize> Bounds<D> {
    fn new() -> Self {
        Bounds {
            lo: Vect::<D>::repeat(Real::INFINITY),
            hi: Vect::<D>::repeat(Real::NEG_INFINITY),
        }
    }
    fn grow(&mut self, lo: &Vect<D>, hi: &Vect<D>) {
        self.lo = self.lo.inf(lo);
        self.hi = self.hi.sup(hi);
    }
}

/// Solids as the builder sees them: non-plane walls and barriers, then bodies.
fn solids<const D: usize>(scene: &Scene) -> Vec<Solid<D>> {
    let mut solids: Vec<Solid<D>> = Vec::new();
    for w in scene.walls.iter().chain(&scene.barriers) {
        if !matches!(w.shape, ShapeSpec::Plane { .. }) {
            let shape = Shape::<D>::from_spec(&w.shape, &scene.assets);
            let (lo, hi) = shape.bounds();
            solids.push(Solid {
                shape,
                pose: None,
                lo,
                hi,
            });
        }
    }
    for b in &scene.bodies {
        let shape = Shape::<D>::from_spec(&b.shape, &scene.assets);
        let c = shape.center();
        let (lo, hi) = shape.bounds();
        // any rotation about the centre stays inside the bounding ball
        let r = (hi - lo).norm() * 0.5;
        solids.push(Solid {
            pose: Some((to3(&c), spec_rotation(b, D))),
            shape,
            lo: c.add_scalar(-r),
            hi: c.add_scalar(r),
        });
    }

    solids
}

/// Fine particles of each region: exact for boxes and shapes with a volume away from
/// solids, else sampled.
fn count_regions<const D: usize>(
    scene: &Scene,
    shapes: &[(&str, &ShapeSpec)],
    res: &Resolution,
    solids: &[Solid<D>],
    rng: &mut Rng,
    bounds: &mut Bounds<D>,
) -> Vec<(String, Real)> {
    let (dp, cell_vol) = (res.dp, res.volume);
    let margin = 0.5 * dp * (1.0 - 1e-6);
    let mut regions = Vec::new();
    for &(name, spec) in shapes {
        let shape = Shape::<D>::from_spec(spec, &scene.assets);
        let (lo, hi) = shape.bounds();
        bounds.grow(&lo, &hi);
        let near: Vec<&Solid<D>> = solids
            .iter()
            .filter(|s| overlaps(&s.lo.add_scalar(-dp), &s.hi.add_scalar(dp), &lo, &hi))
            .collect();
        let exact = match &shape {
            Shape::Box { min, max } => Some(box_count(&(max - min), dp)),
            _ => shape.volume().map(|v| v / cell_vol),
        };
        let count = if exact.is_some() && near.is_empty() {
            exact.unwrap_or(0.0)
        } else {
            let (mut inside, mut kept) = (0usize, 0usize);
            sample_box(&lo, &hi, SAMPLES, rng, |p| {
                if shape.sdf(p) < 0.0 {
                    inside += 1;
                    if !near.iter().any(|s| s.sdf(p) < margin) {
                        kept += 1;
                    }
                }
            });
            match exact {
                Some(e) if inside > 0 => e * kept as Real / inside as Real,
                Some(e) => e,
                None => box_volume(&lo, &hi) * kept as Real / SAMPLES as Real / cell_vol,
            }
        };
        regions.push((name.to_string(), count));
    }

    regions
}

/// Wall particles of walls, barriers and container faces.
fn count_walls<const D: usize>(
    scene: &Scene,
    dp: Real,
    rng: &mut Rng,
    bounds: &mut Bounds<D>,
) -> Real {
    let n = &scene.numerics;
    let depth = n.wall_layers as Real * dp;
    let mut walls = 0.0;
    for w in scene.walls.iter().chain(&scene.barriers) {
        let shape = Shape::<D>::from_spec(&w.shape, &scene.assets);
        walls += match &shape {
            Shape::Plane {
                point, half_extent, ..
            } => {
                bounds.grow(
                    &point.add_scalar(-half_extent.iter().fold(0.0, |a: Real, b| a.max(*b))),
                    &point.add_scalar(half_extent.iter().fold(0.0, |a: Real, b| a.max(*b))),
                );
                half_extent
                    .iter()
                    .map(|h| 2.0 * (h / dp).floor() + 1.0)
                    .product::<Real>()
                    * n.wall_layers as Real
            }
            _ => {
                let (mut lo, hi) = shape.bounds();
                if let Shape::Terrain { .. } = shape {
                    lo[D - 1] -= depth + dp;
                }
                bounds.grow(&lo, &hi);
                shell_count(&shape, &lo, &hi, depth, dp, SAMPLES, rng)
            }
        };
    }
    for c in &scene.containers {
        let (lo, hi) = (Vect::<D>::from_iterator(c.min.iter().copied()), {
            Vect::<D>::from_iterator(c.max.iter().copied())
        });
        let t = depth;
        bounds.grow(&lo.add_scalar(-t), &hi.add_scalar(t));
        let open: Vec<String> = c
            .open
            .clone()
            .unwrap_or_else(|| vec![if D == 2 { "+y".into() } else { "+z".into() }]);
        for a in 0..D {
            for side in ["-", "+"] {
                if open.contains(&format!("{side}{}", ["x", "y", "z"][a])) {
                    continue;
                }
                // the face's box as the builder makes it: t thick along a, spanning the
                // interior on higher axes and the corners on lower ones
                let mut size = hi - lo;
                size[a] = t;
                for b in 0..a {
                    size[b] += 2.0 * t;
                }
                // cut to the period along a periodic axis
                if let Some(p) = &scene.simulation.periodic {
                    if let Some(k) =
                        crate::numerics::periodic::axis_index(&p.axis).filter(|&k| k < D)
                    {
                        size[k] = p.max - p.min;
                    }
                }
                walls += box_count(&size, dp);
            }
        }
    }

    walls
}

/// Coarse particles of each body (a rigid body keeps a shell), and the largest fill.
fn count_bodies<const D: usize>(
    scene: &Scene,
    res: &Resolution,
    solids: &[Solid<D>],
    rng: &mut Rng,
    bounds: &mut Bounds<D>,
) -> (Vec<(String, Real)>, Real) {
    let (dp, cell_vol, trim) = (res.dp, res.volume, res.trim);
    let mut bodies = Vec::new();
    let mut largest_body_fill: Real = 0.0;
    for (b, s) in scene
        .bodies
        .iter()
        .zip(&solids[solids.len() - scene.bodies.len()..])
    {
        bounds.grow(&s.lo, &s.hi);
        let (lo, hi) = s.shape.bounds();
        let full = match s.shape.volume() {
            Some(v) => v / cell_vol,
            None => {
                let mut inside = 0usize;
                sample_box(&lo, &hi, BODY_SAMPLES, rng, |p| {
                    inside += (s.shape.sdf(p) < 0.0) as usize;
                });
                box_volume(&lo, &hi) * inside as Real / BODY_SAMPLES as Real / cell_vol
            }
        }
        .max(2.0);
        let kept = match b.model {
            BodyModel::Elastic => full,
            BodyModel::Rigid => {
                shell_count(&s.shape, &lo, &hi, trim, dp, BODY_SAMPLES, rng).clamp(2.0, full)
            }
        };
        largest_body_fill = largest_body_fill.max(full);
        bodies.push((b.name.clone(), kept));
    }

    (bodies, largest_body_fill)
}

/// Bytes per lattice point while a body is filled: each of the 2^D candidate lattices
/// is a `Vec` of positions (8 D bytes, up to twice that while it grows) and a hash set
/// of lattice keys (24 bytes and its control byte, at most 8/7 full, twice while it
/// grows) for the spike pruning ([`Shape::body_fill`]). Per dimension: ≈ 4 × 8 + 64/D.
const BODY_FILL_BYTES_PER_DIM: Real = 64.0;

/// Bytes per fine particle: its state ([`FineParticles`](crate::fine::state::FineParticles)),
/// the stepper's per-particle scratch (positions at the last list build, new
/// velocities, artificial stress, sort order, pair sums, the cell grid's two index
/// arrays), the offsets of its wall and coarse lists (a particle in bulk has no wall or
/// coarse neighbours), and the cluster-pair lists and buffers. The cell grids go with
/// the cells ([`Estimate::grid_bytes`]). With them this gives 624 (2D) and 920 (3D)
/// bytes for the bundled column collapses, whose built solvers hold 585 and 928
/// (`tests/tests/memory_budget.rs`).
pub fn fine_bytes_per_particle<const D: usize>(smoothing_ratio: Real, skin: Real) -> Real {
    let state = 2 * size_of::<Vect<D>>()
        + 4 * size_of::<Real>()
        + size_of::<Sym>()
        + 2
        + 4
        + size_of::<SMatrix<f32, D, D>>()
        + size_of::<SVector<f32, D>>()
        + 4;
    let scratch = size_of::<SVector<f32, D>>()
        + size_of::<Vect<D>>()
        + size_of::<Sym>()
        + 4
        + size_of::<PairSums<D>>()
        + 2 * 4;
    let lists = 2 * 4;
    let r = 2.0 * smoothing_ratio + skin;
    (state + scratch + lists) as Real + cluster_bytes_per_particle::<D>(r)
}

/// Bytes per fine particle of the cluster-pair passes ([`FineLanes`]) and their lists
/// ([`ClusterPairs`]): the packed state (the passes add their sums straight into the
/// particles' pair sums), each particle's cluster, the clusters' bounds and offsets,
/// and each cluster's pair list, the union of its four members' half lists: about
/// half the lattice points within the list radius `r` plus half a spacing (the
/// members lie about that far from their centre), with a sixteenth of room to grow.
///
/// [`FineLanes`]: crate::fine::lanes::FineLanes
/// [`ClusterPairs`]: crate::numerics::pairs::clusters::ClusterPairs
fn cluster_bytes_per_particle<const D: usize>(r: Real) -> Real {
    let rc = r + 0.5;
    let ball = if D == 2 {
        std::f64::consts::PI * rc * rc
    } else {
        4.0 / 3.0 * std::f64::consts::PI * rc.powi(3)
    };
    let width = WIDTH as Real;
    FineLanes::<D>::bytes_per_particle() as Real
        + 4.0
        + 2.0 * 4.0 / width
        + 17.0 / 16.0 * 4.0 * 0.5 * ball / width
}

/// Bytes per dummy wall particle: position, object index, panel index and the wall
/// grid's three index arrays.
pub fn wall_bytes_per_particle<const D: usize>() -> Real {
    (size_of::<Vect<D>>() + 2 + 4 + 3 * 4) as Real
}

/// Bytes per coarse particle: the nine vectors, mass, body and surface flag of
/// [`CoarseParticles`](crate::coarse::particles::CoarseParticles), its depth, its
/// source for the fine sweeps (position, velocity, normal, volume) and the coarse
/// grid's index arrays.
pub fn coarse_bytes_per_particle<const D: usize>() -> Real {
    (13 * size_of::<Vect<D>>() + 3 * size_of::<Real>() + 4 + 1 + 3 * 4) as Real
}

/// Lattice points of a box of edge lengths `size` anchored at its min corner: along
/// each axis the (i + ½) dp strictly inside.
fn box_count<const D: usize>(size: &Vect<D>, dp: Real) -> Real {
    size.iter()
        .map(|l| (l / dp - 0.5).ceil().max(0.0))
        .product()
}

/// Lattice points of a box within `depth` of its surface (the builder's wall shell).
fn box_shell_count<const D: usize>(size: &Vect<D>, depth: Real, dp: Real) -> Real {
    let all = box_count(size, dp);
    let inner: Real = size
        .iter()
        .map(|l| {
            let n = (l / dp - 0.5).ceil().max(0.0);
            let i0 = (depth / dp - 0.5).ceil();
            let i1 = ((l - depth) / dp - 0.5).floor().min(n - 1.0);
            (i1 - i0 + 1.0).max(0.0)
        })
        .product();
    all - inner
}

/// Lattice points with −depth < sdf < 0 (a wall's layers, a rigid body's kept shell).
fn shell_count<const D: usize>(
    shape: &Shape<D>,
    lo: &Vect<D>,
    hi: &Vect<D>,
    depth: Real,
    dp: Real,
    samples: usize,
    rng: &mut Rng,
) -> Real {
    if let Shape::Box { min, max } = shape {
        return box_shell_count(&(max - min), depth, dp);
    }
    let strata = strata_per_axis::<D>(samples);
    // the band is a couple of strata thick, so that every sample column crosses it
    let w = (0..D)
        .map(|k| (hi[k] - lo[k]) / strata as Real)
        .fold(0.0, Real::max)
        * 2.0;
    let band = depth.max(w);
    let (mut lo, mut hi) = (*lo, *hi);
    if let Shape::Terrain { .. } = shape {
        // the builder's lattice runs one to one and a half spacings past the grid's
        // edges, where the terrain goes on at its edge height (other shapes end inside
        // their bounds), and the band reaches below the lowest point
        for k in 0..D - 1 {
            lo[k] = ((lo[k] / dp - 0.5).floor() - 1.0) * dp;
            hi[k] = ((hi[k] / dp - 0.5).ceil() + 2.0) * dp;
        }
        lo[D - 1] -= band;
    }
    let (lo, hi) = (&lo, &hi);
    let (mut inside, mut shell) = (0usize, 0usize);
    sample_box(lo, hi, samples, rng, |p| {
        let d = shape.sdf(p);
        if d < 0.0 {
            inside += 1;
            shell += (d > -band) as usize;
        }
    });
    let per_sample = box_volume(lo, hi) / strata.pow(D as u32) as Real / dp.powi(D as i32);
    let shell = shell as Real * per_sample * (depth / band);
    shell.min(inside as Real * per_sample)
}

fn strata_per_axis<const D: usize>(samples: usize) -> usize {
    ((samples as Real).powf(1.0 / D as Real).round() as usize).max(1)
}

/// One random point in each of m^D equal cells of [lo, hi] (stratified sampling).
fn sample_box<const D: usize>(
    lo: &Vect<D>,
    hi: &Vect<D>,
    samples: usize,
    rng: &mut Rng,
    mut f: impl FnMut(&Vect<D>),
) {
    let m = strata_per_axis::<D>(samples);
    let total = m.pow(D as u32);
    let step = (hi - lo) / m as Real;
    for i in 0..total {
        let mut p = *lo;
        let mut rest = i;
        for k in 0..D {
            let c = rest % m;
            rest /= m;
            p[k] += (c as Real + rng.uniform()) * step[k];
        }
        f(&p);
    }
}

fn box_volume<const D: usize>(lo: &Vect<D>, hi: &Vect<D>) -> Real {
    (hi - lo).iter().map(|x| x.max(0.0)).product()
}

fn overlaps<const D: usize>(a0: &Vect<D>, a1: &Vect<D>, b0: &Vect<D>, b1: &Vect<D>) -> bool {
    (0..D).all(|k| a0[k] <= b1[k] && b0[k] <= a1[k])
}

/// Δt of Eq. (51) at rest, CFL · h / c0 over the fastest fine material and the water
/// (no particle moves yet, so |v|max = 0), and the water's viscous limit; infinite
/// without fine grains or water; with the bound that sets it.
pub fn rest_dt(scene: &Scene, res: &Resolution) -> RestDt {
    let water = water_speed(scene, res).ok().flatten();
    rest_dt_bound(scene, res, water.as_ref())
}

/// The time step at rest ([`rest_dt`]) and the bound that sets it.
#[derive(Clone, Debug, PartialEq)]
pub struct RestDt {
    /// Δt (s); infinite without fine grains or water.
    pub dt: Real,
    /// The scene key whose value sets the binding bound.
    pub key: String,
    /// The binding bound, described with its values.
    pub what: String,
    /// Whether the bound is the acoustic one, CFL · h / c0 (it scales with the CFL).
    pub acoustic: bool,
}

/// [`rest_dt`] with the bound that sets it, for the water of speeds `water`
/// ([`water_speed`]): the acoustic step of each fine material and of the water, the
/// water's viscous limit ⅛ h² ρ/μ. The seepage drag sets none: it is implicit on both
/// sides ([`seepage_implicit`](crate::interactions::seepage_implicit)).
pub fn rest_dt_bound(scene: &Scene, res: &Resolution, water: Option<&WaterSpeed>) -> RestDt {
    let (h, cfl) = (res.h, scene.simulation.cfl);
    let mut bounds: Vec<RestDt> = Vec::new();
    let take = |bounds: &mut Vec<RestDt>, dt: Real, key: String, what: String, acoustic| {
        bounds.push(RestDt {
            dt,
            key,
            what,
            acoustic,
        })
    };
    for (i, m) in scene.materials.iter().enumerate() {
        let c0 = crate::fine::material::FineMaterial::from_spec(m).c0;
        if c0 > 0.0 {
            take(
                &mut bounds,
                cfl * h / c0,
                format!("materials[{i}].youngs_modulus"),
                format!(
                    "CFL · h / c0 with the sound speed c0 = {} m/s of material `{}`",
                    sig(c0),
                    m.name
                ),
                true,
            );
        }
    }
    if let Some(w) = water.filter(|w| w.c0 > 0.0) {
        take(
            &mut bounds,
            cfl * h / w.c0,
            w.key.to_string(),
            format!(
                "CFL · h / c0 with the water's sound speed c0 = {} m/s",
                sig(w.c0)
            ),
            true,
        );
    }
    // without a sound speed nothing moves: no step bound at all; without water, no
    // viscous limit
    let spec = water.and(water_spec(scene));
    if let Some(w) = spec.filter(|_| !bounds.is_empty()) {
        if w.viscosity > 0.0 {
            take(
                &mut bounds,
                0.125 * h * h * w.density / w.viscosity,
                "water.viscosity".into(),
                format!(
                    "the viscous limit h² ρ / (8 μ) with μ = {:?} Pa·s",
                    w.viscosity
                ),
                false,
            );
        }
    }
    // the tightest bound; NaN counts as the tightest, so that it never hides
    bounds
        .into_iter()
        .reduce(|a, b| if b.dt.is_nan() || b.dt < a.dt { b } else { a })
        .unwrap_or(RestDt {
            dt: Real::INFINITY,
            key: String::new(),
            what: "no fine grains or water".into(),
            acoustic: false,
        })
}

/// `x` to four significant digits, without trailing zeros (55.81, 1e-11, 0.001).
fn sig(x: Real) -> String {
    let s = format!("{x:.3e}");
    let (m, e) = s.split_once('e').unwrap_or((&s, "0"));
    let m = m.trim_end_matches('0').trim_end_matches('.');
    let e: i32 = e.parse().unwrap_or(0);
    if (-3..4).contains(&e) {
        let v: Real = format!("{m}e{e}").parse().unwrap_or(x);
        format!("{v}")
    } else {
        format!("{m}e{e}")
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::input::bundled_scenes;

    #[test]
    fn bound_values_read_to_four_digits() {
        assert_eq!(sig(55.80845216751073), "55.81");
        assert_eq!(sig(14.975199497836416), "14.98");
        assert_eq!(sig(0.001), "0.001");
        assert_eq!(sig(1e-11), "1e-11");
        assert_eq!(sig(2.5e6), "2.5e6");
        assert_eq!(sig(10.0), "10");
    }

    /// The estimate and the build see the scene at one resolution: the one the load
    /// derives ([`Resolution::of_scene`]) is the build's, in every bundled scene.
    #[test]
    fn the_estimate_and_the_build_share_the_resolution() {
        for (name, loaded) in bundled_scenes() {
            let scene = &loaded.scene;
            let built = match scene.simulation.dimension {
                2 => Resolution::of::<2>(scene),
                _ => Resolution::of::<3>(scene),
            };
            let res = Resolution::of_scene(scene);
            assert_eq!(res, built, "{name}");
            assert_eq!(estimate(scene, &res).dp, built.dp, "{name}");
        }
    }
}
