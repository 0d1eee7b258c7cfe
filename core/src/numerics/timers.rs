//! Per-stage wall-clock timers, reported at the end of a run.

use std::time::Instant;

/// The stages of a fine step, in execution order.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Stage {
    Drift,
    Neighbors,
    ArtificialStress,
    Momentum,
    ContinuityStress,
    Finalize,
    Sleep,
    Coupling,
    Contact,
    CoarseSubsteps,
    WaterDriftFinalize,
    WaterNeighbors,
    WaterMomentum,
    WaterContinuity,
    SoilWater,
    Observe,
}

impl Stage {
    pub const ALL: [Stage; 16] = [
        Stage::Drift,
        Stage::Neighbors,
        Stage::ArtificialStress,
        Stage::Momentum,
        Stage::ContinuityStress,
        Stage::Finalize,
        Stage::Sleep,
        Stage::Coupling,
        Stage::Contact,
        Stage::CoarseSubsteps,
        Stage::WaterDriftFinalize,
        Stage::WaterNeighbors,
        Stage::WaterMomentum,
        Stage::WaterContinuity,
        Stage::SoilWater,
        Stage::Observe,
    ];
    pub fn name(self) -> &'static str {
        match self {
            Stage::Drift => "drift",
            Stage::Neighbors => "neighbors",
            Stage::ArtificialStress => "artificial_stress",
            Stage::Momentum => "momentum",
            Stage::ContinuityStress => "continuity_stress",
            Stage::Finalize => "finalize_guard",
            Stage::Sleep => "sleep",
            Stage::Coupling => "coupling",
            Stage::Contact => "contact",
            Stage::CoarseSubsteps => "coarse_substeps",
            Stage::WaterDriftFinalize => "water_drift_finalize",
            Stage::WaterNeighbors => "water_neighbors",
            Stage::WaterMomentum => "water_momentum",
            Stage::WaterContinuity => "water_continuity",
            Stage::SoilWater => "soil_water",
            Stage::Observe => "observe",
        }
    }
}

/// Accumulated seconds per stage.
#[derive(Clone, Debug, Default)]
pub struct StageTimers {
    secs: [f64; 16],
}

impl StageTimers {
    #[inline]
    pub fn time<R>(&mut self, s: Stage, f: impl FnOnce() -> R) -> R {
        let t = Instant::now();
        let r = f();
        self.secs[s as usize] += t.elapsed().as_secs_f64();
        r
    }
    pub fn add(&mut self, s: Stage, secs: f64) {
        self.secs[s as usize] += secs;
    }
    pub fn get(&self, s: Stage) -> f64 {
        self.secs[s as usize]
    }
    /// (name, seconds) for every stage that ran.
    pub fn entries(&self) -> Vec<(&'static str, f64)> {
        Stage::ALL
            .iter()
            .map(|&s| (s.name(), self.get(s)))
            .filter(|(_, t)| *t > 0.0)
            .collect()
    }
    pub fn total(&self) -> f64 {
        self.secs.iter().sum()
    }
}
