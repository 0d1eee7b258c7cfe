//! Contacts of coarse grains with each other and with walls (seeds 001 and 004):
//! particle-level spring–dashpot or Hertz–Mindlin laws with a Coulomb-capped
//! tangential spring (Cundall–Strack) and a restitution coefficient.
//!
//! Every surface particle of a body is a sphere (disc in 2D) of radius dp/2, so a body
//! touches a wall when its shape does. Walls are exact: the overlap is taken from the
//! wall shape's signed distance, so a flat wall is flat (no particle roughness).
//! Candidates are found once per fine step with a margin covering the motion within
//! it; the force is evaluated at every coarse sub-step.

use crate::coarse::{Body, CoarseParticles, SolidMaterial};
use crate::geometry::walls::Walls;
use crate::numerics::load::Load;
use crate::numerics::math::{to3, Real, Vect};
use crate::scene::{ContactModel, ContactSpec};

/// The contact law of a scene.
#[derive(Clone, Debug, PartialEq, serde::Serialize, serde::Deserialize)]
pub struct ContactLaw {
    pub model: ContactModel,
    /// Coulomb coefficient μ.
    pub mu: Real,
    /// Damping ratio ζ = c / (2√(m k)) that gives restitution e (see
    /// [`damping_ratio_for_restitution`] for the linear law; Tsuji's
    /// −ln e / √(ln² e + π²) for Hertz–Mindlin).
    pub gamma: Real,
    /// Normal stiffness override of the linear law.
    pub stiffness: Option<Real>,
    /// Particle spacing dp; contact radius dp/2.
    pub dp: Real,
    pub dim: usize,
}

/// Restitution of the linear spring–dashpot whose force may not pull (F_n ≥ 0), at
/// damping ratio ζ (Schwager & Pöschel 2007). The contact ends when the force, not
/// the overlap, reaches zero, at time t_c, and e = exp(−ζ ω₀ t_c):
/// ζ < 1: ω = ω₀√(1 − ζ²), ω t_c = atan2(2ζω/ω₀, 2ζ² − 1);
/// ζ > 1: e = ((ζ − s)/(ζ + s))^(ζ/s), s = √(ζ² − 1).
pub fn restitution_of_damping(zeta: Real) -> Real {
    if zeta <= 0.0 {
        1.0
    } else if zeta < 1.0 {
        let w = (1.0 - zeta * zeta).sqrt();
        (-(zeta / w) * (2.0 * zeta * w).atan2(2.0 * zeta * zeta - 1.0)).exp()
    } else if zeta == 1.0 {
        (-2.0 as Real).exp()
    } else {
        let s = (zeta * zeta - 1.0).sqrt();
        ((zeta - s) / (zeta + s)).powf(zeta / s)
    }
}

/// The damping ratio ζ at which the no-pull linear law rebounds with restitution e
/// (inverse of [`restitution_of_damping`], which falls monotonically from 1 at ζ = 0
/// to 0 as ζ → ∞), by bisection to machine precision. The textbook
/// −ln e / √(ln² e + π²) assumes the dashpot may pull; without pulling it gives
/// e = 0.22 for a requested 0.1.
pub fn damping_ratio_for_restitution(e: Real) -> Real {
    if e >= 1.0 {
        return 0.0;
    }
    let (mut lo, mut hi): (Real, Real) = (0.0, 1.0);
    while restitution_of_damping(hi) > e {
        hi *= 2.0;
        if hi > 1e12 {
            return hi;
        }
    }
    for _ in 0..200 {
        let mid = 0.5 * (lo + hi);
        if restitution_of_damping(mid) > e {
            lo = mid;
        } else {
            hi = mid;
        }
        if hi - lo <= Real::EPSILON * hi {
            break;
        }
    }
    0.5 * (lo + hi)
}

/// Stiffness and damping of one contact at overlap δ.
#[derive(Clone, Copy, Debug)]
struct Springs {
    kn: Real,
    kt: Real,
    cn: Real,
    ct: Real,
}

/// Effective moduli of a contact kind: E*, G*, R*.
#[derive(Clone, Copy, Debug)]
pub struct Moduli {
    pub e: Real,
    pub g: Real,
    pub r: Real,
}

impl Moduli {
    /// A particle against a rigid wall.
    pub fn wall(m: &SolidMaterial, dp: Real) -> Self {
        Moduli {
            e: m.youngs / (1.0 - m.poisson * m.poisson),
            g: m.shear / (2.0 - m.poisson),
            r: 0.5 * dp,
        }
    }
    /// Two particles of solids a and b.
    pub fn pair(a: &SolidMaterial, b: &SolidMaterial, dp: Real) -> Self {
        let inv_e =
            (1.0 - a.poisson * a.poisson) / a.youngs + (1.0 - b.poisson * b.poisson) / b.youngs;
        let inv_g = (2.0 - a.poisson) / a.shear + (2.0 - b.poisson) / b.shear;
        Moduli {
            e: 1.0 / inv_e,
            g: 1.0 / inv_g,
            r: 0.25 * dp,
        }
    }
}

impl ContactLaw {
    pub fn from_spec(c: &ContactSpec, dp: Real, dim: usize) -> Self {
        let le = c.restitution.ln();
        let gamma = match c.model {
            ContactModel::SpringDashpot => damping_ratio_for_restitution(c.restitution),
            ContactModel::HertzMindlin => {
                -le / (le * le + std::f64::consts::PI * std::f64::consts::PI).sqrt()
            }
        };
        ContactLaw {
            model: c.model,
            mu: c.friction,
            gamma,
            stiffness: c.stiffness,
            dp,
            dim,
        }
    }

    /// Out-of-plane scale: forces per unit depth in 2D are 3D forces over dp.
    fn depth_scale(&self) -> Real {
        if self.dim == 2 {
            1.0 / self.dp
        } else {
            1.0
        }
    }

    /// Linear normal stiffness k_n = E* dp^(d−2) (or the override).
    pub fn linear_kn(&self, m: &Moduli) -> Real {
        self.stiffness.unwrap_or(m.e * self.dp * self.depth_scale())
    }

    /// Normal stiffness used for the time-step bound (Hertz: at δ = 0.05 dp).
    pub fn reference_kn(&self, m: &Moduli) -> Real {
        match self.model {
            ContactModel::SpringDashpot => self.linear_kn(m),
            ContactModel::HertzMindlin => {
                2.0 * m.e * (m.r * 0.05 * self.dp).sqrt() * self.depth_scale()
            }
        }
    }

    fn springs(&self, m: &Moduli, delta: Real, meff: Real) -> Springs {
        match self.model {
            ContactModel::SpringDashpot => {
                let kn = self.linear_kn(m);
                let kt = kn * (4.0 * m.g / m.e).min(1.0);
                Springs {
                    kn,
                    kt,
                    cn: 2.0 * self.gamma * (meff * kn).sqrt(),
                    ct: 2.0 * self.gamma * (meff * kt).sqrt(),
                }
            }
            ContactModel::HertzMindlin => {
                // Tsuji et al.: F_n = 4/3 E* √R* δ^{3/2}, S_n = 2E*√(R*δ), S_t = 8G*√(R*δ)
                let a = (m.r * delta).sqrt() * self.depth_scale();
                let sn = 2.0 * m.e * a;
                let st = 8.0 * m.g * a;
                let c = 2.0 * (5.0_f64 / 6.0).sqrt() * self.gamma;
                Springs {
                    kn: 2.0 / 3.0 * sn,
                    kt: st,
                    cn: c * (meff * sn).sqrt(),
                    ct: c * (meff * st).sqrt(),
                }
            }
        }
    }

    /// Force on side 1 of a contact with overlap δ > 0, unit normal `n` (pointing to
    /// side 1), relative velocity `vrel` = v1 − v2, effective mass `meff` and
    /// tangential spring `xi` (updated).
    #[allow(clippy::too_many_arguments)]
    pub fn force<const D: usize>(
        &self,
        m: &Moduli,
        delta: Real,
        n: &Vect<D>,
        vrel: &Vect<D>,
        meff: Real,
        xi: &mut Vect<D>,
        dt: Real,
    ) -> (Vect<D>, Real) {
        let s = self.springs(m, delta, meff);
        let vn = vrel.dot(n);
        let fn_ = (s.kn * delta - s.cn * vn).max(0.0);
        let vt = vrel - n * vn;
        // keep the spring in the tangent plane, then stretch it
        *xi -= n * xi.dot(n);
        *xi += vt * dt;
        let mut ft = -(*xi * s.kt) - vt * s.ct;
        let cap = self.mu * fn_;
        let ftn = ft.norm();
        if ftn > cap {
            ft *= if ftn > 0.0 { cap / ftn } else { 0.0 };
            // sliding: the spring holds the Coulomb force
            *xi = if s.kt > 0.0 {
                -ft / s.kt
            } else {
                Vect::<D>::zeros()
            };
        }
        // stored energy: normal spring (Hertz: 2/5 k δ², linear: 1/2 k δ²) + tangential
        let en = match self.model {
            ContactModel::SpringDashpot => 0.5,
            ContactModel::HertzMindlin => 0.4,
        } * s.kn
            * delta
            * delta;
        let et = if s.kt > 0.0 {
            0.5 * s.kt * xi.norm_squared()
        } else {
            0.0
        };
        (n * fn_ + ft, en + et)
    }
}

/// Candidate contacts and their tangential springs.
#[derive(Clone, Debug, Default, serde::Serialize, serde::Deserialize)]
pub struct Contacts<const D: usize> {
    /// (particle, wall object), sorted.
    pub wall: Vec<(u32, u32)>,
    wall_xi: Vec<Vect<D>>,
    /// (i, j), i < j, different bodies, sorted.
    pub pair: Vec<(u32, u32)>,
    pair_xi: Vec<Vect<D>>,
    /// Active contacts per body in the last evaluation.
    pub per_body: Vec<usize>,
    /// Candidates per body.
    pub candidates: Vec<usize>,
    /// Energy stored in the contact springs at the last evaluation.
    pub energy: Real,
    /// Barrier loads from contacts in the last evaluation, one per load slot
    /// (`Walls::load_slots`: one per panel).
    pub wall_loads: Vec<Load>,
    /// Signed distance and outward normal of each wall candidate (normal only when
    /// touching), from the first pass of `evaluate`.
    wall_gap: Vec<(Real, Vect<D>)>,
    /// Particle velocities at the previous evaluation (for [`Contacts::vmid`]).
    vel_prev: Vec<Vect<D>>,
    old_keys: Vec<(u32, u32)>,
    old_xi: Vec<Vect<D>>,
    sorted: Vec<(u64, u32)>,
}

/// Keep the springs of contacts that persist from `old` into `new`.
fn carry<const D: usize>(
    old: &[(u32, u32)],
    old_xi: &[Vect<D>],
    new: &[(u32, u32)],
    out: &mut Vec<Vect<D>>,
) {
    out.clear();
    let mut a = 0;
    for k in new {
        while a < old.len() && old[a] < *k {
            a += 1;
        }
        out.push(if a < old.len() && old[a] == *k {
            old_xi[a]
        } else {
            Vect::<D>::zeros()
        });
    }
}

/// The key of the cell of side `cell` that holds `x`, shifted by `off` cells: its
/// coordinates, wrapped to 21 bits each, packed into one integer.
fn cell_key<const D: usize>(x: &Vect<D>, cell: Real, off: [i64; 3]) -> u64 {
    let mut k = 0u64;
    for a in 0..D {
        let c = ((x[a] / cell).floor() as i64 + off[a]).rem_euclid(1 << 21) as u64;
        k = (k << 21) | c;
    }
    k
}

impl<const D: usize> Contacts<D> {
    /// Whether these candidates, restored from a state, fit `particles` coarse
    /// particles, `objects` wall objects and `bodies` bodies: particle–wall candidates
    /// of existing particles and objects, pairs i < j of existing particles, a spring per
    /// candidate, and per-body counts of every body (or none yet).
    pub fn restored_fits(&self, particles: usize, objects: usize, bodies: usize) -> bool {
        let counts = |l: usize| l == bodies || l == 0;
        self.wall
            .iter()
            .all(|&(i, o)| (i as usize) < particles && (o as usize) < objects)
            && self
                .pair
                .iter()
                .all(|&(i, j)| i < j && (j as usize) < particles)
            && self.wall_xi.len() == self.wall.len()
            && self.pair_xi.len() == self.pair.len()
            && (self.wall_gap.len() == self.wall.len() || self.wall_gap.is_empty())
            && counts(self.per_body.len())
            && counts(self.candidates.len())
    }

    /// Find candidates within `margin` of touching.
    pub fn find(
        &mut self,
        p: &CoarseParticles<D>,
        bodies: &[Body<D>],
        walls: &Walls<D>,
        dp: Real,
        margin: Real,
    ) {
        let rp = 0.5 * dp;
        self.find_walls(p, bodies, walls, (rp, margin));
        self.find_pairs(p, bodies, dp + margin);
        self.count_candidates(p, bodies.len());
    }

    /// The particle–wall candidates: every surface particle of a free body within
    /// `margin` of touching a wall of a shape (contact radius `rp`), with the springs
    /// of those that persist.
    fn find_walls(
        &mut self,
        p: &CoarseParticles<D>,
        bodies: &[Body<D>],
        walls: &Walls<D>,
        (rp, margin): (Real, Real),
    ) {
        self.old_keys.clear();
        self.old_keys.extend_from_slice(&self.wall);
        self.old_xi.clear();
        self.old_xi.extend_from_slice(&self.wall_xi);
        self.wall.clear();
        for i in 0..p.len() {
            if !p.surface[i] || bodies[p.body[i] as usize].fixed {
                continue;
            }
            for (o, obj) in walls.objects.iter().enumerate() {
                if let Some(shape) = &obj.shape {
                    let d = shape.sdf(&(p.pos[i] - obj.displacement));
                    if d < rp + margin {
                        self.wall.push((i as u32, o as u32));
                    }
                }
            }
        }
        let (ok, ox) = (
            std::mem::take(&mut self.old_keys),
            std::mem::take(&mut self.old_xi),
        );
        carry(&ok, &ox, &self.wall, &mut self.wall_xi);
        self.old_keys = ok;
        self.old_xi = ox;
    }

    /// The particle–particle candidates of different bodies, not both fixed, closer
    /// than `cell` (dp plus the margin), found by sorting the surface particles by
    /// cell; with the springs of those that persist.
    fn find_pairs(&mut self, p: &CoarseParticles<D>, bodies: &[Body<D>], cell: Real) {
        self.sorted.clear();
        for i in 0..p.len() {
            if p.surface[i] {
                self.sorted
                    .push((cell_key(&p.pos[i], cell, [0; 3]), i as u32));
            }
        }
        self.sorted.sort_unstable();
        self.old_keys.clear();
        self.old_keys.extend_from_slice(&self.pair);
        self.old_xi.clear();
        self.old_xi.extend_from_slice(&self.pair_xi);
        self.pair.clear();
        let r2 = cell * cell;
        let zr = if D == 3 { -1..=1 } else { 0..=0 };
        for &(_, i) in &self.sorted {
            let xi = p.pos[i as usize];
            let bi = p.body[i as usize];
            for dz in zr.clone() {
                for dy in -1..=1i64 {
                    for dx in -1..=1i64 {
                        let k = cell_key(&xi, cell, [dx, dy, dz]);
                        let s = self.sorted.partition_point(|e| e.0 < k);
                        for &(kk, j) in &self.sorted[s..] {
                            if kk != k {
                                break;
                            }
                            let bj = p.body[j as usize];
                            if j <= i || bj == bi {
                                continue;
                            }
                            if bodies[bi as usize].fixed && bodies[bj as usize].fixed {
                                continue;
                            }
                            if (xi - p.pos[j as usize]).norm_squared() < r2 {
                                self.pair.push((i, j));
                            }
                        }
                    }
                }
            }
        }
        self.pair.sort_unstable();
        let (ok, ox) = (
            std::mem::take(&mut self.old_keys),
            std::mem::take(&mut self.old_xi),
        );
        carry(&ok, &ox, &self.pair, &mut self.pair_xi);
        self.old_keys = ok;
        self.old_xi = ox;
    }

    /// The candidates of each of the `n_bodies` bodies, walls and pairs together.
    fn count_candidates(&mut self, p: &CoarseParticles<D>, n_bodies: usize) {
        self.candidates.clear();
        self.candidates.resize(n_bodies, 0);
        for &(i, _) in &self.wall {
            self.candidates[p.body[i as usize] as usize] += 1;
        }
        for &(i, j) in &self.pair {
            self.candidates[p.body[i as usize] as usize] += 1;
            self.candidates[p.body[j as usize] as usize] += 1;
        }
    }

    /// Effective mass of particle `i` in a contact: a rigid body's mass shared by its
    /// active contacts, or the particle's own mass in an elastic body.
    fn meff(&self, p: &CoarseParticles<D>, bodies: &[Body<D>], i: usize) -> Real {
        let b = &bodies[p.body[i] as usize];
        if b.is_rigid() {
            if b.fixed {
                Real::INFINITY
            } else {
                b.mass / self.per_body[p.body[i] as usize].max(1) as Real
            }
        } else {
            p.mass[i]
        }
    }

    /// Contact forces into `p.f_contact`; loads on barrier panels into `wall_loads`.
    ///
    /// Two passes: the overlaps first, so that a rigid body's mass is shared among the
    /// contacts active now (a lagged count would give every contact of a body landing
    /// flat the whole mass, and its dashpots together an explicit damping rate far
    /// past the stable limit), then the forces.
    #[allow(clippy::too_many_arguments)]
    pub fn evaluate(
        &mut self,
        p: &mut CoarseParticles<D>,
        bodies: &[Body<D>],
        solids: &[SolidMaterial],
        walls: &Walls<D>,
        law: &ContactLaw,
        dt: Real,
    ) {
        for f in &mut p.f_contact {
            *f = Vect::<D>::zeros();
        }
        self.count_active(p, bodies.len(), walls, law.dp);
        let energy = self.wall_forces(p, bodies, solids, walls, law, dt);
        self.energy = self.pair_forces(p, (bodies, solids), law, dt, energy);
        self.vel_prev.clear();
        self.vel_prev.extend_from_slice(&p.vel);
    }

    /// The first pass of [`Contacts::evaluate`]: the active contacts of each of the
    /// `n_bodies` bodies now (particle spacing `dp`), and the signed distance and
    /// outward normal (only when touching) of each wall candidate.
    fn count_active(
        &mut self,
        p: &CoarseParticles<D>,
        n_bodies: usize,
        walls: &Walls<D>,
        dp: Real,
    ) {
        let rp = 0.5 * dp;
        self.per_body.clear();
        self.per_body.resize(n_bodies, 0);
        self.wall_gap.clear();
        for &(i, o) in &self.wall {
            let (i, o) = (i as usize, o as usize);
            let obj = &walls.objects[o];
            let gap = match &obj.shape {
                Some(shape) => {
                    let x = p.pos[i] - obj.displacement;
                    let d = shape.sdf(&x);
                    if d < rp {
                        self.per_body[p.body[i] as usize] += 1;
                        (d, shape.normal(&x, 1e-4 * dp))
                    } else {
                        (d, Vect::<D>::zeros())
                    }
                }
                None => (Real::INFINITY, Vect::<D>::zeros()),
            };
            self.wall_gap.push(gap);
        }
        for &(i, j) in &self.pair {
            let (i, j) = (i as usize, j as usize);
            let r2 = (p.pos[i] - p.pos[j]).norm_squared();
            if r2 < dp * dp && r2 > 0.0 {
                self.per_body[p.body[i] as usize] += 1;
                self.per_body[p.body[j] as usize] += 1;
            }
        }
    }

    /// The particle–wall forces into `p.f_contact` and the barrier panels' loads into
    /// `wall_loads`; returns the energy stored in their springs, summed in candidate
    /// order.
    fn wall_forces(
        &mut self,
        p: &mut CoarseParticles<D>,
        bodies: &[Body<D>],
        solids: &[SolidMaterial],
        walls: &Walls<D>,
        law: &ContactLaw,
        dt: Real,
    ) -> Real {
        let rp = 0.5 * law.dp;
        self.wall_loads.clear();
        self.wall_loads.resize(walls.load_slots(), Load::default());
        let mut energy = 0.0;
        for (c, &(i, o)) in self.wall.iter().enumerate() {
            let (i, o) = (i as usize, o as usize);
            let obj = &walls.objects[o];
            let (d, n) = self.wall_gap[c];
            let delta = rp - d;
            if delta <= 0.0 {
                self.wall_xi[c] = Vect::<D>::zeros();
                continue;
            }
            let x = p.pos[i] - obj.displacement;
            let m = Moduli::wall(&solids[bodies[p.body[i] as usize].material], law.dp);
            let meff = self.meff(p, bodies, i);
            let vrel = self.vmid(p, i) - obj.velocity;
            let (f, e) = law.force(&m, delta, &n, &vrel, meff, &mut self.wall_xi[c], dt);
            energy += e;
            p.f_contact[i] += f;
            if let Some(b) = obj.barrier {
                let bar = &walls.barriers[b];
                let arm = to3(&(p.pos[i] - n * d - bar.reference));
                let fw = -to3(&f);
                let slot = bar.slot0 + bar.panel_of(&(x - n * d));
                self.wall_loads[slot].force += fw;
                self.wall_loads[slot].moment += arm.cross(&fw);
            }
        }
        energy
    }

    /// The particle–particle forces into `p.f_contact`; returns `energy` plus the
    /// energy stored in their springs, added in candidate order.
    fn pair_forces(
        &mut self,
        p: &mut CoarseParticles<D>,
        (bodies, solids): (&[Body<D>], &[SolidMaterial]),
        law: &ContactLaw,
        dt: Real,
        mut energy: Real,
    ) -> Real {
        for (c, &(i, j)) in self.pair.iter().enumerate() {
            let (i, j) = (i as usize, j as usize);
            let rij = p.pos[i] - p.pos[j];
            let r = rij.norm();
            let delta = law.dp - r;
            if delta <= 0.0 || r == 0.0 {
                self.pair_xi[c] = Vect::<D>::zeros();
                continue;
            }
            let n = rij / r;
            let (bi, bj) = (p.body[i] as usize, p.body[j] as usize);
            let m = Moduli::pair(
                &solids[bodies[bi].material],
                &solids[bodies[bj].material],
                law.dp,
            );
            let (mi, mj) = (self.meff(p, bodies, i), self.meff(p, bodies, j));
            let meff = if mi.is_infinite() {
                mj
            } else if mj.is_infinite() {
                mi
            } else {
                mi * mj / (mi + mj)
            };
            let vrel = self.vmid(p, i) - self.vmid(p, j);
            let (f, e) = law.force(&m, delta, &n, &vrel, meff, &mut self.pair_xi[c], dt);
            energy += e;
            p.f_contact[i] += f;
            p.f_contact[j] -= f;
        }
        energy
    }

    /// Velocity of particle `i` at the middle of the sub-step, where the overlap is
    /// taken, extrapolated from the last two sub-steps (v + ½(v − v_prev)). The
    /// dashpot then sees the velocity that goes with the overlap, and the rebound
    /// converges to e at second order in the sub-step instead of first.
    #[inline]
    fn vmid(&self, p: &CoarseParticles<D>, i: usize) -> Vect<D> {
        match self.vel_prev.get(i) {
            Some(v0) => p.vel[i] * 1.5 - v0 * 0.5,
            None => p.vel[i],
        }
    }

    /// Largest sub-step for the candidate contacts: ½ CFL / ω with ω² = n k / M for a
    /// rigid body with n candidates (at least one, so that a body in free flight never
    /// steps further than a first contact allows), 2k/m for an elastic particle. At the
    /// default CFL 0.4 a collision lasts about 16 sub-steps (π/ω), which resolves the
    /// dashpot's restitution to within a few per cent (`tests/contact_restitution.rs`).
    pub fn stable_dt(
        &self,
        p: &CoarseParticles<D>,
        bodies: &[Body<D>],
        solids: &[SolidMaterial],
        law: &ContactLaw,
        cfl: Real,
    ) -> Real {
        let mut w2max: Real = 0.0;
        for (b, body) in bodies.iter().enumerate() {
            let n = self.candidates.get(b).copied().unwrap_or(0);
            if body.fixed || (n == 0 && !body.is_rigid()) {
                continue;
            }
            let n = n.max(1);
            let m = &solids[body.material];
            let k = law.reference_kn(&Moduli::wall(m, law.dp));
            let w2 = if body.is_rigid() {
                n as Real * k / body.mass
            } else {
                2.0 * k / p.mass[body.start]
            };
            w2max = w2max.max(w2);
        }
        if w2max > 0.0 {
            0.5 * cfl / w2max.sqrt()
        } else {
            Real::INFINITY
        }
    }
}
