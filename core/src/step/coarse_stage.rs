//! The coarse grains' stages of a fine step: their records for the fine sweeps at the
//! middle of the step (Eq. 60 velocities), and the κ sub-steps after it (Eqs. 57–59)
//! with their contact loads on barriers.

use super::Stepper;
use crate::interactions::fine_coarse;
use crate::numerics::guard::Blowup;
use crate::numerics::math::Real;
use crate::numerics::timers::Stage;
use crate::world::World;

impl<const D: usize> Stepper<D> {
    /// Refresh the coarse normals and pack the coarse particles for a fine step of
    /// `dt` (nothing without coarse grains).
    pub(super) fn pack_coarse(&mut self, world: &mut World<D>, dt: Real) {
        let Some(c) = self.coarse.as_ref() else {
            return;
        };
        c.update_normals(&mut world.coarse);
        let wc = &world.coarse;
        fine_coarse::pack(
            &wc.particles,
            &wc.bodies,
            &wc.solids,
            (dt, self.coarse_vol),
            &world.gravity,
            &mut self.csrc,
        );
    }

    /// κ coarse sub-steps over the fine step `dt`, and their contact loads added to
    /// the barrier loads of the step. A step of Δt = 0 (the force pass on the current
    /// state, `Simulation::state_loads`) has no sub-step to take.
    pub(super) fn coarse_substeps(
        &mut self,
        world: &mut World<D>,
        dt: Real,
        kappa: usize,
    ) -> Result<(), Blowup> {
        let Some(c) = self.coarse.as_mut().filter(|_| dt > 0.0) else {
            return Ok(());
        };
        let t = std::time::Instant::now();
        let (step, time) = (world.steps + 1, world.time + dt);
        c.advance(&mut world.coarse, &world.walls, dt, kappa, step, time)?;
        let secs = t.elapsed().as_secs_f64();
        let contact = std::mem::take(&mut c.contact_secs);
        self.timers.add(Stage::Contact, contact);
        self.timers.add(Stage::CoarseSubsteps, secs - contact);
        for (b, bar) in world.walls.barriers.iter().enumerate() {
            for s in bar.slot0..bar.slot0 + world.walls.panel_count(b) {
                if let Some(l) = c.wall_loads.get(s) {
                    self.slot_loads[s].add(l);
                    self.step_loads[b].add(l);
                }
            }
        }
        Ok(())
    }
}
