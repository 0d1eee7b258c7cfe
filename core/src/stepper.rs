//! The fine-grain step: position-based Verlet (Eqs. 54–56) assembled from the stages
//! this scene needs. The stepper holds scratch memory; the world holds state.

use crate::coarse::coupling::{self, CoarseSource, Coupling};
use crate::coarse::stepper::CoarseStepper;
use crate::fine::artificial_stress::gray2001_artificial_stress;
use crate::fine::continuity::{continuity_sweep, ContinuityOut, ContinuityParams, JumpDiffusion};
use crate::fine::material::uniform_acoustics;
use crate::fine::momentum::{momentum_sweep, ArtificialStress, CoarseSide, MomentumParams};
use crate::fine::pair_sums::PairSums;
use crate::fine::source::{drift_and_pack, pack, Source};
use crate::fine::state::PermuteScratch;
use crate::guard::{Blowup, ChunkFailure};
use crate::kernel::WendlandC2;
use crate::load::Load;
use crate::math::{Real, Sym, Vect};
use crate::neighbors::{Binned, CellGrid, NeighborLists, CHUNK};
use crate::riemann::Riemann;
use crate::scene::{ContinuityJump, Scene, TimeStepping, WallStress};
use crate::timers::{Stage, StageTimers};
use crate::world::{geostatic_tensor, World};
use rayon::prelude::*;

/// Method parameters of one run (one struct per subsystem; defaults from seed 000).
#[derive(Clone, Debug, serde::Serialize, serde::Deserialize)]
pub struct StepParams {
    /// Smoothing length h = smoothing_ratio · dp (1.3 dp).
    pub h: Real,
    /// CFL number of Eq. (51).
    pub cfl: Real,
    /// Limiter coefficient η of Eq. (23).
    pub eta: Real,
    /// Stress-diffusion ζ of Eq. (25).
    pub zeta: Real,
    /// ξ of the hourglass penalty (0: off).
    pub hourglass: Real,
    /// Relaxation time of the stored penalty, in acoustic times h/c0.
    pub hourglass_memory: Real,
    /// Gravity ramp time (s); 0: full gravity from the start.
    pub gravity_ramp: Real,
    /// Verlet skin (m).
    pub skin: Real,
    /// Speed bound of the stability guard (m/s).
    pub max_speed: Real,
    /// Artificial stress (n, ε), only with cohesive materials.
    pub artificial: Option<(Real, Real)>,
    /// Coulomb coefficient between coarse and fine grains, μ_cf.
    pub mu_cf: Real,
    /// Coulomb coefficient of fine grains on walls (0: off).
    pub wall_friction: Real,
    /// Multi-rate (κ coarse sub-steps per fine step) or single-rate.
    pub scheme: TimeStepping,
    /// Pressure of the continuity equation's jump term.
    pub continuity_jump: ContinuityJump,
    /// Deviatoric stress of the dummy wall particles.
    pub wall_stress: WallStress,
}

impl StepParams {
    pub fn from_scene(s: &Scene) -> Self {
        let d = s.simulation.dimension as Real;
        let n = &s.numerics;
        let cohesive = s.materials.iter().any(|m| m.cohesion > 0.0);
        StepParams {
            h: n.smoothing_ratio * s.simulation.dp,
            cfl: s.simulation.cfl,
            eta: n.eta.unwrap_or(20.0 * d),
            zeta: n.stress_diffusion,
            hourglass: n.hourglass,
            hourglass_memory: n.hourglass_memory,
            gravity_ramp: s.simulation.gravity_ramp,
            skin: n.neighbor_skin * s.simulation.dp,
            max_speed: s.simulation.max_speed,
            artificial: cohesive
                .then_some((n.artificial_stress_exponent, n.artificial_stress_epsilon)),
            mu_cf: s.contact.mu_cf,
            wall_friction: n.wall_friction,
            scheme: s.simulation.time_stepping,
            continuity_jump: n.continuity_jump,
            wall_stress: n.wall_stress,
        }
    }
}

/// Statistics of one step.
#[derive(Clone, Copy, Debug, Default)]
pub struct StepStats {
    pub vmax: Real,
    pub rebuilt: bool,
    /// Coarse sub-steps in this step.
    pub kappa: usize,
}

/// Step size and sub-step count of one fine step (Eqs. 51–53).
///
/// Multi-rate: Δt = min(Δt_f, `max_dt`) and κ = ⌈Δt/Δt_c⌉; when the two steps are
/// within 25 % of each other, κ = 1 and Δt = min(Δt, Δt_c) instead. Single-rate:
/// Δt = min(Δt_f, Δt_c, `max_dt`), κ = 1 (Eq. 53). Without fine grains the step is the
/// coarse one.
pub fn choose_step(dt_f: Real, dt_c: Real, max_dt: Real, scheme: TimeStepping) -> (Real, usize) {
    let single = dt_f.min(dt_c).min(max_dt);
    if scheme == TimeStepping::SingleRate || !dt_f.is_finite() || !dt_c.is_finite() {
        return (single, 1);
    }
    let dt = dt_f.min(max_dt);
    let r = dt / dt_c;
    if r <= 1.25 {
        (single, 1)
    } else {
        (dt, r.ceil() as usize)
    }
}

/// Scratch memory and stage assembly for the fine step.
#[derive(Clone, serde::Serialize, serde::Deserialize)]
pub struct Stepper<const D: usize> {
    pub params: StepParams,
    pub kernel: WendlandC2,
    /// Binned afresh at every list build: a serialised state keeps only its geometry.
    #[serde(with = "crate::neighbors::geometry_only")]
    fine_grid: CellGrid<D>,
    /// Binned when the walls moved since the last build: serialised in full.
    wall_grid: CellGrid<D>,
    pub lists: NeighborLists,
    /// Positions at the last list build, in single precision: only displacements
    /// since then are read from them, and `round_off` bounds the rounding.
    pos_at_build: Vec<nalgebra::SVector<f32, D>>,
    /// Largest rounding error of a position stored in `pos_at_build` (m).
    round_off: Real,
    wall_disp_at_build: Vec<Vect<D>>,
    walls_binned: bool,
    /// Largest displacement since the last list build (end of last step).
    max_disp: Real,
    vmax: Real,
    /// Scratch: written in full by every step before it is read (not serialised).
    #[serde(skip)]
    vel_new: Vec<Vect<D>>,
    #[serde(skip)]
    art: Vec<Sym>,
    #[serde(skip)]
    src: Vec<Source>,
    #[serde(skip)]
    chunk_loads: Vec<Load>,
    /// Load on each barrier during the last step.
    pub step_loads: Vec<Load>,
    /// Fine-grain load on each barrier panel during the last step (`Walls::load_slot`).
    pub slot_loads: Vec<Load>,
    /// Scratch: written in full by every step before it is read (not serialised).
    #[serde(skip)]
    permute: PermuteScratch,
    #[serde(skip)]
    order: Vec<u32>,
    /// Pair sums of the two sweeps (zero between steps, so a restored state starts
    /// them from an empty buffer that the step fills with zeros).
    #[serde(skip)]
    pair_sums: Vec<PairSums<D>>,
    geostatic: Vec<Sym>,
    /// Per material: the geostatic pressure gradient of this step (ramp applied).
    #[serde(skip)]
    geostatic_pressure: Vec<Real>,
    /// Per material: ξ G of the hourglass penalty (empty: off).
    hourglass: Vec<Real>,
    /// Per material: share of the stored penalty kept over this step (set per step).
    hourglass_leak: Vec<f32>,
    /// Per material: the grain–boulder interface carries tension (c > 0).
    tension: Vec<bool>,
    /// All fine materials share one impedance and sound speed (fixed for a run).
    uniform: bool,
    /// The scene's full gravity, and the ramp factor of the current step.
    g_full: Vect<D>,
    g_scale: Real,
    up: Vect<D>,
    /// Wall-clock time per stage (a restored state starts them at zero).
    #[serde(skip)]
    pub timers: StageTimers,
    /// Stages left out for this scene, with the reason.
    pub skipped: Vec<(String, String)>,
    #[serde(skip)]
    failures: Vec<(Real, Real, ChunkFailure)>,
    /// Coarse grains: sub-stepper (None without bodies).
    pub coarse: Option<CoarseStepper<D>>,
    csrc: Vec<CoarseSource<D>>,
    #[serde(with = "crate::neighbors::geometry_only")]
    coarse_grid: CellGrid<D>,
    coarse_at_build: Vec<Vect<D>>,
    reactions: Vec<Vec<(u32, Vect<D>)>>,
    coarse_vol: Real,
}

impl<const D: usize> Stepper<D> {
    pub fn new(world: &World<D>, scene: &Scene, params: StepParams) -> Self {
        let kernel = WendlandC2::new(params.h, D);
        let g = world.gravity.norm();
        let up = if g > 0.0 {
            -world.gravity / g
        } else {
            Vect::<D>::zeros()
        };
        let geostatic = world
            .materials
            .iter()
            .map(|m| geostatic_tensor::<D>(&up, m.k0).scale(m.rho0 * g))
            .collect();
        let hourglass = if params.hourglass > 0.0 {
            world
                .materials
                .iter()
                .map(|m| params.hourglass * m.shear)
                .collect()
        } else {
            Vec::new()
        };
        let tension = world.materials.iter().map(|m| m.cohesion > 0.0).collect();
        let cell = kernel.cutoff + params.skin;
        let mut skipped = Vec::new();
        if params.artificial.is_none() {
            skipped.push((
                "artificial_stress".into(),
                "no cohesive material (c = 0)".into(),
            ));
        }
        if params.zeta == 0.0 {
            skipped.push((
                "stress_diffusion".into(),
                "numerics.stress_diffusion = 0".into(),
            ));
        }
        if world.walls.is_empty() {
            skipped.push(("wall_boundary".into(), "scene has no walls".into()));
        } else if world.walls.barriers.is_empty() {
            skipped.push(("barrier_loads".into(), "scene has no barriers".into()));
        }
        let coarse = (!world.coarse.is_empty())
            .then(|| CoarseStepper::new(&world.coarse, scene, &world.gravity));
        if coarse.is_none() {
            skipped.push((
                "coarse_substeps".into(),
                "scene has no coarse grains".into(),
            ));
            skipped.push(("contact".into(), "scene has no coarse grains".into()));
        }
        if coarse.is_none() || world.fine.is_empty() {
            skipped.push((
                "coupling".into(),
                "needs both fine and coarse grains".into(),
            ));
        }
        if world.fine.is_empty() {
            skipped.push(("fine_grains".into(), "scene has no fine grains".into()));
        }
        let nb = world.walls.barriers.len();
        Stepper {
            fine_grid: CellGrid::new(&world.domain.0, &world.domain.1, cell),
            wall_grid: CellGrid::new(&world.domain.0, &world.domain.1, cell),
            params,
            kernel,
            lists: NeighborLists::default(),
            pos_at_build: Vec::new(),
            round_off: 0.0,
            wall_disp_at_build: Vec::new(),
            walls_binned: false,
            max_disp: Real::INFINITY,
            vmax: 0.0,
            vel_new: Vec::new(),
            art: Vec::new(),
            src: Vec::new(),
            chunk_loads: Vec::new(),
            step_loads: vec![Load::default(); nb],
            slot_loads: vec![Load::default(); world.walls.load_slots()],
            permute: PermuteScratch::default(),
            order: Vec::new(),
            pair_sums: Vec::new(),
            geostatic,
            geostatic_pressure: Vec::new(),
            hourglass_leak: vec![1.0; hourglass.len()],
            hourglass,
            tension,
            uniform: uniform_acoustics(&world.materials),
            g_full: world.gravity,
            g_scale: 1.0,
            up,
            timers: StageTimers::default(),
            skipped,
            failures: Vec::new(),
            coarse,
            csrc: Vec::new(),
            coarse_grid: CellGrid::new(&world.domain.0, &world.domain.1, cell),
            coarse_at_build: Vec::new(),
            reactions: Vec::new(),
            coarse_vol: world.dp.powi(D as i32),
        }
    }

    /// Find the coarse contact candidates for a step of about `dt`, then return Δt_c
    /// (infinite without coarse grains).
    pub fn coarse_dt(&mut self, world: &World<D>, dt: Real) -> Real {
        match &mut self.coarse {
            Some(c) => {
                let t = std::time::Instant::now();
                c.prepare(&world.coarse, &world.walls, dt);
                self.timers.add(Stage::Contact, t.elapsed().as_secs_f64());
                c.stable_dt(&world.coarse)
            }
            None => Real::INFINITY,
        }
    }

    /// Δt of Eq. (51) for the current state: CFL · h / (c0 + |v|max).
    pub fn stable_dt(&self, world: &World<D>) -> Real {
        if world.fine.is_empty() {
            return Real::INFINITY;
        }
        self.params.cfl * self.params.h / (world.max_c0() + self.vmax)
    }

    /// Bytes of scratch memory held by the stepper (lists, buffers, grids).
    pub fn bytes(&self) -> usize {
        use std::mem::size_of;
        self.lists.bytes()
            + self.pos_at_build.capacity() * size_of::<nalgebra::SVector<f32, D>>()
            + self.vel_new.capacity() * size_of::<Vect<D>>()
            + self.art.capacity() * size_of::<Sym>()
            + self.src.capacity() * size_of::<Source>()
            + self.order.capacity() * 4
            + self.pair_sums.capacity() * size_of::<PairSums<D>>()
            + self.fine_grid.bytes()
            + self.wall_grid.bytes()
    }

    /// Largest particle speed at the end of the last step.
    pub fn vmax(&self) -> Real {
        self.vmax
    }

    fn needs_rebuild(&self, world: &World<D>, dt: Real) -> bool {
        if self.lists.chunks.is_empty() && !world.fine.is_empty() {
            return true;
        }
        if world.fine.is_empty() {
            return false;
        }
        let fine = self.max_disp + 0.5 * dt * self.vmax;
        let wall = world.walls.max_displacement_since(&self.wall_disp_at_build);
        let coarse = self
            .csrc
            .iter()
            .zip(&self.coarse_at_build)
            .map(|(c, b)| (c.pos - b).norm_squared())
            .fold(0.0, Real::max)
            .sqrt();
        2.0 * fine > self.params.skin
            || fine + wall > self.params.skin
            || fine + coarse > self.params.skin
            || self.coarse_at_build.len() != self.csrc.len()
    }

    /// Re-sort particles by cell and rebuild the Verlet lists.
    fn rebuild(&mut self, world: &mut World<D>) {
        self.fine_grid.bin(&world.fine.pos);
        self.order.clear();
        self.order.extend_from_slice(self.fine_grid.order());
        world.fine.permute(&self.order, &mut self.permute);
        self.fine_grid.bin(&world.fine.pos);
        self.pos_at_build.clear();
        self.pos_at_build
            .par_extend(world.fine.pos.par_iter().map(|x| x.cast::<f32>()));
        // |x − (f32)x| ≤ ½ ulp ≤ |x| ε_f32 / 2 per component
        let reach = world
            .fine
            .pos
            .par_iter()
            .map(|x| x.amax())
            .reduce(|| 0.0, Real::max);
        self.round_off = reach * (f32::EPSILON as Real) * (D as Real).sqrt();
        let walls_moved = world
            .walls
            .objects
            .iter()
            .zip(&self.wall_disp_at_build)
            .any(|(o, d)| o.displacement != *d);
        if !self.walls_binned || walls_moved {
            self.wall_grid.bin(&world.walls.pos);
            self.walls_binned = true;
        }
        self.wall_disp_at_build.clear();
        self.wall_disp_at_build
            .extend(world.walls.objects.iter().map(|o| o.displacement));
        self.coarse_at_build.clear();
        self.coarse_at_build.extend(self.csrc.iter().map(|c| c.pos));
        self.coarse_grid.bin(&self.coarse_at_build);
        let radius = self.kernel.cutoff + self.params.skin;
        self.lists.build(
            &world.fine.pos,
            &self.fine_grid,
            Binned {
                pos: &world.walls.pos,
                grid: &self.wall_grid,
            },
            Binned {
                pos: &self.coarse_at_build,
                grid: &self.coarse_grid,
            },
            radius,
        );
        self.reactions
            .resize_with(self.lists.chunks.len(), Vec::new);
        self.max_disp = 0.0;
    }

    /// Advance the world by one fine step of size `dt` with `kappa` coarse sub-steps.
    pub fn step(
        &mut self,
        world: &mut World<D>,
        dt: Real,
        kappa: usize,
    ) -> Result<StepStats, Blowup> {
        let n = world.fine.len();
        let half = 0.5 * dt;
        world.walls.set_time(world.time);
        self.g_scale = gravity_ramp(world.time + half, self.params.gravity_ramp);
        world.gravity = self.g_full * self.g_scale;
        if let Some(c) = self.coarse.as_mut() {
            c.set_gravity(&world.gravity);
        }
        if let Some(c) = self.coarse.as_ref().filter(|_| n > 0) {
            let t = std::time::Instant::now();
            c.update_normals(&mut world.coarse);
            let wc = &world.coarse;
            coupling::pack(
                &wc.particles,
                &wc.bodies,
                &wc.solids,
                dt,
                self.coarse_vol,
                &mut self.csrc,
            );
            self.timers.add(Stage::Coupling, t.elapsed().as_secs_f64());
        }
        // Eq. (54): positions and density to the half step, packed for the sweeps.
        {
            let (fine, mats, src) = (&mut world.fine, &world.materials, &mut self.src);
            let walls = &mut world.walls;
            self.timers.time(Stage::Drift, || {
                drift_and_pack(fine, mats, half, src);
                walls.advance(half);
            });
        }
        let mut rebuilt = false;
        if self.needs_rebuild(world, dt) {
            let t = std::time::Instant::now();
            self.rebuild(world);
            pack(&world.fine, &world.materials, &mut self.src);
            self.timers.add(Stage::Neighbors, t.elapsed().as_secs_f64());
            rebuilt = true;
        }
        self.vel_new.resize(n, Vect::<D>::zeros());
        // the sweeps leave their sums zero, so only new entries need setting
        self.pair_sums.resize(n, PairSums::zero());
        let nbs = world.walls.load_slots().max(1);
        self.chunk_loads
            .resize(self.lists.chunks.len() * nbs, Load::default());

        let artificial = self.params.artificial.map(|(exponent, eps)| {
            let art = &mut self.art;
            let stress = &world.fine.stress;
            self.timers.time(Stage::ArtificialStress, || {
                art.clear();
                art.par_extend(
                    stress
                        .par_iter()
                        .map(|s| gray2001_artificial_stress::<D>(s, eps)),
                );
            });
            ArtificialStress {
                exponent,
                w_dp: self.kernel.w(world.dp),
            }
        });

        // the stored penalty relaxes over `hourglass_memory` acoustic times h/c0
        let memory = self.params.hourglass_memory * self.params.h;
        for (k, m) in self.hourglass_leak.iter_mut().zip(&world.materials) {
            *k = (-dt * m.c0 / memory).exp() as f32;
        }
        // the continuity sweep's parameters: its terms without velocity are taken in
        // the momentum sweep's pair pass
        self.geostatic_pressure.clear();
        self.geostatic_pressure.extend(
            self.geostatic
                .iter()
                .map(|g| g.scale(self.g_scale).trace() / 3.0),
        );
        let cprm = ContinuityParams {
            kernel: self.kernel,
            gravity: world.gravity,
            dt,
            zeta: self.params.zeta,
            geostatic: &self.geostatic,
            geostatic_pressure: &self.geostatic_pressure,
            geostatic_scale: self.g_scale,
            up: self.up,
            jump: self.params.continuity_jump,
            uniform: self.uniform,
        };
        let jump = JumpDiffusion::new(&cprm);
        // Eqs. (16), (55): v_{n+1}.
        let mprm = MomentumParams {
            kernel: self.kernel,
            riemann: Riemann {
                eta: self.params.eta,
            },
            gravity: world.gravity,
            dt,
            artificial,
            wall_friction: self.params.wall_friction,
            wall_stress: self.params.wall_stress,
            hourglass: &self.hourglass,
            hourglass_leak: &self.hourglass_leak,
            tension: &self.tension,
            materials: &world.materials,
            uniform: self.uniform,
        };
        // updated in place: a particle reads only its own accumulated penalty
        let mut hourglass = std::mem::take(&mut world.fine.hourglass);
        {
            let (fine, walls, lists, art) = (&world.fine, &world.walls, &self.lists, &self.art);
            let (vel_new, loads, src) = (&mut self.vel_new, &mut self.chunk_loads, &mut self.src);
            let sums = &mut self.pair_sums;
            let hg = &mut hourglass;
            let side = CoarseSide {
                src: &self.csrc,
                coupling: Coupling {
                    kernel: self.kernel,
                    riemann: mprm.riemann,
                    mu_cf: self.params.mu_cf,
                    dt,
                    dp: world.dp,
                },
                reactions: &mut self.reactions,
            };
            self.timers.time(Stage::Momentum, || {
                momentum_sweep(
                    fine, src, walls, lists, art, &mprm, vel_new, hg, loads, side, &jump, sums,
                )
            });
        }
        world.fine.hourglass = hourglass;
        if self.coarse.is_some() {
            let t = std::time::Instant::now();
            coupling::gather_reactions(&self.reactions, &mut world.coarse.particles.f_fine);
            self.timers.add(Stage::Coupling, t.elapsed().as_secs_f64());
        }
        std::mem::swap(&mut world.fine.vel, &mut self.vel_new);
        crate::panels::sum_slots(
            &world.walls,
            &self.chunk_loads,
            nbs,
            &mut self.slot_loads,
            &mut self.step_loads,
        );

        // Eqs. (15), (24)–(26), (7)–(12) with v_{n+1}.
        // advanced in place: the sweep reads none of these of a neighbour (the
        // neighbours' stress comes from the packed sources)
        let mut stress = std::mem::take(&mut world.fine.stress);
        let mut drho = std::mem::take(&mut world.fine.drho);
        let mut eps = std::mem::take(&mut world.fine.plastic_strain);
        let mut vel_grad = std::mem::take(&mut world.fine.vel_grad);
        let mut hourglass_kept = std::mem::take(&mut world.fine.hourglass_kept);
        {
            let (fine, walls, lists) = (&world.fine, &world.walls, &self.lists);
            let out = ContinuityOut {
                sums: &mut self.pair_sums,
                drho: &mut drho,
                stress: &mut stress,
                plastic_strain: &mut eps,
                vel_grad: &mut vel_grad,
                hourglass_kept: &mut hourglass_kept,
            };
            let src = &mut self.src;
            let csrc = &self.csrc;
            self.timers.time(Stage::ContinuityStress, || {
                continuity_sweep(fine, src, &world.materials, walls, lists, &cprm, csrc, out)
            });
        }
        world.fine.drho = drho;
        world.fine.stress = stress;
        world.fine.plastic_strain = eps;
        world.fine.vel_grad = vel_grad;
        world.fine.hourglass_kept = hourglass_kept;

        // Eq. (56) and the stability guard.
        let max_speed = self.params.max_speed;
        let failures = &mut self.failures;
        let pos_at_build = &self.pos_at_build;
        self.timers.time(Stage::Finalize, || {
            let f = &mut world.fine;
            f.pos
                .par_chunks_mut(CHUNK)
                .zip(f.rho.par_chunks_mut(CHUNK))
                .zip(f.vel.par_chunks(CHUNK))
                .zip(f.drho.par_chunks(CHUNK))
                .zip(f.stress.par_chunks(CHUNK))
                .zip(pos_at_build.par_chunks(CHUNK))
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
                .collect_into_vec(failures);
            world.walls.advance(half);
        });
        // a step of Δt = 0 (the force pass on the current state,
        // `Simulation::state_loads`) has no coarse sub-step to take
        if let Some(c) = self.coarse.as_mut().filter(|_| dt > 0.0) {
            let t = std::time::Instant::now();
            let (step, time) = (world.steps + 1, world.time + dt);
            c.advance(&mut world.coarse, &world.walls, dt, kappa, step, time)?;
            let secs = t.elapsed().as_secs_f64();
            let contact = std::mem::take(&mut c.contact_secs);
            self.timers.add(Stage::Contact, contact);
            self.timers.add(Stage::CoarseSubsteps, secs - contact);
            for (b, bar) in world.walls.barriers.iter().enumerate() {
                for s in bar.slot0..bar.slot0 + world.walls.panel_count(b) {
                    if let Some(l) = c.wall_loads.get(s) {
                        self.slot_loads[s].add(l);
                        self.step_loads[b].add(l);
                    }
                }
            }
        }
        world.time += dt;
        world.steps += 1;
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
                    position: f.pos[*i].iter().copied().collect(),
                    quantity: q.to_string(),
                    value: *val,
                    limit: speed.then_some(max_speed),
                });
            }
        }
        self.vmax = vmax2.sqrt();
        self.max_disp = disp2.sqrt() + self.round_off;
        Ok(StepStats {
            vmax: self.vmax,
            rebuilt,
            kappa,
        })
    }
}

/// Factor on gravity at time `t` for a ramp of length `ramp`: ½(1 − cos(π t/ramp)),
/// then 1. Smooth (zero rate at both ends), so the ramp excites no wave of its own.
pub fn gravity_ramp(t: Real, ramp: Real) -> Real {
    if ramp > 0.0 && t < ramp {
        0.5 * (1.0 - (std::f64::consts::PI * t / ramp).cos())
    } else {
        1.0
    }
}

#[cfg(test)]
mod ramp_tests {
    use super::gravity_ramp;

    #[test]
    fn gravity_ramp_is_smooth_and_reaches_full_gravity() {
        assert_eq!(gravity_ramp(0.3, 0.0), 1.0);
        assert_eq!(gravity_ramp(0.0, 0.2), 0.0);
        assert!((gravity_ramp(0.1, 0.2) - 0.5).abs() < 1e-15);
        assert!((gravity_ramp(0.2 - 1e-9, 0.2) - 1.0).abs() < 1e-12);
        assert_eq!(gravity_ramp(0.25, 0.2), 1.0);
        // zero rate at the start: the first steps barely load the grains
        assert!(gravity_ramp(0.002, 0.2) < 1e-3);
    }
}
