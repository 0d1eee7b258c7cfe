//! The `Simulation` API shared by the CLI and (later) the FMU: build from a scene,
//! step with landing exactly on requested times, and sample observations.

use crate::fine::momentum::Load;
use crate::guard::Blowup;
use crate::math::{Real, Vect};
use crate::observe::{self, ProbeValue, RunoutSpec};
use crate::scene::Scene;
use crate::stepper::{StepParams, StepStats, Stepper};
use crate::world::{BuildError, World};

/// Barrier load over a sampling interval.
#[derive(Clone, Debug, Default)]
pub struct BarrierSample {
    pub name: String,
    /// Impulse over the interval divided by its length (N, or N/m in 2D).
    pub force: [Real; 3],
    /// Moment about the reference point, impulse-averaged (N·m, or N·m/m in 2D).
    pub moment: [Real; 3],
    /// Largest resultant force of any single step in the interval.
    pub peak_force: Real,
    /// Force of the last step.
    pub last_force: [Real; 3],
}

/// Observations at one sampling time.
#[derive(Clone, Debug, Default)]
pub struct Sample {
    pub time: Real,
    pub steps: u64,
    pub dt: Real,
    pub kinetic_energy: Real,
    pub potential_energy: Real,
    pub runout: Real,
    pub max_speed: Real,
    pub barriers: Vec<BarrierSample>,
    pub probes: Vec<(String, ProbeValue)>,
}

/// A particle snapshot in 3D layout (z = 0 in 2D), for writers.
#[derive(Clone, Debug, Default)]
pub struct Frame {
    pub time: Real,
    pub pos: Vec<[f32; 3]>,
    pub vel: Vec<[f32; 3]>,
    pub pressure: Vec<f32>,
    pub density: Vec<f32>,
    pub plastic_strain: Vec<f32>,
    pub stress: Vec<[f32; 6]>,
    pub id: Vec<u32>,
    pub material: Vec<u16>,
    pub wall_pos: Vec<[f32; 3]>,
    pub wall_object: Vec<u16>,
}

/// One simulation in `D` dimensions.
pub struct Simulation<const D: usize> {
    pub world: World<D>,
    pub stepper: Stepper<D>,
    runout: RunoutSpec<D>,
    impulse: Vec<Load>,
    peak: Vec<Real>,
    interval_start: Real,
    last_dt: Real,
}

fn arr<const D: usize>(v: &Vect<D>) -> [f32; 3] {
    let mut o = [0.0f32; 3];
    for k in 0..D {
        o[k] = v[k] as f32;
    }
    o
}

impl<const D: usize> Simulation<D> {
    pub fn new(scene: &Scene) -> Result<Self, BuildError> {
        let world = World::<D>::build(scene)?;
        let stepper = Stepper::new(&world, StepParams::from_scene(scene));
        let origin = scene.observe.runout_origin.clone().unwrap_or_else(|| {
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
        let runout = RunoutSpec {
            origin,
            direction: scene.observe.runout_direction.unwrap_or(1.0),
        };
        let nb = world.walls.barriers.len();
        Ok(Simulation {
            world,
            stepper,
            runout,
            impulse: vec![Load::default(); nb],
            peak: vec![0.0; nb],
            interval_start: 0.0,
            last_dt: 0.0,
        })
    }

    pub fn time(&self) -> Real {
        self.world.time
    }

    /// Take one step no longer than `max_dt`.
    pub fn step(&mut self, max_dt: Real) -> Result<StepStats, Blowup> {
        let dt = self.stepper.stable_dt(&self.world).min(max_dt);
        let st = self.stepper.step(&mut self.world, dt)?;
        for (b, l) in self.stepper.step_loads.iter().enumerate() {
            self.impulse[b].force += l.force * dt;
            self.impulse[b].moment += l.moment * dt;
            self.peak[b] = self.peak[b].max(l.force.norm());
        }
        self.last_dt = dt;
        Ok(st)
    }

    /// Step until exactly `t` (the last step is shortened).
    pub fn advance_to(&mut self, t: Real) -> Result<(), Blowup> {
        while self.world.time < t {
            let remaining = t - self.world.time;
            if remaining <= 1e-12 * t.abs().max(1e-300) {
                self.world.time = t;
                break;
            }
            self.step(remaining)?;
            if t - self.world.time < 0.0 {
                self.world.time = t;
            }
        }
        Ok(())
    }

    /// Observations now; barrier loads are averaged since the previous sample.
    pub fn sample(&mut self) -> Sample {
        let w = &self.world;
        let span = w.time - self.interval_start;
        let barriers = w
            .walls
            .barriers
            .iter()
            .enumerate()
            .map(|(b, bar)| {
                let inv = if span > 0.0 { 1.0 / span } else { 0.0 };
                let l = &self.stepper.step_loads[b];
                BarrierSample {
                    name: bar.name.clone(),
                    force: (self.impulse[b].force * inv).into(),
                    moment: (self.impulse[b].moment * inv).into(),
                    peak_force: self.peak[b],
                    last_force: l.force.into(),
                }
            })
            .collect();
        let probes = w
            .probes
            .iter()
            .map(|p| {
                (
                    p.name.clone(),
                    observe::probe(&w.fine, &self.stepper.kernel, &p.position),
                )
            })
            .collect();
        let s = Sample {
            time: w.time,
            steps: w.steps,
            dt: self.last_dt,
            kinetic_energy: observe::kinetic_energy(&w.fine),
            potential_energy: observe::potential_energy(&w.fine, &w.gravity),
            runout: observe::runout(&w.fine, &self.runout, w.dp),
            max_speed: self.stepper.vmax(),
            barriers,
            probes,
        };
        for l in &mut self.impulse {
            *l = Load::default();
        }
        for p in &mut self.peak {
            *p = 0.0;
        }
        self.interval_start = w.time;
        s
    }

    /// Particle snapshot for writers.
    pub fn frame(&self) -> Frame {
        let f = &self.world.fine;
        Frame {
            time: self.world.time,
            pos: f.pos.iter().map(arr).collect(),
            vel: f.vel.iter().map(arr).collect(),
            pressure: f.stress.iter().map(|s| (-s.trace() / 3.0) as f32).collect(),
            density: f.rho.iter().map(|&r| r as f32).collect(),
            plastic_strain: f.plastic_strain.iter().map(|&e| e as f32).collect(),
            stress: f.stress.iter().map(|s| s.0.map(|x| x as f32)).collect(),
            id: f.id.clone(),
            material: f.material.clone(),
            wall_pos: self.world.walls.pos.iter().map(arr).collect(),
            wall_object: self.world.walls.object.clone(),
        }
    }
}
