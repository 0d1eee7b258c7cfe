//! granmix-ipc: bulk particle data out of a running simulation.
//!
//! - [`publisher`] / [`subscriber`]: the iceoryx2 publish–subscribe channel
//!   `granmix/<instance>/particles`, a [`payload::FrameHeader`] plus a slice of
//!   [`payload::ParticleRecord`]s, zero-copy between processes.
//! - [`recorder`]: MCAP recordings with Foxglove schemas (particles as
//!   `foxglove.PointCloud`, bodies as `foxglove.FrameTransforms`, the walls' solids as
//!   `foxglove.SceneUpdate` ([`geometry`]), loads and energies as JSON with JSON
//!   Schema, the scene as an attachment).
//!
//! - [`sink`]: the one interface of bulk outputs ([`Sink`], [`Sinks`]) that the CLI
//!   (`granmix run --publish/--record`, CSV and VTK) and the FMU (`ipc.enabled`,
//!   `ipc.service`, `record.path`) feed alike.

pub mod error;
pub mod geometry;
pub mod pattern;
pub mod payload;
pub mod publisher;
pub mod recorder;
pub mod service;
pub mod sink;
pub mod subscriber;

pub use error::IpcError;
/// The Foxglove schemas used in recordings (for readers and tests).
pub use foxglove;
pub use payload::{FrameHeader, ParticleRecord, SCHEMA_VERSION};
pub use publisher::{FrameInfo, FramePublisher, Outcome, PublishStats};
pub use recorder::{RecordCounts, Recorder, SceneInfo};
pub use sink::{ChannelSink, Sink, SinkError, Sinks};
pub use subscriber::{Frame, FrameSubscriber};
