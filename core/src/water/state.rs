//! Water particle state: structure of arrays.

use crate::numerics::math::{Real, Vect};
use crate::numerics::periodic::Separation;
use crate::numerics::permute::{cycle_apply, PermuteScratch};

/// The water particles (updated Lagrangian, position Verlet like the fine grains).
#[derive(Clone, Debug, Default, serde::Serialize, serde::Deserialize)]
pub struct WaterParticles<const D: usize> {
    pub pos: Vec<Vect<D>>,
    pub vel: Vec<Vect<D>>,
    pub rho: Vec<Real>,
    /// dρ/dt from the last continuity sweep.
    pub drho: Vec<Real>,
    pub mass: Vec<Real>,
    /// Stable id (the order of creation), kept through re-sorting and removals.
    pub id: Vec<u32>,
    /// The id of the next particle created.
    #[serde(default)]
    pub next_id: u32,
}

impl<const D: usize> WaterParticles<D> {
    pub fn len(&self) -> usize {
        self.pos.len()
    }
    pub fn is_empty(&self) -> bool {
        self.pos.is_empty()
    }

    pub fn push(&mut self, pos: Vect<D>, vel: Vect<D>, rho: Real, mass: Real) {
        self.id.push(self.next_id);
        self.next_id += 1;
        self.pos.push(pos);
        self.vel.push(vel);
        self.rho.push(rho);
        self.drho.push(0.0);
        self.mass.push(mass);
    }

    /// Release the spare capacity left by filling the arrays one particle at a time.
    pub fn shrink_to_fit(&mut self) {
        self.pos.shrink_to_fit();
        self.vel.shrink_to_fit();
        self.rho.shrink_to_fit();
        self.drho.shrink_to_fit();
        self.mass.shrink_to_fit();
        self.id.shrink_to_fit();
    }

    /// Bytes held by the particle arrays.
    pub fn bytes(&self) -> usize {
        use std::mem::size_of;
        (self.pos.capacity() + self.vel.capacity()) * size_of::<Vect<D>>()
            + (self.rho.capacity() + self.drho.capacity() + self.mass.capacity())
                * size_of::<Real>()
            + self.id.capacity() * 4
    }

    /// Reorder every array by `order` (new index k holds old particle order[k]), in
    /// place ([`cycle_apply`]).
    pub fn permute(&mut self, order: &[u32], scratch: &mut PermuteScratch) {
        cycle_apply(&mut self.pos, order, scratch);
        cycle_apply(&mut self.vel, order, scratch);
        cycle_apply(&mut self.rho, order, scratch);
        cycle_apply(&mut self.drho, order, scratch);
        cycle_apply(&mut self.mass, order, scratch);
        cycle_apply(&mut self.id, order, scratch);
    }

    /// Remove the particles for which `gone(position)` holds, keeping the order of the
    /// others; returns how many left.
    pub fn remove_where(&mut self, gone: impl Fn(&Vect<D>) -> bool) -> usize {
        let keep: Vec<bool> = self.pos.iter().map(|x| !gone(x)).collect();
        let before = self.len();
        retain_marked(&mut self.pos, &keep);
        retain_marked(&mut self.vel, &keep);
        retain_marked(&mut self.rho, &keep);
        retain_marked(&mut self.drho, &keep);
        retain_marked(&mut self.mass, &keep);
        retain_marked(&mut self.id, &keep);
        before - self.len()
    }

    /// The kernel-weighted (Shepard) average of `value` over the particles within the
    /// support of `kernel` around `at` (`zero` its zero), or None if there are none.
    pub fn shepard<T>(
        &self,
        kernel: &crate::numerics::kernel::WendlandC2,
        at: &Vect<D>,
        (value, zero): (impl Fn(usize) -> T, T),
        sep: &impl Separation,
    ) -> Option<T>
    where
        T: std::ops::AddAssign + std::ops::Mul<Real, Output = T>,
    {
        let (mut wsum, mut sum) = (0.0, zero);
        for i in 0..self.len() {
            let r = sep.of(self.pos[i] - at).norm();
            if r < kernel.cutoff {
                let w = kernel.w(r) * self.mass[i] / self.rho[i];
                wsum += w;
                sum += value(i) * w;
            }
        }
        (wsum > 0.0).then(|| sum * (1.0 / wsum))
    }

    /// The depth of water over the point `base` along the vertical `up`: the water's
    /// volume per unit length (2D) or area (3D) across the vertical line through it,
    /// Σ_j V_j W_{d−1}(r⊥_j) over the particles above the base, with r⊥ the distance
    /// from the line and W_{d−1} the Wendland C2 kernel of smoothing length `h` in one
    /// dimension fewer. Under a layer of uniform depth it is the depth; water in the
    /// air above the line (a jet, spray) counts, a cavity under a breaking wave does
    /// not.
    pub fn depth(&self, h: Real, base: &Vect<D>, up: &Vect<D>, sep: &impl Separation) -> Real {
        let lateral = crate::numerics::kernel::WendlandC2::new(h, D - 1);
        (0..self.len())
            .map(|i| {
                let r = sep.of(self.pos[i] - base);
                let height = r.dot(up);
                if height < 0.0 {
                    return 0.0;
                }
                let across = (r - up * height).norm();
                lateral.w(across) * self.mass[i] / self.rho[i]
            })
            .fold(0.0, |a, e| a + e)
    }

    /// Σ ½ m v²; +0 without particles (a float `sum` of nothing is −0).
    pub fn kinetic_energy(&self) -> Real {
        self.vel
            .iter()
            .zip(&self.mass)
            .map(|(v, m)| 0.5 * m * v.norm_squared())
            .fold(0.0, |a, e| a + e)
    }

    /// −Σ m g·x (zero at the origin); +0 without particles.
    pub fn potential_energy(&self, g: &Vect<D>) -> Real {
        self.pos
            .iter()
            .zip(&self.mass)
            .map(|(x, m)| -m * g.dot(x))
            .fold(0.0, |a, e| a + e)
    }

    /// The surge front: the largest x of any water particle; none without water (all
    /// of it gone through an outflow, or not yet come in).
    pub fn front(&self) -> Option<Real> {
        self.pos.iter().map(|x| x[0]).reduce(Real::max)
    }

    /// Largest speed.
    pub fn max_speed(&self) -> Real {
        self.vel
            .iter()
            .map(|v| v.norm_squared())
            .fold(0.0, Real::max)
            .sqrt()
    }

    /// The lowest pressure of any particle under `mat`'s equation of state (0
    /// without particles).
    pub fn min_pressure(&self, mat: &super::material::WaterMaterial) -> Real {
        self.rho
            .iter()
            .map(|&r| mat.pressure(r))
            .reduce(Real::min)
            .unwrap_or(0.0)
    }

    /// Total linear momentum Σ m v.
    pub fn momentum(&self) -> Vect<D> {
        self.vel
            .iter()
            .zip(&self.mass)
            .fold(Vect::<D>::zeros(), |a, (v, m)| a + v * *m)
    }
}

/// Keep the entries of `v` whose mark in `keep` is set, in order.
fn retain_marked<T>(v: &mut Vec<T>, keep: &[bool]) {
    let mut k = keep.iter();
    v.retain(|_| *k.next().expect("one mark per entry"));
}
