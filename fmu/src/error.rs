//! The errors of the FMU's models and of its FMI calls.
//!
//! [`FmiError`] is what an FMI function fails with, classified by what the failure means
//! for the instance; [`crate::ffi`] turns it into the returned `fmi2Status` and the
//! instance's next state in one place. The models ([`crate::granular`],
//! [`crate::structure`]) fail with [`ModelError`], the error of the [`crate::model::Model`]
//! interface, and `fmi2DoStep` with [`StepError`]. [`GranularError`] and
//! [`StructureError`] live here rather than beside their models because
//! [`ModelError`] wraps them and the models implement that interface.
//!
//! Messages are the text the master's logger shows after `<function>: `; each names the
//! variable, key, file or value at fault. Errors of granmix-core and granmix-ipc are kept
//! as their message.

use crate::envelope::EnvelopeError;
use crate::state::State;
use crate::variables::LookupError;
use fmi_sys::fmi2::fmi2StatusKind;
use granmix_core::run::cosim::DriveError;
use granmix_core::scene::SceneError;
use granmix_core::Blowup;
use granmix_core::{SetupError, StateMismatch};
use granmix_ipc::{IpcError, SinkError};
use std::path::PathBuf;
use thiserror::Error;

/// How an FMI call failed. [`crate::ffi`] maps it, in one place, to the status it
/// returns and the state the instance goes to:
///
/// | variant | status | instance state |
/// |---|---|---|
/// | [`FmiError::BadCall`] | fmi2Error | as the call left it |
/// | [`FmiError::Failed`] | fmi2Error | Error |
///
/// A panic inside a call (a defect, or a restored state whose meaning the checks of
/// `fmi2DeSerializeFMUstate` did not catch) is not an `FmiError` either: [`crate::ffi`]
/// catches it and returns fmi2Error with the panic's message and place, and the instance
/// goes to the error state as for [`FmiError::Failed`] (no other instance is touched, so
/// fmi2Fatal would overstate it). No call returns fmi2Warning or fmi2Discard, and fmi2Pending never
/// happens (steps are synchronous).
#[derive(Debug, Error)]
pub enum FmiError {
    /// The call was wrong or could not be served, and nothing the instance holds was
    /// spoilt: the instance stays usable in the state it is in (`fmi2Terminate` has
    /// already ended the instance when closing its outputs fails).
    #[error(transparent)]
    BadCall(#[from] CallError),
    /// The model failed within the call and its state is no longer valid: a blow-up
    /// within `fmi2DoStep`. `fmi2SetFMUstate` or `fmi2Reset` leaves the error state.
    #[error(transparent)]
    Failed(ModelError),
}

impl From<ModelError> for FmiError {
    /// A model error is a bad call unless the function says it failed the model
    /// ([`StepError::Failed`]).
    fn from(e: ModelError) -> Self {
        FmiError::BadCall(CallError::Model(e))
    }
}

impl From<LookupError> for FmiError {
    fn from(e: LookupError) -> Self {
        FmiError::BadCall(CallError::Lookup(e))
    }
}

impl From<StepError> for FmiError {
    fn from(e: StepError) -> Self {
        match e {
            StepError::Rejected(e) => FmiError::BadCall(CallError::Step(e)),
            StepError::Drive(e) => FmiError::BadCall(CallError::Drive(e)),
            StepError::Failed(e) => FmiError::Failed(e),
        }
    }
}

/// What was wrong with a call, or why it could not be served.
#[derive(Debug, Error)]
pub enum CallError {
    /// The function may not be called in the instance's state.
    #[error("may not be called in state {0:?}")]
    State(State),
    /// A call not allowed in the error state (value getters, setters, steps): the
    /// message of the call that failed, and the ways out.
    #[error(
        "may not be called in the error state (entered by `{failure}`); restore a state \
         saved before (fmi2SetFMUstate) or call fmi2Reset"
    )]
    InError { failure: String },
    /// A null pointer where the function needs one: what it is (`size pointer`).
    #[error("null {0}")]
    Null(&'static str),
    /// A null string for String variable `name`.
    #[error("`{name}`: null string")]
    NullString { name: String },
    /// `fmi2SerializeFMUstate` with a buffer of another size than the state's.
    #[error("buffer of {size} bytes for a state of {needed}")]
    Buffer { size: usize, needed: usize },
    /// A setter on output `name`.
    #[error("`{name}` is an output and cannot be set")]
    Output { name: String },
    /// A setter on parameter `name` in step mode.
    #[error("parameter `{name}` is fixed once initialisation has ended")]
    ParameterFixed { name: String },
    /// A status getter asked for a kind it has no value of (`of`: Real, Integer, Boolean).
    #[error("status kind {kind} has no {of} value")]
    StatusKind {
        kind: fmi2StatusKind,
        of: &'static str,
    },
    #[error(transparent)]
    Unsupported(#[from] Unsupported),
    #[error(transparent)]
    Lookup(#[from] LookupError),
    /// `fmi2DoStep` with a communication point or step size the model refuses.
    #[error(transparent)]
    Step(#[from] BadStep),
    /// `fmi2DoStep` with a barrier input the solver cannot follow within the step (not
    /// finite, beyond the guard's speed bound, or too many solver steps).
    #[error(transparent)]
    Drive(DriveError),
    /// The model refused or could not serve the call and is as it was.
    #[error(transparent)]
    Model(#[from] ModelError),
    /// `fmi2SetupExperiment` with a stop time that is not finite or is before the start.
    #[error("stop time {stop:?} s is not a finite time at or after the start time {start:?} s")]
    StopTime { start: f64, stop: f64 },
    /// `fmi2DoStep` that would end after the experiment's stop time.
    #[error(
        "the step from {t:?} s by {h:?} s ends after the experiment's stop time {stop:?} s \
         (fmi2SetupExperiment)"
    )]
    PastStopTime { t: f64, h: f64, stop: f64 },
}

/// FMI functions granmix does not provide (the capability flags of
/// `modelDescription.xml` say so).
#[derive(Clone, Copy, Debug, PartialEq, Eq, Error)]
pub enum Unsupported {
    /// `fmi2GetDirectionalDerivative`.
    #[error("directional derivatives are not provided")]
    DirectionalDerivatives,
    /// `fmi2SetRealInputDerivatives`.
    #[error("input derivatives are not supported (canInterpolateInputs = false)")]
    InputDerivatives,
    /// `fmi2GetRealOutputDerivatives`.
    #[error("output derivatives are not provided (maxOutputDerivativeOrder = 0)")]
    OutputDerivatives,
    /// `fmi2CancelStep` and the status getters of asynchronous steps.
    #[error("steps are synchronous (fmi2DoStep never returns fmi2Pending)")]
    Asynchronous,
}

/// Why `fmi2DoStep` did not advance. The FFI layer adds the function name to the
/// message and decides the instance state from the variant ([`FmiError`]).
#[derive(Debug, Error)]
pub enum StepError {
    /// The call itself is wrong (communication point, step size): nothing was
    /// changed, the instance stays usable.
    #[error(transparent)]
    Rejected(#[from] BadStep),
    /// An input-driven barrier's command cannot be followed within the step: nothing
    /// was changed, the instance stays usable.
    #[error(transparent)]
    Drive(DriveError),
    /// The model failed within the step (blow-up): the state is no longer valid; the
    /// instance goes to the error state, from which `fmi2SetFMUstate` restarts it.
    #[error(transparent)]
    Failed(#[from] ModelError),
}

impl From<GranularError> for StepError {
    fn from(e: GranularError) -> Self {
        StepError::Failed(e.into())
    }
}

/// A communication step `(t, h)` the model refuses ([`crate::model::check_step`]); `now`
/// is the model time.
#[derive(Clone, Copy, Debug, PartialEq, Error)]
pub enum BadStep {
    #[error("communication point {t:?} s is not a finite time (the model is at {now:?} s)")]
    PointNotFinite { t: f64, now: f64 },
    #[error("step size {h:?} s must be positive and finite")]
    Size { h: f64 },
    #[error(
        "step size {h:?} s is too small to change the communication point {t:?} s \
         (t + h == t in double precision)"
    )]
    TooSmall { t: f64, h: f64 },
    #[error("communication point {t:?} s differs from the model time {now:?} s")]
    Mismatch { t: f64, now: f64 },
}

/// The error of the [`crate::model::Model`] interface.
#[derive(Debug, Error)]
pub enum ModelError {
    /// Parameter or input `name` set to a NaN or an infinity.
    #[error("`{name}` set to {value:?}: values must be finite")]
    NotFinite { name: String, value: f64 },
    /// Parameter `name` set outside its range (a structure's mass ≤ 0, a stiffness < 0).
    #[error("`{name}` = {value:?} is out of range")]
    OutOfRange { name: String, value: f64 },
    /// String parameter `name` set after initialisation.
    #[error("`{name}` is fixed once initialisation has ended")]
    Fixed { name: String },
    /// A String getter or setter on a model without String variables.
    #[error("value reference {vr}: the model has no String variables")]
    NoStrings { vr: u32 },
    /// An experiment start that is a NaN or an infinity.
    #[error("start time {0:?} s is not a finite time")]
    StartTime(f64),
    #[error(transparent)]
    State(#[from] StateError),
    #[error(transparent)]
    Granular(#[from] GranularError),
    #[error(transparent)]
    Structure(#[from] StructureError),
}

impl From<EnvelopeError> for ModelError {
    fn from(e: EnvelopeError) -> Self {
        ModelError::State(e.into())
    }
}

/// A serialised FMU state that cannot be written or read back.
#[derive(Debug, Error)]
pub enum StateError {
    /// The envelope (tag, checksum, version, kind, GUID, lengths) or a payload read past
    /// its end.
    #[error(transparent)]
    Envelope(#[from] EnvelopeError),
    /// The granular state does not serialise.
    #[error("serialising the state: {0}")]
    Encode(postcard::Error),
    /// The granular payload does not decode.
    #[error("serialised state: cannot decode its payload: {0}")]
    Decode(postcard::Error),
    /// A granular state with another number of parameter values than the model.
    #[error("serialised state has {saved} values, the model {model}")]
    ValueCount { saved: usize, model: usize },
    /// A structure state with a list of another length than the model's.
    #[error("serialised state: list of {found} values, expected {expected}")]
    ListLength { found: usize, expected: usize },
    /// The saved simulation does not fit the scene.
    #[error("serialised state: {0}")]
    Scene(StateMismatch),
    /// The scene does not build with the parameter values the state was built with.
    #[error("serialised state: the scene does not build with the state's parameters: {0}")]
    Parameters(Box<GranularError>),
}

/// A file that cannot be read.
#[derive(Debug, Error)]
#[error("cannot read {}: {error}", path.display())]
pub struct ReadError {
    pub path: PathBuf,
    pub error: std::io::Error,
}

impl ReadError {
    /// The text of `path`, or why not.
    pub fn read_to_string(path: PathBuf) -> Result<String, ReadError> {
        std::fs::read_to_string(&path).map_err(|error| ReadError { path, error })
    }
}

/// Errors of the granular model ([`crate::granular`]).
#[derive(Debug, Error)]
pub enum GranularError {
    #[error(transparent)]
    Read(#[from] ReadError),
    /// The scene, with the parameter values as overrides, does not load (the error
    /// names the file and key).
    #[error("{0}")]
    Scene(Box<SceneError>),
    /// The simulation cannot be built from the scene.
    #[error("{0}")]
    Setup(Box<SetupError>),
    /// Barrier `barrier` is input-driven in the scene but not in the built world, or the
    /// other way round.
    #[error("barrier `{barrier}`: input flag and world disagree")]
    InputFlag { barrier: String },
    /// Barrier `barrier` has `panels` counts of another number than `counts`.
    #[error("barrier `{barrier}`: panels must have {counts} counts")]
    PanelCounts { barrier: String, counts: usize },
    /// The force pass on the initial state failed.
    #[error("loads of the initial state: {0}")]
    InitialLoads(Box<Blowup>),
    /// The particle service of parameter `ipc.service` cannot be opened.
    #[error("ipc.service: {0}")]
    Publisher(IpcError),
    /// The recording of parameter `record.path` cannot be created.
    #[error("record.path: {0}")]
    Record(IpcError),
    /// An output (the recording of `record.path`) cannot be written.
    #[error("record.path: {}", .0.source)]
    Write(SinkError),
    /// The outputs cannot be closed.
    #[error("{}", .0.source)]
    Finish(SinkError),
    /// A thread panicked while holding the outputs.
    #[error("output sinks poisoned")]
    SinksPoisoned,
    /// An input-driven barrier cannot be driven.
    #[error("{0}")]
    Drive(DriveError),
    /// The solver failed within the step (the stability guard's diagnostic).
    #[error("{0}")]
    Solver(Box<Blowup>),
}

/// Errors of the structural partner models ([`crate::structure`]).
#[derive(Debug, Error)]
pub enum StructureError {
    #[error(transparent)]
    Read(#[from] ReadError),
    /// The structure file is not valid TOML or has unknown or missing keys.
    #[error("{file}: {error}")]
    Toml {
        file: String,
        error: toml::de::Error,
    },
    /// Key `structure.<key>` of `file` has a value out of range.
    #[error("{file}: structure.{key}: {why}")]
    Key {
        file: String,
        key: &'static str,
        why: &'static str,
    },
    /// The state went non-finite within a step ending at `t`.
    #[error("structure `{name}`: non-finite state at t = {t:?} s")]
    NonFinite { name: String, t: f64 },
}
