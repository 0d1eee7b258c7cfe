//! Open boundaries of the water: inflows, where layers of particles enter through the
//! upstream face of an inlet box at a prescribed speed (constant, or the Gumbel
//! hydrograph of seed 001 Eq. 36), and outflows, planes past which particles are
//! removed. Particle counts change: the stage that calls these rebuilds its lists.

use super::material::WaterMaterial;
use super::state::WaterParticles;
use crate::numerics::math::{box_extent, Real, Vect};
use crate::scene::Hydrograph;

/// The inflow speed against time.
#[derive(Clone, Copy, Debug, PartialEq, serde::Serialize, serde::Deserialize)]
pub enum InflowSpeed {
    Constant(Real),
    Hydrograph(Hydrograph),
}

/// One inflow, with the length of water let in since its last layer.
#[derive(Clone, Debug, serde::Serialize, serde::Deserialize)]
pub struct Inflow<const D: usize> {
    pub name: String,
    /// The inlet box.
    pub lo: Vect<D>,
    pub hi: Vect<D>,
    /// Flow axis and its sign.
    pub axis: usize,
    pub sign: Real,
    pub speed: InflowSpeed,
    /// The inflow stops at this time (s).
    pub stop: Real,
    /// Length let in since the last layer entered (m).
    pub fill: Real,
}

impl<const D: usize> Inflow<D> {
    /// The inflow speed at time `t` (0 after `stop`).
    pub fn speed_at(&self, t: Real) -> Real {
        if t >= self.stop {
            return 0.0;
        }
        match self.speed {
            InflowSpeed::Constant(u) => u,
            InflowSpeed::Hydrograph(h) => h.speed(t),
        }
    }

    /// The largest speed: the constant one, or the hydrograph's peak.
    pub fn peak_speed(&self) -> Real {
        match self.speed {
            InflowSpeed::Constant(u) => u,
            InflowSpeed::Hydrograph(h) => h.peak(),
        }
    }

    /// The flow direction.
    pub fn direction(&self) -> Vect<D> {
        let mut d = Vect::<D>::zeros();
        d[self.axis] = self.sign;
        d
    }

    /// True if `x` lies in the inlet box.
    #[inline]
    pub fn holds(&self, x: &Vect<D>) -> bool {
        (0..D).all(|k| x[k] >= self.lo[k] && x[k] <= self.hi[k])
    }

    /// Let water in over a step from `t` to `t + dt`: the speed at the middle of the
    /// step times `dt` fills the inlet, and each particle spacing `dp` of it enters as
    /// a new layer at the upstream face, dp/2 plus the overshoot inside, moving at the
    /// inflow speed, at the hydrostatic pressure below the box's top (gravity `g` along
    /// `-up`). Returns the particles added.
    #[allow(clippy::too_many_arguments)]
    pub fn emit(
        &mut self,
        water: &mut WaterParticles<D>,
        mat: &WaterMaterial,
        (t, dt): (Real, Real),
        (dp, vol): (Real, Real),
        (g, up): (Real, &Vect<D>),
    ) -> usize {
        let u = self.speed_at(t + 0.5 * dt);
        self.fill += u * dt;
        let dir = self.direction();
        let (a, top) = (self.axis, self.extent_along(up).1);
        let face = if self.sign > 0.0 {
            self.lo[a]
        } else {
            self.hi[a]
        };
        let mut added = 0;
        while self.fill >= dp {
            self.fill -= dp;
            // the layer's distance into the box: dp/2 plus how far it has moved since
            let s = face + self.sign * (0.5 * dp + self.fill);
            for mut x in self.cross_section(dp) {
                x[a] = s;
                let rho = mat.density(mat.hydrostatic_pressure(g, (top - x.dot(up)).max(0.0)));
                water.push(x, dir * u, rho, rho * vol);
                added += 1;
            }
        }
        added
    }

    /// The lowest and highest coordinate of the box's corners along `up`.
    pub fn extent_along(&self, up: &Vect<D>) -> (Real, Real) {
        box_extent(&self.lo, &self.hi, up)
    }

    /// The lattice points of the box's cross-section across the flow axis (the axis's
    /// own coordinate left at 0), spacing dp from dp/2 inside the faces.
    fn cross_section(&self, dp: Real) -> Vec<Vect<D>> {
        let mut pts = vec![Vect::<D>::zeros()];
        for k in (0..D).filter(|&k| k != self.axis) {
            let n = (((self.hi[k] - self.lo[k]) / dp).round() as usize).max(1);
            pts = pts
                .into_iter()
                .flat_map(|p| {
                    (0..n).map(move |i| {
                        let mut q = p;
                        q[k] = self.lo[k] + (i as Real + 0.5) * dp;
                        q
                    })
                })
                .collect();
        }
        pts
    }

    /// Impose the inflow velocity on the particles in the inlet box (their pressure
    /// does not move them there), at time `t`.
    pub fn drive(&self, pos: &[Vect<D>], vel: &mut [Vect<D>], t: Real) {
        let v = self.direction() * self.speed_at(t);
        for (x, vi) in pos.iter().zip(vel.iter_mut()) {
            if self.holds(x) {
                *vi = v;
            }
        }
    }

    /// Hold the density of the particles in the inlet box: they move as one block, and
    /// the continuity equation would read the growing gap to the wall behind the last
    /// layer (until the next layer enters) as an expansion.
    pub fn hold_density(&self, pos: &[Vect<D>], drho: &mut [Real]) {
        for (x, d) in pos.iter().zip(drho.iter_mut()) {
            if self.holds(x) {
                *d = 0.0;
            }
        }
    }
}

/// One outflow plane.
#[derive(Clone, Debug, PartialEq, serde::Serialize, serde::Deserialize)]
pub struct Outflow<const D: usize> {
    pub name: String,
    pub point: Vect<D>,
    /// Unit normal out of the domain.
    pub normal: Vect<D>,
}

impl<const D: usize> Outflow<D> {
    /// Remove the particles past the plane; returns how many left.
    pub fn remove(&self, water: &mut WaterParticles<D>) -> usize {
        water.remove_where(|x| (x - self.point).dot(&self.normal) > 0.0)
    }
}
