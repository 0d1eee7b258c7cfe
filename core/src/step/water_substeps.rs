//! The water's part of a step, as κ_w sub-steps of Δt/κ_w: the multi-rate scheme of
//! seed 000 Eqs. (51)–(53), read for the water. When the water's stable Δt (acoustic
//! and viscous, [`WaterMaterial::stable_dt`]) fits k ≥ 2 times into the fine grains'
//! Δt_f, the step is k Δt_w (at most Δt_f) and the water takes κ_w = k sub-steps of
//! its own Δt_w; the cost per unit time falls from N_f + N_w particle-steps per Δt_w
//! to N_f/k + N_w. Otherwise both take one step of min(Δt_f, Δt_w).
//!
//! The coarse particles stay at their half-step positions over the sub-steps (as the
//! fine sweeps see them), and they receive the water's force averaged over the
//! sub-steps, so that the impulse they receive equals the water's to round-off; the
//! barrier loads are averaged the same way.
//!
//! [`WaterMaterial::stable_dt`]: crate::water::material::WaterMaterial::stable_dt

use super::Stepper;
use crate::numerics::guard::Blowup;
use crate::numerics::load::Load;
use crate::numerics::math::Real;
use crate::numerics::timers::Stage;
use crate::world::World;

impl<const D: usize> Stepper<D> {
    /// The water's κ_w sub-steps of a step of `dt` (inflow, drift, lists, sweeps,
    /// finalize, guard and outflow each); the water's loads of the step kept in its
    /// family's loads for the step's totals. Returns the water's largest speed (0
    /// without water).
    pub(super) fn water_substeps(
        &mut self,
        world: &mut World<D>,
        dt: Real,
    ) -> Result<Real, Blowup> {
        let Stepper {
            water,
            timers,
            csrc,
            up,
            kernel,
            params,
            soil_water,
            fine,
            ..
        } = self;
        let Some((w, m)) = water.as_mut().zip(world.water.material) else {
            return Ok(0.0);
        };
        let k = w.substeps(&m, params.h, params.cfl, dt);
        let (dt_w, share) = (dt / k as Real, 1.0 / k as Real);
        let half = 0.5 * dt_w;
        // the sub-steps' mean loads (k > 1)
        let mut mean: Option<(Vec<Load>, Vec<Load>)> = None;
        let mut vmax: Real = 0.0;
        // with a soil the water's particles stay put in memory over the sub-steps (its
        // drag is kept per particle): water comes in and lists are rebuilt before the
        // first, for the whole step, and water leaves after the last
        let mut seep = soil_water.as_mut().filter(|_| !world.fine.is_empty());
        let block = seep.is_some();
        for s in 0..k {
            let t0 = world.time + s as Real * dt_w;
            let first = !block || s == 0;
            if !world.water.inflows.is_empty() && first {
                let span = if block { dt } else { dt_w };
                w.let_in(world, &m, (t0, span, &*up), timers);
            }
            w.drift(world, &m, half, timers);
            if first {
                let span = if block { dt } else { dt_w };
                w.refresh_lists(world, &m, csrc, span, timers);
            }
            if w.steps == 0 && m.incompressible_start {
                timers.time(Stage::WaterNeighbors, || {
                    w.start_incompressible(world, &m, *kernel, csrc)
                });
            }
            if let Some(sw) = seep.as_mut().filter(|_| s == 0) {
                timers.time(Stage::SoilWater, || {
                    let builds = [fine.family.lists.builds, w.family.lists.builds];
                    sw.freeze(world, (builds, w.grid()), kernel, m.mu)
                });
            }
            let step = seep.as_mut().map(|sw| sw.step(share));
            w.sweeps(world, &m, *kernel, csrc, (t0, dt_w), (s, k), step, timers);
            w.steps += 1;
            if k > 1 {
                let (step, slot) = mean.get_or_insert_with(|| {
                    (
                        vec![Load::default(); w.family.step_loads.len()],
                        vec![Load::default(); w.family.slot_loads.len()],
                    )
                });
                for (a, l) in step.iter_mut().zip(&w.family.step_loads) {
                    a.add(&l.scaled(share));
                }
                for (a, l) in slot.iter_mut().zip(&w.family.slot_loads) {
                    a.add(&l.scaled(share));
                }
            }
            w.finalize(world, half, params.max_speed, timers);
            vmax = vmax.max(w.guard(world, params.max_speed)?);
            if !world.water.outflows.is_empty() && seep.is_none() {
                w.let_out(world, timers);
            }
        }
        if let Some((step, slot)) = mean {
            w.family.step_loads = step;
            w.family.slot_loads = slot;
        }
        Ok(vmax)
    }

    /// The soil side of the soil–water coupling after the water's sub-steps (nothing
    /// without it): every soil particle gathers the exact opposite of the water's drag
    /// impulse over the sub-steps and its buoyancy (seed 001 Eqs. 8–10), which its
    /// momentum sweep adds.
    pub(super) fn soil_gathers(&mut self, world: &mut World<D>, dt: Real) {
        let Stepper {
            timers,
            kernel,
            soil_water,
            ..
        } = self;
        let Some((m, sw)) = world
            .water
            .material
            .zip(soil_water.as_mut().filter(|_| !world.fine.is_empty()))
        else {
            return;
        };
        timers.time(Stage::SoilWater, || sw.gather(world, &m, kernel, dt));
    }

    /// After the soil's momentum sweep (nothing without a soil–water coupling): the
    /// seepage drag closed implicitly on both sides and the pore water's surplus
    /// inertia handed to the grains ([`SoilWater::close`]); then the
    /// water leaves through the outflows, which with a soil it does once per step.
    ///
    /// [`SoilWater::close`]: super::SoilWater::close
    pub(super) fn close_seepage(&mut self, world: &mut World<D>, dt: Real) {
        let Stepper {
            water,
            timers,
            soil_water,
            ..
        } = self;
        let Some(((w, sw), m)) = water
            .as_mut()
            .zip(soil_water.as_mut().filter(|_| !world.fine.is_empty()))
            .zip(world.water.material)
        else {
            return;
        };
        timers.time(Stage::SoilWater, || sw.close(world, &m, dt));
        if !world.water.outflows.is_empty() {
            w.let_out(world, timers);
        }
    }
}
