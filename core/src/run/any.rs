//! Dimension dispatch: one enum over the 2D and 3D simulations.

use crate::input::LoadedScene;
use crate::numerics::guard::Blowup;
use crate::numerics::math::Real;
use crate::numerics::timers::StageTimers;
use crate::run::simulation::{BarrierSample, Frame, ParticleRecord, Sample, Simulation};
use crate::scene::SceneError;
use crate::step::{StepStats, Stepping};

/// A simulation of either dimension. Cloning copies the whole state (FMU rollback).
#[derive(Clone, serde::Serialize, serde::Deserialize)]
pub enum AnySimulation {
    D2(Box<Simulation<2>>),
    D3(Box<Simulation<3>>),
}

/// Error while setting up a simulation from a scene.
#[derive(Debug, Clone, thiserror::Error)]
pub enum SetupError {
    /// The world cannot be built: the scene key at fault, located in its file.
    #[error(transparent)]
    Scene(SceneError),
}

/// Run `$e` on the simulation inside an [`AnySimulation`], whichever its dimension.
macro_rules! dispatch {
    ($self:expr, $s:ident => $e:expr) => {
        match $self {
            AnySimulation::D2($s) => $e,
            AnySimulation::D3($s) => $e,
        }
    };
}
pub(crate) use dispatch;

impl AnySimulation {
    /// Build from a loaded scene.
    pub fn new(loaded: &LoadedScene) -> Result<Self, SetupError> {
        let scene = &loaded.scene;
        let err = |e: crate::scene::build_error::BuildError| {
            SetupError::Scene(loaded.locate(crate::scene::KeyError::new(e.path, e.message)))
        };
        Ok(match scene.simulation.dimension {
            2 => AnySimulation::D2(Box::new(Simulation::<2>::new(scene).map_err(err)?)),
            _ => AnySimulation::D3(Box::new(Simulation::<3>::new(scene).map_err(err)?)),
        })
    }
    pub fn dimension(&self) -> usize {
        match self {
            AnySimulation::D2(_) => 2,
            AnySimulation::D3(_) => 3,
        }
    }
    pub fn time(&self) -> Real {
        dispatch!(self, s => s.time())
    }
    pub fn steps(&self) -> u64 {
        dispatch!(self, s => s.world.steps)
    }
    pub fn fine_count(&self) -> usize {
        dispatch!(self, s => s.world.fine.len())
    }
    /// Resting fine grains sleep (`numerics.sleep`).
    pub fn sleeps(&self) -> bool {
        dispatch!(self, s => s.stepper.params.sleep.is_some())
    }
    /// Where fine grains sleep: the share awake now, and its mean over the steps.
    pub fn fine_awake(&self) -> Option<(f64, f64)> {
        dispatch!(self, s => s
            .stepper
            .fine_awake_share(&s.world)
            .zip(s.stepper.fine_awake_mean()))
    }
    /// The scene has `[water]` (its particles may come later, through inflows).
    pub fn has_water(&self) -> bool {
        dispatch!(self, s => s.world.has_water())
    }
    pub fn water_count(&self) -> usize {
        dispatch!(self, s => s.water_count())
    }
    /// The wall particles and their object indices ([`Simulation::wall_points`]).
    pub fn wall_points(&self) -> (Vec<[f32; 3]>, Vec<u16>) {
        dispatch!(self, s => s.wall_points())
    }
    /// The wall objects as solids ([`Simulation::wall_solids`]).
    pub fn wall_solids(&self) -> Vec<crate::geometry::solids::WallSolid> {
        dispatch!(self, s => s.wall_solids())
    }
    /// Each wall object's offset since t = 0 ([`Simulation::wall_offsets`]).
    pub fn wall_offsets(&self) -> Vec<[Real; 3]> {
        dispatch!(self, s => s.wall_offsets())
    }
    /// The wall particles' pressure ([`Simulation::wall_pressure`]).
    pub fn wall_pressure(&self) -> (Vec<f32>, Option<Vec<f32>>) {
        dispatch!(self, s => s.wall_pressure())
    }
    pub fn wall_count(&self) -> usize {
        dispatch!(self, s => s.world.walls.len())
    }
    pub fn region_counts(&self) -> Vec<(String, usize)> {
        dispatch!(self, s => s.world.region_counts.clone())
    }
    /// Panel counts of each barrier (scene key `panels`; empty for one panel).
    pub fn barrier_panels(&self) -> Vec<Vec<usize>> {
        dispatch!(self, s => s.world.walls.barriers.iter().map(|b| b.panels.clone()).collect())
    }
    pub fn barrier_names(&self) -> Vec<String> {
        dispatch!(self, s => s.world.walls.barriers.iter().map(|b| b.name.clone()).collect())
    }
    pub fn gauge_names(&self) -> Vec<String> {
        dispatch!(self, s => s.world.gauges.iter().map(|p| p.name.clone()).collect())
    }
    pub fn probe_names(&self) -> Vec<String> {
        dispatch!(self, s => s.world.probes.iter().map(|p| p.name.clone()).collect())
    }
    /// Δt of Eq. (51) for the current state.
    pub fn stable_dt(&self) -> Real {
        dispatch!(self, s => s.stepper.stable_dt(&s.world))
    }
    pub fn step(&mut self, max_dt: Real) -> Result<StepStats, Blowup> {
        dispatch!(self, s => s.step(max_dt))
    }
    pub fn advance_to(&mut self, t: Real) -> Result<(), Blowup> {
        dispatch!(self, s => s.advance_to(t))
    }
    pub fn sample(&mut self) -> Sample {
        dispatch!(self, s => s.sample())
    }
    /// See [`Simulation::state_loads`].
    pub fn state_loads(&self) -> Result<Vec<BarrierSample>, Blowup> {
        dispatch!(self, s => s.state_loads())
    }
    pub fn frame(&self) -> Frame {
        dispatch!(self, s => s.frame())
    }
    /// Fine and coarse particle counts.
    pub fn particle_counts(&self) -> (usize, usize) {
        dispatch!(self, s => s.particle_counts())
    }
    /// Fill `out` with every particle's record, fine first then coarse (see
    /// [`Simulation::fill_particles`]).
    pub fn fill_particles(&self, out: &mut [ParticleRecord]) {
        dispatch!(self, s => s.fill_particles(out))
    }
    pub fn timers(&self) -> &StageTimers {
        dispatch!(self, s => &s.stepper.timers)
    }
    pub fn timers_mut(&mut self) -> &mut StageTimers {
        dispatch!(self, s => &mut s.stepper.timers)
    }
    pub fn skipped(&self) -> Vec<(String, String)> {
        dispatch!(self, s => s.stepper.skipped.clone())
    }
    /// Bytes held by the fine particles and the stepper's scratch (walls excluded).
    /// Bytes held by the water particles' state (the water stage's scratch is in
    /// [`Self::fine_bytes`]).
    pub fn water_bytes(&self) -> usize {
        dispatch!(self, s => s.world.water.particles.bytes())
    }
    pub fn fine_bytes(&self) -> usize {
        dispatch!(self, s => s.world.fine.bytes() + s.stepper.bytes())
    }
    pub fn body_names(&self) -> Vec<String> {
        dispatch!(self, s => s.world.coarse.bodies.iter().map(|b| b.name.clone()).collect())
    }
    /// (name, model, particles, mass) of every body.
    pub fn body_summaries(&self) -> Vec<(String, String, usize, Real)> {
        dispatch!(self, s => s.world.coarse.bodies.iter().map(|b| {
            (b.name.clone(), format!("{:?}", b.model).to_lowercase(), b.len(), b.mass)
        }).collect())
    }
    /// Δt_c and κ for the initial state.
    pub fn coarse_estimate(&mut self) -> (Real, usize) {
        dispatch!(self, s => {
            let dt_f = s.stepper.stable_dt(&s.world);
            let dt_c = s.stepper.coarse_dt(&s.world, dt_f);
            let (_, k) = crate::step::choose_step(dt_f, dt_c, Real::INFINITY, s.stepper.params.scheme);
            (dt_c, k)
        })
    }
    pub fn coarse_count(&self) -> usize {
        dispatch!(self, s => s.world.coarse.particles.len())
    }
    /// Coarse sub-steps so far.
    pub fn coarse_steps(&self) -> u64 {
        dispatch!(self, s => s.stepper.coarse.as_ref().map(|c| c.steps).unwrap_or(0))
    }
    /// Water steps so far, its sub-steps counted (equal to the fine steps unless the
    /// water sub-steps).
    pub fn water_steps(&self) -> u64 {
        dispatch!(self, s => s.stepper.water.as_ref().map(|w| w.steps).unwrap_or(0))
    }
    /// The families' relations with their list builds and pairs at the last build.
    pub fn relations(&self) -> Vec<(crate::step::Relation, crate::step::RelationStats)> {
        dispatch!(self, s => s.stepper.relations(&s.world))
    }
    pub fn neighbor_builds(&self) -> usize {
        dispatch!(self, s => s.stepper.fine.family.lists.builds)
    }
}

impl Stepping for AnySimulation {
    fn now(&self) -> Real {
        self.time()
    }
    fn set_now(&mut self, t: Real) {
        dispatch!(self, s => s.set_now(t))
    }
    fn step_at_most(&mut self, max_dt: Real) -> Result<StepStats, Blowup> {
        self.step(max_dt)
    }
}
