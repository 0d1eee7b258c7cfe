//! One FMU instance: its model, its place in the FMI 2.0 Co-Simulation state machine
//! ([`crate::state`]) and its logger, and what `fmi2Instantiate` checks before it makes
//! one ([`open`]). No `unsafe` here: the FFI layer ([`crate::ffi`]) owns all of it.

use crate::error::{GranularError, StructureError};
use crate::granular::Granular;
use crate::logger::Logger;
use crate::model::Model;
use crate::state::State;
use crate::structure::Structure;
use std::path::{Path, PathBuf};

/// One instance handed to the master as `fmi2Component`.
pub struct Instance {
    pub logger: Logger,
    pub state: State,
    pub model: Box<dyn Model>,
    /// The unpacked `resources/` directory.
    pub resources: PathBuf,
    /// Strings handed out by the last `fmi2GetString`, alive until the next one.
    pub strings: Vec<std::ffi::CString>,
    /// In the error state: the logged message of the call that put it there, repeated
    /// to every call refused in that state.
    pub failure: Option<String>,
    /// The stop time given to `fmi2SetupExperiment`, if it defined one: no step may end
    /// after it (cleared by `fmi2Reset`).
    pub stop_time: Option<f64>,
}

/// Why `fmi2Instantiate` returns no instance.
#[derive(Debug, thiserror::Error)]
pub enum InstanceError {
    #[error("missing instance name")]
    NoName,
    #[error("this FMU supports Co-Simulation only")]
    NotCoSimulation,
    #[error("missing fmuResourceLocation")]
    NoResourceLocation,
    #[error("resource location `{uri}` is not a local file URI")]
    NotLocal { uri: String },
    #[error("resource location `{uri}` is not a file URI")]
    NotFileUri { uri: String },
    /// The decoded path is not UTF-8.
    #[error("resource location `{uri}`: {error}")]
    NotUtf8 {
        uri: String,
        error: std::string::FromUtf8Error,
    },
    #[error(
        "resources directory {} holds neither scene.toml nor structure.toml",
        dir.display()
    )]
    NoModel { dir: PathBuf },
    #[error(transparent)]
    Granular(#[from] GranularError),
    #[error(transparent)]
    Structure(#[from] StructureError),
    /// The master's GUID is not the one of the model in the resources.
    #[error(
        "GUID {given} does not match this FMU's {expected} (modelDescription.xml and \
         resources out of step?)"
    )]
    Guid { given: String, expected: String },
}

/// Check what `fmi2Instantiate` was given (`name`, whether it asks for Co-Simulation,
/// `guid`, `resource_location`) and load the model from the resources: the model, named
/// `name`, and the resources directory.
pub fn open(
    name: &str,
    co_simulation: bool,
    guid: &str,
    resource_location: Option<&str>,
) -> Result<(Box<dyn Model>, PathBuf), InstanceError> {
    if name.is_empty() {
        return Err(InstanceError::NoName);
    }
    if !co_simulation {
        return Err(InstanceError::NotCoSimulation);
    }
    let uri = resource_location.ok_or(InstanceError::NoResourceLocation)?;
    let dir = resource_dir(uri)?;
    let (mut model, expected) = load_model(&dir)?;
    if guid != expected {
        return Err(InstanceError::Guid {
            given: guid.to_string(),
            expected,
        });
    }
    model.set_instance_name(name);
    Ok((model, dir))
}

/// Turn an `fmuResourceLocation` URI (`file:///path/` or `file:/path`) into a path.
pub fn resource_dir(uri: &str) -> Result<PathBuf, InstanceError> {
    let rest = if let Some(r) = uri.strip_prefix("file://") {
        // file://host/path: only an empty host or localhost is local
        let r = r.strip_prefix("localhost").unwrap_or(r);
        if !r.starts_with('/') {
            return Err(InstanceError::NotLocal {
                uri: uri.to_string(),
            });
        }
        r
    } else if let Some(r) = uri.strip_prefix("file:") {
        r
    } else {
        return Err(InstanceError::NotFileUri {
            uri: uri.to_string(),
        });
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
    let s = String::from_utf8(out).map_err(|error| InstanceError::NotUtf8 {
        uri: uri.to_string(),
        error,
    })?;
    Ok(PathBuf::from(s))
}

/// The model found in a resources directory, and its GUID.
pub fn load_model(dir: &Path) -> Result<(Box<dyn Model>, String), InstanceError> {
    if dir.join("scene.toml").is_file() {
        let g = Granular::from_resources(dir)?;
        let guid = g.info("granmix").guid;
        Ok((Box::new(g), guid))
    } else if dir.join("structure.toml").is_file() {
        let s = Structure::from_resources(dir)?;
        let guid = s.info("granmix").guid;
        Ok((Box::new(s), guid))
    } else {
        Err(InstanceError::NoModel {
            dir: dir.to_path_buf(),
        })
    }
}
