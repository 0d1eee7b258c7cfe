//! Coarse-grain sub-steps: position-based Verlet (Eqs. 57–59) for elastic and rigid
//! bodies, κ of them per fine step (multi-rate) with the fine-grain force of Eq. (50)
//! held over the fine step, then the time-averaged velocity of Eq. (60).
//! Δt_c follows Eq. (52), tightened by the contact stiffness of nearby contacts.

use super::params::StepParams;
use crate::coarse::build::Coarse;
use crate::coarse::rigid;
use crate::coarse::tlsph::Tlsph;
use crate::coarse::{Body, CoarseParticles};
use crate::geometry::walls::Walls;
use crate::interactions::contact::{ContactLaw, Contacts};
use crate::interactions::gap_water::GapWater;
use crate::numerics::guard::Blowup;
use crate::numerics::load::Load;
use crate::numerics::math::{from3, to3, Real, Vect};
use nalgebra::{Matrix3, UnitQuaternion, Vector3};

/// Sub-stepping state and scratch of the coarse grains.
#[derive(Clone, Debug, serde::Serialize, serde::Deserialize)]
pub struct CoarseStepper<const D: usize> {
    pub law: ContactLaw,
    pub contacts: Contacts<D>,
    /// Gap partners of the wet bodies: where their missed uplift pushes.
    #[serde(default)]
    pub gaps: GapWater<D>,
    pub tlsph: Tlsph<D>,
    /// CFL^c of Eq. (52).
    pub cfl: Real,
    /// Coarse smoothing length h = 1.15 dp.
    pub h: Real,
    pub dp: Real,
    /// Largest particle speed and acceleration of the last sub-step.
    pub vmax: Real,
    pub amax: Real,
    /// Coarse sub-steps taken so far.
    pub steps: u64,
    /// Coarse sub-step Δt_f/κ of the last fine step.
    pub dt: Real,
    /// Impulse (force, torque) of the fine grains + contacts on each body over the
    /// fine step (3D).
    impulse: Vec<(Vector3<Real>, Vector3<Real>)>,
    /// Contact load on each barrier load slot (panel) over the fine step, impulse / Δt_f.
    pub wall_loads: Vec<Load>,
    /// Seconds spent in contact evaluation since last taken.
    #[serde(skip)]
    pub contact_secs: f64,
    gravity: Vector3<Real>,
    /// Runaway bound on any coarse particle's speed (`simulation.max_speed`).
    max_speed: Real,
}

impl<const D: usize> CoarseStepper<D> {
    /// Whether the speed, acceleration and sub-step the next Δt_c reads are finite, not
    /// negative and (the speed) at most `max_speed`.
    pub fn motion_in_range(&self) -> bool {
        let v = self.vmax.is_finite() && (0.0..=self.max_speed).contains(&self.vmax);
        v && self.amax.is_finite() && self.amax >= 0.0 && self.dt.is_finite() && self.dt >= 0.0
    }

    /// Whether this sub-stepper, restored from a state, fits `template` (the scene's
    /// as built) and `coarse` among `objects` wall objects: the same contact law,
    /// constants and reference configuration, and candidates of existing particles.
    pub fn restored_fits(
        &self,
        template: &Self,
        coarse: &Coarse<D>,
        objects: usize,
    ) -> Result<(), &'static str> {
        let t = template;
        let bits = |x: Real| x.to_bits();
        if self.law != t.law
            || bits(self.cfl) != bits(t.cfl)
            || bits(self.h) != bits(t.h)
            || bits(self.dp) != bits(t.dp)
            || bits(self.max_speed) != bits(t.max_speed)
            || !self.gravity.iter().all(|g| g.is_finite())
        {
            return Err("coarse sub-stepper's constants");
        }
        if !self.tlsph.restored_fits(&t.tlsph) {
            return Err("elastic bodies' reference configuration");
        }
        let (n, bodies) = (coarse.particles.len(), coarse.bodies.len());
        if !self.contacts.restored_fits(n, objects, bodies)
            || !self.gaps.restored_fits(n, objects, bodies)
            || self.impulse.len() != bodies
        {
            return Err("contact candidates");
        }
        Ok(())
    }

    /// Gravity of the coming sub-steps (changes while the scene ramps it up).
    pub fn set_gravity(&mut self, gravity: &Vect<D>) {
        self.gravity = to3(gravity);
    }

    /// The sub-stepper of `coarse` at spacing `dp`.
    pub fn new(coarse: &Coarse<D>, params: &StepParams, dp: Real, gravity: &Vect<D>) -> Self {
        CoarseStepper {
            law: params.contact.clone(),
            contacts: Contacts::default(),
            gaps: GapWater::default(),
            tlsph: Tlsph::new(&coarse.particles, &coarse.bodies, dp),
            cfl: params.cfl_coarse,
            h: 1.15 * dp,
            dp,
            vmax: coarse
                .particles
                .vel
                .iter()
                .map(|v| v.norm())
                .fold(0.0, Real::max),
            amax: 0.0,
            steps: 0,
            dt: 0.0,
            impulse: vec![Default::default(); coarse.bodies.len()],
            wall_loads: Vec::new(),
            contact_secs: 0.0,
            gravity: to3(gravity),
            max_speed: params.max_speed,
        }
    }

    /// Find contact candidates for a fine step of about `dt`.
    pub fn prepare(&mut self, coarse: &Coarse<D>, walls: &Walls<D>, dt: Real) {
        let wall_speed = walls
            .objects
            .iter()
            .map(|o| o.velocity.norm())
            .fold(0.0, Real::max);
        let margin = 2.0 * (self.vmax + wall_speed) * dt + 0.05 * self.dp;
        self.contacts
            .find(&coarse.particles, &coarse.bodies, walls, self.dp, margin);
    }

    /// Δt_c: Eq. (52) for elastic bodies, the acceleration bound for all, and the
    /// contact bound for bodies with contact candidates. Infinite when nothing limits.
    pub fn stable_dt(&self, coarse: &Coarse<D>) -> Real {
        let mut dt = Real::INFINITY;
        let c0 = coarse.max_elastic_c0();
        if c0 > 0.0 {
            dt = dt.min(self.cfl * self.h / (c0 + self.vmax));
        }
        if self.amax > 0.0 {
            dt = dt.min(self.cfl * (self.h / self.amax).sqrt());
        }
        dt.min(self.contacts.stable_dt(
            &coarse.particles,
            &coarse.bodies,
            &coarse.solids,
            &self.law,
            self.cfl,
        ))
    }

    /// κ sub-steps of Δt_f/κ. The fine-grain forces `f_fine` must be set.
    pub fn advance(
        &mut self,
        coarse: &mut Coarse<D>,
        walls: &Walls<D>,
        dt_f: Real,
        kappa: usize,
        step: u64,
        time: Real,
    ) -> Result<(), Blowup> {
        let dt = dt_f / kappa as Real;
        self.dt = dt;
        let p = &mut coarse.particles;
        p.pos_start.copy_from_slice(&p.pos);
        for imp in &mut self.impulse {
            *imp = Default::default();
        }
        self.wall_loads.clear();
        self.wall_loads.resize(walls.load_slots(), Load::default());
        // the water in the wet bodies' gaps, held over the fine step like f_water
        self.gaps.find(p, &coarse.bodies, walls, self.dp);
        let mut gap_loads = vec![Load::default(); walls.load_slots()];
        self.gaps.react(p, &coarse.bodies, walls, &mut gap_loads);
        for _ in 0..kappa {
            self.substep(coarse, walls, dt);
        }
        let p = &mut coarse.particles;
        let inv = 1.0 / dt_f;
        for i in 0..p.len() {
            p.vbar[i] = (p.pos[i] - p.pos_start[i]) * inv;
        }
        for (l, g) in self.wall_loads.iter_mut().zip(&gap_loads) {
            l.force = l.force * inv + g.force;
            l.moment = l.moment * inv + g.moment;
        }
        for (b, (f, t)) in coarse.bodies.iter_mut().zip(&self.impulse) {
            b.force = f * inv;
            b.torque = t * inv;
            // the fine-grain force is held over the fine step: its sum needs no average
            b.fine_force = (b.start..b.end).fold(Vector3::zeros(), |a, i| a + to3(&p.f_fine[i]));
            b.water_force = (b.start..b.end).fold(Vector3::zeros(), |a, i| a + to3(&p.f_water[i]));
        }
        for (b, n) in coarse.bodies.iter_mut().zip(&self.contacts.per_body) {
            b.contacts = *n;
        }
        for (b, n) in coarse.bodies.iter_mut().zip(&self.gaps.per_body) {
            b.gaps = *n;
        }
        for b in coarse.bodies.iter_mut().filter(|b| !b.is_rigid()) {
            elastic_summary(b, p);
        }
        self.check(coarse, step, time)
    }

    fn substep(&mut self, coarse: &mut Coarse<D>, walls: &Walls<D>, dt: Real) {
        let half = 0.5 * dt;
        self.drift(coarse, half, false);
        let (p, bodies, solids) = (&mut coarse.particles, &coarse.bodies, &coarse.solids);
        let t = std::time::Instant::now();
        self.contacts
            .evaluate(p, bodies, solids, walls, &self.law, dt);
        self.contact_secs += t.elapsed().as_secs_f64();
        for (acc, l) in self.wall_loads.iter_mut().zip(&self.contacts.wall_loads) {
            acc.force += l.force * dt;
            acc.moment += l.moment * dt;
        }
        if !self.tlsph.is_empty() {
            self.tlsph.stress(p, bodies, solids);
            self.tlsph.acceleration(p, bodies, solids);
        }
        // kick, Eq. (58)
        let g = from3::<D>(&self.gravity);
        let mut amax2: Real = 0.0;
        for (k, &i) in self.tlsph.elastic.iter().enumerate() {
            let i = i as usize;
            let a =
                self.tlsph.acc[k] + (p.f_fine[i] + p.f_water[i] + p.f_contact[i]) / p.mass[i] + g;
            amax2 = amax2.max(a.norm_squared());
            p.vel[i] += a * dt;
        }
        for (bi, b) in coarse.bodies.iter_mut().enumerate() {
            let (f, t) = rigid::resultant(b, p, |i| p.f_fine[i] + p.f_water[i] + p.f_contact[i]);
            let imp = &mut self.impulse[bi];
            imp.0 += f * dt;
            imp.1 += t * dt;
            if b.is_rigid() {
                rigid::kick(b, &f, &t, &self.gravity, dt);
                if !b.fixed {
                    amax2 = amax2.max((f / b.mass + self.gravity).norm_squared());
                }
            }
        }
        if !self.tlsph.is_empty() {
            self.tlsph.deformation_rate(p);
        }
        self.drift(coarse, half, true);
        self.amax = amax2.sqrt();
        self.vmax = coarse
            .particles
            .vel
            .iter()
            .map(|v| v.norm_squared())
            .fold(0.0, Real::max)
            .sqrt();
        self.steps += 1;
    }

    /// Half-step drift of Eqs. (57)/(59): 𝔽, positions (elastic), pose (rigid).
    /// At the end of a sub-step (`end`) ω is refreshed for the new orientation
    /// before the rigid particles are placed.
    fn drift(&mut self, coarse: &mut Coarse<D>, half: Real, end: bool) {
        let p = &mut coarse.particles;
        if !self.tlsph.is_empty() {
            self.tlsph.advance_deformation(half);
            for &i in &self.tlsph.elastic {
                let i = i as usize;
                p.pos[i] += p.vel[i] * half;
            }
        }
        for b in coarse.bodies.iter_mut().filter(|b| b.is_rigid()) {
            rigid::drift(b, half);
            if end && !b.fixed {
                rigid::refresh_omega(b);
            }
            rigid::place(b, p);
        }
    }

    /// Stop on non-finite coarse state or a speed beyond `simulation.max_speed`.
    fn check(&self, coarse: &Coarse<D>, step: u64, time: Real) -> Result<(), Blowup> {
        let p = &coarse.particles;
        for i in 0..p.len() {
            let speed = p.vel[i].norm();
            let bad = if !p.vel[i].iter().all(|x| x.is_finite()) {
                Some(("velocity", speed, None))
            } else if !p.pos[i].iter().all(|x| x.is_finite()) {
                Some(("position", p.pos[i].norm(), None))
            } else if speed > self.max_speed {
                Some(("speed", speed, Some(self.max_speed)))
            } else {
                None
            };
            if let Some((q, v, limit)) = bad {
                let b = &coarse.bodies[p.body[i] as usize];
                return Err(Blowup {
                    step,
                    time,
                    particle: (i - b.start) as u32,
                    body: Some(b.name.clone()),
                    family: crate::numerics::guard::Family::Coarse,
                    position: p.pos[i].iter().copied().collect(),
                    quantity: q.to_string(),
                    value: v,
                    limit,
                });
            }
        }
        Ok(())
    }

    /// Update elastic normals after the sub-steps (used by the coupling).
    pub fn update_normals(&self, coarse: &mut Coarse<D>) {
        self.tlsph.update_normals(&mut coarse.particles);
    }
}

/// Centre of mass, velocity, angular momentum/velocity and best-fit rotation of an
/// elastic body, for output.
fn elastic_summary<const D: usize>(b: &mut Body<D>, p: &CoarseParticles<D>) {
    let mut m = 0.0;
    let mut c = Vector3::zeros();
    let mut v = Vector3::zeros();
    let mut c0 = Vector3::zeros();
    for i in b.start..b.end {
        m += p.mass[i];
        c += to3(&p.pos[i]) * p.mass[i];
        v += to3(&p.vel[i]) * p.mass[i];
        c0 += to3(&p.local[i]) * p.mass[i];
    }
    c /= m;
    v /= m;
    c0 /= m;
    let mut l = Vector3::zeros();
    let mut a = Matrix3::zeros();
    for i in b.start..b.end {
        let r = to3(&p.pos[i]) - c;
        l += r.cross(&((to3(&p.vel[i]) - v) * p.mass[i]));
        a += r * (to3(&p.local[i]) - c0).transpose() * p.mass[i];
    }
    if D == 2 {
        a[(2, 2)] = 1.0;
    }
    b.com = c;
    b.vel = v;
    b.ang_mom = l;
    // rotation part of the best-fit linear map (polar decomposition via SVD)
    let svd = a.svd(true, true);
    if let (Some(u), Some(vt)) = (svd.u, svd.v_t) {
        let mut r = u * vt;
        if r.determinant() < 0.0 {
            let mut u2 = u;
            for k in 0..3 {
                u2[(k, 2)] = -u2[(k, 2)];
            }
            r = u2 * vt;
        }
        b.orientation = UnitQuaternion::from_matrix(&r);
    }
    let rot = b.rotation();
    b.omega = rot * b.inv_inertia * rot.transpose() * l;
}
