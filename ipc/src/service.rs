//! Naming and opening the particle service `granmix/<instance>/particles`. Publisher
//! and subscriber open it through [`open`], so both ask for the same payload types.

use crate::error::IpcError;
use crate::payload::{FrameHeader, ParticleRecord};
use iceoryx2::node::Node;
use iceoryx2::prelude::*;
use iceoryx2::service::port_factory::publish_subscribe::PortFactory;

/// The iceoryx2 service flavour: ports may move between threads (the FMU's master
/// may call from any thread).
pub type Flavor = ipc_threadsafe::Service;

/// The opened particle service.
pub type ParticleService = PortFactory<Flavor, [ParticleRecord], FrameHeader>;

/// Full service name for `spec`: an instance name (`run1` → `granmix/run1/particles`)
/// or, when it contains `/`, a full service name used as given.
pub fn service_name(spec: &str) -> Result<String, IpcError> {
    let bad = |reason: &str| IpcError::ServiceName {
        name: spec.to_string(),
        reason: reason.to_string(),
    };
    let spec = spec.trim();
    if spec.is_empty() {
        return Err(bad("it is empty"));
    }
    let name = if spec.contains('/') {
        spec.to_string()
    } else {
        format!("granmix/{spec}/particles")
    };
    ServiceName::new(&name).map_err(|e| bad(&format!("{e:?}")))?;
    Ok(name)
}

/// A node for this process's ports. Signal handling is left to the host (the FMU runs
/// inside someone else's process) unless `signals`: then SIGINT and SIGTERM are caught
/// and reported by [`Node::wait`], so a standalone subscriber can shut down cleanly.
pub fn node(service: &str, signals: bool) -> Result<Node<Flavor>, IpcError> {
    // iceoryx2 warns on stderr that it runs without a config file; only errors
    // matter here (IOX2_LOG_LEVEL overrides)
    set_log_level_from_env_or(LogLevel::Error);
    NodeBuilder::new()
        .signal_handling_mode(if signals {
            SignalHandlingMode::HandleTerminationRequests
        } else {
            SignalHandlingMode::Disabled
        })
        .create::<Flavor>()
        .map_err(|e| IpcError::Setup {
            service: service.to_string(),
            what: "create an iceoryx2 node",
            reason: format!("{e:?}"),
        })
}

/// How the service is opened.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub enum Delivery {
    /// Full subscriber queues drop their oldest frame (the solver's setting: the
    /// publisher never waits).
    #[default]
    Overflow,
    /// Create the service without overflow, so a publisher that retries delivers
    /// every frame (test tools only; the service must not exist yet).
    Lossless,
}

/// Open (or create) the particle service `name`.
pub fn open(
    node: &Node<Flavor>,
    name: &str,
    delivery: Delivery,
) -> Result<ParticleService, IpcError> {
    let setup = |what, e: String| IpcError::Setup {
        service: name.to_string(),
        what,
        reason: e,
    };
    let sn =
        ServiceName::new(name).map_err(|e| setup("parse the service name", format!("{e:?}")))?;
    let b = node
        .service_builder(&sn)
        .publish_subscribe::<[ParticleRecord]>()
        .user_header::<FrameHeader>();
    match delivery {
        Delivery::Overflow => b
            .open_or_create()
            .map_err(|e| setup("open the publish-subscribe service", format!("{e:?}"))),
        Delivery::Lossless => b
            .enable_safe_overflow(false)
            .subscriber_max_buffer_size(8)
            .create()
            .map_err(|e| setup("create the publish-subscribe service", format!("{e:?}"))),
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn names() {
        assert_eq!(service_name("run1").unwrap(), "granmix/run1/particles");
        assert_eq!(service_name("a/b").unwrap(), "a/b");
        let e = service_name(" ").unwrap_err().to_string();
        assert!(e.contains("empty"), "{e}");
    }
}
