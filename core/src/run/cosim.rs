//! Co-simulation hooks over [`Simulation`]: input-driven barriers and state snapshots.
//! The FMU (crate `granmix-fmu`) is the user; the CLI never drives barriers.

use crate::numerics::math::{Real, Vect};
use crate::run::any::dispatch;
use crate::run::any::AnySimulation;
use crate::run::simulation::Simulation;

/// Most solver steps a driven barrier's motion may call for within one communication
/// step: the time step keeps every wall to CFL·h per step
/// ([`crate::step::Stepper::stable_dt`]), so a displacement of more than
/// `MAX_DRIVE_STEPS`·CFL·h within one call is refused rather than stepped.
pub const MAX_DRIVE_STEPS: Real = 100_000.0;

/// A barrier that cannot be driven, or not with this velocity.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum DriveError {
    #[error("no barrier with index {0}")]
    NoBarrier(usize),
    #[error("barrier `{0}` is not input-driven (scene key `input`)")]
    NotDriven(String),
    /// The commanded velocity (from a displacement input over the step, or given) is a
    /// NaN or an infinity.
    #[error(
        "barrier `{barrier}`: the commanded motion gives a velocity of {speed:?} m/s, \
         which is not finite"
    )]
    NotFinite { barrier: String, speed: Real },
    /// Faster than the stability guard's speed bound: every wall particle would fail it.
    #[error(
        "barrier `{barrier}`: the commanded motion is {speed:?} m/s, beyond \
         simulation.max_speed = {max_speed:?} m/s (the stability guard's bound); move it \
         over more or longer communication steps, or raise simulation.max_speed"
    )]
    TooFast {
        barrier: String,
        speed: Real,
        max_speed: Real,
    },
    /// The motion within the communication step of `span` s would need more solver
    /// steps than [`MAX_DRIVE_STEPS`].
    #[error(
        "barrier `{barrier}`: moving {distance:?} m within one communication step of \
         {span:?} s takes {steps:.3e} solver steps at CFL·h = {limit:?} m per step, \
         more than the {MAX_DRIVE_STEPS:e} allowed; use shorter communication steps"
    )]
    TooManySteps {
        barrier: String,
        distance: Real,
        span: Real,
        steps: Real,
        limit: Real,
    },
}

impl<const D: usize> Simulation<D> {
    /// True when barrier `b` is driven by co-simulation inputs (scene key `input`).
    pub fn barrier_driven(&self, b: usize) -> bool {
        let walls = &self.world.walls;
        walls.objects[walls.barriers[b].object].driven
    }

    /// Rigid displacement of barrier `b` since the start (3D layout, z = 0 in 2D).
    pub fn barrier_displacement(&self, b: usize) -> [Real; 3] {
        let walls = &self.world.walls;
        pad(&walls.objects[walls.barriers[b].object].displacement)
    }

    /// Current rigid velocity of barrier `b` (3D layout).
    pub fn barrier_velocity(&self, b: usize) -> [Real; 3] {
        let walls = &self.world.walls;
        pad(&walls.objects[walls.barriers[b].object].velocity)
    }

    /// Whether input-driven barrier `b` may move with `velocity` (components beyond `D`
    /// ignored) for the next `span` seconds: the barrier exists and is driven, the
    /// velocity is finite and within the stability guard's bound, and the motion needs
    /// at most [`MAX_DRIVE_STEPS`] solver steps of CFL·h each. Changes nothing, so a
    /// master's refused call leaves the state as it was.
    pub fn check_drive(&self, b: usize, velocity: [Real; 3], span: Real) -> Result<(), DriveError> {
        let walls = &self.world.walls;
        let bar = walls.barriers.get(b).ok_or(DriveError::NoBarrier(b))?;
        if !walls.objects[bar.object].driven {
            return Err(DriveError::NotDriven(bar.name.clone()));
        }
        let speed = Vect::<D>::from_iterator(velocity.iter().copied().take(D)).norm();
        let barrier = || bar.name.clone();
        if !speed.is_finite() {
            return Err(DriveError::NotFinite {
                barrier: barrier(),
                speed,
            });
        }
        let p = &self.stepper.params;
        if speed > p.max_speed {
            return Err(DriveError::TooFast {
                barrier: barrier(),
                speed,
                max_speed: p.max_speed,
            });
        }
        let limit = p.cfl * p.h;
        let steps = speed * span / limit;
        if steps > MAX_DRIVE_STEPS {
            return Err(DriveError::TooManySteps {
                barrier: barrier(),
                distance: speed * span,
                span,
                steps,
                limit,
            });
        }
        Ok(())
    }

    /// Move input-driven barrier `b` with `velocity` (components beyond `D` ignored)
    /// from now on, until driven again. Errors name the barrier when it is not driven.
    pub fn drive_barrier(&mut self, b: usize, velocity: [Real; 3]) -> Result<(), DriveError> {
        let walls = &mut self.world.walls;
        let bar = walls.barriers.get(b).ok_or(DriveError::NoBarrier(b))?;
        let object = bar.object;
        if !walls.objects[object].driven {
            return Err(DriveError::NotDriven(bar.name.clone()));
        }
        let v = Vect::<D>::from_iterator(velocity.iter().copied().take(D));
        walls.drive(object, v);
        Ok(())
    }
}

fn pad<const D: usize>(v: &Vect<D>) -> [Real; 3] {
    let mut o = [0.0; 3];
    for k in 0..D {
        o[k] = v[k];
    }
    o
}

impl AnySimulation {
    /// See [`Simulation::barrier_driven`].
    pub fn barrier_driven(&self, b: usize) -> bool {
        dispatch!(self, s => s.barrier_driven(b))
    }
    /// See [`Simulation::barrier_displacement`].
    pub fn barrier_displacement(&self, b: usize) -> [Real; 3] {
        dispatch!(self, s => s.barrier_displacement(b))
    }
    /// See [`Simulation::barrier_velocity`].
    pub fn barrier_velocity(&self, b: usize) -> [Real; 3] {
        dispatch!(self, s => s.barrier_velocity(b))
    }
    /// See [`Simulation::check_drive`].
    pub fn check_drive(&self, b: usize, velocity: [Real; 3], span: Real) -> Result<(), DriveError> {
        dispatch!(self, s => s.check_drive(b, velocity, span))
    }
    /// See [`Simulation::drive_barrier`].
    pub fn drive_barrier(&mut self, b: usize, velocity: [Real; 3]) -> Result<(), DriveError> {
        dispatch!(self, s => s.drive_barrier(b, velocity))
    }
}
