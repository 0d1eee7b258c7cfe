//! The water in the gaps between a body and what it touches (issue 42): where a body
//! lies within a spacing of a wall or another body, no water particle fits between them,
//! and the uplift the body misses there ([`water_buoyancy`](super::water_buoyancy),
//! [`Body::uplift`]) is the push of that gap's water. Its reaction goes to the other
//! side of the gap: to the wall (its barrier load) or to the other body (as water force
//! on its particle), shared equally among the body's gap partners.
//!
//! Gap partners of a wet body (one the water's forces reach) are found once per fine
//! step: each surface particle within a spacing of touching a wall (signed distance
//! under 3dp/2 for the contact radius dp/2), and each pair of surface particles of two
//! bodies closer than two spacings.

use crate::coarse::{Body, CoarseParticles};
use crate::geometry::walls::Walls;
use crate::numerics::load::Load;
use crate::numerics::math::{from3, to3, Real, Vect};
use nalgebra::Vector3;

/// The gap partners of the wet bodies at the start of a fine step.
#[derive(Clone, Debug, Default, serde::Serialize, serde::Deserialize)]
pub struct GapWater<const D: usize> {
    /// (coarse particle, wall object, signed distance, outward normal).
    walls: Vec<(u32, u32, Real, Vect<D>)>,
    /// (i, j) of different bodies, i < j.
    pairs: Vec<(u32, u32)>,
    /// Gap partners of each body.
    pub per_body: Vec<usize>,
}

impl<const D: usize> GapWater<D> {
    /// Whether these gap partners, restored from a state, fit `particles` coarse
    /// particles, `objects` wall objects and `bodies` bodies (see
    /// [`Contacts::restored_fits`](crate::interactions::contact::Contacts::restored_fits)).
    pub fn restored_fits(&self, particles: usize, objects: usize, bodies: usize) -> bool {
        self.walls
            .iter()
            .all(|&(i, o, _, _)| (i as usize) < particles && (o as usize) < objects)
            && self
                .pairs
                .iter()
                .all(|&(i, j)| i < j && (j as usize) < particles)
            && (self.per_body.len() == bodies || self.per_body.is_empty())
    }

    /// Find the gap partners of the bodies the water reaches (a nonzero `f_water` or
    /// `uplift`), at spacing `dp`.
    pub fn find(&mut self, p: &CoarseParticles<D>, bodies: &[Body<D>], walls: &Walls<D>, dp: Real) {
        self.walls.clear();
        self.pairs.clear();
        self.per_body.clear();
        self.per_body.resize(bodies.len(), 0);
        let wet: Vec<bool> = bodies
            .iter()
            .map(|b| {
                !b.fixed
                    && (b.uplift != Vector3::zeros()
                        || p.f_water[b.start..b.end]
                            .iter()
                            .any(|f| *f != Vect::<D>::zeros()))
            })
            .collect();
        if !wet.iter().any(|&w| w) {
            return;
        }
        let reach = 1.5 * dp;
        for (bi, b) in bodies.iter().enumerate().filter(|(bi, _)| wet[*bi]) {
            for i in (b.start..b.end).filter(|&i| p.surface[i]) {
                for (o, obj) in walls.objects.iter().enumerate() {
                    let Some(shape) = &obj.shape else { continue };
                    let x = p.pos[i] - obj.displacement;
                    let d = shape.sdf(&x);
                    if d < reach {
                        let n = shape.normal(&x, 1e-4 * dp);
                        self.walls.push((i as u32, o as u32, d, n));
                        self.per_body[bi] += 1;
                    }
                }
            }
        }
        // pairs: bodies whose bounding spheres come within two spacings
        let radius: Vec<Real> = bodies
            .iter()
            .map(|b| {
                let c = from3::<D>(&b.com);
                (b.start..b.end)
                    .map(|i| (p.pos[i] - c).norm())
                    .fold(0.0, Real::max)
            })
            .collect();
        let r2 = 4.0 * dp * dp;
        for (bi, a) in bodies.iter().enumerate() {
            for (bj, b) in bodies.iter().enumerate().skip(bi + 1) {
                if !(wet[bi] || wet[bj]) || (a.fixed && b.fixed) {
                    continue;
                }
                if (a.com - b.com).norm() > radius[bi] + radius[bj] + 2.0 * dp {
                    continue;
                }
                for i in (a.start..a.end).filter(|&i| p.surface[i]) {
                    for j in (b.start..b.end).filter(|&j| p.surface[j]) {
                        if (p.pos[i] - p.pos[j]).norm_squared() < r2 {
                            self.pairs.push((i as u32, j as u32));
                            self.per_body[bi] += 1;
                            self.per_body[bj] += 1;
                        }
                    }
                }
            }
        }
    }

    /// The share of one gap partner of body `b` in its uplift.
    fn share(&self, bodies: &[Body<D>], b: usize) -> Vector3<Real> {
        match self.per_body[b] {
            0 => Vector3::zeros(),
            n => bodies[b].uplift / n as Real,
        }
    }

    /// The reactions of the bodies' uplifts: on the other bodies' particles into their
    /// `f_water`, on barrier walls into `loads` (one per load slot).
    pub fn react(
        &self,
        p: &mut CoarseParticles<D>,
        bodies: &[Body<D>],
        walls: &Walls<D>,
        loads: &mut [Load],
    ) {
        for &(i, o, d, n) in &self.walls {
            let i = i as usize;
            let obj = &walls.objects[o as usize];
            let Some(b) = obj.barrier else { continue };
            let f = -self.share(bodies, p.body[i] as usize);
            let bar = &walls.barriers[b];
            let at = p.pos[i] - n * d;
            let slot = bar.slot0 + bar.panel_of(&(at - obj.displacement));
            loads[slot].force += f;
            loads[slot].moment += to3(&(at - bar.reference)).cross(&f);
        }
        for &(i, j) in &self.pairs {
            let (i, j) = (i as usize, j as usize);
            let (bi, bj) = (p.body[i] as usize, p.body[j] as usize);
            p.f_water[j] -= from3::<D>(&self.share(bodies, bi));
            p.f_water[i] -= from3::<D>(&self.share(bodies, bj));
        }
    }
}
