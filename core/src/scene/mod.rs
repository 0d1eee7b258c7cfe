//! Scene files: schema, text with overrides, validation. Reading a scene with the
//! files its shapes name is [`input`](crate::input)'s work.

pub mod build_error;
mod error;
pub mod names_check;
mod one_or_many;
mod periodic_check;
mod polygon_check;
mod pores_check;
pub mod resolution;
mod soil_model;
mod soil_model_check;
mod text;
mod types;
mod validate;
mod water;
mod water_check;

pub use error::{KeyError, SceneError};
pub use names_check::{unsafe_name, MAX_NAME_CHARS};
pub use soil_model::{DilatancySpec, HardeningSpec, MuISpec, YieldSurface, PHI_MAX};
pub use text::{apply_overrides, at, attribute, locate, parse, reattribute};
pub use types::*;
pub use validate::{unknown_solid, validate_shape};

/// Semantic checks on a deserialised scene: the names, the soils' models (before their
/// angles: a μ(I) block's μ_s sets φ), the grains, walls and probes, then the water, then the soils' pores, then a periodic axis. Errors carry the key path.
pub fn validate(s: &Scene) -> Result<(), KeyError> {
    names_check::validate_names(s)?;
    soil_model_check::validate_soil_models(s)?;
    validate::validate_grains(s)?;
    water_check::validate_water(s)?;
    pores_check::validate_pores(s)?;
    periodic_check::validate_periodic(s)
}
pub use water::*;
