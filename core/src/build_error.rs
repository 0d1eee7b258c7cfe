//! The error of building a world from a validated scene: geometry problems the schema
//! cannot see (a region outside every container, a body that cannot be filled, a scene
//! over the memory budget). Its own module so that the family builders (`coarse::build`)
//! and the world that calls them share it without importing each other.

/// Error raised while building the world, with the scene key at fault.
#[derive(Clone, Debug, PartialEq, thiserror::Error)]
#[error("`{path}`: {message}")]
pub struct BuildError {
    /// Scene key path, e.g. `bodies[2].shape`.
    pub path: String,
    pub message: String,
}
