//! The small model interface the FFI layer drives: the granular simulation
//! ([`crate::granular`]) and the structural partners ([`crate::structure`]) implement it.

use crate::variables::Variable;

/// A co-simulation model behind one FMU instance. Errors are messages for the logger.
pub trait Model: Send {
    /// The value-reference table (value reference = index).
    fn variables(&self) -> &[Variable];
    /// Current value of variable `vr` (Reals, Integers and Booleans as f64).
    fn get(&mut self, vr: u32) -> Result<f64, String>;
    /// Set parameter or input `vr` (the FFI layer has checked causality and state).
    fn set(&mut self, vr: u32, value: f64) -> Result<(), String>;
    /// Current value of String variable `vr`.
    fn get_string(&mut self, vr: u32) -> Result<String, String> {
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
    /// Advance from `t` by `h`, landing exactly on `t + h`.
    fn do_step(&mut self, t: f64, h: f64) -> Result<(), String>;
    /// Model time (s).
    fn time(&self) -> f64;
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
