//! [`FrameSubscriber`]: receives particle frames; used by `granmix watch` and tests.

use crate::error::IpcError;
use crate::payload::{FrameHeader, ParticleRecord, SCHEMA_VERSION};
use crate::service::{self, Delivery, Flavor, ParticleService};
use iceoryx2::node::Node;
use iceoryx2::port::subscriber::Subscriber;
use iceoryx2::sample::Sample;
use std::time::Duration;

/// One received frame, borrowed from shared memory until dropped.
pub struct Frame {
    sample: Sample<Flavor, [ParticleRecord], FrameHeader>,
}

impl Frame {
    pub fn header(&self) -> &FrameHeader {
        self.sample.user_header()
    }
    /// All records: fine particles, then coarse.
    pub fn records(&self) -> &[ParticleRecord] {
        self.sample.payload()
    }
}

/// Subscriber on one particle service.
pub struct FrameSubscriber {
    name: String,
    node: Node<Flavor>,
    _service: ParticleService,
    subscriber: Subscriber<Flavor, [ParticleRecord], FrameHeader>,
}

impl FrameSubscriber {
    /// Open the service named by `spec` (see [`service::service_name`]), creating it
    /// when no publisher has yet. Signals are left to the process.
    pub fn open(spec: &str) -> Result<Self, IpcError> {
        Self::open_with(spec, false)
    }

    /// [`Self::open`] for a standalone subscriber process: SIGINT and SIGTERM are
    /// caught, and [`Self::idle`] reports them.
    pub fn open_interruptible(spec: &str) -> Result<Self, IpcError> {
        Self::open_with(spec, true)
    }

    fn open_with(spec: &str, signals: bool) -> Result<Self, IpcError> {
        let name = service::service_name(spec)?;
        let node = service::node(&name, signals)?;
        let svc = service::open(&node, &name, Delivery::Overflow)?;
        let subscriber = svc
            .subscriber_builder()
            .create()
            .map_err(|e| IpcError::Setup {
                service: name.clone(),
                what: "create a subscriber",
                reason: format!("{e:?}"),
            })?;
        Ok(FrameSubscriber {
            name,
            node,
            _service: svc,
            subscriber,
        })
    }

    /// The full service name.
    pub fn name(&self) -> &str {
        &self.name
    }

    /// Wait `d` between polls; false once termination was requested (SIGINT or
    /// SIGTERM, for [`Self::open_interruptible`] subscribers).
    pub fn idle(&self, d: Duration) -> bool {
        self.node.wait(d).is_ok()
    }

    /// The next frame, if one is waiting; checks it against this build's layout.
    pub fn receive(&self) -> Result<Option<Frame>, IpcError> {
        let sample = self.subscriber.receive().map_err(|e| IpcError::Receive {
            service: self.name.clone(),
            reason: format!("{e:?}"),
        })?;
        let Some(sample) = sample else {
            return Ok(None);
        };
        let frame = Frame { sample };
        let h = frame.header();
        let bad = |reason: String| IpcError::BadFrame {
            service: self.name.clone(),
            reason,
        };
        if h.schema_version != SCHEMA_VERSION {
            return Err(bad(format!(
                "schema version {} (this build reads {SCHEMA_VERSION})",
                h.schema_version
            )));
        }
        if h.count() != frame.records().len() {
            return Err(bad(format!(
                "header counts {} + {} + {} particles, payload holds {}",
                h.fine_count,
                h.coarse_count,
                h.water_count,
                frame.records().len()
            )));
        }
        Ok(Some(frame))
    }
}
