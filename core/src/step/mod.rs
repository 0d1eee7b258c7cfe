//! The step: seed 000 §4.2 (Eqs. 54–60), one fine step with κ coarse sub-steps,
//! assembled from stages in their own files (drift and sweeps, neighbours, finalize
//! and guard, coarse stages). The stepper holds scratch memory; the world holds state.

use crate::interactions::fine_coarse::CoarseSource;
use crate::numerics::guard::{Blowup, Family};
use crate::numerics::kernel::WendlandC2;
use crate::numerics::load::Load;
use crate::numerics::math::{up, Real, Vect};
use crate::numerics::timers::{Stage, StageTimers};
use crate::world::World;
use coarse_substeps::CoarseStepper;
use fine_stage::{FineContext, FineStepper};

mod coarse_stage;
pub mod coarse_substeps;
mod family;
mod fine_stage;
pub mod landing;
mod params;
mod relations;
mod soil_water_stage;
mod water_open;
mod water_stage;
mod water_substeps;

pub use landing::{land_on, Stepping};
pub use params::{choose_step, gravity_ramp, StepParams, StepStats};
pub use relations::{Relation, RelationStats};
pub use soil_water_stage::SoilWater;
pub use water_stage::WaterStepper;

/// The step's orchestrator: it runs the families' stages in the order of seed 000
/// §4.2 (and the water's and the soil–water coupling's in theirs), and holds what they
/// share: the parameters, the kernel, gravity and its ramp, the coarse particles at
/// the middle of the step, the barrier loads summed over the families, and the stage
/// timers. The world holds the state.
#[derive(Clone, serde::Serialize, serde::Deserialize)]
pub struct Stepper<const D: usize> {
    pub params: StepParams,
    pub kernel: WendlandC2,
    /// The fine grains: their lists, sources and sweep buffers.
    pub fine: FineStepper<D>,
    /// Load on each barrier during the last step, all families.
    pub step_loads: Vec<Load>,
    /// The same per barrier panel (`Walls::load_slot`).
    pub slot_loads: Vec<Load>,
    /// The scene's full gravity, and the ramp factor of the current step.
    g_full: Vect<D>,
    g_scale: Real,
    up: Vect<D>,
    /// Wall-clock time per stage (a restored state starts them at zero).
    #[serde(skip)]
    pub timers: StageTimers,
    /// Stages left out for this scene, with the reason.
    pub skipped: Vec<(String, String)>,
    /// Coarse grains: sub-stepper (None without bodies).
    pub coarse: Option<CoarseStepper<D>>,
    csrc: Vec<CoarseSource<D>>,
    coarse_vol: Real,
    /// Water: its stages' lists and scratch (None without water).
    #[serde(default)]
    pub water: Option<WaterStepper<D>>,
    /// Soil and water: the coupling's scratch (None without water or a soil with
    /// pores).
    #[serde(default)]
    pub soil_water: Option<SoilWater<D>>,
    /// Where fine grains sleep: the sum over the steps of the share of fine particles
    /// awake at each step's end, and the steps summed.
    #[serde(default)]
    pub awake_tally: (Real, u64),
}

impl<const D: usize> Stepper<D> {
    pub fn new(world: &World<D>, params: StepParams) -> Self {
        let kernel = WendlandC2::new(params.h, D);
        // along a periodic slope, normal to the bed
        let up = up(&world.hydrostatic_gravity());
        let cell = kernel.cutoff + params.skin;
        let skipped = skipped_stages(world, &params);
        let coarse = (!world.coarse.is_empty()).then(|| {
            CoarseStepper::new(&world.coarse, &params, world.resolution.dp, &world.gravity)
        });
        let water = world
            .has_water()
            .then(|| WaterStepper::new(world, cell, params.skin));
        let soil_water = SoilWater::new(world, &kernel, (params.skin, params.seepage_midpoint));
        let nb = world.walls.barriers.len();
        Stepper {
            fine: FineStepper::new(world, &params, cell, &up),
            params,
            kernel,
            step_loads: vec![Load::default(); nb],
            slot_loads: vec![Load::default(); world.walls.load_slots()],
            g_full: world.gravity,
            g_scale: 1.0,
            up,
            timers: StageTimers::default(),
            skipped,
            coarse,
            csrc: Vec::new(),
            coarse_vol: world.resolution.volume,
            water,
            soil_water,
            awake_tally: (0.0, 0),
        }
    }

    /// Whether this stepper, restored from a state, fits `template` (the stepper the
    /// scene builds with the state's parameters) and `world` (the restored particles):
    /// the same parameters, kernel, gravity and stages, loads of every barrier and
    /// panel, and each family's stepper fitting its particles. Says which part does not.
    pub fn restored_fits(&self, template: &Self, world: &World<D>) -> Result<(), &'static str> {
        let t = template;
        if self.params != t.params || self.kernel != t.kernel {
            return Err("method parameters");
        }
        if self.g_full != t.g_full
            || self.up != t.up
            || self.coarse_vol.to_bits() != t.coarse_vol.to_bits()
            || self.skipped != t.skipped
        {
            return Err("gravity or stages");
        }
        if self.step_loads.len() != t.step_loads.len()
            || self.slot_loads.len() != t.slot_loads.len()
        {
            return Err("barrier loads");
        }
        let walls = world.walls.len();
        self.fine.restored_fits(&t.fine, world.fine.len(), walls)?;
        match (&self.coarse, &t.coarse) {
            (Some(c), Some(tc)) => c.restored_fits(tc, &world.coarse, world.walls.objects.len())?,
            (None, None) => {}
            _ => return Err("coarse sub-stepper"),
        }
        match (&self.water, &t.water) {
            (Some(w), Some(tw)) => w.restored_fits(tw, world.water.particles.len(), walls)?,
            (None, None) => {}
            _ => return Err("water stepper"),
        }
        match (&self.soil_water, &t.soil_water) {
            (Some(s), Some(ts)) if s.restored_fits(ts) => {}
            (None, None) => {}
            _ => return Err("soil–water coupling"),
        }
        Ok(())
    }

    /// Whether the motion the next Δt and list rebuilds read (each family's largest
    /// speed and displacement since its lists' build, the coarse sub-stepper's speed,
    /// acceleration and sub-step) is finite and in range: a restored state's, before it
    /// steps. Says which is not.
    pub fn restored_motion_fits(&self) -> Result<(), &'static str> {
        let v = self.params.max_speed;
        if !self.fine.family.motion_in_range(v) {
            return Err("fine particles' largest speed or displacement");
        }
        if self
            .water
            .as_ref()
            .is_some_and(|w| !w.family.motion_in_range(v))
        {
            return Err("water particles' largest speed or displacement");
        }
        if self.coarse.as_ref().is_some_and(|c| !c.motion_in_range()) {
            return Err("coarse particles' largest speed or acceleration");
        }
        if !(self.g_scale.is_finite() && (0.0..=1.0).contains(&self.g_scale)) {
            return Err("gravity ramp");
        }
        Ok(())
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
            self.params.cfl * self.params.h / (world.max_c0() + self.fine_vmax())
        };
        let water = match (&self.water, &world.water.material) {
            (Some(w), Some(m)) => w.stable_dt(m, self.params.h, self.params.cfl),
            _ => Real::INFINITY,
        };
        // multi-rate: where the water's Δt fits twice or more into the fine Δt, the
        // step is the largest whole multiple of it and the water sub-steps
        // ([`water_substeps`])
        let multi = self.params.scheme == crate::scene::TimeStepping::MultiRate;
        // a moving wall or barrier (prescribed or driven) moves at most CFL·h per step,
        // so that it cannot pass through a layer of particles within one step
        let wall = self.params.cfl * self.params.h / world.walls.max_speed_at(world.time);
        if multi && fine.is_finite() && water.is_finite() {
            let k = (fine.min(wall) / water).floor();
            if k >= 2.0 {
                return k * water;
            }
        }
        fine.min(water).min(wall)
    }

    /// Bytes of scratch memory held by the stepper (lists, buffers, grids).
    pub fn bytes(&self) -> usize {
        self.fine.bytes() + self.water.as_ref().map_or(0, |w| w.bytes())
    }

    /// The relations of the scene's families, with their list builds and pairs at the
    /// last build (summary.json `relations`).
    pub fn relations(&self, world: &World<D>) -> Vec<(Relation, RelationStats)> {
        use Relation::*;
        let mut out = Vec::new();
        if !world.fine.is_empty() {
            out.extend(
                self.fine
                    .family
                    .relation_stats([FineFine, FineWall, FineCoarse]),
            );
        }
        if let Some(w) = &self.water {
            out.extend(
                w.family
                    .relation_stats([WaterWater, WaterWall, WaterCoarse]),
            );
        }
        if let Some(s) = &self.soil_water {
            let (builds, pairs) = s.relation.stats();
            out.push((SoilWater, RelationStats { builds, pairs }));
        }
        out
    }

    /// The share of fine particles awake (None where they do not sleep or there are
    /// none).
    pub fn fine_awake_share(&self, world: &World<D>) -> Option<Real> {
        let rule = self.params.sleep.as_ref()?;
        (!world.fine.is_empty())
            .then(|| crate::numerics::sleep::awake_share(rule, &world.fine.quiet))
    }

    /// The mean share of fine particles awake over the steps taken (None where they
    /// do not sleep or no step was taken): awake particle-steps over particle-steps.
    pub fn fine_awake_mean(&self) -> Option<Real> {
        self.params.sleep?;
        let (sum, steps) = self.awake_tally;
        (steps > 0).then(|| sum / steps as Real)
    }

    /// Largest fine-grain speed at the end of the last step.
    pub fn fine_vmax(&self) -> Real {
        self.fine.family.vmax()
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
        // Eq. (54): x and ρ to the half step; the walls move with them
        self.timed(Stage::Drift, |s| {
            s.fine.drift(world, half);
            world.walls.advance(half);
        });
        let rebuilt = self.timed(Stage::Neighbors, |s| {
            s.fine.refresh_lists(world, &s.csrc, dt)
        });
        // the water, in κ_w sub-steps, with the fine grains at the half step; its force
        // on the coarse grains feeds theirs. With a soil with pores the soil–water
        // coupling (soil_water_stage.rs) runs in them: the soil is frozen at the half
        // step before the first sub-step and the drag is implicit in each;
        let water_vmax = self.water_substeps(world, dt)?;
        // after the last, the soil gathers the opposite of the water's drag and its
        // buoyancy, which the fine sweeps add
        self.soil_gathers(world, dt);
        // Eq. (27), cohesive soils only
        let artificial = self.params.artificial.and_then(|_| {
            self.timed(Stage::ArtificialStress, |s| {
                s.fine.artificial_stress(world, &s.params, &s.kernel)
            })
        });
        // Eqs. (16), (55) then (15), (24)–(26), (7)–(12), with walls and coarse grains
        self.fine_sweeps(world, dt, artificial);
        // Eq. (56) and the per-chunk stability checks; the walls to the end of the step
        self.timed(Stage::Finalize, |s| {
            s.fine.finalize(world, half, s.params.max_speed);
            world.walls.advance(half);
        });
        if let Some(rule) = self.params.sleep {
            // resting particles fall asleep; the restless wake their neighbours
            self.timed(Stage::Sleep, |s| {
                s.fine
                    .settle(world, &rule, (s.kernel.cutoff, s.g_scale < 1.0));
                if !world.fine.is_empty() {
                    s.awake_tally.0 +=
                        crate::numerics::sleep::awake_share(&rule, &world.fine.quiet);
                    s.awake_tally.1 += 1;
                }
            });
        }
        self.sum_family_loads();
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

    /// The fine sweeps of a step of `dt` ([`FineStepper::momentum`] and
    /// [`FineStepper::continuity`]), with what they read of the step; between them the
    /// seepage drag is closed implicitly on both sides ([`SoilWater::close`]), so that
    /// the stress sees the soil's velocity of the step's end.
    fn fine_sweeps(
        &mut self,
        world: &mut World<D>,
        dt: Real,
        artificial: Option<crate::fine::momentum::ArtificialStress>,
    ) {
        let cx = FineContext {
            params: &self.params,
            kernel: self.kernel,
            g_scale: self.g_scale,
            up: self.up,
            csrc: &self.csrc,
            coarse: self.coarse.is_some(),
            soil_water: self.soil_water.as_ref(),
        };
        self.fine
            .momentum(world, dt, artificial, &cx, &mut self.timers);
        self.close_seepage(world, dt);
        let cx = FineContext {
            params: &self.params,
            kernel: self.kernel,
            g_scale: self.g_scale,
            up: self.up,
            csrc: &self.csrc,
            coarse: self.coarse.is_some(),
            soil_water: self.soil_water.as_ref(),
        };
        self.fine.continuity(world, dt, &cx, &mut self.timers);
    }

    /// The step's barrier loads: the fine grains' and the water's (the coarse grains'
    /// contact loads join in their sub-steps).
    fn sum_family_loads(&mut self) {
        self.step_loads.clone_from(&self.fine.family.step_loads);
        self.slot_loads.clone_from(&self.fine.family.slot_loads);
        let Some(w) = &self.water else {
            return;
        };
        for (total, l) in self.step_loads.iter_mut().zip(&w.family.step_loads) {
            total.add(l);
        }
        for (total, l) in self.slot_loads.iter_mut().zip(&w.family.slot_loads) {
            total.add(l);
        }
    }

    /// Stop on a wall object whose motion is not finite or faster than the bound, or
    /// on the first failing fine particle of the step; otherwise return the fine
    /// grains' largest speed.
    fn guard(&mut self, world: &World<D>) -> Result<Real, Blowup> {
        let max_speed = self.params.max_speed;
        // the walls' rigid motion (prescribed or driven) first: a barrier sent to
        // infinity stops the run as a particle would, and is the cause of what its
        // neighbours do in the same step
        if let Some((o, quantity, value, speed)) = world.walls.check(max_speed) {
            let w = &world.walls.objects[o];
            return Err(Blowup {
                step: world.steps,
                time: world.time,
                particle: o as u32,
                body: Some(w.name.clone()),
                family: Family::Wall,
                position: w.displacement.iter().copied().collect(),
                quantity: quantity.to_string(),
                value,
                limit: speed.then_some(max_speed),
            });
        }
        self.fine.guard(world, max_speed)
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

/// The stages a scene leaves out, with the reason (summary.json `skipped`).
fn skipped_stages<const D: usize>(world: &World<D>, params: &StepParams) -> Vec<(String, String)> {
    let mut skipped: Vec<(String, String)> = Vec::new();
    let mut skip = |stage: &str, why: &str| skipped.push((stage.into(), why.into()));
    if params.artificial.is_none() {
        skip("artificial_stress", "no cohesive material (c = 0)");
    }
    if params.zeta == 0.0 {
        skip("stress_diffusion", "numerics.stress_diffusion = 0");
    }
    if world.walls.is_empty() {
        skip("wall_boundary", "scene has no walls");
    } else if world.walls.barriers.is_empty() {
        skip("barrier_loads", "scene has no barriers");
    }
    if world.coarse.is_empty() {
        skip("coarse_substeps", "scene has no coarse grains");
        skip("contact", "scene has no coarse grains");
    }
    if world.coarse.is_empty() || world.fine.is_empty() {
        skip("coupling", "needs both fine and coarse grains");
    }
    if world.fine.is_empty() {
        skip("fine_grains", "scene has no fine grains");
    }
    if !world.has_water() {
        skip("water", "scene has no water");
    }
    let pores = world.materials.iter().any(|m| m.pores.is_some());
    if !world.has_water() || !pores {
        skip(
            "soil_water",
            "needs water and a soil with `permeability` or `grain_size`",
        );
    }
    skipped
}
