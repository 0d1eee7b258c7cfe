//! Co-simulation hooks over [`Simulation`]: input-driven barriers and state snapshots.
//! The FMU (crate `granmix-fmu`) is the user; the CLI never drives barriers.

use crate::any::dispatch;
use crate::math::{Real, Vect};
use crate::simulation::Simulation;
use crate::AnySimulation;

/// A barrier that cannot be driven.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum DriveError {
    #[error("no barrier with index {0}")]
    NoBarrier(usize),
    #[error("barrier `{0}` is not input-driven (scene key `input`)")]
    NotDriven(String),
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
    /// See [`Simulation::drive_barrier`].
    pub fn drive_barrier(&mut self, b: usize, velocity: [Real; 3]) -> Result<(), DriveError> {
        dispatch!(self, s => s.drive_barrier(b, velocity))
    }
}
