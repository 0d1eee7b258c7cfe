//! The last stages of a fine step: positions and density to the end of the step
//! (Eq. 56) with the per-chunk stability checks, and the guard that stops the run on
//! a non-finite or runaway particle.

use super::Stepper;
use crate::guard::{Blowup, ChunkFailure};
use crate::math::Real;
use crate::neighbors::CHUNK;
use crate::world::World;
use rayon::prelude::*;

impl<const D: usize> Stepper<D> {
    /// Eq. (56): x and ρ to the end of the step; each chunk records its largest speed
    /// and displacement since the list build, and its first failing particle.
    pub(super) fn finalize(&mut self, world: &mut World<D>, half: Real) {
        let max_speed = self.params.max_speed;
        let f = &mut world.fine;
        f.pos
            .par_chunks_mut(CHUNK)
            .zip(f.rho.par_chunks_mut(CHUNK))
            .zip(f.vel.par_chunks(CHUNK))
            .zip(f.drho.par_chunks(CHUNK))
            .zip(f.stress.par_chunks(CHUNK))
            .zip(self.pos_at_build.par_chunks(CHUNK))
            .enumerate()
            .map(|(c, (((((x, r), v), d), s), x0))| {
                let mut vmax2: Real = 0.0;
                let mut disp2: Real = 0.0;
                let mut fail: ChunkFailure = None;
                for k in 0..x.len() {
                    x[k] += v[k] * half;
                    r[k] += d[k] * half;
                    let v2 = v[k].norm_squared();
                    vmax2 = vmax2.max(v2);
                    disp2 = disp2.max((x[k] - x0[k].cast::<Real>()).norm_squared());
                    if fail.is_none() {
                        let i = c * CHUNK + k;
                        if !v2.is_finite() {
                            fail = Some((i, "velocity", v2.sqrt(), false));
                        } else if !x[k].iter().all(|q| q.is_finite()) {
                            fail = Some((i, "position", x[k].norm(), false));
                        } else if !(r[k].is_finite() && r[k] > 0.0) {
                            fail = Some((i, "density", r[k], false));
                        } else if !s[k].is_finite() {
                            fail = Some((i, "stress", s[k].trace(), false));
                        } else if v2 > max_speed * max_speed {
                            fail = Some((i, "speed", v2.sqrt(), true));
                        }
                    }
                }
                (vmax2, disp2, fail)
            })
            .collect_into_vec(&mut self.failures);
        world.walls.advance(half);
    }

    /// Stop on the first failing particle of the step; otherwise keep the step's
    /// largest speed and displacement for Δt and the neighbour skin.
    pub(super) fn guard(&mut self, world: &World<D>) -> Result<Real, Blowup> {
        let max_speed = self.params.max_speed;
        let mut vmax2: Real = 0.0;
        let mut disp2: Real = 0.0;
        for (v, d, fail) in &self.failures {
            vmax2 = vmax2.max(*v);
            disp2 = disp2.max(*d);
            if let Some((i, q, val, speed)) = fail {
                let f = &world.fine;
                return Err(Blowup {
                    step: world.steps,
                    time: world.time,
                    particle: f.id[*i],
                    body: None,
                    family: crate::guard::Family::Fine,
                    position: f.pos[*i].iter().copied().collect(),
                    quantity: q.to_string(),
                    value: *val,
                    limit: speed.then_some(max_speed),
                });
            }
        }
        self.vmax = vmax2.sqrt();
        self.max_disp = disp2.sqrt() + self.round_off;
        Ok(self.vmax)
    }
}
