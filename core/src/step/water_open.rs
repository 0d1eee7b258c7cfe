//! The water's open boundaries in the step: inflows let water in before the drift,
//! outflows take it out after the guard ([`water::boundary`](crate::water::boundary));
//! either way the water's lists are rebuilt.

use super::water_stage::WaterStepper;
use crate::numerics::math::{Real, Vect};
use crate::numerics::timers::{Stage, StageTimers};
use crate::water::material::WaterMaterial;
use crate::world::World;
use std::time::Instant;

impl<const D: usize> WaterStepper<D> {
    /// Let water in through the inflows over a step from `t` to `t + dt` (before the
    /// drift), and rebuild the lists if any came in.
    pub fn let_in(
        &mut self,
        world: &mut World<D>,
        mat: &WaterMaterial,
        (t, dt, up): (Real, Real, &Vect<D>),
        timers: &mut StageTimers,
    ) {
        let start = Instant::now();
        let g = world.gravity.norm();
        let res = (world.resolution.dp, world.resolution.volume);
        let mut added = 0;
        for f in &mut world.water.inflows {
            added += f.emit(&mut world.water.particles, mat, (t, dt), res, (g, up));
        }
        if added > 0 {
            self.family.invalidate();
        }
        timers.add(Stage::WaterDriftFinalize, start.elapsed().as_secs_f64());
    }

    /// Remove the water past the outflows (after the step), and rebuild the lists next
    /// step if any left.
    pub fn let_out(&mut self, world: &mut World<D>, timers: &mut StageTimers) {
        let start = Instant::now();
        let mut removed = 0;
        for o in &world.water.outflows {
            removed += o.remove(&mut world.water.particles);
        }
        if removed > 0 {
            self.family.invalidate();
        }
        timers.add(Stage::WaterDriftFinalize, start.elapsed().as_secs_f64());
    }
}
