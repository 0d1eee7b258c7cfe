//! The granular model: a scene's [`AnySimulation`] behind the FMU variable table.
//!
//! Outputs come from the [`Sample`] taken at the end of each communication step, so
//! barrier loads are the impulse over the step divided by its length. Input-driven
//! barriers (scene key `input`) move rigidly during each step: with the given velocity,
//! or with (target displacement − current displacement)/h.

mod table;

use crate::envelope::{self, Encoding, ModelKind};
use crate::error::{GranularError, ModelError, ReadError, StateError, StepError};
use crate::model::{check_step, Model};
use crate::state::Place;
use crate::variables::Variable;
use crate::xml::{self, ModelInfo};
use granmix_core::input::{load_scene_in, LoadedScene};
use granmix_core::run::simulation::Sample;
use granmix_core::scene::BarrierInput;
use granmix_core::AnySimulation;
use granmix_ipc::{ChannelSink, FramePublisher, Recorder, SceneInfo, Sinks};
use std::path::{Path, PathBuf};
use std::sync::{Arc, Mutex};
use table::{build_table, Slot, Table};

/// What one communication step applies: where it ends and the barrier drives.
#[derive(Clone, Debug)]
struct StepRecord {
    /// Time at the end of the step.
    end: f64,
    /// Velocity applied to each driven barrier during the step.
    drives: Vec<(usize, [f64; 3])>,
}

/// How the payload of a serialised state is stored (measured in docs/fmu.md).
const STATE_ENCODING: Encoding = Encoding::Deflate;

/// The serialised state, as written ([`SavedRef`]) and read back ([`Saved`]): the
/// same fields in the same order.
#[derive(serde::Serialize)]
struct SavedRef<'a> {
    initialised: bool,
    start: f64,
    now: f64,
    built_with: &'a [f64],
    values: &'a [f64],
    last: &'a Sample,
    sim: &'a AnySimulation,
}

#[derive(serde::Deserialize)]
struct Saved {
    initialised: bool,
    start: f64,
    now: f64,
    built_with: Vec<f64>,
    values: Vec<f64>,
    last: Sample,
    sim: AnySimulation,
}

/// The granular FMU model.
#[derive(Clone)]
pub struct Granular {
    loaded: Arc<LoadedScene>,
    dir: Arc<PathBuf>,
    table: Arc<Table>,
    /// Values of parameters and inputs by value reference (outputs unused).
    values: Vec<f64>,
    /// Parameter values the simulation was built with.
    built_with: Vec<f64>,
    sim: AnySimulation,
    last: Sample,
    initialised: bool,
    /// Values of String parameters by value reference (empty for other kinds).
    texts: Vec<String>,
    /// The FMU instance name (default particle service).
    instance: String,
    sinks: Option<Arc<Mutex<Sinks>>>,
    /// Start time of the experiment (`fmi2SetupExperiment`); the simulation itself
    /// starts at 0, so it steps bitwise as an experiment started at 0 would.
    start: f64,
    /// The communication point reached, as the master computed it (`t + h` of the
    /// last step; `start` before any).
    now: f64,
    /// Wall time spent in the solver's `advance_to` (s), see [`Model::solver_seconds`].
    solver_seconds: f64,
}

fn build_sim(loaded: &LoadedScene) -> Result<AnySimulation, GranularError> {
    AnySimulation::new(loaded).map_err(|e| GranularError::Setup(Box::new(e)))
}

/// The outputs before any step: the state's observations, with the loads the
/// barriers carry in it (the force pass on the initial state, not 0).
fn initial_sample(sim: &mut AnySimulation) -> Result<Sample, GranularError> {
    let mut s = sim.sample();
    s.barriers = sim
        .state_loads()
        .map_err(|e| GranularError::InitialLoads(Box::new(e)))?;
    Ok(s)
}

impl Granular {
    /// Load `scene.toml` from the FMU's resources directory.
    pub fn from_resources(dir: &Path) -> Result<Self, GranularError> {
        let path = dir.join("scene.toml");
        let file = path.display().to_string();
        let text = ReadError::read_to_string(path)?;
        let loaded =
            load_scene_in(&text, &file, &[], dir).map_err(|e| GranularError::Scene(Box::new(e)))?;
        Self::new(loaded, dir)
    }

    /// Build from a loaded scene whose shape files live in `dir`.
    pub fn new(loaded: LoadedScene, dir: &Path) -> Result<Self, GranularError> {
        let mut sim = build_sim(&loaded)?;
        let table = build_table(&loaded, &sim)?;
        let values: Vec<f64> = table
            .variables
            .iter()
            .map(|v| v.start.unwrap_or(0.0))
            .collect();
        let last = initial_sample(&mut sim)?;
        let texts = table
            .variables
            .iter()
            .map(|v| v.start_text.clone().unwrap_or_default())
            .collect();
        Ok(Granular {
            loaded: Arc::new(loaded),
            dir: Arc::new(dir.to_path_buf()),
            built_with: values.clone(),
            values,
            table: Arc::new(table),
            sim,
            last,
            initialised: false,
            texts,
            instance: String::from("granmix"),
            sinks: None,
            start: 0.0,
            now: 0.0,
            solver_seconds: 0.0,
        })
    }

    /// Model-level facts for `modelDescription.xml`.
    pub fn info(&self, model_identifier: &str) -> ModelInfo {
        let s = &self.loaded.scene.simulation;
        ModelInfo {
            model_name: s
                .name
                .clone()
                .unwrap_or_else(|| model_identifier.to_string()),
            model_identifier: model_identifier.to_string(),
            guid: guid(&self.loaded.text),
            description: format!(
                "granmix: {}D SPH of binary granular mixtures against barriers",
                self.sim.dimension()
            ),
            stop_time: s.end_time,
            step_size: s.output_interval,
        }
    }

    fn params_changed(&self) -> bool {
        self.table.slots.iter().enumerate().any(|(i, slot)| {
            matches!(slot, Slot::SceneValue(_) | Slot::MultiRate)
                && self.values[i].to_bits() != self.built_with[i].to_bits()
        })
    }

    fn text_of(&self, wanted: Slot) -> &str {
        self.table
            .slots
            .iter()
            .position(|s| *s == wanted)
            .map(|i| self.texts[i].as_str())
            .unwrap_or("")
    }

    /// Open the particle channel and the recording the parameters ask for.
    fn open_sinks(&mut self) -> Result<(), GranularError> {
        let enabled = self
            .table
            .slots
            .iter()
            .position(|s| *s == Slot::IpcEnabled)
            .is_some_and(|i| self.values[i] != 0.0);
        // where the bulk outputs go, shared by the copies a master keeps for rollback,
        // so that a repeated step is published and recorded again
        let mut sinks = Sinks::default();
        if enabled {
            let spec = match self.text_of(Slot::IpcService) {
                "" => self.instance.clone(),
                s => s.to_string(),
            };
            let (f, c) = self.sim.particle_counts();
            let p = FramePublisher::open(&spec, f + c).map_err(GranularError::Publisher)?;
            sinks.push(ChannelSink::new(p, None));
        }
        let path = self.text_of(Slot::RecordPath).to_string();
        if !path.is_empty() {
            let l = &self.loaded;
            let info = SceneInfo {
                text: l.text.clone(),
                file: l.file.clone(),
                name: l.scene.simulation.name.clone(),
                dimension: self.sim.dimension(),
                water: self.sim.has_water(),
            };
            sinks.push(Recorder::create(Path::new(&path), &info).map_err(GranularError::Record)?);
        }
        self.sinks = (!sinks.is_empty()).then(|| Arc::new(Mutex::new(sinks)));
        Ok(())
    }

    /// Publish and record the state at the current communication point. Publishing
    /// never fails the step (a frame nobody can take is dropped); recording errors do.
    fn emit(&mut self) -> Result<(), GranularError> {
        let Some(sinks) = &self.sinks else {
            return Ok(());
        };
        let mut s = sinks.lock().map_err(|_| GranularError::SinksPoisoned)?;
        // stamped with the communication point (the experiment's start included)
        let sample = Sample {
            time: self.now,
            ..self.last.clone()
        };
        s.sample(&self.sim, &sample).map_err(GranularError::Write)
    }

    /// Rebuild the simulation when parameters changed since it was built.
    fn ensure_built(&mut self) -> Result<(), GranularError> {
        if !self.params_changed() {
            return Ok(());
        }
        self.sim = self.sim_with(&self.values)?;
        self.last = initial_sample(&mut self.sim)?;
        self.built_with = self.values.clone();
        Ok(())
    }

    /// The simulation the scene builds with parameter values `values`.
    fn sim_with(&self, values: &[f64]) -> Result<AnySimulation, GranularError> {
        let mut sets = Vec::new();
        for (i, slot) in self.table.slots.iter().enumerate() {
            let v = values[i];
            match slot {
                Slot::SceneValue(path) => sets.push(format!("{path}={v:?}")),
                Slot::MultiRate => sets.push(format!(
                    "simulation.time_stepping=\"{}\"",
                    if v != 0.0 {
                        "multi-rate"
                    } else {
                        "single-rate"
                    }
                )),
                _ => {}
            }
        }
        let l = &self.loaded;
        let loaded = load_scene_in(&l.text, &l.file, &sets, &self.dir)
            .map_err(|e| GranularError::Scene(Box::new(e)))?;
        build_sim(&loaded)
    }

    /// Run one communication step with the given barrier velocities.
    fn advance(&mut self, rec: StepRecord) -> Result<(), GranularError> {
        for &(b, v) in &rec.drives {
            self.sim.drive_barrier(b, v).map_err(GranularError::Drive)?;
        }
        let start = std::time::Instant::now();
        let r = self.sim.advance_to(rec.end);
        self.solver_seconds += start.elapsed().as_secs_f64();
        self.last = self.sim.sample();
        r.map_err(|e| GranularError::Solver(Box::new(e)))
    }
}

/// GUID of a granular FMU: derived from the scene text and the granmix version.
pub fn guid(scene_text: &str) -> String {
    let mut content = format!("granmix {}\n", env!("CARGO_PKG_VERSION")).into_bytes();
    content.extend_from_slice(scene_text.as_bytes());
    xml::guid_of(&content)
}

impl Model for Granular {
    fn variables(&self) -> &[Variable] {
        &self.table.variables
    }

    fn get(&mut self, vr: u32) -> Result<f64, ModelError> {
        if !self.initialised {
            self.ensure_built()?;
        }
        let i = vr as usize;
        let s = &self.last;
        Ok(match &self.table.slots[i] {
            Slot::Output(k) => self.table.outputs[*k].real(s),
            Slot::BarrierInput(..)
            | Slot::SceneValue(_)
            | Slot::MultiRate
            | Slot::IpcEnabled
            | Slot::IpcService
            | Slot::RecordPath => self.values[i],
        })
    }

    fn get_string(&mut self, vr: u32) -> Result<String, ModelError> {
        Ok(self.texts[vr as usize].clone())
    }

    fn check_string(&self, vr: u32) -> Result<(), ModelError> {
        if self.initialised {
            return Err(ModelError::Fixed {
                name: self.table.variables[vr as usize].name.clone(),
            });
        }
        Ok(())
    }

    fn set_string(&mut self, vr: u32, value: &str) -> Result<(), ModelError> {
        self.check_string(vr)?;
        self.texts[vr as usize] = value.to_string();
        Ok(())
    }

    fn set_instance_name(&mut self, name: &str) {
        self.instance = name.to_string();
    }

    fn terminate(&mut self) -> Result<(), ModelError> {
        match self.sinks.take() {
            Some(s) => Ok(s
                .lock()
                .map_err(|_| GranularError::SinksPoisoned)?
                .finish()
                .map_err(GranularError::Finish)?),
            None => Ok(()),
        }
    }

    fn check(&self, vr: u32, value: f64) -> Result<(), ModelError> {
        let v = &self.table.variables[vr as usize];
        if !value.is_finite() {
            return Err(ModelError::NotFinite {
                name: v.name.clone(),
                value,
            });
        }
        Ok(())
    }

    fn values_mut(&mut self) -> &mut [f64] {
        &mut self.values
    }

    /// Build with the final parameters, open the outputs and emit the first frame; on
    /// failure the model stays as before the call (not initialised, no outputs open).
    fn exit_initialization(&mut self) -> Result<(), ModelError> {
        self.ensure_built()?;
        self.open_sinks()?;
        if let Err(e) = self.emit() {
            self.sinks = None;
            return Err(e.into());
        }
        self.initialised = true;
        Ok(())
    }

    fn set_start_time(&mut self, start: f64) -> Result<(), ModelError> {
        if !start.is_finite() {
            return Err(ModelError::StartTime(start));
        }
        self.start = start;
        self.now = start;
        Ok(())
    }

    fn initialised(&self) -> bool {
        self.initialised
    }

    fn do_step(&mut self, t: f64, h: f64) -> Result<(), StepError> {
        check_step(t, h, self.now)?;
        // The simulation runs from 0: it lands on `sim time + h` when the master's
        // point is the one the model reached (so an experiment started at t0 steps
        // bitwise as one started at 0), on the master's `t + h` otherwise.
        let end = if t == self.now {
            self.sim.time() + h
        } else {
            (t + h) - self.start
        };
        let mut drives = Vec::new();
        for (b, mode) in self.table.inputs.iter().enumerate() {
            let Some(mode) = mode else { continue };
            let mut input = [0.0; 3];
            for (i, slot) in self.table.slots.iter().enumerate() {
                if let Slot::BarrierInput(bb, k) = slot {
                    if *bb == b {
                        input[*k] = self.values[i];
                    }
                }
            }
            let v = match mode {
                BarrierInput::Velocity => input,
                BarrierInput::Displacement => {
                    let d = self.sim.barrier_displacement(b);
                    [
                        (input[0] - d[0]) / h,
                        (input[1] - d[1]) / h,
                        (input[2] - d[2]) / h,
                    ]
                }
            };
            drives.push((b, v));
        }
        // every command checked before any is applied: a refused step changes nothing
        let span = end - self.sim.time();
        for &(b, v) in &drives {
            self.sim.check_drive(b, v, span).map_err(StepError::Drive)?;
        }
        self.advance(StepRecord { end, drives })?;
        self.now = t + h;
        Ok(self.emit()?)
    }

    fn time(&self) -> f64 {
        self.now
    }

    fn solver_seconds(&self) -> f64 {
        self.solver_seconds
    }

    fn reset(&mut self) -> Result<(), ModelError> {
        let instance = std::mem::take(&mut self.instance);
        *self = Granular::new((*self.loaded).clone(), &self.dir)?;
        self.instance = instance;
        Ok(())
    }

    fn snapshot(&self) -> Box<dyn Model> {
        Box::new(self.clone())
    }

    /// The state is the simulation itself (particles, walls, coarse grains, stepper
    /// state and neighbour lists, load accumulators, time and counters), the outputs of
    /// the last communication point and the parameter values, written with postcard
    /// and deflated inside the envelope of [`crate::envelope`]. Restoring costs
    /// O(particles) whatever the number of steps taken.
    fn to_bytes(&self, place: &Place) -> Result<Vec<u8>, ModelError> {
        let state = SavedRef {
            initialised: self.initialised,
            start: self.start,
            now: self.now,
            built_with: &self.built_with,
            values: &self.values,
            last: &self.last,
            sim: &self.sim,
        };
        let payload = postcard::to_stdvec(&state).map_err(StateError::Encode)?;
        Ok(envelope::seal(
            ModelKind::Granular,
            &guid(&self.loaded.text),
            STATE_ENCODING,
            place,
            &payload,
        )?)
    }

    fn restore_bytes(&self, bytes: &[u8]) -> Result<(Box<dyn Model>, Option<Place>), ModelError> {
        let opened = envelope::open(bytes, ModelKind::Granular, &guid(&self.loaded.text))?;
        let saved: Saved = postcard::from_bytes(&opened.payload).map_err(StateError::Decode)?;
        let n = self.values.len();
        if saved.values.len() != n || saved.built_with.len() != n {
            return Err(StateError::ValueCount {
                saved: saved.values.len(),
                model: n,
            }
            .into());
        }
        // the template: this instance's simulation if the state was built with the
        // same parameters, else the scene built with the state's (a state of another
        // instance of this FMU)
        let same = |a: &[f64], b: &[f64]| a.iter().zip(b).all(|(x, y)| x.to_bits() == y.to_bits());
        let other;
        let template = if same(&saved.built_with, &self.built_with) {
            &self.sim
        } else {
            other = self
                .sim_with(&saved.built_with)
                .map_err(|e| StateError::Parameters(Box::new(e)))?;
            &other
        };
        // a state taken in the error state may hold the blow-up's values; it cannot be
        // stepped before another restore or a reset
        let steppable = opened
            .place
            .as_ref()
            .is_none_or(|p| p.state != crate::state::State::Error);
        let mut sim = saved.sim;
        sim.take_static_from(template, steppable)
            .map_err(StateError::Scene)?;
        let model = Box::new(Granular {
            loaded: self.loaded.clone(),
            dir: self.dir.clone(),
            table: self.table.clone(),
            values: saved.values,
            built_with: saved.built_with,
            sim,
            last: saved.last,
            initialised: saved.initialised,
            texts: self.texts.clone(),
            instance: self.instance.clone(),
            sinks: self.sinks.clone(),
            start: saved.start,
            now: saved.now,
            solver_seconds: 0.0,
        });
        Ok((model, opened.place))
    }
}
