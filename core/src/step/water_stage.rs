//! The water's stages of a step, on the fine step's Δt and with its position-Verlet
//! scheme (seed 000 Eqs. 54–56 applied to the water): drift to the half step, its own
//! neighbour lists (water–water and water–wall), the momentum sweep (v_{n+1}), the
//! continuity sweep with v_{n+1}, and x, ρ to the end of the step with the guard.

use super::family::{Closing, FamilyLists};
use super::relations::WallRelation;
use super::soil_water_stage::SeepStep;
use crate::coarse::body::Body;
use crate::interactions::fine_coarse::{self, CoarseSource};
use crate::interactions::water_buoyancy::Hydrostatics;
use crate::interactions::water_pass::{
    continuity_pairs, continuity_sweep, correction_and_gradient_sweep, correction_sweep,
    momentum_pairs, momentum_sweep, WaterCoarse,
};
use crate::interactions::water_start::incompressible_start;
use crate::numerics::guard::{Blowup, Family};
use crate::numerics::kernel::WendlandC2;
use crate::numerics::math::{to3, Real, Vect};
use crate::numerics::neighbors::CellGrid;
use crate::numerics::pairs::quad::Lanes;
use crate::numerics::timers::{Stage, StageTimers};
use crate::scene::WallSlip;
use crate::water::correction::Corr;
use crate::water::lanes::WaterLanes;
use crate::water::material::WaterMaterial;
use crate::water::momentum::{WaterParams, WaterSums};
use crate::water::source::{drift_and_pack, pack, WaterSource};
use crate::world::World;
use nalgebra::Vector3;
use std::time::Instant;

/// The water's stepper: the family skeleton ([`FamilyLists`]) and the water's own
/// sources and sweep buffers.
#[derive(Clone, serde::Serialize, serde::Deserialize)]
pub struct WaterStepper<const D: usize> {
    /// Lists, marks, loads and scratch of the family.
    pub family: FamilyLists<D>,
    /// Water steps taken (sub-steps counted).
    #[serde(default)]
    pub steps: u64,
    /// The water has no free surface (found by the incompressible start): its pressure
    /// has no reference level, and walls take its tension as well as its push.
    #[serde(default)]
    pub confined: bool,
    #[serde(skip)]
    src: Vec<WaterSource>,
    #[serde(skip)]
    vel_new: Vec<Vect<D>>,
    #[serde(skip)]
    sums: Vec<WaterSums<D>>,
    #[serde(skip)]
    corr: Vec<Corr<D>>,
    /// Each particle's velocity gradient with `water.muscl` (empty without).
    #[serde(skip)]
    grad: Vec<Corr<D>>,
    /// The sums M and L of the water pairs with `water.muscl` (empty without).
    #[serde(skip)]
    moment_grad: Vec<[Corr<D>; 2]>,
    /// Each particle's acceleration from a soil's seepage force in the last sub-step
    /// (empty without a soil).
    #[serde(skip)]
    body: Vec<Vect<D>>,
    /// The bodies' hydrostatic fields of the sub-step ([`Hydrostatics`]).
    #[serde(skip)]
    hydro: Hydrostatics<D>,
    /// Per chunk: each water–body pair's share of the hydrostatic field on the body.
    #[serde(skip)]
    shares: Vec<Vec<(u32, Vect<D>)>>,
    /// Archimedes' force on each coarse particle in the sub-step.
    #[serde(skip)]
    archimedes: Vec<Vect<D>>,
    /// The cluster-pair passes' packed state and sums.
    #[serde(skip)]
    lanes: WaterLanes<D>,
}

impl<const D: usize> WaterStepper<D> {
    /// Whether this stepper, restored from a state, fits `template` (the scene's as
    /// built) and the water of `n` particles among `walls` wall particles.
    pub fn restored_fits(
        &self,
        template: &Self,
        n: usize,
        walls: usize,
    ) -> Result<(), &'static str> {
        if self.confined != template.confined {
            return Err("water's confinement");
        }
        self.family.restored_fits(&template.family, n, walls)
    }

    /// Lists with cells of `cell` over the world's domain and Verlet skin `skin`.
    pub fn new(world: &World<D>, cell: Real, skin: Real) -> Self {
        let (lo, hi) = &world.domain;
        let grid = || CellGrid::periodic(lo, hi, cell, world.periodic);
        WaterStepper {
            family: FamilyLists::new(
                grid(),
                WallRelation::for_water(grid()),
                (cell, skin),
                (world.walls.barriers.len(), world.walls.load_slots()),
            ),
            steps: 0,
            confined: false,
            src: Vec::new(),
            vel_new: Vec::new(),
            sums: Vec::new(),
            corr: Vec::new(),
            grad: Vec::new(),
            moment_grad: Vec::new(),
            body: Vec::new(),
            hydro: Hydrostatics::default(),
            shares: Vec::new(),
            archimedes: Vec::new(),
            lanes: WaterLanes::default(),
        }
    }

    /// The cells the water was binned in at the last list build.
    pub fn grid(&self) -> &CellGrid<D> {
        self.family.grid()
    }

    /// Largest water speed at the end of the last step.
    pub fn vmax(&self) -> Real {
        self.family.vmax()
    }

    /// Largest stable Δt of the water (acoustic and viscous limits).
    pub fn stable_dt(&self, mat: &WaterMaterial, h: Real, cfl: Real) -> Real {
        mat.stable_dt(h, cfl, self.family.vmax())
    }

    /// Sub-steps κ_w = ⌈Δt/Δt_w⌉ the water needs within a step of `dt` (1 where Δt
    /// is within its stable Δt).
    pub fn substeps(&self, mat: &WaterMaterial, h: Real, cfl: Real, dt: Real) -> usize {
        let dw = self.stable_dt(mat, h, cfl);
        if dt <= dw * (1.0 + 1e-9) {
            1
        } else {
            (dt / dw).ceil() as usize
        }
    }

    /// Bytes of scratch memory held (lists, buffers, grids).
    pub fn bytes(&self) -> usize {
        use std::mem::size_of;
        self.family.bytes()
            + self.vel_new.capacity() * size_of::<Vect<D>>()
            + self.src.capacity() * size_of::<WaterSource>()
            + self.sums.capacity() * size_of::<WaterSums<D>>()
            + self.lanes.bytes()
    }

    /// x and ρ to the half step, and the sources at the half step.
    pub fn drift(
        &mut self,
        world: &mut World<D>,
        mat: &WaterMaterial,
        half: Real,
        t: &mut StageTimers,
    ) {
        t.time(Stage::WaterDriftFinalize, || {
            drift_and_pack(&mut world.water.particles, mat, half, &mut self.src)
        });
    }

    /// Rebuild the lists (particles re-sorted by cell) once the motion since the last
    /// build may have used up the skin over a step of `dt`.
    pub fn refresh_lists(
        &mut self,
        world: &mut World<D>,
        mat: &WaterMaterial,
        csrc: &[CoarseSource<D>],
        dt: Real,
        t: &mut StageTimers,
    ) {
        let start = Instant::now();
        let n = world.water.particles.len();
        if self.family.needs_rebuild(n, &world.walls, csrc, dt) {
            let w = &mut world.water.particles;
            self.family.rebuild(w, &world.walls, csrc, &world.periodic);
            pack(&world.water.particles, mat, &mut self.src);
        }
        t.add(Stage::WaterNeighbors, start.elapsed().as_secs_f64());
    }

    /// Replace the hydrostatic start by the pressure of an incompressible fluid
    /// released at rest ([`incompressible_start`]), on the lists of the first step:
    /// each particle's density from it by the equation of state, at its volume.
    /// Nothing changes where the water has no free surface; such water is confined
    /// ([`confined`](Self::confined)).
    pub fn start_incompressible(
        &mut self,
        world: &mut World<D>,
        mat: &WaterMaterial,
        kernel: WendlandC2,
        csrc: &[CoarseSource<D>],
    ) {
        let prm = water_params(world, mat, kernel, (world.time, 0.0), self.confined);
        let w = &world.water.particles;
        let p0: Vec<Real> = w.rho.iter().map(|&r| mat.pressure(r)).collect();
        let Some(start) = incompressible_start(
            w,
            (|i| w.mass[i] / w.rho[i], &p0),
            (&world.walls, csrc),
            &self.family.lists,
            &prm,
            world.resolution.dp,
        ) else {
            self.confined = true;
            return;
        };
        let w = &mut world.water.particles;
        for (i, p) in start.pressure.iter().enumerate() {
            let rho = mat.density(*p);
            w.mass[i] *= rho / w.rho[i];
            w.rho[i] = rho;
        }
        pack(&world.water.particles, mat, &mut self.src);
    }

    /// The two sweeps of sub-step `s` of `k`, from `t0` to `t0 + dt`: v_{n+1}, then
    /// dρ/dt with v_{n+1}; the water's barrier loads of the sub-step into `step_loads`
    /// and `slot_loads`, and its force on the coarse particles, averaged over the `k`
    /// sub-steps, into their `f_water`. With a soil (`seep`), the seepage drag is
    /// applied to v_{n+1} before the continuity sweep reads it.
    #[allow(clippy::too_many_arguments)]
    pub fn sweeps(
        &mut self,
        world: &mut World<D>,
        mat: &WaterMaterial,
        kernel: WendlandC2,
        csrc: &[CoarseSource<D>],
        (t0, dt): (Real, Real),
        (s, k): (usize, usize),
        seep: Option<SeepStep<'_, D>>,
        t: &mut StageTimers,
    ) {
        let n = world.water.particles.len();
        self.vel_new.resize(n, Vect::<D>::zeros());
        self.sums.resize(n, WaterSums::zero());
        self.family.prepare_pass(&world.walls);
        let prm = water_params(world, mat, kernel, (t0, dt), self.confined);
        let no_slip = mat.wall == WallSlip::NoSlip;
        self.corr.resize(n, Corr::<D>::identity());

        let (lists, chunk_loads, reactions) = self.family.pass_outputs();
        self.shares.resize_with(reactions.len(), Vec::new);
        t.time(Stage::WaterMomentum, || {
            if !csrc.is_empty() {
                let w = &world.water.particles;
                let c = &world.coarse;
                self.hydro.update(
                    (&w.pos, &self.src),
                    (csrc, &c.particles.body, &c.bodies),
                    (lists, &world.walls),
                    (&prm, world.resolution.dp),
                );
            }
            self.lanes
                .pack(&lists.clusters, &world.water.particles, &self.src);
            let lanes = Lanes::detect();
            let w = &world.water.particles;
            let pairs = (&mut self.lanes, &lists.clusters, lanes);
            if mat.muscl {
                // B and the gradient L B, from one walk over the pairs
                self.grad.resize(n, Corr::<D>::zeros());
                self.moment_grad.resize(n, [Corr::<D>::zeros(); 2]);
                correction_and_gradient_sweep(
                    w,
                    &world.walls,
                    csrc,
                    lists,
                    &prm,
                    (mat.correction, pairs),
                    &mut self.moment_grad,
                    (&mut self.corr, &mut self.grad),
                );
            } else {
                let on = (mat.correction, pairs);
                correction_sweep(w, &world.walls, csrc, lists, &prm, on, &mut self.corr);
                self.grad.clear();
                self.moment_grad.clear();
            }
            momentum_pairs(
                (&self.corr, &self.grad),
                &prm,
                (&mut self.lanes, &lists.clusters, lanes),
                &mut self.sums,
            );
            momentum_sweep(
                &world.water.particles,
                &self.src,
                &self.corr,
                &world.walls,
                WaterCoarse {
                    src: csrc,
                    reactions,
                    field: &self.hydro,
                    shares: &mut self.shares,
                },
                lists,
                &prm,
                (no_slip, &self.body),
                &mut self.vel_new,
                chunk_loads,
                &mut self.sums,
            )
        });
        if seep.is_none() {
            self.body.clear();
        }
        if let Some(mut seep) = seep {
            t.time(Stage::SoilWater, || {
                seep.apply(&mut self.vel_new, &self.src, dt, &mut self.body)
            });
        }
        std::mem::swap(&mut world.water.particles.vel, &mut self.vel_new);
        self.after_momentum(world, csrc, (t0, dt), (s, k));
        self.continuity(world, csrc, &prm, t);
    }

    /// After the momentum sweep of sub-step `s` of `k` over (`t0`, `t0 + dt`): the
    /// inlets' water at the inflow speed, the water's force on the coarse particles
    /// (the mean over the sub-steps) and its barrier loads.
    fn after_momentum(
        &mut self,
        world: &mut World<D>,
        csrc: &[CoarseSource<D>],
        (t0, dt): (Real, Real),
        (s, k): (usize, usize),
    ) {
        // the inlets move their water at the inflow speed
        let mid = t0 + 0.5 * dt;
        for f in &world.water.inflows {
            f.drive(
                &world.water.particles.pos,
                &mut world.water.particles.vel,
                mid,
            );
        }
        if !csrc.is_empty() {
            let coarse = &mut world.coarse;
            let f = &mut coarse.particles.f_water;
            if s == 0 {
                f.iter_mut().for_each(|x| *x = Vect::<D>::zeros());
                coarse
                    .bodies
                    .iter_mut()
                    .for_each(|b| b.uplift = Vector3::zeros());
            }
            // the mean over the k sub-steps: the pairs' forces less their share of the
            // hydrostatic fields, and Archimedes' force in its place
            let kk = 1.0 / k as Real;
            fine_coarse::add_reactions(self.family.reactions(), f, kk);
            let mut miss = std::mem::take(&mut self.archimedes);
            let dp = world.resolution.dp;
            let solids = &coarse.solids;
            let volume = |b: &Body<D>| b.mass / solids[b.material].rho0;
            self.hydro.archimedes(&coarse.bodies, volume, dp, &mut miss);
            for (c, a) in miss.iter().enumerate() {
                f[c] += a * kk;
            }
            fine_coarse::add_reactions(&self.shares, f, -kk);
            fine_coarse::add_reactions(&self.shares, &mut miss, -1.0);
            // ΔF_b, what the pairs miss of Archimedes' force: its reaction to the
            // body's gap partners
            for b in coarse.bodies.iter_mut().filter(|b| b.gaps > 0) {
                let df = miss[b.start..b.end]
                    .iter()
                    .fold(Vect::<D>::zeros(), |a, x| a + x);
                b.uplift += to3(&df) * kk;
            }
            self.archimedes = miss;
        }
        self.family.sum_loads(&world.walls);
    }

    /// The continuity sweep with v_{n+1}: dρ/dt of every water particle, held at the
    /// inlets.
    fn continuity(
        &mut self,
        world: &mut World<D>,
        csrc: &[CoarseSource<D>],
        prm: &WaterParams<D>,
        t: &mut StageTimers,
    ) {
        let mut drho = std::mem::take(&mut world.water.particles.drho);
        t.time(Stage::WaterContinuity, || {
            let lists = &self.family.lists;
            continuity_pairs(
                &world.water.particles,
                prm,
                &self.body,
                (&mut self.lanes, &lists.clusters, Lanes::detect()),
                &mut self.sums,
            );
            continuity_sweep(
                &world.water.particles,
                &world.walls,
                csrc,
                lists,
                prm,
                &mut drho,
                &mut self.sums,
            )
        });
        for f in &world.water.inflows {
            f.hold_density(&world.water.particles.pos, &mut drho);
        }
        world.water.particles.drho = drho;
    }

    /// x and ρ to the end of the step (seed 000 Eq. 56, [`FamilyLists::close_step`]).
    pub fn finalize(
        &mut self,
        world: &mut World<D>,
        half: Real,
        max_speed: Real,
        t: &mut StageTimers,
    ) {
        let start = Instant::now();
        let w = &mut world.water.particles;
        let closing = Closing {
            pos: &mut w.pos,
            rho: &mut w.rho,
            vel: &w.vel,
            drho: &w.drho,
            floor: None,
        };
        self.family.close_step(closing, half, max_speed, |_| None);
        t.add(Stage::WaterDriftFinalize, start.elapsed().as_secs_f64());
    }

    /// Stop on the first failing water particle of the step; otherwise keep the
    /// step's largest speed and displacement.
    pub fn guard(&mut self, world: &World<D>, max_speed: Real) -> Result<Real, Blowup> {
        let w = &world.water.particles;
        let at = (world.steps, world.time);
        self.family
            .guard(Family::Water, (&w.id, &w.pos), at, max_speed)
    }
}

/// The water's parameters of a sweep over (`t0`, `t0 + dt`); `confined` water (no
/// free surface) is not clamped at the walls.
fn water_params<const D: usize>(
    world: &World<D>,
    mat: &WaterMaterial,
    kernel: WendlandC2,
    (t0, dt): (Real, Real),
    confined: bool,
) -> WaterParams<D> {
    WaterParams {
        kernel,
        gravity: world.gravity,
        hydrostatic: world.hydrostatic_gravity(),
        wrap: world.periodic,
        dt,
        z: mat.impedance(),
        inv_c: 1.0 / mat.c0,
        eta: mat.limiter,
        mu: mat.mu,
        keep: mat.velocity_kept(t0, dt),
        push_only: mat.walls_push_only && !confined,
    }
}
