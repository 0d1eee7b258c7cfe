//! The `Simulation` API shared by the CLI and (later) the FMU: build from a scene,
//! step with landing exactly on requested times, and sample observations.

use crate::numerics::guard::Blowup;
use crate::numerics::load::Load;
use crate::numerics::math::{to3, Real, Vect};
use crate::numerics::neighbors::CellGrid;
use crate::run::observe::{self, RunoutSpec};
use crate::run::pore_field::PoreField;
pub use crate::run::sample::{
    BarrierSample, BodySample, Frame, ParticleRecord, ProbeValue, Sample, WaterSample,
};
use crate::scene::build_error::BuildError;
use crate::scene::resolution::Resolution;
use crate::scene::Scene;
use crate::step::{choose_step, land_on, StepParams, StepStats, Stepper, Stepping};
use crate::world::World;

/// One simulation in `D` dimensions. Cloning copies the whole state (world, stepper
/// scratch and neighbour lists, load accumulators), so a clone steps on bitwise
/// identically: the FMU's state rollback.
#[derive(Clone, serde::Serialize, serde::Deserialize)]
pub struct Simulation<const D: usize> {
    pub world: World<D>,
    pub stepper: Stepper<D>,
    pub(super) runout: RunoutSpec<D>,
    pub(super) impulse: Vec<Load>,
    /// Impulse on each barrier panel since the last sample.
    pub(super) panel_impulse: Vec<Load>,
    /// Impulse (force, torque) on each body since the last sample.
    pub(super) body_impulse: Vec<Load>,
    /// The water's part of `impulse`.
    #[serde(default)]
    pub(super) water_impulse: Vec<Load>,
    /// The water's part of `panel_impulse`.
    #[serde(default)]
    pub(super) panel_water_impulse: Vec<Load>,
    pub(super) peak: Vec<Real>,
    pub(super) interval_start: Real,
    pub(super) last_dt: Real,
    /// No step is longer than this (the scene's output interval).
    pub(super) dt_cap: Real,
    /// Stable Δt_f (Eq. 51) and Δt_c (Eq. 52 and contacts) of the last step.
    pub(super) last_dt_f: Real,
    pub(super) last_dt_c: Real,
    /// κ = ⌈Δt_f/Δt_c⌉ of the last full (not output-clipped) step.
    pub(super) last_kappa: usize,
}

fn arr<const D: usize>(v: &Vect<D>) -> [f32; 3] {
    let mut o = [0.0f32; 3];
    for k in 0..D {
        o[k] = v[k] as f32;
    }
    o
}

impl<const D: usize> Simulation<D> {
    /// Build from a validated scene. Everything the run needs of the scene is read
    /// here, before the world is built; nothing reads the scene afterwards.
    pub fn new(scene: &Scene) -> Result<Self, BuildError> {
        let resolution = Resolution::of::<D>(scene);
        let params = StepParams::from_scene(scene, &resolution);
        let origin = scene.observe.runout_origin.clone();
        let direction = scene.observe.runout_direction.unwrap_or(1.0);
        let dt_cap = scene.simulation.output_interval;
        let world = World::<D>::build(scene, resolution)?;
        let stepper = Stepper::new(&world, params);
        let origin = origin.unwrap_or_else(|| {
            // default: the horizontal centre of the initial particles (3D) or min x (2D)
            let n = world.fine.len().max(1) as Real;
            if D == 2 {
                vec![world
                    .fine
                    .pos
                    .iter()
                    .map(|p| p[0])
                    .fold(Real::INFINITY, Real::min)]
            } else {
                let c = world.fine.pos.iter().fold(Vect::<D>::zeros(), |a, p| a + p) / n;
                vec![c[0], c[1]]
            }
        });
        let runout = RunoutSpec { origin, direction };
        let nb = world.walls.barriers.len();
        let slots = world.walls.load_slots();
        let bodies = world.coarse.bodies.len();
        Ok(Simulation {
            world,
            stepper,
            runout,
            impulse: vec![Load::default(); nb],
            panel_impulse: vec![Load::default(); slots],
            body_impulse: vec![Load::default(); bodies],
            water_impulse: vec![Load::default(); nb],
            panel_water_impulse: vec![Load::default(); slots],
            peak: vec![0.0; nb],
            interval_start: 0.0,
            last_dt: 0.0,
            dt_cap,
            last_dt_f: 0.0,
            last_dt_c: 0.0,
            last_kappa: 1,
        })
    }

    pub fn time(&self) -> Real {
        self.world.time
    }

    /// Take one step no longer than `max_dt`.
    pub fn step(&mut self, max_dt: Real) -> Result<StepStats, Blowup> {
        let max_dt = max_dt.min(self.dt_cap);
        let dt_f = self.stepper.stable_dt(&self.world);
        let dt_c = self.stepper.coarse_dt(&self.world, dt_f.min(max_dt));
        let (dt, kappa) = choose_step(dt_f, dt_c, max_dt, self.stepper.params.scheme);
        self.last_dt_f = dt_f;
        self.last_dt_c = dt_c;
        // the step itself may be shortened to land on an output time; κ is reported
        // for the full step, as in seed 000 Table 3
        self.last_kappa = choose_step(dt_f, dt_c, self.dt_cap, self.stepper.params.scheme).1;
        let st = self.stepper.step(&mut self.world, dt, kappa)?;
        for (b, l) in self.stepper.step_loads.iter().enumerate() {
            self.impulse[b].force += l.force * dt;
            self.impulse[b].moment += l.moment * dt;
            self.peak[b] = self.peak[b].max(l.force.norm());
        }
        if let Some(w) = &self.stepper.water {
            for (b, l) in self.water_impulse.iter_mut().zip(&w.family.step_loads) {
                b.force += l.force * dt;
                b.moment += l.moment * dt;
            }
            for (p, l) in self
                .panel_water_impulse
                .iter_mut()
                .zip(&w.family.slot_loads)
            {
                p.force += l.force * dt;
            }
        }
        for (p, l) in self.panel_impulse.iter_mut().zip(&self.stepper.slot_loads) {
            p.force += l.force * dt;
        }
        for (p, b) in self.body_impulse.iter_mut().zip(&self.world.coarse.bodies) {
            p.force += b.force * dt;
            p.moment += b.torque * dt;
        }
        self.last_dt = dt;
        Ok(st)
    }

    /// Step until exactly `t` (the last step is shortened).
    ///
    /// The steps run on a worker of the thread pool (in place when called from one):
    /// a parallel loop started from outside the pool, e.g. from an FMI master's
    /// thread, is handed to a sleeping worker and back, two thread switches per loop.
    pub fn advance_to(&mut self, t: Real) -> Result<(), Blowup> {
        let mut out = Ok(());
        rayon::scope(|_| out = self.advance_to_here(t));
        out
    }

    fn advance_to_here(&mut self, t: Real) -> Result<(), Blowup> {
        land_on(self, t, &mut |_| {})
    }

    /// Observations now; barrier loads are averaged since the previous sample.
    pub fn sample(&mut self) -> Sample {
        let w = &self.world;
        let span = w.time - self.interval_start;
        let inv = if span > 0.0 { 1.0 / span } else { 0.0 };
        let barriers = self.barrier_samples(inv);
        let probes = self.probe_samples();
        let bodies = self.body_samples(inv);
        let cp = &w.coarse.particles;
        let coarse_ke: Real = (0..cp.len())
            .map(|i| 0.5 * cp.mass[i] * cp.vel[i].norm_squared())
            .fold(0.0, |a, e| a + e);
        let coarse_pe: Real = (0..cp.len())
            .map(|i| -cp.mass[i] * cp.pos[i].dot(&w.gravity))
            .sum();
        let mut momentum = nalgebra::Vector3::<Real>::zeros();
        for i in 0..w.fine.len() {
            momentum += to3(&w.fine.vel[i]) * w.fine.mass[i];
        }
        for i in 0..cp.len() {
            momentum += to3(&cp.vel[i]) * cp.mass[i];
        }
        let (steps_coarse, kappa, strain, contact) = match &self.stepper.coarse {
            Some(c) => (
                c.steps,
                self.last_kappa,
                c.tlsph
                    .strain_energy(cp, &w.coarse.bodies, &w.coarse.solids, w.resolution.volume),
                c.contacts.energy,
            ),
            None => (0, 1, 0.0, 0.0),
        };
        let coarse_volumes: Vec<(Vect<D>, Real)> = (0..cp.len())
            .map(|i| {
                let b = &w.coarse.bodies[cp.body[i] as usize];
                (cp.pos[i], cp.mass[i] / w.coarse.solids[b.material].rho0)
            })
            .collect();
        let rho0: Vec<Real> = w.materials.iter().map(|m| m.rho0).collect();
        let s = Sample {
            time: w.time,
            steps: w.steps,
            dt: self.last_dt,
            kinetic_energy: observe::kinetic_energy(&w.fine),
            potential_energy: observe::potential_energy(&w.fine, &w.gravity),
            runout: observe::runout(&w.fine, &coarse_volumes, &self.runout, w.resolution.dp),
            max_speed: self.stepper.fine_vmax(),
            density_ratio: observe::density_ratio(&w.fine, &rho0),
            awake_fine: self.stepper.fine_awake_share(w),
            coarse_max_speed: cp.vel.iter().map(|v| v.norm()).fold(0.0, Real::max),
            barriers,
            probes,
            gauges: self.gauge_samples(),
            steps_coarse,
            kappa,
            dt_fine: self.last_dt_f,
            dt_coarse: self.last_dt_c,
            coarse_kinetic_energy: coarse_ke,
            strain_energy: strain,
            contact_energy: contact,
            coarse_potential_energy: coarse_pe,
            momentum: momentum.into(),
            bodies,
            water: w.water.material.map(|_| {
                let wp = &w.water.particles;
                WaterSample {
                    particles: wp.len(),
                    kinetic_energy: wp.kinetic_energy(),
                    potential_energy: wp.potential_energy(&w.hydrostatic_gravity()),
                    front: wp.front(),
                    max_speed: wp.max_speed(),
                    momentum: to3(&wp.momentum()).into(),
                    min_pressure: w
                        .water
                        .material
                        .as_ref()
                        .map_or(0.0, |m| wp.min_pressure(m)),
                    carried: self
                        .stepper
                        .soil_water
                        .as_ref()
                        .map_or([0.0; 3], |sw| to3(&sw.carried).into()),
                }
            }),
        };
        self.start_interval();
        s
    }

    /// Every probe's fine-grain stress and velocity, and the water's pressure and
    /// velocity there (Shepard-weighted kernel means).
    fn probe_samples(&self) -> Vec<(String, crate::run::sample::ProbeValue)> {
        let w = &self.world;
        w.probes
            .iter()
            .map(|p| {
                let mut v = observe::probe(&w.fine, &self.stepper.kernel, &p.position);
                if let Some(m) = &w.water.material {
                    // pressure and velocity in one pass: (p, v_x, v_y, v_z)
                    let water = &w.water.particles;
                    let value = |i: usize| {
                        let mut q = nalgebra::Vector4::<Real>::zeros();
                        q[0] = m.pressure(water.rho[i]);
                        for k in 0..D {
                            q[k + 1] = water.vel[i][k];
                        }
                        q
                    };
                    let zero = nalgebra::Vector4::zeros();
                    let at = &p.position;
                    let kernel = &self.stepper.kernel;
                    if let Some(q) = water.shepard(kernel, at, (value, zero), &w.periodic) {
                        v.water_pressure = Some(q[0]);
                        v.water_velocity = Some([q[1], q[2], q[3]]);
                    }
                }
                (p.name.clone(), v)
            })
            .collect()
    }

    /// Every gauge's depth of water above its base ([`WaterParticles::depth`]).
    ///
    /// [`WaterParticles::depth`]: crate::water::state::WaterParticles::depth
    fn gauge_samples(&self) -> Vec<(String, Real)> {
        let w = &self.world;
        let up = crate::numerics::math::up(&w.gravity);
        w.gauges
            .iter()
            .map(|g| {
                let d =
                    w.water
                        .particles
                        .depth(self.stepper.kernel.h, &g.position, &up, &w.periodic);
                (g.name.clone(), d)
            })
            .collect()
    }

    /// Start a new sampling interval: the accumulated impulses and peaks to zero.
    fn start_interval(&mut self) {
        for l in &mut self.impulse {
            *l = Load::default();
        }
        for p in &mut self.peak {
            *p = 0.0;
        }
        for l in self
            .panel_impulse
            .iter_mut()
            .chain(&mut self.body_impulse)
            .chain(&mut self.water_impulse)
            .chain(&mut self.panel_water_impulse)
        {
            *l = Load::default();
        }
        self.interval_start = self.world.time;
    }

    /// Each barrier's loads over the sampling interval (`inv` = 1 / its length).
    fn barrier_samples(&self, inv: Real) -> Vec<BarrierSample> {
        let w = &self.world;
        w.walls
            .barriers
            .iter()
            .enumerate()
            .map(|(b, bar)| {
                let l = &self.stepper.step_loads[b];
                let panels = if bar.panels.is_empty() {
                    Vec::new()
                } else {
                    (0..w.walls.panel_count(b))
                        .map(|i| (self.panel_impulse[bar.slot0 + i].force * inv).into())
                        .collect()
                };
                let panels_water = if bar.panels.is_empty() || !w.has_water() {
                    Vec::new()
                } else {
                    (0..w.walls.panel_count(b))
                        .map(|i| (self.panel_water_impulse[bar.slot0 + i].force * inv).into())
                        .collect()
                };
                let force_water = self
                    .water_impulse
                    .get(b)
                    .map_or([0.0; 3], |l| (l.force * inv).into());
                let imp = &self.impulse[b];
                let loads = (
                    (imp.force * inv).into(),
                    (imp.moment * inv).into(),
                    self.peak[b],
                    l.force.into(),
                );
                BarrierSample::new(bar.name.clone(), loads, (panels, panels_water), force_water)
            })
            .collect()
    }

    /// Each body's state, with its loads averaged over the sampling interval.
    fn body_samples(&self, inv: Real) -> Vec<BodySample> {
        self.world
            .coarse
            .bodies
            .iter()
            .zip(&self.body_impulse)
            .map(|(b, imp)| {
                let q = b.orientation.quaternion();
                BodySample {
                    name: b.name.clone(),
                    position: b.com.into(),
                    orientation: [q.w, q.i, q.j, q.k],
                    velocity: b.vel.into(),
                    angular_velocity: b.omega.into(),
                    force: b.force.into(),
                    torque: b.torque.into(),
                    fine_force: b.fine_force.into(),
                    water_force: b.water_force.into(),
                    mean_force: (imp.force * inv).into(),
                    mean_torque: (imp.moment * inv).into(),
                    contacts: b.contacts,
                }
            })
            .collect()
    }

    /// The loads the barriers carry in the current state, without advancing it: the
    /// momentum sweep of a step (seed 000 Eqs. (16), (35), (55)) run with Δt = 0 on a
    /// copy of the world and the stepper, so the wall forces come from the solver's
    /// own formulas. `force`, `last_force` and `peak_force` are this instantaneous
    /// load. Contacts of coarse grains with a barrier enter from the first step (a
    /// zero-length step takes no coarse sub-step). A non-finite state is an error; a
    /// particle beyond `max_speed` is left to the first step's guard. The FMU reports
    /// this load before any step.
    pub fn state_loads(&self) -> Result<Vec<BarrierSample>, Blowup> {
        let mut world = self.world.clone();
        let mut stepper = self.stepper.clone();
        match stepper.step(&mut world, 0.0, 1) {
            // the speed bound (max_speed) is the steps' to enforce: a state that
            // starts beyond it still has its loads, and the first step reports it
            Err(b) if b.limit.is_none() => return Err(b),
            _ => {}
        }
        let walls = &self.world.walls;
        Ok(walls
            .barriers
            .iter()
            .enumerate()
            .map(|(b, bar)| {
                let l = &stepper.step_loads[b];
                let panels = if bar.panels.is_empty() {
                    Vec::new()
                } else {
                    (0..walls.panel_count(b))
                        .map(|i| stepper.slot_loads[bar.slot0 + i].force.into())
                        .collect()
                };
                let panels_water = match (&stepper.water, bar.panels.is_empty()) {
                    (Some(w), false) => (0..walls.panel_count(b))
                        .map(|i| w.family.slot_loads[bar.slot0 + i].force.into())
                        .collect(),
                    _ => Vec::new(),
                };
                let force_water = stepper
                    .water
                    .as_ref()
                    .map_or([0.0; 3], |w| w.family.step_loads[b].force.into());
                let loads = (
                    l.force.into(),
                    l.moment.into(),
                    l.force.norm(),
                    l.force.into(),
                );
                BarrierSample::new(bar.name.clone(), loads, (panels, panels_water), force_water)
            })
            .collect())
    }

    /// Fill `out` (fine particles first, then coarse, then water;
    /// [`Self::particle_counts`], [`Self::water_count`]) with every particle's
    /// [`ParticleRecord`], in parallel, as far as `out` reaches. Reads only: the solver
    /// state is untouched, so publishing cannot change results.
    pub fn fill_particles(&self, out: &mut [ParticleRecord]) {
        use rayon::prelude::*;
        let pores = self.pore_field();
        let pores = &pores;
        let (nf, nc) = self.particle_counts();
        let (fine_out, coarse_out) = out.split_at_mut(nf.min(out.len()));
        let (coarse_out, water_out) = coarse_out.split_at_mut(nc.min(coarse_out.len()));
        water_out
            .par_iter_mut()
            .with_min_len(4096)
            .take(self.world.water.particles.len())
            .enumerate()
            .for_each(|(i, o)| *o = self.water_record(i, pores));
        fine_out
            .par_iter_mut()
            .with_min_len(4096)
            .enumerate()
            .for_each(|(i, o)| *o = self.fine_record(i, pores));
        coarse_out
            .par_iter_mut()
            .with_min_len(4096)
            .take(nc)
            .enumerate()
            .for_each(|(i, o)| *o = self.coarse_record(i));
    }

    /// Pore pressures of the present state for the records ([`PoreField`]).
    fn pore_field(&self) -> PoreField {
        PoreField::of(
            &self.world,
            self.stepper.soil_water.as_ref(),
            &self.stepper.kernel,
        )
    }

    /// The record of fine particle `i`.
    fn fine_record(&self, i: usize, pores: &PoreField) -> ParticleRecord {
        let f = &self.world.fine;
        let [pore, excess] = pores.fine.get(i).copied().unwrap_or_default();
        let m = &self.world.materials[f.material[i] as usize];
        ParticleRecord {
            position: arr(&f.pos[i]),
            velocity: arr(&f.vel[i]),
            pressure: (-f.stress[i].trace() / 3.0) as f32,
            plastic_strain: f.plastic_strain[i] as f32,
            id: f.id[i],
            group: f.material[i] as u32,
            family: crate::run::sample::FAMILY_FINE,
            pore_pressure: pore,
            excess_pore_pressure: excess,
            porosity: m.pores.map_or(0.0, |p| p.porosity_at(f.rho[i], m.rho0)) as f32,
        }
    }

    /// The record of coarse particle `i`.
    fn coarse_record(&self, i: usize) -> ParticleRecord {
        let c = &self.world.coarse.particles;
        ParticleRecord {
            position: arr(&c.pos[i]),
            velocity: arr(&c.vel[i]),
            pressure: 0.0,
            plastic_strain: 0.0,
            id: i as u32,
            group: c.body[i],
            family: crate::run::sample::FAMILY_COARSE,
            pore_pressure: 0.0,
            excess_pore_pressure: 0.0,
            porosity: 0.0,
        }
    }

    /// The record of water particle `i`.
    fn water_record(&self, i: usize, pores: &PoreField) -> ParticleRecord {
        let w = &self.world.water.particles;
        let p = self
            .world
            .water
            .material
            .map_or(0.0, |m| m.pressure(w.rho[i]));
        ParticleRecord {
            position: arr(&w.pos[i]),
            velocity: arr(&w.vel[i]),
            pressure: p as f32,
            plastic_strain: 0.0,
            id: w.id[i],
            group: 0,
            family: crate::run::sample::FAMILY_WATER,
            pore_pressure: p as f32,
            excess_pore_pressure: pores.water.get(i).copied().unwrap_or_default(),
            porosity: 0.0,
        }
    }

    /// Water particles.
    pub fn water_count(&self) -> usize {
        self.world.water.particles.len()
    }

    /// Fine and coarse particle counts.
    pub fn particle_counts(&self) -> (usize, usize) {
        (self.world.fine.len(), self.world.coarse.particles.len())
    }

    /// The wall objects as solids for viewers, at t = 0 ([`crate::geometry::solids`]).
    pub fn wall_solids(&self) -> Vec<crate::geometry::solids::WallSolid> {
        crate::geometry::solids::wall_solids(&self.world.walls, self.world.resolution.dp)
    }

    /// Each wall object's rigid offset (m) since t = 0, in 3D coordinates.
    pub fn wall_offsets(&self) -> Vec<[Real; 3]> {
        crate::geometry::solids::offsets(&self.world.walls)
    }

    /// The pressure (Pa) of every wall particle: the fine grains' P̄_w plus the
    /// water's, and the water's part alone (`None` without water), each the Shepard
    /// mean of its wall law's extrapolation
    /// ([`wall_pressure`](crate::interactions::wall_pressure)). Taken when asked
    /// (output time), in one pass over the particles.
    pub fn wall_pressure(&self) -> (Vec<f32>, Option<Vec<f32>>) {
        use crate::interactions::wall_pressure::{shepard, Family, Law};
        let w = &self.world;
        let kernel = &self.stepper.kernel;
        let mut grid = CellGrid::periodic(&w.domain.0, &w.domain.1, kernel.cutoff, w.periodic);
        grid.bin(&w.walls.pos);
        let fine_p: Vec<Real> = w.fine.stress.iter().map(|s| -s.trace() / 3.0).collect();
        let fine = Family {
            pos: &w.fine.pos,
            rho: &w.fine.rho,
            mass: &w.fine.mass,
            p: &fine_p,
        };
        let law = Law::Fine { gravity: w.gravity };
        let mut total = shepard(&w.walls, &grid, kernel, &w.periodic, &fine, law);
        let water = w.water.material.map(|m| {
            let wp = &w.water.particles;
            let p: Vec<Real> = wp.rho.iter().map(|&r| m.pressure(r)).collect();
            let water = Family {
                pos: &wp.pos,
                rho: &wp.rho,
                mass: &wp.mass,
                p: &p,
            };
            let law = Law::Water {
                hydrostatic: w.hydrostatic_gravity(),
            };
            let pw = shepard(&w.walls, &grid, kernel, &w.periodic, &water, law);
            for (t, p) in total.iter_mut().zip(&pw) {
                *t += p;
            }
            pw.iter().map(|&p| p as f32).collect()
        });
        (total.iter().map(|&p| p as f32).collect(), water)
    }

    /// The wall particles (3D layout) and each one's object index (walls, barriers
    /// and container faces in scene order), for writers that draw the geometry once.
    pub fn wall_points(&self) -> (Vec<[f32; 3]>, Vec<u16>) {
        let walls = &self.world.walls;
        (walls.pos.iter().map(arr).collect(), walls.object.clone())
    }

    /// Particle snapshot for writers.
    pub fn frame(&self) -> Frame {
        let (f, w) = (&self.world.fine, &self.world);
        let (nf, nc) = self.particle_counts();
        let pores = self.pore_field();
        Frame {
            time: w.time,
            fine: (0..nf).map(|i| self.fine_record(i, &pores)).collect(),
            density: f.rho.iter().map(|&r| r as f32).collect(),
            stress: f.stress.iter().map(|s| s.0.map(|x| x as f32)).collect(),
            awake: self.stepper.params.sleep.map_or(Vec::new(), |r| {
                f.quiet.iter().map(|&q| u8::from(!r.asleep(q))).collect()
            }),
            coarse: (0..nc).map(|i| self.coarse_record(i)).collect(),
            coarse_fine_force: w.coarse.particles.f_fine.iter().map(arr).collect(),
            coarse_water_force: w.coarse.particles.f_water.iter().map(arr).collect(),
            wall_pos: w.walls.pos.iter().map(arr).collect(),
            wall_object: w.walls.object.clone(),
            water: (0..w.water.particles.len())
                .map(|i| self.water_record(i, &pores))
                .collect(),
            water_density: w.water.particles.rho.iter().map(|&r| r as f32).collect(),
        }
    }
}

impl<const D: usize> Stepping for Simulation<D> {
    fn now(&self) -> Real {
        self.world.time
    }
    fn set_now(&mut self, t: Real) {
        self.world.time = t;
    }
    fn step_at_most(&mut self, max_dt: Real) -> Result<StepStats, Blowup> {
        self.step(max_dt)
    }
}
