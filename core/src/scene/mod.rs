//! Scene files: schema, text with overrides, validation. Reading a scene with the
//! files its shapes name is [`input`](crate::input)'s work.

mod error;
mod text;
mod types;
mod validate;
mod water;
mod water_check;

pub use error::{KeyError, SceneError};
pub use text::{apply_overrides, at, locate, parse};
pub use types::*;
pub use validate::{unknown_solid, validate, validate_shape};
pub use water::*;
