//! A simulation deserialised from a saved state (the FMU's `fmi2DeSerializeFMUstate`)
//! takes back what its serialised form leaves out, from a simulation built from the same
//! scene, and is checked against it before it steps.
//!
//! Left out of the serialised form: the wall shapes (static, rebuilt identically from
//! the scene), stage timers, and scratch buffers that every step writes in full before
//! it reads them (see the `#[serde(skip)]` fields of [`crate::step::Stepper`]).

use crate::run::any::AnySimulation;
use crate::run::simulation::Simulation;

/// A saved state that does not fit the scene it is restored into.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum StateMismatch {
    #[error("the saved state's walls differ from the scene's")]
    Walls,
    #[error("the saved state's barriers or bodies differ from the scene's")]
    BarriersOrBodies,
    #[error(
        "the saved state's {0} fine particles have arrays of other lengths or unknown materials"
    )]
    FineArrays(usize),
    #[error("the saved state's {0} coarse particles have arrays of other lengths")]
    CoarseArrays(usize),
    #[error("the saved state's wall particles are inconsistent")]
    WallParticles,
    #[error(
        "the saved state's {0} water particles have arrays of other lengths, or its water \
         differs from the scene's (water, inflows, outflows)"
    )]
    WaterArrays(usize),
    #[error("the saved state is {state}D, the scene {scene}D")]
    Dimension { state: usize, scene: usize },
}

impl<const D: usize> Simulation<D> {
    /// Take the wall shapes from `template`, a simulation of the same scene, and check
    /// that this state fits it: same walls, barriers and bodies, and every per-particle
    /// array of one length.
    pub fn take_static_from(&mut self, template: &Simulation<D>) -> Result<(), StateMismatch> {
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
        if [c.vel.len(), c.mass.len(), c.body.len(), c.f_fine.len()]
            .iter()
            .any(|&l| l != nc)
            || c.body.iter().any(|&b| b as usize >= bodies)
        {
            return Err(StateMismatch::CoarseArrays(nc));
        }
        if w.walls.pos.len() != w.walls.object.len() {
            return Err(StateMismatch::WallParticles);
        }
        for (o, from) in w.walls.objects.iter_mut().zip(&t.walls.objects) {
            o.shape = from.shape.clone();
        }
        Ok(())
    }
}

impl AnySimulation {
    /// [`Simulation::take_static_from`] for either dimension.
    pub fn take_static_from(&mut self, template: &AnySimulation) -> Result<(), StateMismatch> {
        match (self, template) {
            (AnySimulation::D2(s), AnySimulation::D2(t)) => s.take_static_from(t),
            (AnySimulation::D3(s), AnySimulation::D3(t)) => s.take_static_from(t),
            (s, t) => Err(StateMismatch::Dimension {
                state: s.dimension(),
                scene: t.dimension(),
            }),
        }
    }
}
