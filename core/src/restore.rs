//! A simulation deserialised from a saved state (the FMU's `fmi2DeSerializeFMUstate`)
//! takes back what its serialised form leaves out, from a simulation built from the same
//! scene, and is checked against it before it steps.
//!
//! Left out of the serialised form: the wall shapes (static, rebuilt identically from
//! the scene), stage timers, and scratch buffers that every step writes in full before
//! it reads them (see the `#[serde(skip)]` fields of [`crate::step::Stepper`]).

use crate::any::AnySimulation;
use crate::simulation::Simulation;

impl<const D: usize> Simulation<D> {
    /// Take the wall shapes from `template`, a simulation of the same scene, and check
    /// that this state fits it: same walls, barriers and bodies, and every per-particle
    /// array of one length.
    pub fn take_static_from(&mut self, template: &Simulation<D>) -> Result<(), String> {
        let (w, t) = (&mut self.world, &template.world);
        let names = |o: &[crate::walls::WallObject<D>]| -> Vec<String> {
            o.iter().map(|o| o.name.clone()).collect()
        };
        if names(&w.walls.objects) != names(&t.walls.objects) {
            return Err("the saved state's walls differ from the scene's".into());
        }
        if w.walls.barriers.len() != t.walls.barriers.len()
            || w.coarse.bodies.len() != t.coarse.bodies.len()
        {
            return Err("the saved state's barriers or bodies differ from the scene's".into());
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
            return Err(format!(
                "the saved state's {n} fine particles have arrays of other lengths or \
                 unknown materials"
            ));
        }
        let c = &w.coarse.particles;
        let nc = c.pos.len();
        let bodies = w.coarse.bodies.len();
        if [c.vel.len(), c.mass.len(), c.body.len(), c.f_fine.len()]
            .iter()
            .any(|&l| l != nc)
            || c.body.iter().any(|&b| b as usize >= bodies)
        {
            return Err(format!(
                "the saved state's {nc} coarse particles have arrays of other lengths"
            ));
        }
        if w.walls.pos.len() != w.walls.object.len() {
            return Err("the saved state's wall particles are inconsistent".into());
        }
        for (o, from) in w.walls.objects.iter_mut().zip(&t.walls.objects) {
            o.shape = from.shape.clone();
        }
        Ok(())
    }
}

impl AnySimulation {
    /// [`Simulation::take_static_from`] for either dimension.
    pub fn take_static_from(&mut self, template: &AnySimulation) -> Result<(), String> {
        match (self, template) {
            (AnySimulation::D2(s), AnySimulation::D2(t)) => s.take_static_from(t),
            (AnySimulation::D3(s), AnySimulation::D3(t)) => s.take_static_from(t),
            (s, t) => Err(format!(
                "the saved state is {}D, the scene {}D",
                s.dimension(),
                t.dimension()
            )),
        }
    }
}
