//! A simulation deserialised from a saved state (the FMU's `fmi2DeSerializeFMUstate`)
//! takes back what its serialised form leaves out, from a simulation built from the same
//! scene with the same parameters (the template), and is checked against it before it
//! steps.
//!
//! Left out of the serialised form: the wall shapes (static, rebuilt identically from
//! the scene), stage timers, and scratch buffers that every step writes in full before
//! it reads them (see the `#[serde(skip)]` fields of [`crate::step::Stepper`]).
//!
//! Checked, so that no forged or corrupted state that passes the envelope's checksum
//! reaches a step: what the scene fixes equals the template's bit for bit (materials,
//! resolution, domain, gravity, walls, barriers, bodies' constants, method parameters,
//! cell grids, elastic bodies' reference data); every per-particle array has the
//! family's length; every stored index (neighbour lists, contact candidates, cell bins,
//! bodies' particle ranges) points into what it indexes; and, unless the state was
//! taken in the error state, every value is finite and in its range
//! ([`crate::run::restore_values`]).

use crate::numerics::math::Real;
use crate::run::any::AnySimulation;
use crate::run::simulation::Simulation;
pub use crate::run::state_mismatch::StateMismatch;

impl<const D: usize> Simulation<D> {
    /// Take the wall shapes from `template`, a simulation of the same scene built with
    /// the state's parameters, and check that this state fits it (see the module
    /// docs); `values`: check the values too (not for a state taken in the error
    /// state, which may hold the blow-up's non-finite values and cannot be stepped).
    pub fn take_static_from(
        &mut self,
        template: &Simulation<D>,
        values: bool,
    ) -> Result<(), StateMismatch> {
        self.fit_arrays(template)?;
        self.fit_accumulators(template, values)?;
        crate::run::restore_values::scene_constants(&self.world, &template.world)?;
        self.stepper
            .restored_fits(&template.stepper, &self.world)
            .map_err(StateMismatch::Lists)?;
        if values {
            self.stepper.restored_motion_fits().map_err(|what| {
                StateMismatch::Value(format!(
                    "{what} out of range (not finite, negative or \
                    above simulation.max_speed)"
                ))
            })?;
            crate::run::restore_values::finite_in_range(
                &self.world,
                self.stepper.params.max_speed,
            )?;
        }
        for (o, from) in self
            .world
            .walls
            .objects
            .iter_mut()
            .zip(&template.world.walls.objects)
        {
            o.shape = from.shape.clone();
        }
        Ok(())
    }

    /// The run's own fields: the step cap and run-out rule of the scene, load
    /// accumulators of every barrier, panel and body, and (with `values`) the last
    /// steps' Δt, κ and the output interval's start finite and in range.
    fn fit_accumulators(&self, t: &Simulation<D>, values: bool) -> Result<(), StateMismatch> {
        if self.dt_cap.to_bits() != t.dt_cap.to_bits()
            || self.runout.origin != t.runout.origin
            || self.runout.direction.to_bits() != t.runout.direction.to_bits()
        {
            return Err(StateMismatch::Scene("output interval or run-out rule"));
        }
        let water = |l: usize, full: usize| l == full || l == 0;
        if self.impulse.len() != t.impulse.len()
            || self.peak.len() != t.peak.len()
            || self.panel_impulse.len() != t.panel_impulse.len()
            || self.body_impulse.len() != t.body_impulse.len()
            || !water(self.water_impulse.len(), t.water_impulse.len())
            || !water(self.panel_water_impulse.len(), t.panel_water_impulse.len())
        {
            return Err(StateMismatch::BarriersOrBodies);
        }
        if !values {
            return Ok(());
        }
        let dt_ok = |x: Real| x.is_finite() && x >= 0.0;
        let time = self.world.time;
        let start_ok = self.interval_start.is_finite()
            && self.interval_start >= 0.0
            && self.interval_start <= time;
        // Δt_c is infinite where nothing limits it
        let dt_c_ok = self.last_dt_c >= 0.0 && !self.last_dt_c.is_nan();
        let steps_ok = dt_ok(self.last_dt) && dt_ok(self.last_dt_f) && dt_c_ok;
        if !(steps_ok && self.last_kappa >= 1 && start_ok) {
            return Err(StateMismatch::Value(format!(
                "a last step of Δt = {:?} s (Δt_f {:?}, Δt_c {:?}, κ = {}) or an output \
                 interval from {:?} s at t = {time:?} s (must be finite, not negative, \
                 κ ≥ 1, the interval's start not after t)",
                self.last_dt, self.last_dt_f, self.last_dt_c, self.last_kappa, self.interval_start
            )));
        }
        Ok(())
    }

    /// The counts and lengths of [`Simulation::take_static_from`].
    fn fit_arrays(&mut self, template: &Simulation<D>) -> Result<(), StateMismatch> {
        let (w, t) = (&mut self.world, &template.world);
        let names = |o: &[crate::geometry::walls::WallObject<D>]| -> Vec<String> {
            o.iter().map(|o| o.name.clone()).collect()
        };
        if names(&w.walls.objects) != names(&t.walls.objects) {
            return Err(StateMismatch::Walls);
        }
        if w.walls.barriers.len() != t.walls.barriers.len()
            || w.coarse.bodies.len() != t.coarse.bodies.len()
        {
            return Err(StateMismatch::BarriersOrBodies);
        }
        let f = &w.fine;
        let n = f.pos.len();
        let lens = [
            f.vel.len(),
            f.rho.len(),
            f.drho.len(),
            f.stress.len(),
            f.plastic_strain.len(),
            f.mass.len(),
            f.material.len(),
            f.id.len(),
            f.vel_grad.len(),
            f.hourglass.len(),
            f.hourglass_kept.len(),
            f.quiet.len(),
        ];
        let materials = w.materials.len();
        if lens.iter().any(|&l| l != n) || f.material.iter().any(|&m| m as usize >= materials) {
            return Err(StateMismatch::FineArrays(n));
        }
        let wa = &w.water.particles;
        let nw = wa.pos.len();
        if [
            wa.vel.len(),
            wa.rho.len(),
            wa.drho.len(),
            wa.mass.len(),
            wa.id.len(),
        ]
        .iter()
        .any(|&l| l != nw)
            || w.has_water() != t.has_water()
            || w.water.inflows.len() != t.water.inflows.len()
            || w.water.outflows.len() != t.water.outflows.len()
            || self.stepper.water.is_some() != template.stepper.water.is_some()
        {
            return Err(StateMismatch::WaterArrays(nw));
        }
        // a state saved before the water family carries no water force on coarse
        // particles
        let nc = w.coarse.particles.pos.len();
        if w.coarse.particles.f_water.len() != nc {
            w.coarse.particles.f_water = vec![crate::numerics::math::Vect::<D>::zeros(); nc];
        }
        let c = &w.coarse.particles;
        let bodies = w.coarse.bodies.len();
        if [
            c.vel.len(),
            c.local.len(),
            c.local_normal.len(),
            c.normal.len(),
            c.mass.len(),
            c.body.len(),
            c.surface.len(),
            c.depth.len(),
            c.f_fine.len(),
            c.f_contact.len(),
            c.pos_start.len(),
            c.vbar.len(),
        ]
        .iter()
        .any(|&l| l != nc)
            || nc != t.coarse.particles.pos.len()
            || c.body.iter().any(|&b| b as usize >= bodies)
        {
            return Err(StateMismatch::CoarseArrays(nc));
        }
        let walls = &w.walls;
        if walls.pos.len() != walls.object.len()
            || walls.object != t.walls.object
            || walls.panel != t.walls.panel
        {
            return Err(StateMismatch::WallParticles);
        }
        Ok(())
    }
}

impl AnySimulation {
    /// [`Simulation::take_static_from`] for either dimension.
    pub fn take_static_from(
        &mut self,
        template: &AnySimulation,
        values: bool,
    ) -> Result<(), StateMismatch> {
        match (self, template) {
            (AnySimulation::D2(s), AnySimulation::D2(t)) => s.take_static_from(t, values),
            (AnySimulation::D3(s), AnySimulation::D3(t)) => s.take_static_from(t, values),
            (s, t) => Err(StateMismatch::Dimension {
                state: s.dimension(),
                scene: t.dimension(),
            }),
        }
    }
}
