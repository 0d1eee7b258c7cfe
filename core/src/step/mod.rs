//! The step: seed 000 §4.2 (Eqs. 54–60), one fine step with κ coarse sub-steps,
//! assembled from stages in their own files (drift and sweeps, neighbours, finalize
//! and guard, coarse stages). The stepper holds scratch memory; the world holds state.

use crate::fine::material::uniform_acoustics;
use crate::fine::pair_sums::PairSums;
use crate::fine::source::Source;
use crate::guard::{Blowup, ChunkFailure};
use crate::interactions::fine_coarse::CoarseSource;
use crate::kernel::WendlandC2;
use crate::load::Load;
use crate::math::{up, Real, Sym, Vect};
use crate::neighbors::{CellGrid, NeighborLists};
use crate::permute::PermuteScratch;
use crate::timers::{Stage, StageTimers};
use crate::world::{geostatic_tensor, World};
use build_marks::{CoarseBins, PositionMarks, WallBins};
use coarse_substeps::CoarseStepper;

mod build_marks;
mod coarse_stage;
pub mod coarse_substeps;
mod finalize;
mod fine_sweeps;
pub mod landing;
mod neighbours;
mod params;
mod soil_water_stage;
mod water_open;
mod water_stage;
mod water_substeps;

pub use landing::{land_on, Stepping};
pub use params::{choose_step, gravity_ramp, StepParams, StepStats};
pub use soil_water_stage::SoilWater;
pub use water_stage::WaterStepper;

/// Scratch memory and stage assembly for the fine step.
#[derive(Clone, serde::Serialize, serde::Deserialize)]
pub struct Stepper<const D: usize> {
    pub params: StepParams,
    pub kernel: WendlandC2,
    /// Binned afresh at every list build: a serialised state keeps only its geometry.
    #[serde(with = "crate::neighbors::geometry_only")]
    fine_grid: CellGrid<D>,
    walls: WallBins<D>,
    pub lists: NeighborLists,
    at_build: PositionMarks<D>,
    /// Largest displacement since the last list build (end of last step).
    max_disp: Real,
    vmax: Real,
    /// Scratch: written in full by every step before it is read (not serialised).
    #[serde(skip)]
    vel_new: Vec<Vect<D>>,
    #[serde(skip)]
    art: Vec<Sym>,
    #[serde(skip)]
    src: Vec<Source>,
    #[serde(skip)]
    chunk_loads: Vec<Load>,
    /// Load on each barrier during the last step.
    pub step_loads: Vec<Load>,
    /// Fine-grain load on each barrier panel during the last step (`Walls::load_slot`).
    pub slot_loads: Vec<Load>,
    /// Scratch: written in full by every step before it is read (not serialised).
    #[serde(skip)]
    permute: PermuteScratch,
    #[serde(skip)]
    order: Vec<u32>,
    /// Pair sums of the two sweeps (zero between steps, so a restored state starts
    /// them from an empty buffer that the step fills with zeros).
    #[serde(skip)]
    pair_sums: Vec<PairSums<D>>,
    geostatic: Vec<Sym>,
    /// Per material: the geostatic pressure gradient of this step (ramp applied).
    #[serde(skip)]
    geostatic_pressure: Vec<Real>,
    /// Per material: ξ G of the hourglass penalty (empty: off).
    hourglass: Vec<Real>,
    /// Per material: share of the stored penalty kept over this step (set per step).
    hourglass_leak: Vec<f32>,
    /// Per material: the grain–boulder interface carries tension (c > 0).
    tension: Vec<bool>,
    /// All fine materials share one impedance and sound speed (fixed for a run).
    uniform: bool,
    /// The scene's full gravity, and the ramp factor of the current step.
    g_full: Vect<D>,
    g_scale: Real,
    up: Vect<D>,
    /// Wall-clock time per stage (a restored state starts them at zero).
    #[serde(skip)]
    pub timers: StageTimers,
    /// Stages left out for this scene, with the reason.
    pub skipped: Vec<(String, String)>,
    #[serde(skip)]
    failures: Vec<(Real, Real, ChunkFailure)>,
    /// Coarse grains: sub-stepper (None without bodies).
    pub coarse: Option<CoarseStepper<D>>,
    csrc: Vec<CoarseSource<D>>,
    coarse_bins: CoarseBins<D>,
    reactions: Vec<Vec<(u32, Vect<D>)>>,
    coarse_vol: Real,
    /// Water: its stages' lists and scratch (None without water).
    #[serde(default)]
    pub water: Option<WaterStepper<D>>,
    /// Soil and water: the coupling's scratch (None without water or a soil with
    /// pores).
    #[serde(default)]
    pub soil_water: Option<SoilWater<D>>,
}

impl<const D: usize> Stepper<D> {
    pub fn new(world: &World<D>, params: StepParams) -> Self {
        let kernel = WendlandC2::new(params.h, D);
        let g = world.gravity.norm();
        let up = up(&world.gravity);
        // a saturated soil's skeleton carries its submerged weight
        let rho_w = world.water_material.map(|w| w.rho0);
        let geostatic = world
            .materials
            .iter()
            .map(|m| geostatic_tensor::<D>(&up, m.k0).scale(m.skeleton_density(rho_w) * g))
            .collect();
        let hourglass = if params.hourglass > 0.0 {
            world
                .materials
                .iter()
                .map(|m| params.hourglass * m.shear)
                .collect()
        } else {
            Vec::new()
        };
        let tension = world.materials.iter().map(|m| m.cohesion > 0.0).collect();
        let cell = kernel.cutoff + params.skin;
        let mut skipped = Vec::new();
        if params.artificial.is_none() {
            skipped.push((
                "artificial_stress".into(),
                "no cohesive material (c = 0)".into(),
            ));
        }
        if params.zeta == 0.0 {
            skipped.push((
                "stress_diffusion".into(),
                "numerics.stress_diffusion = 0".into(),
            ));
        }
        if world.walls.is_empty() {
            skipped.push(("wall_boundary".into(), "scene has no walls".into()));
        } else if world.walls.barriers.is_empty() {
            skipped.push(("barrier_loads".into(), "scene has no barriers".into()));
        }
        let coarse = (!world.coarse.is_empty()).then(|| {
            CoarseStepper::new(&world.coarse, &params, world.resolution.dp, &world.gravity)
        });
        if coarse.is_none() {
            skipped.push((
                "coarse_substeps".into(),
                "scene has no coarse grains".into(),
            ));
            skipped.push(("contact".into(), "scene has no coarse grains".into()));
        }
        if coarse.is_none() || world.fine.is_empty() {
            skipped.push((
                "coupling".into(),
                "needs both fine and coarse grains".into(),
            ));
        }
        if world.fine.is_empty() {
            skipped.push(("fine_grains".into(), "scene has no fine grains".into()));
        }
        let water = world
            .water_material
            .is_some()
            .then(|| WaterStepper::new(world, cell, params.skin));
        if water.is_none() {
            skipped.push(("water".into(), "scene has no water".into()));
        }
        let soil_water = SoilWater::new(world, &kernel, params.skin);
        if soil_water.is_none() {
            skipped.push((
                "soil_water".into(),
                "needs water and a soil with `permeability` or `grain_size`".into(),
            ));
        }
        let nb = world.walls.barriers.len();
        Stepper {
            fine_grid: CellGrid::new(&world.domain.0, &world.domain.1, cell),
            walls: WallBins::new(CellGrid::new(&world.domain.0, &world.domain.1, cell)),
            params,
            kernel,
            lists: NeighborLists::default(),
            at_build: PositionMarks::default(),
            max_disp: Real::INFINITY,
            vmax: 0.0,
            vel_new: Vec::new(),
            art: Vec::new(),
            src: Vec::new(),
            chunk_loads: Vec::new(),
            step_loads: vec![Load::default(); nb],
            slot_loads: vec![Load::default(); world.walls.load_slots()],
            permute: PermuteScratch::default(),
            order: Vec::new(),
            pair_sums: Vec::new(),
            geostatic,
            geostatic_pressure: Vec::new(),
            hourglass_leak: vec![1.0; hourglass.len()],
            hourglass,
            tension,
            uniform: uniform_acoustics(&world.materials),
            g_full: world.gravity,
            g_scale: 1.0,
            up,
            timers: StageTimers::default(),
            skipped,
            failures: Vec::new(),
            coarse,
            csrc: Vec::new(),
            coarse_bins: CoarseBins::new(CellGrid::new(&world.domain.0, &world.domain.1, cell)),
            reactions: Vec::new(),
            coarse_vol: world.resolution.volume,
            water,
            soil_water,
        }
    }

    /// Find the coarse contact candidates for a step of about `dt`, then return Δt_c
    /// (infinite without coarse grains).
    pub fn coarse_dt(&mut self, world: &World<D>, dt: Real) -> Real {
        match &mut self.coarse {
            Some(c) => {
                let t = std::time::Instant::now();
                c.prepare(&world.coarse, &world.walls, dt);
                self.timers.add(Stage::Contact, t.elapsed().as_secs_f64());
                c.stable_dt(&world.coarse)
            }
            None => Real::INFINITY,
        }
    }

    /// Δt of Eq. (51) for the current state: CFL · h / (c0 + |v|max) of the fine grains,
    /// the water's Δt_w (whose viscous limit joins in), and CFL · h / |v_wall| of the
    /// fastest moving wall or barrier. The smaller of the two,
    /// unless the scheme is multi-rate and Δt_w fits k ≥ 2 times into the fine Δt:
    /// then k Δt_w, and the water takes k sub-steps ([`water_substeps`]).
    pub fn stable_dt(&self, world: &World<D>) -> Real {
        let fine = if world.fine.is_empty() {
            Real::INFINITY
        } else {
            self.params.cfl * self.params.h / (world.max_c0() + self.vmax)
        };
        let water = match (&self.water, &world.water_material) {
            (Some(w), Some(m)) => w.stable_dt(m, self.params.h, self.params.cfl),
            _ => Real::INFINITY,
        };
        // multi-rate: where the water's Δt fits twice or more into the fine Δt, the
        // step is the largest whole multiple of it and the water sub-steps
        // ([`water_substeps`])
        let multi = self.params.scheme == crate::scene::TimeStepping::MultiRate;
        // the soil's side of the seepage drag is explicit
        let seep = self
            .soil_water
            .as_ref()
            .map_or(Real::INFINITY, |s| s.dt_max);
        // a moving wall or barrier (prescribed or driven) moves at most CFL·h per step,
        // so that it cannot pass through a layer of particles within one step
        let wall = self.params.cfl * self.params.h / world.walls.max_speed_at(world.time);
        if multi && fine.is_finite() && water.is_finite() {
            let k = (fine.min(seep).min(wall) / water).floor();
            if k >= 2.0 {
                return k * water;
            }
        }
        fine.min(water).min(seep).min(wall)
    }

    /// Bytes of scratch memory held by the stepper (lists, buffers, grids).
    pub fn bytes(&self) -> usize {
        use std::mem::size_of;
        self.lists.bytes()
            + self.at_build.bytes()
            + self.vel_new.capacity() * size_of::<Vect<D>>()
            + self.art.capacity() * size_of::<Sym>()
            + self.src.capacity() * size_of::<Source>()
            + self.order.capacity() * 4
            + self.pair_sums.capacity() * size_of::<PairSums<D>>()
            + self.fine_grid.bytes()
            + self.walls.grid.bytes()
            + self.water.as_ref().map_or(0, |w| w.bytes())
    }

    /// Largest fine-grain speed at the end of the last step.
    pub fn fine_vmax(&self) -> Real {
        self.vmax
    }

    /// Advance the world by one fine step of size `dt` with `kappa` coarse sub-steps,
    /// seed 000 §4.2: the fine grains by position-based Verlet (Eqs. 54–56), the coarse
    /// grains by κ sub-steps under the fine grains' force of the step (Eqs. 57–60).
    pub fn step(
        &mut self,
        world: &mut World<D>,
        dt: Real,
        kappa: usize,
    ) -> Result<StepStats, Blowup> {
        let half = 0.5 * dt;
        self.set_loads_of_time(world, half);
        // the coarse particles at the middle of the step, as the fine sweeps see them
        if self.coarse.is_some() && !(world.fine.is_empty() && self.water.is_none()) {
            self.timed(Stage::Coupling, |s| s.pack_coarse(world, dt));
        }
        // Eq. (54): x and ρ to the half step
        self.timed(Stage::Drift, |s| s.drift(world, half));
        let rebuilt = self.timed(Stage::Neighbors, |s| s.refresh_lists(world, dt));
        // the water, in κ_w sub-steps, with the fine grains at the half step; its force
        // on the coarse grains feeds theirs, on a soil the fine sweeps
        let water_vmax = self.water_substeps(world, dt)?;
        // Eq. (27), cohesive soils only
        let artificial = self
            .params
            .artificial
            .and_then(|_| self.timed(Stage::ArtificialStress, |s| s.artificial_stress(world)));
        // Eqs. (16), (55) then (15), (24)–(26), (7)–(12), with walls and coarse grains
        self.fine_sweeps(world, dt, artificial);
        // Eq. (56) and the per-chunk stability checks
        self.timed(Stage::Finalize, |s| s.finalize(world, half));
        self.add_water_loads();
        // Eqs. (57)–(60): κ coarse sub-steps
        self.coarse_substeps(world, dt, kappa)?;
        world.time += dt;
        world.steps += 1;
        let vmax = self.guard(world)?.max(water_vmax);
        Ok(StepStats {
            vmax,
            rebuilt,
            kappa,
        })
    }

    /// What changes with time at the start of a step: the wall velocities and the
    /// gravity ramp (evaluated at the middle of the step).
    fn set_loads_of_time(&mut self, world: &mut World<D>, half: Real) {
        world.walls.set_time(world.time);
        self.g_scale = gravity_ramp(world.time + half, self.params.gravity_ramp);
        world.gravity = self.g_full * self.g_scale;
        if let Some(c) = self.coarse.as_mut() {
            c.set_gravity(&world.gravity);
        }
    }

    /// Run stage `f`, its wall-clock time added to `stage`.
    fn timed<R>(&mut self, stage: Stage, f: impl FnOnce(&mut Self) -> R) -> R {
        let t = std::time::Instant::now();
        let r = f(self);
        self.timers.add(stage, t.elapsed().as_secs_f64());
        r
    }
}
