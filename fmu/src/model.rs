//! The small model interface the FFI layer drives: the granular simulation
//! ([`crate::granular`]) and the structural partners ([`crate::structure`]) implement it.

use crate::variables::Variable;

/// Why `fmi2DoStep` did not advance. The FFI layer adds the function name to the
/// message and decides the instance state from the variant.
#[derive(Clone, Debug, PartialEq, Eq)]
pub enum StepError {
    /// The call itself is wrong (communication point, step size): nothing was
    /// changed, the instance stays usable.
    Rejected(String),
    /// The solver failed within the step (blow-up): the state is no longer valid;
    /// the instance goes to the error state, from which `fmi2SetFMUstate` restarts it.
    Failed(String),
}

impl std::fmt::Display for StepError {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        match self {
            StepError::Rejected(m) | StepError::Failed(m) => f.write_str(m),
        }
    }
}

/// Check a communication step `(t, h)` against the model time `now`: both finite,
/// `h > 0` large enough to change `t`, and `t` within 1e-9 (relative) of `now`.
pub fn check_step(t: f64, h: f64, now: f64) -> Result<(), StepError> {
    let bad = |m: String| Err(StepError::Rejected(m));
    if !t.is_finite() {
        return bad(format!(
            "communication point {t:?} s is not a finite time (the model is at {now:?} s)"
        ));
    }
    if !(h.is_finite() && h > 0.0) {
        return bad(format!("step size {h:?} s must be positive and finite"));
    }
    if t + h == t {
        return bad(format!(
            "step size {h:?} s is too small to change the communication point {t:?} s \
             (t + h == t in double precision)"
        ));
    }
    if (t - now).abs() > 1e-9 * t.abs().max(h) {
        return bad(format!(
            "communication point {t:?} s differs from the model time {now:?} s"
        ));
    }
    Ok(())
}

/// A co-simulation model behind one FMU instance. Errors are messages for the logger.
pub trait Model: Send {
    /// The value-reference table (value reference = index).
    fn variables(&self) -> &[Variable];
    /// Current value of variable `vr` (Reals, Integers and Booleans as f64).
    fn get(&mut self, vr: u32) -> Result<f64, String>;
    /// Whether `value` is acceptable for parameter or input `vr` (the FFI layer has
    /// checked causality and state). Checked for every entry of a multi-value set
    /// before any is applied.
    fn check(&self, vr: u32, value: f64) -> Result<(), String>;
    /// Set parameter or input `vr` to a value [`Model::check`] accepted.
    fn set(&mut self, vr: u32, value: f64) -> Result<(), String>;
    /// Current value of String variable `vr`.
    fn get_string(&mut self, vr: u32) -> Result<String, String> {
        Err(format!(
            "value reference {vr}: the model has no String variables"
        ))
    }
    /// Whether String parameter `vr` may be set now.
    fn check_string(&self, vr: u32) -> Result<(), String> {
        Err(format!(
            "value reference {vr}: the model has no String variables"
        ))
    }
    /// Set String parameter `vr` (the FFI layer has checked causality and state).
    fn set_string(&mut self, vr: u32, _value: &str) -> Result<(), String> {
        Err(format!(
            "value reference {vr}: the model has no String variables"
        ))
    }
    /// The instance name the master gave in `fmi2Instantiate`.
    fn set_instance_name(&mut self, _name: &str) {}
    /// `fmi2Terminate`: close what the model writes.
    fn terminate(&mut self) -> Result<(), String> {
        Ok(())
    }
    /// Leave initialisation mode: parameters are final.
    fn exit_initialization(&mut self) -> Result<(), String>;
    /// `fmi2SetupExperiment`: the experiment starts at `start` (s); model time,
    /// communication points and output stamps are shifted by it.
    fn set_start_time(&mut self, start: f64) -> Result<(), String>;
    /// Whether initialisation has ended (a deserialised state in step mode).
    fn initialised(&self) -> bool;
    /// Advance from `t` by `h`, landing exactly on `t + h` ([`check_step`] first).
    fn do_step(&mut self, t: f64, h: f64) -> Result<(), StepError>;
    /// Model time (s), start time included.
    fn time(&self) -> f64;
    /// Wall time (s) spent inside the solver's own stepping since the model was built,
    /// so that the FMI layer around it can be measured (`granmix bench --suite fmi`).
    fn solver_seconds(&self) -> f64 {
        0.0
    }
    /// Back to the freshly instantiated state.
    fn reset(&mut self) -> Result<(), String>;
    /// A full copy of the state, for `fmi2GetFMUstate`.
    fn snapshot(&self) -> Box<dyn Model>;
    /// Bytes from which [`Model::restore_bytes`] rebuilds this exact state.
    fn to_bytes(&self) -> Result<Vec<u8>, String>;
    /// Rebuild the state written by [`Model::to_bytes`] (of a model of the same FMU).
    fn restore_bytes(&self, bytes: &[u8]) -> Result<Box<dyn Model>, String>;
}

/// Little-endian byte writer and reader for the payload of serialised structure states
/// (inside the envelope of [`crate::envelope`]).
pub mod bytes {
    /// Append-only writer.
    #[derive(Default)]
    pub struct Writer(pub Vec<u8>);
    impl Writer {
        pub fn f64(&mut self, x: f64) {
            self.0.extend_from_slice(&x.to_le_bytes());
        }
        pub fn u64(&mut self, x: u64) {
            self.0.extend_from_slice(&x.to_le_bytes());
        }
    }
    /// Reader over a serialised state; every read checks the length.
    pub struct Reader<'a> {
        pub data: &'a [u8],
        pub at: usize,
    }
    impl<'a> Reader<'a> {
        pub fn new(data: &'a [u8]) -> Self {
            Reader { data, at: 0 }
        }
        fn take(&mut self, n: usize) -> Result<&'a [u8], String> {
            let end = self.at.checked_add(n).filter(|&e| e <= self.data.len());
            let end = end.ok_or_else(|| {
                format!(
                    "serialised state truncated at byte {} of {}",
                    self.at,
                    self.data.len()
                )
            })?;
            let s = &self.data[self.at..end];
            self.at = end;
            Ok(s)
        }
        pub fn f64(&mut self) -> Result<f64, String> {
            let b = self.take(8)?;
            Ok(f64::from_le_bytes(b.try_into().expect("8 bytes")))
        }
        pub fn u64(&mut self) -> Result<u64, String> {
            let b = self.take(8)?;
            Ok(u64::from_le_bytes(b.try_into().expect("8 bytes")))
        }
    }
}
