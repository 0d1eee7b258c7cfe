//! The 34 FMI 2.0 Co-Simulation functions. Every export checks its pointers at run
//! time, runs inside `catch_unwind` (a panic becomes fmi2Error and the error state,
//! never an unwind into the host) and checks the instance state against [`allowed`]. Functions granmix does
//! not support (derivatives, asynchronous stepping) return fmi2Error with a message.
//!
//! Safety contract of every export: `c` is null or a component returned by
//! `fmi2Instantiate` and not yet freed; array arguments point to at least `nvr`
//! elements; strings are NUL-terminated. This is the only module with `unsafe`.

use crate::error::{CallError, FmiError, ModelError, Unsupported};
use crate::instance::{self, Instance};
use crate::logger::{c_string, Logger, Write};
use crate::model::Model;
use crate::state::{allowed, Place, State};
use crate::variables::{lookup, Causality, Kind};
use fmi_sys::fmi2::*;
use std::ffi::{c_char, CStr};

/// The master's logger callback as a [`Write`] closure. User text goes through a `"%s"`
/// format so `%` in it is never interpreted.
fn logger_write(functions: &fmi2CallbackFunctions, instance_name: &str) -> Option<Write> {
    let callback = functions.logger?;
    let environment = functions.componentEnvironment;
    let name = c_string(instance_name);
    Some(Box::new(move |status, category: &CStr, message: &CStr| {
        // SAFETY: the master gave us this logger in fmi2Instantiate for the life of the
        // instance; all strings are NUL-terminated and outlive the call.
        unsafe {
            callback(
                environment,
                name.as_ptr(),
                status,
                category.as_ptr(),
                c"%s".as_ptr(),
                message.as_ptr(),
            )
        }
    }))
}

const OK: fmi2Status = fmi2Status_fmi2OK;
const ERROR: fmi2Status = fmi2Status_fmi2Error;

/// Run `f` on the instance behind `c` if `function` may be called in its state, and
/// return the status of its outcome ([`report`]); a panic returns fmi2Error with its
/// message and place ([`crate::panics`]) and puts the instance in the error state.
unsafe fn with_instance(
    c: fmi2Component,
    function: &str,
    states: u8,
    f: impl FnOnce(&mut Instance) -> Result<(), FmiError>,
) -> fmi2Status {
    if c.is_null() {
        return ERROR;
    }
    // SAFETY: non-null components are boxed instances from fmi2Instantiate.
    let inst = unsafe { &mut *(c as *mut Instance) };
    let r = crate::panics::catch(|| {
        if !inst.state.in_set(states) {
            if let (State::Error, Some(failure)) = (inst.state, &inst.failure) {
                let failure = failure.clone();
                return Err(CallError::InError { failure }.into());
            }
            return Err(CallError::State(inst.state).into());
        }
        f(inst)
    });
    match r {
        Ok(r) => report(inst, function, r),
        Err(what) => {
            // the instance's model may be half-updated: only fmi2SetFMUstate and
            // fmi2Reset lead out, as after a blow-up
            let message = format!(
                "{function}: internal error: {what}; the instance is in the error state \
                 (restore a saved state with fmi2SetFMUstate, or call fmi2Reset)"
            );
            inst.state = State::Error;
            inst.failure = Some(message.clone());
            inst.logger.log(ERROR, "logStatusError", &message);
            ERROR
        }
    }
}

/// The status of a call of `function` that ended with `r`, the one place where an
/// [`FmiError`] becomes an `fmi2Status`: both kinds return fmi2Error with the message
/// logged as `<function>: <message>`; [`FmiError::Failed`] also puts the instance in the
/// error state, [`FmiError::BadCall`] leaves its state as the call left it.
fn report(inst: &mut Instance, function: &str, r: Result<(), FmiError>) -> fmi2Status {
    let e = match r {
        Ok(()) => return OK,
        Err(e) => e,
    };
    let message = format!("{function}: {e}");
    if let FmiError::Failed(_) = e {
        inst.state = State::Error;
        inst.failure = Some(message.clone());
    }
    inst.logger.log(ERROR, "logStatusError", &message);
    ERROR
}

/// Catch panics of functions that have no instance.
fn guard<T>(fallback: T, f: impl FnOnce() -> T) -> T {
    crate::panics::catch(f).unwrap_or(fallback)
}

unsafe fn slice<'a, T>(p: *const T, n: usize) -> Result<&'a [T], CallError> {
    if n == 0 {
        return Ok(&[]);
    }
    if p.is_null() {
        return Err(CallError::Null("array pointer"));
    }
    // SAFETY: caller guarantees `n` readable elements.
    Ok(unsafe { std::slice::from_raw_parts(p, n) })
}

unsafe fn slice_mut<'a, T>(p: *mut T, n: usize) -> Result<&'a mut [T], CallError> {
    if n == 0 {
        return Ok(&mut []);
    }
    if p.is_null() {
        return Err(CallError::Null("array pointer"));
    }
    // SAFETY: caller guarantees `n` writable elements.
    Ok(unsafe { std::slice::from_raw_parts_mut(p, n) })
}

unsafe fn string(p: fmi2String) -> Option<String> {
    if p.is_null() {
        return None;
    }
    // SAFETY: caller guarantees a NUL-terminated string.
    Some(unsafe { CStr::from_ptr(p) }.to_string_lossy().into_owned())
}

/// fmi2GetTypesPlatform: "default".
#[no_mangle]
pub extern "C" fn fmi2GetTypesPlatform() -> *const c_char {
    fmi2TypesPlatform.as_ptr() as *const c_char
}

/// fmi2GetVersion: "2.0".
#[no_mangle]
pub extern "C" fn fmi2GetVersion() -> *const c_char {
    fmi2Version.as_ptr() as *const c_char
}

/// fmi2SetDebugLogging: switch informational messages on or off (categories ignored).
///
/// # Safety
/// See the module documentation.
#[no_mangle]
pub unsafe extern "C" fn fmi2SetDebugLogging(
    c: fmi2Component,
    logging_on: fmi2Boolean,
    _n_categories: usize,
    _categories: *const fmi2String,
) -> fmi2Status {
    unsafe {
        with_instance(c, "fmi2SetDebugLogging", allowed::ANY_BUT_FATAL, |i| {
            i.logger.debug = logging_on != 0;
            Ok(())
        })
    }
}

/// fmi2Instantiate: load the model from `resources/`, check the GUID and return a new
/// component, or null (with a logged reason) on failure.
///
/// # Safety
/// Strings are null or NUL-terminated; `functions` is null or valid for the call.
#[no_mangle]
pub unsafe extern "C" fn fmi2Instantiate(
    instance_name: fmi2String,
    fmu_type: fmi2Type,
    guid: fmi2String,
    resource_location: fmi2String,
    functions: *const fmi2CallbackFunctions,
    _visible: fmi2Boolean,
    logging_on: fmi2Boolean,
) -> fmi2Component {
    guard(std::ptr::null_mut(), || {
        if functions.is_null() {
            return std::ptr::null_mut();
        }
        // SAFETY: checked non-null; the master keeps it valid during the call.
        let f = unsafe { &*functions };
        let name = unsafe { string(instance_name) }.unwrap_or_default();
        let logger = Logger::new(logger_write(f, &name), logging_on != 0);
        let uri = unsafe { string(resource_location) };
        let given = unsafe { string(guid) }.unwrap_or_default();
        let co_simulation = fmu_type == fmi2Type_fmi2CoSimulation;
        let (model, dir) = match instance::open(&name, co_simulation, &given, uri.as_deref()) {
            Ok(m) => m,
            Err(e) => {
                logger.log(ERROR, "logStatusError", &format!("fmi2Instantiate: {e}"));
                return std::ptr::null_mut();
            }
        };
        logger.log(
            OK,
            "logAll",
            &format!("instantiated from {}", dir.display()),
        );
        Box::into_raw(Box::new(Instance {
            logger,
            state: State::Instantiated,
            model,
            resources: dir,
            strings: Vec::new(),
            failure: None,
            stop_time: None,
        })) as fmi2Component
    })
}

/// fmi2FreeInstance: release the component (null is ignored).
///
/// # Safety
/// See the module documentation; `c` is invalid afterwards.
#[no_mangle]
pub unsafe extern "C" fn fmi2FreeInstance(c: fmi2Component) {
    if c.is_null() {
        return;
    }
    guard((), || {
        // SAFETY: `c` came from Box::into_raw in fmi2Instantiate.
        drop(unsafe { Box::from_raw(c as *mut Instance) });
    })
}

/// fmi2SetupExperiment: the experiment starts at `start_time` (any finite time: model
/// time, communication points and output stamps are shifted by it) and, if
/// `stop_time_defined`, ends at `stop_time` (finite, not before the start): no step may
/// end after it. The tolerance is unused.
///
/// # Safety
/// See the module documentation.
#[no_mangle]
pub unsafe extern "C" fn fmi2SetupExperiment(
    c: fmi2Component,
    _tolerance_defined: fmi2Boolean,
    _tolerance: fmi2Real,
    start_time: fmi2Real,
    stop_time_defined: fmi2Boolean,
    stop_time: fmi2Real,
) -> fmi2Status {
    unsafe {
        with_instance(c, "fmi2SetupExperiment", allowed::INSTANTIATED, |i| {
            if !start_time.is_finite() {
                return Err(ModelError::StartTime(start_time).into());
            }
            let stop = (stop_time_defined != 0).then_some(stop_time);
            if let Some(stop) = stop {
                if !stop.is_finite() || stop < start_time {
                    return Err(CallError::StopTime {
                        start: start_time,
                        stop,
                    }
                    .into());
                }
            }
            i.model.set_start_time(start_time)?;
            i.stop_time = stop;
            Ok(())
        })
    }
}

/// fmi2EnterInitializationMode.
///
/// # Safety
/// See the module documentation.
#[no_mangle]
pub unsafe extern "C" fn fmi2EnterInitializationMode(c: fmi2Component) -> fmi2Status {
    unsafe {
        with_instance(
            c,
            "fmi2EnterInitializationMode",
            allowed::INSTANTIATED,
            |i| {
                i.state = State::InitializationMode;
                Ok(())
            },
        )
    }
}

/// fmi2ExitInitializationMode: parameters become final (the simulation is rebuilt if
/// any changed).
///
/// # Safety
/// See the module documentation.
#[no_mangle]
pub unsafe extern "C" fn fmi2ExitInitializationMode(c: fmi2Component) -> fmi2Status {
    unsafe {
        with_instance(c, "fmi2ExitInitializationMode", allowed::INIT, |i| {
            // a refusal (parameters that do not build, the memory budget, an output
            // that cannot be opened) leaves the instance in initialisation mode, so
            // the master can set other parameters and try again
            i.model.exit_initialization()?;
            i.state = State::StepMode;
            Ok(())
        })
    }
}

/// fmi2Terminate.
///
/// # Safety
/// See the module documentation.
#[no_mangle]
pub unsafe extern "C" fn fmi2Terminate(c: fmi2Component) -> fmi2Status {
    unsafe {
        with_instance(c, "fmi2Terminate", allowed::TERMINATE, |i| {
            i.state = State::Terminated;
            i.model.terminate()?;
            Ok(())
        })
    }
}

/// fmi2Reset: back to the instantiated state with start values.
///
/// # Safety
/// See the module documentation.
#[no_mangle]
pub unsafe extern "C" fn fmi2Reset(c: fmi2Component) -> fmi2Status {
    unsafe {
        with_instance(c, "fmi2Reset", allowed::ANY_BUT_FATAL, |i| {
            i.model.reset()?;
            i.state = State::Instantiated;
            i.failure = None;
            i.stop_time = None;
            Ok(())
        })
    }
}

/// Shared getter path: look each value reference up with its type and read it.
unsafe fn get_values<T>(
    c: fmi2Component,
    function: &str,
    kind: Kind,
    vr: *const fmi2ValueReference,
    nvr: usize,
    value: *mut T,
    convert: fn(f64) -> T,
) -> fmi2Status {
    unsafe {
        with_instance(c, function, allowed::GET, |i| {
            let vrs = slice(vr, nvr)?;
            let out = slice_mut(value, nvr)?;
            for (o, &r) in out.iter_mut().zip(vrs) {
                lookup(i.model.variables(), r, kind)?;
                *o = convert(i.model.get(r)?);
            }
            Ok(())
        })
    }
}

/// Whether variable `vr` of type `kind` may be set in state `state`.
fn settable(model: &dyn Model, vr: u32, kind: Kind, state: State) -> Result<(), CallError> {
    let var = lookup(model.variables(), vr, kind)?;
    let name = var.name.clone();
    match (var.causality, state) {
        (Causality::Output, _) => Err(CallError::Output { name }),
        (Causality::Parameter, State::StepMode) => Err(CallError::ParameterFixed { name }),
        _ => Ok(()),
    }
}

/// Shared setter path: parameters before step mode, inputs at any time before the end.
/// Every entry is checked (value reference, type, causality, state, the model's own
/// checks) before any is applied, so a rejected call changes nothing.
unsafe fn set_values<T: Copy>(
    c: fmi2Component,
    function: &str,
    kind: Kind,
    vr: *const fmi2ValueReference,
    nvr: usize,
    value: *const T,
    convert: fn(T) -> f64,
) -> fmi2Status {
    unsafe {
        with_instance(c, function, allowed::SET, |i| {
            let vrs = slice(vr, nvr)?;
            let vals = slice(value, nvr)?;
            for (&v, &r) in vals.iter().zip(vrs) {
                settable(i.model.as_ref(), r, kind, i.state)?;
                i.model.check(r, convert(v))?;
            }
            for (&v, &r) in vals.iter().zip(vrs) {
                i.model.set(r, convert(v))?;
            }
            Ok(())
        })
    }
}

/// fmi2GetReal.
///
/// # Safety
/// See the module documentation.
#[no_mangle]
pub unsafe extern "C" fn fmi2GetReal(
    c: fmi2Component,
    vr: *const fmi2ValueReference,
    nvr: usize,
    value: *mut fmi2Real,
) -> fmi2Status {
    unsafe { get_values(c, "fmi2GetReal", Kind::Real, vr, nvr, value, |x| x) }
}

/// fmi2GetInteger.
///
/// # Safety
/// See the module documentation.
#[no_mangle]
pub unsafe extern "C" fn fmi2GetInteger(
    c: fmi2Component,
    vr: *const fmi2ValueReference,
    nvr: usize,
    value: *mut fmi2Integer,
) -> fmi2Status {
    unsafe {
        get_values(c, "fmi2GetInteger", Kind::Integer, vr, nvr, value, |x| {
            x.clamp(i32::MIN as f64, i32::MAX as f64) as fmi2Integer
        })
    }
}

/// fmi2GetBoolean.
///
/// # Safety
/// See the module documentation.
#[no_mangle]
pub unsafe extern "C" fn fmi2GetBoolean(
    c: fmi2Component,
    vr: *const fmi2ValueReference,
    nvr: usize,
    value: *mut fmi2Boolean,
) -> fmi2Status {
    unsafe {
        get_values(c, "fmi2GetBoolean", Kind::Boolean, vr, nvr, value, |x| {
            (x != 0.0) as fmi2Boolean
        })
    }
}

/// fmi2GetString: the strings stay valid until the next fmi2GetString on this
/// instance (the instance keeps them).
///
/// # Safety
/// See the module documentation.
#[no_mangle]
pub unsafe extern "C" fn fmi2GetString(
    c: fmi2Component,
    vr: *const fmi2ValueReference,
    nvr: usize,
    value: *mut fmi2String,
) -> fmi2Status {
    unsafe {
        with_instance(c, "fmi2GetString", allowed::GET, |i| {
            let vrs = slice(vr, nvr)?;
            let out = slice_mut(value, nvr)?;
            let mut held = Vec::with_capacity(nvr);
            for &r in vrs {
                lookup(i.model.variables(), r, Kind::String)?;
                held.push(c_string(&i.model.get_string(r)?));
            }
            for (o, h) in out.iter_mut().zip(&held) {
                *o = h.as_ptr();
            }
            i.strings = held;
            Ok(())
        })
    }
}

/// fmi2SetReal.
///
/// # Safety
/// See the module documentation.
#[no_mangle]
pub unsafe extern "C" fn fmi2SetReal(
    c: fmi2Component,
    vr: *const fmi2ValueReference,
    nvr: usize,
    value: *const fmi2Real,
) -> fmi2Status {
    unsafe { set_values(c, "fmi2SetReal", Kind::Real, vr, nvr, value, |x| x) }
}

/// fmi2SetInteger.
///
/// # Safety
/// See the module documentation.
#[no_mangle]
pub unsafe extern "C" fn fmi2SetInteger(
    c: fmi2Component,
    vr: *const fmi2ValueReference,
    nvr: usize,
    value: *const fmi2Integer,
) -> fmi2Status {
    unsafe {
        set_values(c, "fmi2SetInteger", Kind::Integer, vr, nvr, value, |x| {
            x as f64
        })
    }
}

/// fmi2SetBoolean.
///
/// # Safety
/// See the module documentation.
#[no_mangle]
pub unsafe extern "C" fn fmi2SetBoolean(
    c: fmi2Component,
    vr: *const fmi2ValueReference,
    nvr: usize,
    value: *const fmi2Boolean,
) -> fmi2Status {
    unsafe {
        set_values(c, "fmi2SetBoolean", Kind::Boolean, vr, nvr, value, |x| {
            (x != 0) as u8 as f64
        })
    }
}

/// fmi2SetString: String parameters, before step mode; all entries are checked before
/// any is applied.
///
/// # Safety
/// See the module documentation.
#[no_mangle]
pub unsafe extern "C" fn fmi2SetString(
    c: fmi2Component,
    vr: *const fmi2ValueReference,
    nvr: usize,
    value: *const fmi2String,
) -> fmi2Status {
    unsafe {
        with_instance(c, "fmi2SetString", allowed::SET, |i| {
            let vrs = slice(vr, nvr)?;
            let vals = slice(value, nvr)?;
            let mut texts = Vec::with_capacity(nvr);
            for (&p, &r) in vals.iter().zip(vrs) {
                settable(i.model.as_ref(), r, Kind::String, i.state)?;
                i.model.check_string(r)?;
                let Some(text) = string(p) else {
                    let name = i.model.variables()[r as usize].name.clone();
                    return Err(CallError::NullString { name }.into());
                };
                texts.push(text);
            }
            for (text, &r) in texts.iter().zip(vrs) {
                i.model.set_string(r, text)?;
            }
            Ok(())
        })
    }
}

/// An FMU state: a full copy of the model and the instance's place in the state
/// machine, so that restoring a state taken before an fmi2Error leaves the error
/// state (FMI 2.0 §2.1.3, status fmi2Error: "it can be tried to restart the
/// simulation from a formerly stored FMU state by calling fmi2SetFMUstate").
struct Snapshot {
    model: Box<dyn Model>,
    place: Place,
}

/// fmi2GetFMUstate: copy the model state into `*state` (reusing it when non-null).
///
/// # Safety
/// See the module documentation; `state` points to null or a state from this FMU.
#[no_mangle]
pub unsafe extern "C" fn fmi2GetFMUstate(c: fmi2Component, state: *mut fmi2FMUstate) -> fmi2Status {
    unsafe {
        with_instance(c, "fmi2GetFMUstate", allowed::STATE, |i| {
            if state.is_null() {
                return Err(CallError::Null("FMUstate pointer").into());
            }
            let snap = Snapshot {
                model: i.model.snapshot(),
                place: Place {
                    state: i.state,
                    failure: i.failure.clone(),
                },
            };
            if (*state).is_null() {
                *state = Box::into_raw(Box::new(snap)) as fmi2FMUstate;
            } else {
                // SAFETY: non-null states are boxed snapshots made here.
                *(*state as *mut Snapshot) = snap;
            }
            Ok(())
        })
    }
}

/// fmi2SetFMUstate: restore the model and the instance state from a state (the state
/// stays valid). From the error state this is the retry FMI 2.0 allows: a state taken
/// in step mode puts the instance back in step mode.
///
/// # Safety
/// See the module documentation; `state` is a state from this FMU.
#[no_mangle]
pub unsafe extern "C" fn fmi2SetFMUstate(c: fmi2Component, state: fmi2FMUstate) -> fmi2Status {
    unsafe {
        with_instance(c, "fmi2SetFMUstate", allowed::STATE, |i| {
            if state.is_null() {
                return Err(CallError::Null("FMUstate").into());
            }
            // SAFETY: non-null states are boxed snapshots made here.
            let snap = &*(state as *const Snapshot);
            i.model = snap.model.snapshot();
            i.state = snap.place.state;
            i.failure = snap.place.failure.clone();
            Ok(())
        })
    }
}

/// fmi2FreeFMUstate: release `*state` and set it to null.
///
/// # Safety
/// See the module documentation.
#[no_mangle]
pub unsafe extern "C" fn fmi2FreeFMUstate(
    c: fmi2Component,
    state: *mut fmi2FMUstate,
) -> fmi2Status {
    unsafe {
        with_instance(c, "fmi2FreeFMUstate", allowed::STATE, |_| {
            if state.is_null() || (*state).is_null() {
                return Ok(());
            }
            // SAFETY: non-null states are boxed snapshots made here.
            drop(Box::from_raw(*state as *mut Snapshot));
            *state = std::ptr::null_mut();
            Ok(())
        })
    }
}

unsafe fn state_bytes(state: fmi2FMUstate) -> Result<Vec<u8>, FmiError> {
    if state.is_null() {
        return Err(CallError::Null("FMUstate").into());
    }
    // SAFETY: non-null states are boxed snapshots made here.
    let snap = unsafe { &*(state as *const Snapshot) };
    Ok(snap.model.to_bytes(&snap.place)?)
}

/// fmi2SerializedFMUstateSize.
///
/// # Safety
/// See the module documentation.
#[no_mangle]
pub unsafe extern "C" fn fmi2SerializedFMUstateSize(
    c: fmi2Component,
    state: fmi2FMUstate,
    size: *mut usize,
) -> fmi2Status {
    unsafe {
        with_instance(c, "fmi2SerializedFMUstateSize", allowed::STATE, |_| {
            if size.is_null() {
                return Err(CallError::Null("size pointer").into());
            }
            *size = state_bytes(state)?.len();
            Ok(())
        })
    }
}

/// fmi2SerializeFMUstate: write the state into `serialized` (`size` bytes).
///
/// # Safety
/// See the module documentation.
#[no_mangle]
pub unsafe extern "C" fn fmi2SerializeFMUstate(
    c: fmi2Component,
    state: fmi2FMUstate,
    serialized: *mut fmi2Byte,
    size: usize,
) -> fmi2Status {
    unsafe {
        with_instance(c, "fmi2SerializeFMUstate", allowed::STATE, |_| {
            let bytes = state_bytes(state)?;
            if bytes.len() != size {
                return Err(CallError::Buffer {
                    size,
                    needed: bytes.len(),
                }
                .into());
            }
            let out = slice_mut(serialized as *mut u8, size)?;
            out.copy_from_slice(&bytes);
            Ok(())
        })
    }
}

/// fmi2DeSerializeFMUstate: rebuild a state from bytes into `*state`.
///
/// # Safety
/// See the module documentation.
#[no_mangle]
pub unsafe extern "C" fn fmi2DeSerializeFMUstate(
    c: fmi2Component,
    serialized: *const fmi2Byte,
    size: usize,
    state: *mut fmi2FMUstate,
) -> fmi2Status {
    unsafe {
        with_instance(c, "fmi2DeSerializeFMUstate", allowed::STATE, |i| {
            if state.is_null() {
                return Err(CallError::Null("FMUstate pointer").into());
            }
            let bytes = slice(serialized as *const u8, size)?;
            let (model, place) = i.model.restore_bytes(bytes)?;
            // the bytes carry the instance's place (the error and terminated states
            // included); in a version 2 state it follows from the model
            let place = place.unwrap_or_else(|| Place {
                state: if model.initialised() {
                    State::StepMode
                } else {
                    State::Instantiated
                },
                failure: None,
            });
            let snap = Snapshot { model, place };
            if (*state).is_null() {
                *state = Box::into_raw(Box::new(snap)) as fmi2FMUstate;
            } else {
                *(*state as *mut Snapshot) = snap;
            }
            Ok(())
        })
    }
}

/// fmi2GetDirectionalDerivative: not provided (providesDirectionalDerivative = false).
///
/// # Safety
/// See the module documentation.
#[no_mangle]
pub unsafe extern "C" fn fmi2GetDirectionalDerivative(
    c: fmi2Component,
    _unknown: *const fmi2ValueReference,
    _n_unknown: usize,
    _known: *const fmi2ValueReference,
    _n_known: usize,
    _dv_known: *const fmi2Real,
    _dv_unknown: *mut fmi2Real,
) -> fmi2Status {
    unsafe {
        with_instance(
            c,
            "fmi2GetDirectionalDerivative",
            allowed::ANY_BUT_FATAL,
            |_| Err(CallError::from(Unsupported::DirectionalDerivatives).into()),
        )
    }
}

/// fmi2SetRealInputDerivatives: not supported (canInterpolateInputs = false).
///
/// # Safety
/// See the module documentation.
#[no_mangle]
pub unsafe extern "C" fn fmi2SetRealInputDerivatives(
    c: fmi2Component,
    _vr: *const fmi2ValueReference,
    _nvr: usize,
    _order: *const fmi2Integer,
    _value: *const fmi2Real,
) -> fmi2Status {
    unsafe {
        with_instance(
            c,
            "fmi2SetRealInputDerivatives",
            allowed::ANY_BUT_FATAL,
            |_| Err(CallError::from(Unsupported::InputDerivatives).into()),
        )
    }
}

/// fmi2GetRealOutputDerivatives: not supported (maxOutputDerivativeOrder = 0).
///
/// # Safety
/// See the module documentation.
#[no_mangle]
pub unsafe extern "C" fn fmi2GetRealOutputDerivatives(
    c: fmi2Component,
    _vr: *const fmi2ValueReference,
    _nvr: usize,
    _order: *const fmi2Integer,
    _value: *mut fmi2Real,
) -> fmi2Status {
    unsafe {
        with_instance(
            c,
            "fmi2GetRealOutputDerivatives",
            allowed::ANY_BUT_FATAL,
            |_| Err(CallError::from(Unsupported::OutputDerivatives).into()),
        )
    }
}

/// fmi2DoStep: advance from `t` by `h`, landing exactly on t + h. A rejected call
/// (non-finite or mismatched `t`, `h` not positive and finite or too small to change
/// `t`) returns fmi2Error and leaves the instance as it was; a numerical blow-up
/// returns fmi2Error with the diagnostic and puts the instance in the error state,
/// from which `fmi2SetFMUstate` restarts it.
///
/// # Safety
/// See the module documentation.
#[no_mangle]
pub unsafe extern "C" fn fmi2DoStep(
    c: fmi2Component,
    t: fmi2Real,
    h: fmi2Real,
    _no_set_prior: fmi2Boolean,
) -> fmi2Status {
    unsafe {
        with_instance(c, "fmi2DoStep", allowed::STEP, |i| {
            if let Some(stop) = i.stop_time {
                past_stop(t, h, stop)?;
            }
            Ok(i.model.do_step(t, h)?)
        })
    }
}

/// Whether a step from `t` by `h` ends after `stop`, beyond the rounding of a master
/// that sums its step sizes (a relative 1e-9 of the stop time, at least 1e-9 s).
fn past_stop(t: f64, h: f64, stop: f64) -> Result<(), CallError> {
    let slack = 1e-9 * stop.abs().max(1.0);
    if t + h > stop + slack {
        return Err(CallError::PastStopTime { t, h, stop });
    }
    Ok(())
}

/// fmi2CancelStep: steps are synchronous, there is nothing to cancel.
///
/// # Safety
/// See the module documentation.
#[no_mangle]
pub unsafe extern "C" fn fmi2CancelStep(c: fmi2Component) -> fmi2Status {
    unsafe {
        with_instance(c, "fmi2CancelStep", allowed::ANY_BUT_FATAL, |_| {
            Err(CallError::from(Unsupported::Asynchronous).into())
        })
    }
}

/// fmi2GetStatus: only meaningful after fmi2Pending, which never happens.
///
/// # Safety
/// See the module documentation.
#[no_mangle]
pub unsafe extern "C" fn fmi2GetStatus(
    c: fmi2Component,
    _kind: fmi2StatusKind,
    _value: *mut fmi2Status,
) -> fmi2Status {
    unsafe {
        with_instance(c, "fmi2GetStatus", allowed::ANY_BUT_FATAL, |_| {
            Err(CallError::from(Unsupported::Asynchronous).into())
        })
    }
}

/// fmi2GetRealStatus: fmi2LastSuccessfulTime gives the model time.
///
/// # Safety
/// See the module documentation.
#[no_mangle]
pub unsafe extern "C" fn fmi2GetRealStatus(
    c: fmi2Component,
    kind: fmi2StatusKind,
    value: *mut fmi2Real,
) -> fmi2Status {
    unsafe {
        with_instance(c, "fmi2GetRealStatus", allowed::STATUS, |i| {
            if kind != fmi2StatusKind_fmi2LastSuccessfulTime {
                return Err(CallError::StatusKind { kind, of: "Real" }.into());
            }
            if value.is_null() {
                return Err(CallError::Null("value pointer").into());
            }
            *value = i.model.time();
            Ok(())
        })
    }
}

/// fmi2GetIntegerStatus: no Integer status exists.
///
/// # Safety
/// See the module documentation.
#[no_mangle]
pub unsafe extern "C" fn fmi2GetIntegerStatus(
    c: fmi2Component,
    kind: fmi2StatusKind,
    _value: *mut fmi2Integer,
) -> fmi2Status {
    unsafe {
        with_instance(c, "fmi2GetIntegerStatus", allowed::ANY_BUT_FATAL, |_| {
            Err(CallError::StatusKind {
                kind,
                of: "Integer",
            }
            .into())
        })
    }
}

/// fmi2GetBooleanStatus: fmi2Terminated is always false (the model never ends a
/// simulation on its own).
///
/// # Safety
/// See the module documentation.
#[no_mangle]
pub unsafe extern "C" fn fmi2GetBooleanStatus(
    c: fmi2Component,
    kind: fmi2StatusKind,
    value: *mut fmi2Boolean,
) -> fmi2Status {
    unsafe {
        with_instance(c, "fmi2GetBooleanStatus", allowed::STATUS, |_| {
            if kind != fmi2StatusKind_fmi2Terminated {
                return Err(CallError::StatusKind {
                    kind,
                    of: "Boolean",
                }
                .into());
            }
            if value.is_null() {
                return Err(CallError::Null("value pointer").into());
            }
            *value = 0;
            Ok(())
        })
    }
}

/// fmi2GetStringStatus: only meaningful after fmi2Pending, which never happens.
///
/// # Safety
/// See the module documentation.
#[no_mangle]
pub unsafe extern "C" fn fmi2GetStringStatus(
    c: fmi2Component,
    _kind: fmi2StatusKind,
    _value: *mut fmi2String,
) -> fmi2Status {
    unsafe {
        with_instance(c, "fmi2GetStringStatus", allowed::ANY_BUT_FATAL, |_| {
            Err(CallError::from(Unsupported::Asynchronous).into())
        })
    }
}

/// Why a [`LocalInstance`] call failed (the instance has no logger to say more).
#[derive(Debug, thiserror::Error)]
pub enum LocalError {
    /// `fmi2Instantiate` returned null for the unpacked `resources`.
    #[error(
        "fmi2Instantiate failed on {} (no scene.toml or structure.toml, or another GUID)",
        resources.display()
    )]
    Instantiate { resources: std::path::PathBuf },
    /// Arrays of value references and values of different lengths.
    #[error("{function}: as many values as value references")]
    Lengths { function: &'static str },
    /// `function` returned `status`, not fmi2OK.
    #[error("{function} returned status {status}")]
    Status {
        function: &'static str,
        status: fmi2Status,
    },
}

/// An FMU instance driven from inside this process through the exported functions, as a
/// master drives one through the shared library: `granmix bench --suite fmi` times these
/// calls to measure the FMI layer (C entry point to the solver and back) against the
/// solver's own time. The instance has no logger, so a failed call reports its function
/// and status only.
pub struct LocalInstance {
    c: fmi2Component,
}

impl LocalInstance {
    /// fmi2Instantiate on an unpacked `resources` directory
    /// ([`crate::package::write_resources`]) with the FMU's `guid`, then
    /// fmi2SetupExperiment (start 0), fmi2EnterInitializationMode and
    /// fmi2ExitInitializationMode.
    pub fn new(name: &str, guid: &str, resources: &std::path::Path) -> Result<Self, LocalError> {
        let functions = fmi2CallbackFunctions {
            logger: None,
            allocateMemory: None,
            freeMemory: None,
            stepFinished: None,
            componentEnvironment: std::ptr::null_mut(),
        };
        let (name, guid) = (c_string(name), c_string(guid));
        let uri = c_string(&format!("file://{}", resources.display()));
        // SAFETY: NUL-terminated strings and a callback table that outlive the call.
        let c = unsafe {
            fmi2Instantiate(
                name.as_ptr(),
                fmi2Type_fmi2CoSimulation,
                guid.as_ptr(),
                uri.as_ptr(),
                &functions,
                0,
                0,
            )
        };
        if c.is_null() {
            return Err(LocalError::Instantiate {
                resources: resources.to_path_buf(),
            });
        }
        let inst = LocalInstance { c };
        // SAFETY (all calls below): `c` is a live component from fmi2Instantiate.
        check("fmi2SetupExperiment", unsafe {
            fmi2SetupExperiment(c, 0, 0.0, 0.0, 0, 0.0)
        })?;
        check("fmi2EnterInitializationMode", unsafe {
            fmi2EnterInitializationMode(c)
        })?;
        check("fmi2ExitInitializationMode", unsafe {
            fmi2ExitInitializationMode(c)
        })?;
        Ok(inst)
    }

    /// fmi2SetReal.
    pub fn set_real(&mut self, vr: &[u32], value: &[f64]) -> Result<(), LocalError> {
        if vr.len() != value.len() {
            return Err(LocalError::Lengths {
                function: "fmi2SetReal",
            });
        }
        // SAFETY: a live component and two arrays of `vr.len()` elements.
        check("fmi2SetReal", unsafe {
            fmi2SetReal(self.c, vr.as_ptr(), vr.len(), value.as_ptr())
        })
    }

    /// fmi2GetReal.
    pub fn get_real(&mut self, vr: &[u32], value: &mut [f64]) -> Result<(), LocalError> {
        if vr.len() != value.len() {
            return Err(LocalError::Lengths {
                function: "fmi2GetReal",
            });
        }
        // SAFETY: a live component and two arrays of `vr.len()` elements.
        check("fmi2GetReal", unsafe {
            fmi2GetReal(self.c, vr.as_ptr(), vr.len(), value.as_mut_ptr())
        })
    }

    /// fmi2GetInteger.
    pub fn get_integer(&mut self, vr: &[u32], value: &mut [i32]) -> Result<(), LocalError> {
        if vr.len() != value.len() {
            return Err(LocalError::Lengths {
                function: "fmi2GetInteger",
            });
        }
        // SAFETY: a live component and two arrays of `vr.len()` elements.
        check("fmi2GetInteger", unsafe {
            fmi2GetInteger(self.c, vr.as_ptr(), vr.len(), value.as_mut_ptr())
        })
    }

    /// fmi2DoStep from `t` by `h`.
    pub fn do_step(&mut self, t: f64, h: f64) -> Result<(), LocalError> {
        // SAFETY: a live component.
        check("fmi2DoStep", unsafe { fmi2DoStep(self.c, t, h, 1) })
    }

    /// fmi2GetFMUstate, fmi2SerializedFMUstateSize and fmi2SerializeFMUstate: the
    /// instance's state as bytes.
    pub fn state_bytes(&mut self) -> Result<Vec<u8>, LocalError> {
        let mut state: fmi2FMUstate = std::ptr::null_mut();
        // SAFETY (all calls below): a live component, a state pointer it fills, and a
        // buffer of the size it reports.
        check("fmi2GetFMUstate", unsafe {
            fmi2GetFMUstate(self.c, &mut state)
        })?;
        let mut size = 0usize;
        let r = check("fmi2SerializedFMUstateSize", unsafe {
            fmi2SerializedFMUstateSize(self.c, state, &mut size)
        })
        .and_then(|()| {
            let mut bytes = vec![0u8; size];
            check("fmi2SerializeFMUstate", unsafe {
                fmi2SerializeFMUstate(self.c, state, bytes.as_mut_ptr() as *mut fmi2Byte, size)
            })
            .map(|()| bytes)
        });
        unsafe { fmi2FreeFMUstate(self.c, &mut state) };
        r
    }

    /// fmi2DeSerializeFMUstate of `bytes`, then fmi2SetFMUstate and fmi2FreeFMUstate.
    pub fn restore(&mut self, bytes: &[u8]) -> Result<(), LocalError> {
        let mut state: fmi2FMUstate = std::ptr::null_mut();
        // SAFETY (all calls below): a live component, `bytes.len()` readable bytes and a
        // state pointer it fills.
        let r = check("fmi2DeSerializeFMUstate", unsafe {
            fmi2DeSerializeFMUstate(
                self.c,
                bytes.as_ptr() as *const fmi2Byte,
                bytes.len(),
                &mut state,
            )
        })
        .and_then(|()| check("fmi2SetFMUstate", unsafe { fmi2SetFMUstate(self.c, state) }));
        if !state.is_null() {
            unsafe { fmi2FreeFMUstate(self.c, &mut state) };
        }
        r
    }

    /// fmi2GetRealStatus(fmi2LastSuccessfulTime): the last communication point reached.
    pub fn time(&mut self) -> Result<f64, LocalError> {
        let mut t = 0.0;
        // SAFETY: a live component and a value it writes.
        check("fmi2GetRealStatus", unsafe {
            fmi2GetRealStatus(self.c, fmi2StatusKind_fmi2LastSuccessfulTime, &mut t)
        })?;
        Ok(t)
    }

    /// In the error state, the message of the call that put the instance there.
    pub fn failure(&self) -> Option<String> {
        // SAFETY: `c` is the boxed instance made by fmi2Instantiate, alive until drop.
        unsafe { &*(self.c as *const Instance) }.failure.clone()
    }

    /// The model's [`Model::solver_seconds`]: wall time inside the solver so far.
    pub fn solver_seconds(&self) -> f64 {
        // SAFETY: `c` is the boxed instance made by fmi2Instantiate, alive until drop.
        unsafe { &*(self.c as *const Instance) }
            .model
            .solver_seconds()
    }
}

impl Drop for LocalInstance {
    fn drop(&mut self) {
        // SAFETY: a live component, freed once; fmi2Terminate may fail in some states,
        // which does not matter before freeing.
        unsafe {
            fmi2Terminate(self.c);
            fmi2FreeInstance(self.c);
        }
    }
}

fn check(function: &'static str, status: fmi2Status) -> Result<(), LocalError> {
    if status == OK {
        return Ok(());
    }
    Err(LocalError::Status { function, status })
}
