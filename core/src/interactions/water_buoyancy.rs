//! A body's buoyancy taken whole from the water around it (issue 42): the hydrostatic
//! part of the water's pressure on a body as Archimedes' force, the rest resolved by the
//! particles.
//!
//! Through the dummy particles alone ([`water_coarse`](super::water_coarse)) a body
//! feels only the water that reaches it. No water particle fits in a gap narrower than
//! a spacing, so a body resting on the floor, a wall or another body loses the uplift of
//! its contact zone: a disc of 2 ρ_w on the floor at R/dp = 10 read 260–290 N/m of
//! contact force against its net weight of 154 N/m. Anchor codes share the gap
//! (SPHinXsys, DualSPHysics and Chrono::FSI give a boundary particle without fluid
//! neighbours no pressure).
//!
//! For a body with gap partners ([`gap_water`](super::gap_water): within a spacing of a
//! wall or of another body) the water's pressure near it splits into a hydrostatic
//! field and the rest:
//!
//!   p_b(x) = p̄_b + ρ̄_b g_h·(x − x_b),
//!
//! with ρ̄_b and p̄_b from the water particles within the kernel of the body's particles,
//! each weighted by Σ_c W(r_ic) V_c over the body's particles c near it: ρ̄_b their mean
//! density, p̄_b their mean pressure extrapolated hydrostatically to the centre of mass
//! x_b. The field's force on the body is Archimedes' −ρ̄_b g_h V_s, exactly, with V_s the
//! body's volume (mass over density) below p_b = 0: each body particle carries the share
//! s_c / N_b of it, s_c = clamp(p_b(x_c)/(ρ̄_b |g_h| dp) + ½, 0, 1), so that it acts at
//! the centroid of the submerged part. The particles resolve only p − p_b: each
//! water–body pair's force on the body less the same pair's with P* replaced by the
//! field's mean ½ (p_b(x_i) + p_b(x_c)) (P* is linear in the two pressures). The water
//! feels the full pressure as before.
//!
//! Water in the film between the body and its partner, where the gap between the two
//! surfaces measured through the particle is under two kernel supports, is not
//! resolved: its pairs give the body the field's share only, and it does not enter the
//! means. Left in, its pressure, a few per cent above hydrostatic in the wedge by the
//! contact, lifted a resting disc of 2 ρ_w by 6–12 % of its net weight.
//!
//! What the pairs miss of the field, ΔF_b = −ρ̄_b g_h V_s less the field's force as
//! they resolve it, is the uplift of the dry contact zone and the error of the
//! displaced volume. Its reaction goes where that water would push: to the body's gap
//! partners, shared equally ([`gap_water`](super::gap_water)), so the momentum the
//! water and the bodies exchange stays balanced.
//!
//! A body near nothing keeps the pairs' full force: subtracting the field there takes
//! out, with the field, the part of the added mass that the particles' arrangement
//! carries (a rising disc then accelerated 43 % too fast).

use super::fine_coarse::CoarseSource;
use crate::coarse::body::Body;
use crate::geometry::walls::Walls;
use crate::numerics::math::{from3, Real, Vect};
use crate::numerics::neighbors::{NeighborLists, CHUNK};
use crate::numerics::periodic::Separation;
use crate::water::momentum::WaterParams;
use crate::water::source::WaterSource;
use rayon::prelude::*;

/// The bodies' hydrostatic fields for one water sub-step.
#[derive(Clone, Debug)]
pub struct Hydrostatics<const D: usize> {
    /// p_b(x_c) of every coarse particle; NaN on a body no water reaches.
    pub p: Vec<Real>,
    /// g_h, the hydrostatic gravity.
    pub g: Vect<D>,
    /// ρ̄_b g_h of each body (ρ̄_b the mean density of the water around it).
    pub rho_g: Vec<Vect<D>>,
    /// Per coarse particle: its body, plus one, where the body has gap partners
    /// ([`Body::gaps`]); zero elsewhere.
    pub gap: Vec<u32>,
    /// The body of each coarse particle.
    body: Vec<u32>,
    /// The particle spacing.
    dp: Real,
}

impl<const D: usize> Default for Hydrostatics<D> {
    fn default() -> Self {
        Hydrostatics {
            p: Vec::new(),
            g: Vect::<D>::zeros(),
            rho_g: Vec::new(),
            gap: Vec::new(),
            body: Vec::new(),
            dp: 0.0,
        }
    }
}

impl<const D: usize> Hydrostatics<D> {
    /// The fields of the bodies from the water particles `pos` with pressures in `src`
    /// and their coarse neighbour lists: p̄_b of each body, p_b at each coarse particle.
    #[allow(clippy::too_many_arguments)]
    pub fn update(
        &mut self,
        (pos, src): (&[Vect<D>], &[WaterSource]),
        (csrc, body_of, bodies): (&[CoarseSource<D>], &[u32], &[Body<D>]),
        (lists, walls): (&NeighborLists, &Walls<D>),
        (prm, dp): (&WaterParams<D>, Real),
    ) {
        let (kernel, wrap) = (&prm.kernel, &prm.wrap);
        self.dp = dp;
        self.g = prm.hydrostatic;
        self.body.clear();
        self.body.extend_from_slice(body_of);
        self.gap.clear();
        self.gap.extend(body_of.iter().map(|&b| {
            if bodies[b as usize].gaps > 0 {
                b + 1
            } else {
                0
            }
        }));
        if bodies.iter().all(|b| b.gaps == 0) {
            // no body takes the field: skip the pass over the water
            self.p.clear();
            self.p.resize(csrc.len(), Real::NAN);
            return;
        }
        let this = &*self;
        let shell: Vec<Vec<(u32, u32, Real)>> = lists
            .chunks
            .par_iter()
            .enumerate()
            .map(|(c, cl)| {
                let mut out = Vec::new();
                for k in 0..cl.coarse_off.len().saturating_sub(1) {
                    let i = c * CHUNK + k;
                    if this.film(prm, (walls, csrc), &pos[i], cl.coarse(k)) {
                        // a film's pressure is not the field's (module notes)
                        continue;
                    }
                    let first = out.len();
                    for &j in cl.coarse(k) {
                        let cj = &csrc[j as usize];
                        let r = wrap.of(pos[i] - cj.pos).norm();
                        if r >= kernel.cutoff {
                            continue;
                        }
                        let wgt = kernel.w(r) * cj.vol;
                        let b = body_of[j as usize];
                        match out[first..]
                            .iter_mut()
                            .find(|s: &&mut (u32, u32, Real)| s.1 == b)
                        {
                            Some(s) => s.2 += wgt,
                            None => out.push((i as u32, b, wgt)),
                        }
                    }
                }
                out
            })
            .collect();
        // the means, in chunk order (the same at any thread count): weight, pressure,
        // density and position
        let n = bodies.len();
        let mut sums = vec![(0.0, 0.0, 0.0, Vect::<D>::zeros()); n];
        let com: Vec<Vect<D>> = bodies.iter().map(|b| from3::<D>(&b.com)).collect();
        for &(i, b, wgt) in shell.iter().flatten() {
            let (i, b) = (i as usize, b as usize);
            let s = &mut sums[b];
            s.0 += wgt;
            s.1 += wgt * src[i].p;
            s.2 += wgt * src[i].rho;
            s.3 += wrap.of(pos[i] - com[b]) * wgt;
        }
        self.rho_g.clear();
        let mean = |s: &(Real, Real, Real, Vect<D>)| {
            // p̄_b at the centre of mass, from the mean pressure at the mean position
            let rho_g = self.g * (s.2 / s.0);
            (s.1 / s.0 - rho_g.dot(&(s.3 / s.0)), rho_g)
        };
        // only a body within a spacing of a wall or another body takes the field
        let field: Vec<(Real, Vect<D>)> = sums
            .iter()
            .zip(bodies)
            .map(|(s, b)| {
                if s.0 > 0.0 && b.gaps > 0 {
                    mean(s)
                } else {
                    (Real::NAN, Vect::<D>::zeros())
                }
            })
            .collect();
        self.rho_g.extend(field.iter().map(|f| f.1));
        self.p.clear();
        self.p.extend(csrc.iter().zip(body_of).map(|(c, &b)| {
            let (pb, rho_g) = field[b as usize];
            pb + rho_g.dot(&wrap.of(c.pos - com[b as usize]))
        }));
    }

    /// ρ̄_b g_h of coarse particle `c`'s body.
    #[inline(always)]
    pub fn rho_g(&self, c: usize) -> &Vect<D> {
        &self.rho_g[self.body[c] as usize]
    }

    /// Coarse particle `c`'s body has gap partners.
    #[inline(always)]
    pub fn in_gap(&self, c: usize) -> bool {
        self.gap[c] != 0
    }

    /// A water particle at `xi` with coarse neighbours `cl` lies in a film: next to a
    /// body with gap partners, where the gap between that body's surface and a wall's
    /// (or a second body's) measured through the particle is under two kernel
    /// supports, `2 × cutoff` (module notes). The distance to a body's surface is the
    /// nearest of its particles' less dp/2, to a wall's its signed distance.
    pub fn film(
        &self,
        prm: &WaterParams<D>,
        (walls, csrc): (&Walls<D>, &[CoarseSource<D>]),
        xi: &Vect<D>,
        cl: &[u32],
    ) -> bool {
        let Some(&first) = cl.iter().find(|&&j| self.gap[j as usize] != 0) else {
            return false;
        };
        let body = self.body[first as usize];
        let gap = 2.0 * prm.kernel.cutoff;
        let (mut own, mut other) = (Real::INFINITY, Real::INFINITY);
        for &j in cl {
            let r = prm.wrap.of(xi - csrc[j as usize].pos).norm() - 0.5 * self.dp;
            if self.body[j as usize] == body {
                own = own.min(r);
            } else {
                other = other.min(r);
            }
        }
        if own + other < gap {
            return true;
        }
        walls.objects.iter().any(|o| match &o.shape {
            Some(shape) => own + shape.sdf(&(xi - o.displacement)) < gap,
            None => false,
        })
    }

    /// Archimedes' force on each coarse particle into `out` (zero on dry bodies):
    /// −ρ̄_b g_h V_b s_c / N_b, with V_b the body's volume `mass / density` and N_b its
    /// particle count (module notes); `dp` the particle spacing.
    pub fn archimedes(
        &self,
        bodies: &[Body<D>],
        volume: impl Fn(&Body<D>) -> Real,
        dp: Real,
        out: &mut Vec<Vect<D>>,
    ) {
        out.clear();
        out.resize(self.p.len(), Vect::<D>::zeros());
        for (bi, b) in bodies.iter().enumerate() {
            if b.is_empty() || !self.p[b.start].is_finite() {
                continue;
            }
            let rho_g = self.rho_g[bi];
            if rho_g == Vect::<D>::zeros() {
                // no gravity, no buoyancy
                continue;
            }
            let scale = 1.0 / (rho_g.norm() * dp);
            let share = -rho_g * (volume(b) / b.len() as Real);
            for (o, p) in out[b.start..b.end].iter_mut().zip(&self.p[b.start..b.end]) {
                *o = share * (p * scale + 0.5).clamp(0.0, 1.0);
            }
        }
    }
}
