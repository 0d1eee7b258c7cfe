//! granmix-ipc: bulk particle data out of a running simulation.
//!
//! - [`publisher`] / [`subscriber`]: the iceoryx2 publish–subscribe channel
//!   `granmix/<instance>/particles`, a [`payload::FrameHeader`] plus a slice of
//!   [`payload::ParticleRecord`]s, zero-copy between processes.
//! - [`recorder`]: MCAP recordings with Foxglove schemas (particles as
//!   `foxglove.PointCloud`, bodies as `foxglove.FrameTransforms`, loads and energies as
//!   JSON with JSON Schema, the scene as an attachment).
//!
//! The CLI (`granmix run --publish/--record`, `granmix watch`) and the FMU
//! (`ipc.enabled`, `ipc.service`, `record.path`) share these types.

pub mod error;
pub mod pattern;
pub mod payload;
pub mod publisher;
pub mod recorder;
pub mod service;
pub mod subscriber;

pub use error::IpcError;
/// The Foxglove schemas used in recordings (for readers and tests).
pub use foxglove;
pub use payload::{FrameHeader, ParticleRecord, SCHEMA_VERSION};
pub use publisher::{FrameInfo, FramePublisher, Outcome, PublishStats};
pub use recorder::{RecordCounts, Recorder, SceneInfo};
pub use subscriber::{Frame, FrameSubscriber};
