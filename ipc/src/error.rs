//! Errors of the particle channel and the recorder, each naming what failed.

use thiserror::Error;

/// What went wrong while setting up or using the particle channel or a recording.
#[derive(Debug, Error)]
pub enum IpcError {
    /// The service name given by the user is not a valid iceoryx2 service name.
    #[error("`{name}` is not a valid particle service name: {reason}")]
    ServiceName { name: String, reason: String },
    /// Creating the iceoryx2 node, service or port failed.
    #[error("particle service `{service}`: cannot {what}: {reason}")]
    Setup {
        service: String,
        what: &'static str,
        reason: String,
    },
    /// Receiving from the service failed.
    #[error("particle service `{service}`: receive failed: {reason}")]
    Receive { service: String, reason: String },
    /// A frame's header disagrees with its payload or with this build's layout.
    #[error("particle service `{service}`: bad frame: {reason}")]
    BadFrame { service: String, reason: String },
    /// Writing or reading an MCAP recording failed.
    #[error("recording {path}: {reason}")]
    Record { path: String, reason: String },
}
