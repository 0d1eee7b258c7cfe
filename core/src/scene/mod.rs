//! Scene files: schema, loading with overrides, validation.

mod error;
mod load;
mod placement;
mod rocks;
mod types;
mod validate;

pub use error::SceneError;
pub use load::{
    apply_overrides, load_scene_file, load_scene_in, load_scene_str, locate, LoadedScene,
};
pub use types::*;
