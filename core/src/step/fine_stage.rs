//! The fine grains' stepper: the family skeleton ([`FamilyLists`]) and the fine
//! grains' own stages: the drift to the half step (Eq. 54), the neighbour lists, the
//! artificial stress of cohesive soils (Eq. 27), the momentum sweep (Eqs. 16, 55, with
//! walls and coarse grains), the continuity and stress sweep (Eqs. 15, 24–26, 7–12)
//! and x, ρ to the end of the step (Eq. 56) with the stress check.

use super::family::{Closing, FamilyLists};
use super::params::StepParams;
use super::relations::WallRelation;
use super::soil_water_stage::SoilWater;
use crate::fine::artificial_stress::gray2001_artificial_stress;
use crate::fine::continuity::{ContinuityOut, ContinuityParams, JumpDiffusion};
use crate::fine::lanes::{FineLanes, FinePairs};
use crate::fine::material::{uniform_acoustics, DensityFloor};
use crate::fine::momentum::{ArtificialStress, MomentumParams};
use crate::fine::pair_sums::PairSums;
use crate::fine::source;
use crate::interactions::continuity_pass::continuity_sweep;
use crate::interactions::fine_coarse::{self, CoarseSide, CoarseSource, Coupling};
use crate::interactions::fine_wall::WallLaw;
use crate::interactions::momentum_pass::{momentum_sweep, FineSleep};
use crate::numerics::guard::{Blowup, Family};
use crate::numerics::kernel::WendlandC2;
use crate::numerics::math::{Real, Sym, Vect};
use crate::numerics::neighbors::CellGrid;
use crate::numerics::pairs::quad::Lanes;
use crate::numerics::riemann::Riemann;
use crate::numerics::sleep::{self, Asleep, SleepFlags, SleepRule};
use crate::numerics::timers::{Stage, StageTimers};
use crate::world::{geostatic_tensor, World};
use rayon::prelude::*;

/// What the fine stages read of the step that the orchestrator holds.
pub(super) struct FineContext<'a, const D: usize> {
    pub params: &'a StepParams,
    pub kernel: WendlandC2,
    /// The gravity ramp's factor of this step.
    pub g_scale: Real,
    pub up: Vect<D>,
    /// The coarse particles at the middle of the step.
    pub csrc: &'a [CoarseSource<D>],
    /// Whether the scene has coarse grains (their reactions are gathered).
    pub coarse: bool,
    pub soil_water: Option<&'a SoilWater<D>>,
}

/// The fine grains' stepper: the family skeleton and the fine grains' sources, sweep
/// buffers and per-material factors.
#[derive(Clone, serde::Serialize, serde::Deserialize)]
pub struct FineStepper<const D: usize> {
    /// Lists, marks, loads and scratch of the family.
    pub family: FamilyLists<D>,
    /// Scratch: written in full by every step before it is read (not serialised).
    #[serde(skip)]
    vel_new: Vec<Vect<D>>,
    #[serde(skip)]
    art: Vec<Sym>,
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
    /// Per material: the least density (`numerics.density_floor`; empty: off).
    density_floor: Vec<Real>,
    /// The cluster-pair passes' packed state and sums (the continuity sweep reads the
    /// state the momentum sweep packed).
    #[serde(skip)]
    lanes: FineLanes<D>,
    /// The sleep's flags of the step (sized every step; written by the sweeps).
    #[serde(skip)]
    sleep: SleepFlags,
    /// Per wall object: whether it wakes the particles within its reach (a barrier,
    /// or a wall that can move).
    #[serde(skip)]
    waking_walls: Vec<bool>,
}

impl<const D: usize> FineStepper<D> {
    /// Whether this stepper, restored from a state, fits `template` (the scene's as
    /// built) and the family of `n` fine and `walls` wall particles: the same
    /// per-material constants, and lists that fit ([`FamilyLists::restored_fits`]).
    pub fn restored_fits(
        &self,
        template: &Self,
        n: usize,
        walls: usize,
    ) -> Result<(), &'static str> {
        let t = template;
        if self.geostatic != t.geostatic
            || self.hourglass != t.hourglass
            || self.hourglass_leak.len() != t.hourglass_leak.len()
            || self.tension != t.tension
            || self.uniform != t.uniform
            || self.density_floor != t.density_floor
        {
            return Err("fine materials' constants");
        }
        self.family.restored_fits(&t.family, n, walls)
    }

    /// Lists with cells of `cell` over the world's domain; `up` and `params` set the
    /// per-material factors.
    pub fn new(world: &World<D>, params: &StepParams, cell: Real, up: &Vect<D>) -> Self {
        // along a periodic slope the geostatic state holds the weight normal to the bed
        let g = world.hydrostatic_gravity().norm();
        // a saturated soil's skeleton carries its submerged weight
        let rho_w = world.water.material.map(|w| w.rho0);
        let geostatic = world
            .materials
            .iter()
            .map(|m| geostatic_tensor::<D>(up, m.k0).scale(m.skeleton_density(rho_w) * g))
            .collect();
        let hourglass: Vec<Real> = if params.hourglass > 0.0 {
            world
                .materials
                .iter()
                .map(|m| params.hourglass * m.shear)
                .collect()
        } else {
            Vec::new()
        };
        let (lo, hi) = &world.domain;
        let grid = || CellGrid::periodic(lo, hi, cell, world.periodic);
        FineStepper {
            family: FamilyLists::new(
                grid(),
                WallRelation::new(grid()),
                (cell, params.skin),
                (world.walls.barriers.len(), world.walls.load_slots()),
            ),
            vel_new: Vec::new(),
            art: Vec::new(),
            pair_sums: Vec::new(),
            geostatic,
            geostatic_pressure: Vec::new(),
            hourglass_leak: vec![1.0; hourglass.len()],
            hourglass,
            tension: world.materials.iter().map(|m| m.cohesion > 0.0).collect(),
            uniform: uniform_acoustics(&world.materials),
            density_floor: if params.density_floor {
                world.materials.iter().map(|m| m.density_floor()).collect()
            } else {
                Vec::new()
            },
            lanes: FineLanes::default(),
            sleep: SleepFlags::default(),
            waking_walls: Vec::new(),
        }
    }

    /// Bytes of scratch memory held (lists, buffers, grids).
    pub fn bytes(&self) -> usize {
        use std::mem::size_of;
        self.family.bytes()
            + self.vel_new.capacity() * size_of::<Vect<D>>()
            + self.art.capacity() * size_of::<Sym>()
            + self.pair_sums.capacity() * size_of::<PairSums<D>>()
            + self.lanes.bytes()
            + self.sleep.bytes()
    }

    /// Rebuild the lists (particles re-sorted by cell) if the skin may be used up over
    /// a step of `dt`; true if it did.
    pub(super) fn refresh_lists(
        &mut self,
        world: &mut World<D>,
        csrc: &[CoarseSource<D>],
        dt: Real,
    ) -> bool {
        if !self
            .family
            .needs_rebuild(world.fine.len(), &world.walls, csrc, dt)
        {
            return false;
        }
        let f = &mut world.fine;
        self.family.rebuild(f, &world.walls, csrc, &world.periodic);
        true
    }

    /// Eq. (56): x and ρ to the end of the step, with the stress check of every
    /// particle beside the common ones ([`FamilyLists::close_step`]).
    pub(super) fn finalize(&mut self, world: &mut World<D>, half: Real, max_speed: Real) {
        let f = &mut world.fine;
        let stress = &f.stress;
        let closing = Closing {
            pos: &mut f.pos,
            rho: &mut f.rho,
            vel: &f.vel,
            drho: &f.drho,
            floor: floor_of(&self.density_floor, &f.material),
        };
        self.family.close_step(closing, half, max_speed, |i| {
            (!stress[i].is_finite()).then(|| ("stress", stress[i].trace()))
        });
    }

    /// Stop on the first failing fine particle of the step.
    pub(super) fn guard(&mut self, world: &World<D>, max_speed: Real) -> Result<Real, Blowup> {
        let f = &world.fine;
        let at = (world.steps, world.time);
        self.family
            .guard(Family::Fine, (&f.id, &f.pos), at, max_speed)
    }

    /// Eq. (54): positions and density to the half step (density held at its floor).
    pub(super) fn drift(&mut self, world: &mut World<D>, half: Real) {
        let floor = &self.density_floor;
        source::drift(&mut world.fine, (half, floor));
    }

    /// Eq. (27): the artificial stress of every particle (cohesive soils only).
    pub(super) fn artificial_stress(
        &mut self,
        world: &World<D>,
        params: &StepParams,
        kernel: &WendlandC2,
    ) -> Option<ArtificialStress> {
        let (exponent, eps) = params.artificial?;
        self.art.clear();
        self.art.par_extend(
            world
                .fine
                .stress
                .par_iter()
                .map(|s| gray2001_artificial_stress::<D>(s, eps)),
        );
        Some(ArtificialStress {
            exponent,
            w_dp: kernel.w(world.resolution.dp),
        })
    }

    /// The sleep of this step (`rule`; None: every particle is stepped): the flags
    /// sized, each particle's quiet count (a restored or new particle starts awake),
    /// the wall objects that wake, and the clusters the lane passes evaluate.
    fn prepare_sleep(&mut self, world: &mut World<D>, rule: Option<&SleepRule>) {
        let n = world.fine.len();
        // the sweeps zip over the flags: sized even without sleep (never read then)
        if self.sleep.flags.len() != n {
            self.sleep.reset(n);
        }
        let Some(rule) = rule else {
            return;
        };
        world.fine.quiet.resize(n, 0);
        let walls = &world.walls;
        self.waking_walls.clear();
        self.waking_walls.extend(
            (0..walls.objects.len())
                .map(|o| walls.objects[o].barrier.is_some() || walls.can_move(o)),
        );
        let lists = &mut self.family.lists;
        self.sleep.refresh_reach(&lists.clusters, lists.builds);
        sleep::mark_runs(
            &mut lists.clusters,
            rule,
            &world.fine.quiet,
            &mut self.sleep,
        );
    }

    /// After Eq. (56): wake the neighbours of the step's restless particles, advance
    /// every particle's quiet count (held at zero while gravity ramps up, `ramping`)
    /// and freeze the particles that fall asleep (v = 0, dρ/dt = 0).
    pub(super) fn settle(
        &mut self,
        world: &mut World<D>,
        rule: &SleepRule,
        (cutoff, ramping): (Real, bool),
    ) {
        use crate::numerics::periodic::Separation;
        let wrap = world.periodic;
        let f = &mut world.fine;
        if f.is_empty() || self.family.lists.clusters.particles() != f.len() {
            return;
        }
        let cp = &self.family.lists.clusters;
        let pos = &f.pos;
        let near = |i: usize, j: usize| wrap.of(pos[i] - pos[j]).norm_squared() < cutoff * cutoff;
        let fell = sleep::wake(cp, rule, &mut self.sleep, &mut f.quiet, ramping, near);
        for &i in &fell {
            f.vel[i as usize] = Vect::<D>::zeros();
            f.drho[i as usize] = 0.0;
        }
    }

    /// Buffers sized for this step and the per-material factors of a step of `dt`.
    fn prepare_sweeps(&mut self, world: &mut World<D>, dt: Real, cx: &FineContext<'_, D>) {
        let n = world.fine.len();
        self.vel_new.resize(n, Vect::<D>::zeros());
        // the sweeps leave their sums zero, so only new entries need setting
        self.pair_sums.resize(n, PairSums::zero());
        self.family.prepare_pass(&world.walls);
        self.prepare_sleep(world, cx.params.sleep.as_ref());
        // the stored penalty relaxes over `hourglass_memory` acoustic times h/c0
        let memory = cx.params.hourglass_memory * cx.params.h;
        for (k, m) in self.hourglass_leak.iter_mut().zip(&world.materials) {
            *k = (-dt * m.c0 / memory).exp() as f32;
        }
        // the continuity sweep's parameters: its terms without velocity are taken in
        // the momentum sweep's pair pass
        self.geostatic_pressure.clear();
        self.geostatic_pressure.extend(
            self.geostatic
                .iter()
                .map(|g| g.scale(cx.g_scale).trace() / 3.0),
        );
    }

    /// The first fine sweep of a step of `dt`: v_{n+1} (Eqs. 16, 55), with the walls'
    /// and the coarse grains' reactions and the barrier loads.
    pub(super) fn momentum(
        &mut self,
        world: &mut World<D>,
        dt: Real,
        artificial: Option<ArtificialStress>,
        cx: &FineContext<'_, D>,
        timers: &mut StageTimers,
    ) {
        self.prepare_sweeps(world, dt, cx);
        let cprm = continuity_params(
            (&self.geostatic, &self.geostatic_pressure, self.uniform),
            world,
            dt,
            cx,
        );
        let mprm = MomentumParams {
            kernel: cx.kernel,
            riemann: Riemann { eta: cx.params.eta },
            gravity: world.gravity,
            dt,
            artificial,
            hourglass: &self.hourglass,
            hourglass_leak: &self.hourglass_leak,
            materials: &world.materials,
            uniform: self.uniform,
            wrap: world.periodic,
            muscl: cx.params.muscl,
        };
        let wall = WallLaw {
            kernel: cx.kernel,
            riemann: mprm.riemann,
            // no hydrostatic increase along a periodic axis (the bed of a slope)
            gravity: world.hydrostatic_gravity(),
            dt,
            friction: cx.params.wall_friction,
            stress: cx.params.wall_stress,
            wrap: world.periodic,
        };
        let (lists, chunk_loads, reactions) = self.family.pass_outputs();
        let side = CoarseSide {
            src: cx.csrc,
            coupling: Coupling {
                kernel: cx.kernel,
                riemann: mprm.riemann,
                mu_cf: cx.params.mu_cf,
                dt,
                dp: world.resolution.dp,
            },
            tension: &self.tension,
            reactions,
        };
        // updated in place: a particle reads only its own accumulated penalty
        let mut hourglass = std::mem::take(&mut world.fine.hourglass);
        timers.time(Stage::Momentum, || {
            momentum_sweep(
                &world.fine,
                &world.walls,
                lists,
                &self.art,
                &mprm,
                &wall,
                &mut self.vel_new,
                &mut hourglass,
                chunk_loads,
                side,
                &JumpDiffusion::new(&cprm),
                &mut self.pair_sums,
                cx.soil_water.map_or(&[], |s| &s.force[..]),
                (&mut self.lanes, &lists.clusters, Lanes::detect()),
                FineSleep {
                    asleep: Asleep {
                        rule: cx.params.sleep.as_ref(),
                        quiet: &world.fine.quiet,
                    },
                    waking_walls: &self.waking_walls,
                    flags: &mut self.sleep.flags,
                },
            )
        });
        world.fine.hourglass = hourglass;
        if cx.coarse {
            timers.time(Stage::Coupling, || {
                fine_coarse::gather_reactions(
                    self.family.reactions(),
                    &mut world.coarse.particles.f_fine,
                )
            });
        }
        std::mem::swap(&mut world.fine.vel, &mut self.vel_new);
        self.family.sum_loads(&world.walls);
    }

    /// The second fine sweep of a step of `dt`: density, velocity gradient and stress
    /// with v_{n+1} (Eqs. 15, 24–26, 7–12).
    pub(super) fn continuity(
        &mut self,
        world: &mut World<D>,
        dt: Real,
        cx: &FineContext<'_, D>,
        timers: &mut StageTimers,
    ) {
        let cprm = continuity_params(
            (&self.geostatic, &self.geostatic_pressure, self.uniform),
            world,
            dt,
            cx,
        );
        let sweep = ContinuitySweep {
            lists: &self.family.lists,
            cprm: &cprm,
            csrc: cx.csrc,
            sleep: cx.params.sleep.as_ref(),
        };
        let pairs = (
            &mut self.lanes,
            &self.family.lists.clusters,
            Lanes::detect(),
        );
        let flags = &mut self.sleep.flags;
        timers.time(Stage::ContinuityStress, || {
            sweep.run(world, &mut self.pair_sums, pairs, flags)
        });
    }
}

/// The continuity sweep's parameters of a step of `dt` (its terms without velocity
/// are taken in the momentum sweep's pair pass), from the stepper's per-material
/// geostatic gradients and pressures and its uniform-acoustics flag.
fn continuity_params<'a, const D: usize>(
    (geostatic, geostatic_pressure, uniform): (&'a [Sym], &'a [Real], bool),
    world: &World<D>,
    dt: Real,
    cx: &FineContext<'a, D>,
) -> ContinuityParams<'a, D> {
    ContinuityParams {
        kernel: cx.kernel,
        gravity: world.gravity,
        dt,
        zeta: cx.params.zeta,
        geostatic,
        geostatic_pressure,
        geostatic_scale: cx.g_scale,
        weight: cx.soil_water.map_or(&[], |s| &s.weight[..]),
        up: cx.up,
        jump: cx.params.continuity_jump,
        uniform,
        wrap: world.periodic,
    }
}

/// The continuity and stress sweep of a step (Eqs. 15, 24–26, 7–12) over the fine
/// lists, with v_{n+1}.
struct ContinuitySweep<'a, const D: usize> {
    lists: &'a crate::numerics::neighbors::NeighborLists,
    cprm: &'a ContinuityParams<'a, D>,
    csrc: &'a [CoarseSource<D>],
    sleep: Option<&'a SleepRule>,
}

impl<const D: usize> ContinuitySweep<'_, D> {
    /// dρ/dt, the stress, the plastic strain, the velocity gradient and the kept
    /// hourglass penalty of every fine particle, advanced in place: the sweep reads
    /// none of these of a neighbour (the neighbours' stress comes from the packed
    /// sources).
    fn run(
        &self,
        world: &mut World<D>,
        sums: &mut [PairSums<D>],
        pairs: FinePairs<'_, D>,
        flags: &mut [u8],
    ) {
        let f = &mut world.fine;
        let mut stress = std::mem::take(&mut f.stress);
        let mut drho = std::mem::take(&mut f.drho);
        let mut eps = std::mem::take(&mut f.plastic_strain);
        let mut vel_grad = std::mem::take(&mut f.vel_grad);
        let mut hourglass_kept = std::mem::take(&mut f.hourglass_kept);
        let out = ContinuityOut {
            sums,
            drho: &mut drho,
            stress: &mut stress,
            plastic_strain: &mut eps,
            vel_grad: &mut vel_grad,
            hourglass_kept: &mut hourglass_kept,
        };
        let (f, mats, walls) = (&world.fine, &world.materials, &world.walls);
        let asleep = Asleep {
            rule: self.sleep,
            quiet: &f.quiet,
        };
        let sleep = (asleep, flags);
        continuity_sweep(
            f, mats, walls, self.lists, self.cprm, self.csrc, out, pairs, sleep,
        );
        let f = &mut world.fine;
        f.drho = drho;
        f.stress = stress;
        f.plastic_strain = eps;
        f.vel_grad = vel_grad;
        f.hourglass_kept = hourglass_kept;
    }
}

/// The density floor of particles of `material` (per-material `floor`; empty: off).
fn floor_of<'a>(floor: &'a [Real], material: &'a [u16]) -> Option<DensityFloor<'a>> {
    (!floor.is_empty()).then_some(DensityFloor { material, floor })
}
