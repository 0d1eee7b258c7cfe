//! One FMU instance: its model, its place in the FMI 2.0 Co-Simulation state machine and
//! its logger. No `unsafe` here: the FFI layer ([`crate::ffi`]) owns all of it.

use crate::granular::Granular;
use crate::logger::Logger;
use crate::model::Model;
use crate::structure::Structure;
use fmi_sys::fmi2::*;
use std::path::{Path, PathBuf};

/// Instance states of the FMI 2.0 Co-Simulation state machine (as bit flags for the
/// table of which function may be called when).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
#[repr(u8)]
pub enum State {
    Instantiated = 1,
    InitializationMode = 2,
    StepMode = 4,
    Terminated = 8,
    Error = 16,
    Fatal = 32,
}

/// Sets of states in which a function may be called.
pub mod allowed {
    use super::State::*;
    pub const ANY_BUT_FATAL: u8 = Instantiated as u8
        | InitializationMode as u8
        | StepMode as u8
        | Terminated as u8
        | Error as u8;
    pub const INSTANTIATED: u8 = Instantiated as u8;
    pub const INIT: u8 = InitializationMode as u8;
    pub const STEP: u8 = StepMode as u8;
    pub const TERMINATE: u8 = StepMode as u8 | Error as u8;
    pub const GET: u8 = InitializationMode as u8 | StepMode as u8 | Terminated as u8 | Error as u8;
    pub const SET: u8 = Instantiated as u8 | InitializationMode as u8 | StepMode as u8;
    pub const STATE: u8 = ANY_BUT_FATAL;
}

/// One instance handed to the master as `fmi2Component`.
pub struct Instance {
    pub logger: Logger,
    pub state: State,
    pub model: Box<dyn Model>,
    /// The unpacked `resources/` directory.
    pub resources: PathBuf,
    /// Strings handed out by the last `fmi2GetString`, alive until the next one.
    pub strings: Vec<std::ffi::CString>,
}

/// Turn an `fmuResourceLocation` URI (`file:///path/` or `file:/path`) into a path.
pub fn resource_dir(uri: &str) -> Result<PathBuf, String> {
    let rest = if let Some(r) = uri.strip_prefix("file://") {
        // file://host/path: only an empty host or localhost is local
        let r = r.strip_prefix("localhost").unwrap_or(r);
        if !r.starts_with('/') {
            return Err(format!("resource location `{uri}` is not a local file URI"));
        }
        r
    } else if let Some(r) = uri.strip_prefix("file:") {
        r
    } else {
        return Err(format!("resource location `{uri}` is not a file URI"));
    };
    let bytes = rest.as_bytes();
    let mut out = Vec::with_capacity(bytes.len());
    let mut i = 0;
    while i < bytes.len() {
        if bytes[i] == b'%' && i + 2 < bytes.len() {
            let hex = std::str::from_utf8(&bytes[i + 1..i + 3]).unwrap_or("");
            if let Ok(b) = u8::from_str_radix(hex, 16) {
                out.push(b);
                i += 3;
                continue;
            }
        }
        out.push(bytes[i]);
        i += 1;
    }
    let s = String::from_utf8(out).map_err(|e| format!("resource location `{uri}`: {e}"))?;
    Ok(PathBuf::from(s))
}

/// The model found in a resources directory, and its GUID.
pub fn load_model(dir: &Path) -> Result<(Box<dyn Model>, String), String> {
    if dir.join("scene.toml").is_file() {
        let g = Granular::from_resources(dir)?;
        let guid = g.info("granmix").guid;
        Ok((Box::new(g), guid))
    } else if dir.join("structure.toml").is_file() {
        let s = Structure::from_resources(dir)?;
        let guid = s.info("granmix").guid;
        Ok((Box::new(s), guid))
    } else {
        Err(format!(
            "resources directory {} holds neither scene.toml nor structure.toml",
            dir.display()
        ))
    }
}

impl Instance {
    /// Log an error from function `function` and return fmi2Error.
    pub fn error(&self, function: &str, message: &str) -> fmi2Status {
        self.logger.log(
            fmi2Status_fmi2Error,
            "logStatusError",
            &format!("{function}: {message}"),
        );
        fmi2Status_fmi2Error
    }

    /// Check that `function` may be called in the current state.
    pub fn check_state(&self, allowed: u8) -> Result<(), String> {
        if self.state as u8 & allowed == 0 {
            return Err(format!("may not be called in state {:?}", self.state));
        }
        Ok(())
    }
}
