//! The fine grains' stages of a step: the drift to the half step (Eq. 54), the
//! artificial stress of cohesive soils (Eq. 27), the momentum sweep (Eqs. 16, 55, with
//! walls and coarse grains) and the continuity and stress sweep (Eqs. 15, 24–26,
//! 7–12).

use super::Stepper;
use crate::fine::artificial_stress::gray2001_artificial_stress;
use crate::fine::continuity::{ContinuityOut, ContinuityParams, JumpDiffusion};
use crate::fine::momentum::{ArtificialStress, MomentumParams};
use crate::fine::pair_sums::PairSums;
use crate::fine::source::drift_and_pack;
use crate::interactions::continuity_pass::continuity_sweep;
use crate::interactions::fine_coarse::{self, CoarseSide, Coupling};
use crate::interactions::fine_wall::WallLaw;
use crate::interactions::momentum_pass::momentum_sweep;
use crate::load::Load;
use crate::math::{Real, Vect};
use crate::riemann::Riemann;
use crate::timers::Stage;
use crate::world::World;
use rayon::prelude::*;

impl<const D: usize> Stepper<D> {
    /// Eq. (54): positions and density to the half step, packed for the sweeps; the
    /// walls move with them.
    pub(super) fn drift(&mut self, world: &mut World<D>, half: Real) {
        drift_and_pack(&mut world.fine, &world.materials, half, &mut self.src);
        world.walls.advance(half);
    }

    /// Eq. (27): the artificial stress of every particle (cohesive soils only).
    pub(super) fn artificial_stress(&mut self, world: &World<D>) -> Option<ArtificialStress> {
        let (exponent, eps) = self.params.artificial?;
        self.art.clear();
        self.art.par_extend(
            world
                .fine
                .stress
                .par_iter()
                .map(|s| gray2001_artificial_stress::<D>(s, eps)),
        );
        Some(ArtificialStress {
            exponent,
            w_dp: self.kernel.w(world.resolution.dp),
        })
    }

    /// Buffers sized for this step and the per-material factors of a step of `dt`.
    fn prepare_sweeps(&mut self, world: &World<D>, dt: Real) {
        let n = world.fine.len();
        self.vel_new.resize(n, Vect::<D>::zeros());
        // the sweeps leave their sums zero, so only new entries need setting
        self.pair_sums.resize(n, PairSums::zero());
        let nbs = world.walls.load_slots().max(1);
        self.chunk_loads
            .resize(self.lists.chunks.len() * nbs, Load::default());
        // the stored penalty relaxes over `hourglass_memory` acoustic times h/c0
        let memory = self.params.hourglass_memory * self.params.h;
        for (k, m) in self.hourglass_leak.iter_mut().zip(&world.materials) {
            *k = (-dt * m.c0 / memory).exp() as f32;
        }
        // the continuity sweep's parameters: its terms without velocity are taken in
        // the momentum sweep's pair pass
        self.geostatic_pressure.clear();
        self.geostatic_pressure.extend(
            self.geostatic
                .iter()
                .map(|g| g.scale(self.g_scale).trace() / 3.0),
        );
    }

    /// The two fine sweeps of a step of `dt`: v_{n+1} (Eqs. 16, 55), then density,
    /// velocity gradient and stress with v_{n+1} (Eqs. 15, 24–26, 7–12).
    pub(super) fn fine_sweeps(
        &mut self,
        world: &mut World<D>,
        dt: Real,
        artificial: Option<ArtificialStress>,
    ) {
        self.prepare_sweeps(world, dt);
        let nbs = world.walls.load_slots().max(1);
        let cprm = ContinuityParams {
            kernel: self.kernel,
            gravity: world.gravity,
            dt,
            zeta: self.params.zeta,
            geostatic: &self.geostatic,
            geostatic_pressure: &self.geostatic_pressure,
            geostatic_scale: self.g_scale,
            weight: self.soil_water.as_ref().map_or(&[], |s| &s.weight[..]),
            up: self.up,
            jump: self.params.continuity_jump,
            uniform: self.uniform,
        };
        let mprm = MomentumParams {
            kernel: self.kernel,
            riemann: Riemann {
                eta: self.params.eta,
            },
            gravity: world.gravity,
            dt,
            artificial,
            hourglass: &self.hourglass,
            hourglass_leak: &self.hourglass_leak,
            materials: &world.materials,
            uniform: self.uniform,
        };
        let wall = WallLaw {
            kernel: self.kernel,
            riemann: mprm.riemann,
            gravity: world.gravity,
            dt,
            friction: self.params.wall_friction,
            stress: self.params.wall_stress,
        };
        let side = CoarseSide {
            src: &self.csrc,
            coupling: Coupling {
                kernel: self.kernel,
                riemann: mprm.riemann,
                mu_cf: self.params.mu_cf,
                dt,
                dp: world.resolution.dp,
            },
            tension: &self.tension,
            reactions: &mut self.reactions,
        };
        // updated in place: a particle reads only its own accumulated penalty
        let mut hourglass = std::mem::take(&mut world.fine.hourglass);
        self.timers.time(Stage::Momentum, || {
            momentum_sweep(
                &world.fine,
                &self.src,
                &world.walls,
                &self.lists,
                &self.art,
                &mprm,
                &wall,
                &mut self.vel_new,
                &mut hourglass,
                &mut self.chunk_loads,
                side,
                &JumpDiffusion::new(&cprm),
                &mut self.pair_sums,
                self.soil_water.as_ref().map_or(&[], |s| &s.force[..]),
            )
        });
        world.fine.hourglass = hourglass;
        if self.coarse.is_some() {
            self.timers.time(Stage::Coupling, || {
                fine_coarse::gather_reactions(&self.reactions, &mut world.coarse.particles.f_fine)
            });
        }
        std::mem::swap(&mut world.fine.vel, &mut self.vel_new);
        crate::panels::sum_slots(
            &world.walls,
            &self.chunk_loads,
            nbs,
            &mut self.slot_loads,
            &mut self.step_loads,
        );
        // advanced in place: the sweep reads none of these of a neighbour (the
        // neighbours' stress comes from the packed sources)
        let f = &mut world.fine;
        let mut stress = std::mem::take(&mut f.stress);
        let mut drho = std::mem::take(&mut f.drho);
        let mut eps = std::mem::take(&mut f.plastic_strain);
        let mut vel_grad = std::mem::take(&mut f.vel_grad);
        let mut hourglass_kept = std::mem::take(&mut f.hourglass_kept);
        let out = ContinuityOut {
            sums: &mut self.pair_sums,
            drho: &mut drho,
            stress: &mut stress,
            plastic_strain: &mut eps,
            vel_grad: &mut vel_grad,
            hourglass_kept: &mut hourglass_kept,
        };
        self.timers.time(Stage::ContinuityStress, || {
            let (f, mats, walls) = (&world.fine, &world.materials, &world.walls);
            continuity_sweep(
                f,
                &self.src,
                mats,
                walls,
                &self.lists,
                &cprm,
                &self.csrc,
                out,
            )
        });
        let f = &mut world.fine;
        f.drho = drho;
        f.stress = stress;
        f.plastic_strain = eps;
        f.vel_grad = vel_grad;
        f.hourglass_kept = hourglass_kept;
    }
}
