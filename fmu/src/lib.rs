//! granmix-fmu: the FMI 2.0 Co-Simulation interface of granmix.
//!
//! One shared library serves every granmix FMU: `fmi2Instantiate` looks in the FMU's
//! `resources/` for `scene.toml` (the granular model, [`granular`]) or `structure.toml`
//! (a structural partner, [`structure`]). Both implement the small [`model::Model`]
//! interface that [`ffi`] drives; [`variables`] is the one table behind both
//! `modelDescription.xml` ([`xml`]) and the run-time value references.

pub mod envelope;
pub mod error;
pub mod ffi;
pub mod granular;
pub mod instance;
pub mod logger;
pub mod model;
pub mod package;
pub mod panics;
pub mod state;
pub mod structure;
pub mod variables;
pub mod xml;
pub mod zip;
