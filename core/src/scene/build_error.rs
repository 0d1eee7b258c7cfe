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

/// The message for a region (`what`: "region" or "water region") named `name` that
/// holds no particle at spacing `dp`: the build's and the estimate's.
pub fn empty_region_message(what: &str, name: &str, dp: crate::numerics::math::Real) -> String {
    format!("{what} `{name}` holds no particle at dp = {dp:?} m; enlarge it or refine dp")
}
