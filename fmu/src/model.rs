//! The small model interface the FFI layer drives: the granular simulation
//! ([`crate::granular`]) and the structural partners ([`crate::structure`]) implement it.

use crate::error::{BadStep, ModelError, StepError};
use crate::state::Place;
use crate::variables::Variable;

/// Check a communication step `(t, h)` against the model time `now`: both finite,
/// `h > 0` large enough to change `t`, and `t` within 1e-9 (relative) of `now`.
pub fn check_step(t: f64, h: f64, now: f64) -> Result<(), BadStep> {
    if !t.is_finite() {
        return Err(BadStep::PointNotFinite { t, now });
    }
    if !(h.is_finite() && h > 0.0) {
        return Err(BadStep::Size { h });
    }
    if t + h == t {
        return Err(BadStep::TooSmall { t, h });
    }
    if (t - now).abs() > 1e-9 * t.abs().max(h) {
        return Err(BadStep::Mismatch { t, now });
    }
    Ok(())
}

/// A co-simulation model behind one FMU instance. Error messages are for the master's
/// logger. The FFI layer treats a [`StepError::Failed`] of [`Model::do_step`] as a
/// failed model (the instance goes to
/// the error state); any other error as a bad call ([`crate::error::FmiError`]).
pub trait Model: Send {
    /// The value-reference table (value reference = index).
    fn variables(&self) -> &[Variable];
    /// Current value of variable `vr` (Reals, Integers and Booleans as f64).
    fn get(&mut self, vr: u32) -> Result<f64, ModelError>;
    /// Whether `value` is acceptable for parameter or input `vr` (the FFI layer has
    /// checked causality and state). Checked for every entry of a multi-value set
    /// before any is applied.
    fn check(&self, vr: u32, value: f64) -> Result<(), ModelError>;
    /// Set parameter or input `vr` to a value [`Model::check`] accepted.
    fn set(&mut self, vr: u32, value: f64) -> Result<(), ModelError> {
        self.check(vr, value)?;
        self.values_mut()[vr as usize] = value;
        Ok(())
    }
    /// The Real values, indexed by value reference.
    fn values_mut(&mut self) -> &mut [f64];
    /// Current value of String variable `vr`.
    fn get_string(&mut self, vr: u32) -> Result<String, ModelError> {
        Err(ModelError::NoStrings { vr })
    }
    /// Whether String parameter `vr` may be set now.
    fn check_string(&self, vr: u32) -> Result<(), ModelError> {
        Err(ModelError::NoStrings { vr })
    }
    /// Set String parameter `vr` (the FFI layer has checked causality and state).
    fn set_string(&mut self, vr: u32, _value: &str) -> Result<(), ModelError> {
        Err(ModelError::NoStrings { vr })
    }
    /// The instance name the master gave in `fmi2Instantiate`.
    fn set_instance_name(&mut self, _name: &str) {}
    /// `fmi2Terminate`: close what the model writes.
    fn terminate(&mut self) -> Result<(), ModelError> {
        Ok(())
    }
    /// Leave initialisation mode: parameters are final. An error leaves the model as it
    /// was, still in initialisation mode.
    fn exit_initialization(&mut self) -> Result<(), ModelError>;
    /// `fmi2SetupExperiment`: the experiment starts at `start` (s); model time,
    /// communication points and output stamps are shifted by it.
    fn set_start_time(&mut self, start: f64) -> Result<(), ModelError>;
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
    fn reset(&mut self) -> Result<(), ModelError>;
    /// A full copy of the state, for `fmi2GetFMUstate`.
    fn snapshot(&self) -> Box<dyn Model>;
    /// Bytes from which [`Model::restore_bytes`] rebuilds this exact state, taken by an
    /// instance at `place` of the state machine (carried in the envelope).
    fn to_bytes(&self, place: &Place) -> Result<Vec<u8>, ModelError>;
    /// Rebuild the state written by [`Model::to_bytes`] (of a model of the same FMU),
    /// with the place it was taken at (None for a state written before places were
    /// carried).
    fn restore_bytes(&self, bytes: &[u8]) -> Result<(Box<dyn Model>, Option<Place>), ModelError>;
}

/// Little-endian byte writer and reader for the payload of serialised structure states
/// (inside the envelope of [`crate::envelope`]).
pub mod bytes {
    use crate::envelope::EnvelopeError;

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
        fn take(&mut self, n: usize) -> Result<&'a [u8], EnvelopeError> {
            let end = self.at.checked_add(n).filter(|&e| e <= self.data.len());
            let end = end.ok_or(EnvelopeError::Truncated {
                at: self.at,
                len: self.data.len(),
            })?;
            let s = &self.data[self.at..end];
            self.at = end;
            Ok(s)
        }
        pub fn f64(&mut self) -> Result<f64, EnvelopeError> {
            let b = self.take(8)?;
            Ok(f64::from_le_bytes(b.try_into().expect("8 bytes")))
        }
        pub fn u64(&mut self) -> Result<u64, EnvelopeError> {
            let b = self.take(8)?;
            Ok(u64::from_le_bytes(b.try_into().expect("8 bytes")))
        }
    }
}
