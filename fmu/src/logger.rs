//! The master's logger as an instance holds it. The master's C callback is wrapped by the
//! FFI layer ([`crate::ffi`], the only module with `unsafe`) into a [`Write`] closure;
//! this module decides what is sent and turns the text into C strings.

use fmi_sys::fmi2::{fmi2Status, fmi2Status_fmi2OK};
use std::ffi::{CStr, CString};

/// Sends one message to the master: status, category and message text (the closure
/// holds the master's callback, its environment pointer and the instance name).
pub type Write = Box<dyn Fn(fmi2Status, &CStr, &CStr)>;

/// The master's logger of one instance.
pub struct Logger {
    /// None when the master gave no callback.
    write: Option<Write>,
    /// Informational messages (fmi2OK) are sent only when this is on
    /// (`fmi2Instantiate`'s `loggingOn`, then `fmi2SetDebugLogging`).
    pub debug: bool,
}

/// `s` as a C string, NUL bytes replaced by spaces.
pub fn c_string(s: &str) -> CString {
    CString::new(s.replace('\0', " ")).unwrap_or_default()
}

impl Logger {
    /// A logger writing through `write`, with debug logging `debug`.
    pub fn new(write: Option<Write>, debug: bool) -> Self {
        Logger { write, debug }
    }

    /// Send `message` to the master. Informational messages only when debug logging is
    /// on.
    pub fn log(&self, status: fmi2Status, category: &str, message: &str) {
        if status == fmi2Status_fmi2OK && !self.debug {
            return;
        }
        let Some(write) = &self.write else { return };
        write(status, &c_string(category), &c_string(message));
    }
}
