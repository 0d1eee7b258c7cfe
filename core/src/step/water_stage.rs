//! The water's stages of a step, on the fine step's Δt and with its position-Verlet
//! scheme (seed 000 Eqs. 54–56 applied to the water): drift to the half step, its own
//! neighbour lists (water–water and water–wall), the momentum sweep (v_{n+1}), the
//! continuity sweep with v_{n+1}, and x, ρ to the end of the step with the guard.

use super::build_marks::{CoarseBins, PositionMarks, WallBins};
use super::soil_water_stage::SeepStep;
use crate::guard::{check, Blowup, ChunkFailure, Family};
use crate::interactions::fine_coarse::{self, CoarseSource};
use crate::interactions::water_pass::{
    continuity_sweep, correction_sweep, momentum_sweep, WaterCoarse,
};
use crate::kernel::WendlandC2;
use crate::load::Load;
use crate::math::{Real, Vect};
use crate::neighbors::{CellGrid, NeighborLists, CHUNK};
use crate::permute::PermuteScratch;
use crate::scene::WallSlip;
use crate::timers::{Stage, StageTimers};
use crate::water::correction::Corr;
use crate::water::material::WaterMaterial;
use crate::water::momentum::{WaterParams, WaterSums};
use crate::water::source::{drift_and_pack, pack, WaterSource};
use crate::world::World;
use rayon::prelude::*;
use std::time::Instant;

/// Scratch memory and lists of the water stages.
#[derive(Clone, serde::Serialize, serde::Deserialize)]
pub struct WaterStepper<const D: usize> {
    #[serde(with = "crate::neighbors::geometry_only")]
    grid: CellGrid<D>,
    walls: WallBins<D>,
    coarse_bins: CoarseBins<D>,
    pub lists: NeighborLists,
    at_build: PositionMarks<D>,
    max_disp: Real,
    vmax: Real,
    skin: Real,
    /// List radius: kernel cut-off plus skin.
    radius: Real,
    /// Water steps taken (sub-steps counted).
    #[serde(default)]
    pub steps: u64,
    /// Load of the water on each barrier during the last step.
    pub step_loads: Vec<Load>,
    /// The same per barrier panel (`Walls::load_slot`).
    pub slot_loads: Vec<Load>,
    #[serde(skip)]
    src: Vec<WaterSource>,
    #[serde(skip)]
    vel_new: Vec<Vect<D>>,
    #[serde(skip)]
    sums: Vec<WaterSums<D>>,
    #[serde(skip)]
    corr: Vec<Corr<D>>,
    /// Each particle's acceleration from a soil's seepage force in the last sub-step
    /// (empty without a soil).
    #[serde(skip)]
    body: Vec<Vect<D>>,

    #[serde(skip)]
    chunk_loads: Vec<Load>,
    #[serde(skip)]
    permute: PermuteScratch,
    #[serde(skip)]
    order: Vec<u32>,
    #[serde(skip)]
    failures: Vec<(Real, Real, ChunkFailure)>,
    /// Per chunk: the water's reactions on coarse particles in the last step.
    #[serde(skip)]
    reactions: Vec<Vec<(u32, Vect<D>)>>,
}

impl<const D: usize> WaterStepper<D> {
    /// Lists with cells of `cell` over the world's domain and Verlet skin `skin`.
    pub fn new(world: &World<D>, cell: Real, skin: Real) -> Self {
        let (lo, hi) = &world.domain;
        let grid = || CellGrid::periodic(lo, hi, cell, world.periodic);
        WaterStepper {
            grid: grid(),
            walls: WallBins::for_water(grid()),
            coarse_bins: CoarseBins::new(grid()),
            lists: NeighborLists::default(),
            at_build: PositionMarks::default(),
            steps: 0,
            max_disp: Real::INFINITY,
            vmax: 0.0,
            skin,
            radius: cell,
            step_loads: vec![Load::default(); world.walls.barriers.len()],
            slot_loads: vec![Load::default(); world.walls.load_slots()],
            src: Vec::new(),
            vel_new: Vec::new(),
            sums: Vec::new(),
            corr: Vec::new(),
            body: Vec::new(),
            chunk_loads: Vec::new(),
            permute: PermuteScratch::default(),
            order: Vec::new(),
            failures: Vec::new(),
            reactions: Vec::new(),
        }
    }

    /// The cells the water was binned in at the last list build.
    pub fn grid(&self) -> &CellGrid<D> {
        &self.grid
    }

    /// Largest water speed at the end of the last step.
    pub fn vmax(&self) -> Real {
        self.vmax
    }

    /// Largest stable Δt of the water (acoustic and viscous limits).
    pub fn stable_dt(&self, mat: &WaterMaterial, h: Real, cfl: Real) -> Real {
        mat.stable_dt(h, cfl, self.vmax)
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
        self.lists.bytes()
            + self.at_build.bytes()
            + self.vel_new.capacity() * size_of::<Vect<D>>()
            + self.src.capacity() * size_of::<WaterSource>()
            + self.sums.capacity() * size_of::<WaterSums<D>>()
            + self.grid.bytes()
            + self.walls.grid.bytes()
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
            drift_and_pack(&mut world.water, mat, half, &mut self.src)
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
        let moved = self.max_disp + 0.5 * dt * self.vmax;
        let wall = self.walls.moved_since_build(&world.walls);
        // infinite when the coarse particles' count changed
        let coarse = self.coarse_bins.moved_since_build(csrc);
        if self.lists.chunks.is_empty()
            || 2.0 * moved > self.skin
            || moved + wall > self.skin
            || moved + coarse > self.skin
        {
            self.rebuild(world, csrc);
            pack(&world.water, mat, &mut self.src);
        }
        t.add(Stage::WaterNeighbors, start.elapsed().as_secs_f64());
    }

    fn rebuild(&mut self, world: &mut World<D>, csrc: &[CoarseSource<D>]) {
        let w = &mut world.water;
        if let Some(p) = world.periodic {
            w.pos.par_iter_mut().for_each(|x| p.wrap_point(x));
        }
        self.grid.bin(&w.pos);
        self.order.clear();
        self.order.extend_from_slice(self.grid.order());
        w.permute(&self.order, &mut self.permute);
        self.grid.bin(&w.pos);
        self.at_build.mark(&w.pos);
        self.walls.refresh(&world.walls);
        self.coarse_bins.refresh(csrc);
        self.lists.build(
            &w.pos,
            &self.grid,
            self.walls.binned(&world.walls),
            self.coarse_bins.binned(),
            self.radius,
            &world.periodic,
        );
        self.reactions
            .resize_with(self.lists.chunks.len(), Vec::new);
        self.max_disp = 0.0;
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
        let n = world.water.len();
        let nbs = world.walls.load_slots().max(1);
        self.vel_new.resize(n, Vect::<D>::zeros());
        self.sums.resize(n, WaterSums::zero());
        self.chunk_loads
            .resize(self.lists.chunks.len() * nbs, Load::default());
        let prm = WaterParams {
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
        };
        let no_slip = mat.wall == WallSlip::NoSlip;
        self.corr.resize(n, Corr::<D>::identity());
        // scratch, not serialised: a restored state has none yet
        self.reactions
            .resize_with(self.lists.chunks.len(), Vec::new);

        t.time(Stage::WaterMomentum, || {
            correction_sweep(
                &world.water,
                &self.src,
                &world.walls,
                csrc,
                &self.lists,
                &prm,
                mat.correction,
                &mut self.corr,
            );
            momentum_sweep(
                &world.water,
                &self.src,
                &self.corr,
                &world.walls,
                WaterCoarse {
                    src: csrc,
                    reactions: &mut self.reactions,
                },
                &self.lists,
                &prm,
                (no_slip, &self.body),
                &mut self.vel_new,
                &mut self.chunk_loads,
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
        std::mem::swap(&mut world.water.vel, &mut self.vel_new);
        // the inlets move their water at the inflow speed
        let mid = t0 + 0.5 * dt;
        for f in &world.water_inflows {
            f.drive(&world.water.pos, &mut world.water.vel, mid);
        }
        if !csrc.is_empty() {
            let f = &mut world.coarse.particles.f_water;
            if s == 0 {
                f.iter_mut().for_each(|x| *x = Vect::<D>::zeros());
            }
            // the mean over the k sub-steps
            fine_coarse::add_reactions(&self.reactions, f, 1.0 / k as Real);
        }
        crate::panels::sum_slots(
            &world.walls,
            &self.chunk_loads,
            nbs,
            &mut self.slot_loads,
            &mut self.step_loads,
        );
        let mut drho = std::mem::take(&mut world.water.drho);
        t.time(Stage::WaterContinuity, || {
            continuity_sweep(
                &world.water,
                &self.src,
                &world.walls,
                csrc,
                &self.lists,
                &prm,
                &self.body,
                &mut drho,
                &mut self.sums,
            )
        });
        for f in &world.water_inflows {
            f.hold_density(&world.water.pos, &mut drho);
        }
        world.water.drho = drho;
    }

    /// x and ρ to the end of the step; each chunk records its largest speed and
    /// displacement since the list build, and its first failing particle.
    pub fn finalize(
        &mut self,
        world: &mut World<D>,
        half: Real,
        max_speed: Real,
        t: &mut StageTimers,
    ) {
        let start = Instant::now();
        let (w, marks) = (&mut world.water, &self.at_build);
        w.pos
            .par_chunks_mut(CHUNK)
            .zip(w.rho.par_chunks_mut(CHUNK))
            .zip(w.vel.par_chunks(CHUNK))
            .zip(w.drho.par_chunks(CHUNK))
            .enumerate()
            .map(|(c, (((x, r), v), d))| {
                let mut vmax2: Real = 0.0;
                let mut disp2: Real = 0.0;
                let mut fail: ChunkFailure = None;
                for k in 0..x.len() {
                    let i = c * CHUNK + k;
                    let (v2, d2) = marks.close_step(i, (&mut x[k], &mut r[k]), (&v[k], d[k]), half);
                    vmax2 = vmax2.max(v2);
                    disp2 = disp2.max(d2);
                    if fail.is_none() {
                        fail = check(i, v2, &x[k], r[k], || None, max_speed);
                    }
                }
                (vmax2, disp2, fail)
            })
            .collect_into_vec(&mut self.failures);
        t.add(Stage::WaterDriftFinalize, start.elapsed().as_secs_f64());
    }

    /// Stop on the first failing water particle of the step; otherwise keep the
    /// step's largest speed and displacement.
    pub fn guard(&mut self, world: &World<D>, max_speed: Real) -> Result<Real, Blowup> {
        let (vmax2, disp2) = crate::guard::reduce(&self.failures).map_err(|f| {
            let (p, at) = (&world.water, (world.steps, world.time));
            let x = p.pos[f.0].iter().copied().collect();
            Blowup::of_particle(at, Family::Water, p.id[f.0], x, f, max_speed)
        })?;
        self.vmax = vmax2.sqrt();
        self.max_disp = disp2.sqrt() + self.at_build.round_off;
        Ok(self.vmax)
    }
}
