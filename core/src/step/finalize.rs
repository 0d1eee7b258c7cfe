//! The last stages of a fine step: positions and density to the end of the step
//! (Eq. 56) with the per-chunk stability checks, and the guard that stops the run on
//! a non-finite or runaway particle.

use super::Stepper;
use crate::guard::{check, Blowup, ChunkFailure, Family};
use crate::math::Real;
use crate::neighbors::CHUNK;
use crate::world::World;
use rayon::prelude::*;

impl<const D: usize> Stepper<D> {
    /// Eq. (56): x and ρ to the end of the step; each chunk records its largest speed
    /// and displacement since the list build, and its first failing particle.
    pub(super) fn finalize(&mut self, world: &mut World<D>, half: Real) {
        let max_speed = self.params.max_speed;
        let (f, marks) = (&mut world.fine, &self.at_build);
        f.pos
            .par_chunks_mut(CHUNK)
            .zip(f.rho.par_chunks_mut(CHUNK))
            .zip(f.vel.par_chunks(CHUNK))
            .zip(f.drho.par_chunks(CHUNK))
            .zip(f.stress.par_chunks(CHUNK))
            .enumerate()
            .map(|(c, ((((x, r), v), d), s))| {
                let mut vmax2: Real = 0.0;
                let mut disp2: Real = 0.0;
                let mut fail: ChunkFailure = None;
                for k in 0..x.len() {
                    let i = c * CHUNK + k;
                    let (v2, d2) = marks.close_step(i, (&mut x[k], &mut r[k]), (&v[k], d[k]), half);
                    vmax2 = vmax2.max(v2);
                    disp2 = disp2.max(d2);
                    if fail.is_none() {
                        let stress = || (!s[k].is_finite()).then(|| ("stress", s[k].trace()));
                        fail = check(i, v2, &x[k], r[k], stress, max_speed);
                    }
                }
                (vmax2, disp2, fail)
            })
            .collect_into_vec(&mut self.failures);
        world.walls.advance(half);
    }

    /// Stop on the first failing particle of the step, or on a wall object whose motion
    /// is not finite or faster than the bound; otherwise keep the step's
    /// largest speed and displacement for Δt and the neighbour skin.
    pub(super) fn guard(&mut self, world: &World<D>) -> Result<Real, Blowup> {
        let max_speed = self.params.max_speed;
        // the walls' rigid motion (prescribed or driven) first: a barrier sent to
        // infinity stops the run as a particle would, and is the cause of what its
        // neighbours do in the same step
        if let Some((o, quantity, value, speed)) = world.walls.check(max_speed) {
            let w = &world.walls.objects[o];
            return Err(Blowup {
                step: world.steps,
                time: world.time,
                particle: o as u32,
                body: Some(w.name.clone()),
                family: Family::Wall,
                position: w.displacement.iter().copied().collect(),
                quantity: quantity.to_string(),
                value,
                limit: speed.then_some(max_speed),
            });
        }
        let (vmax2, disp2) = crate::guard::reduce(&self.failures).map_err(|f| {
            let (p, at) = (&world.fine, (world.steps, world.time));
            let x = p.pos[f.0].iter().copied().collect();
            Blowup::of_particle(at, Family::Fine, p.id[f.0], x, f, max_speed)
        })?;
        self.vmax = vmax2.sqrt();
        self.max_disp = disp2.sqrt() + self.at_build.round_off;
        Ok(self.vmax)
    }
}
