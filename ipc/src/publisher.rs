//! [`FramePublisher`]: sends particle frames without ever blocking the solver.
//!
//! - With no subscriber connected, [`FramePublisher::publish`] returns at once and no
//!   frame is built.
//! - The publisher discards data for full subscriber queues (and the service lets
//!   queues overflow), so a stalled subscriber costs nothing.
//! - When no sample can be loaned (subscribers hold all of them), the frame is dropped
//!   and counted; dead subscribers' resources are reclaimed now and then.

use crate::error::IpcError;
use crate::payload::{FrameHeader, ParticleRecord, SCHEMA_VERSION};
use crate::service::{self, Delivery, Flavor, ParticleService};
use granmix_core::AnySimulation;
use iceoryx2::node::Node;
use iceoryx2::port::publisher::Publisher;
use iceoryx2::prelude::*;
use std::time::{SystemTime, UNIX_EPOCH};

/// Frames between sweeps for dead subscribers.
const CLEANUP_EVERY: u64 = 64;

/// What one call to [`FramePublisher::publish`] did.
#[derive(Clone, Debug, PartialEq, Eq)]
pub enum Outcome {
    /// Sent to this many subscriber queues.
    Sent(usize),
    /// Nobody listens: no frame was built.
    NoSubscriber,
    /// The frame was dropped (no sample could be loaned, or sending failed).
    Dropped(String),
}

/// Counters over a publisher's life.
#[derive(Clone, Debug, Default, PartialEq, Eq)]
pub struct PublishStats {
    pub sent: u64,
    pub no_subscriber: u64,
    pub dropped: u64,
    /// Why the first frame was dropped.
    pub first_drop: Option<String>,
}

/// Frame contents handed to [`FramePublisher::publish_with`].
#[derive(Clone, Copy, Debug)]
pub struct FrameInfo {
    pub time: f64,
    pub step: u64,
    pub fine_count: usize,
    pub coarse_count: usize,
    pub water_count: usize,
    pub dimension: u32,
}

/// How a frame's records get into the loaned sample.
enum Fill<'a, F: FnOnce(&mut [ParticleRecord])> {
    /// One copy of ready records.
    Copy(&'a [ParticleRecord]),
    /// Written in place (in parallel) into a zeroed slice.
    With(F),
}

/// The `F` of a [`Fill::Copy`].
type NoFill = fn(&mut [ParticleRecord]);

/// Publisher of particle frames on one service.
pub struct FramePublisher {
    name: String,
    node: Node<Flavor>,
    service: ParticleService,
    publisher: Publisher<Flavor, [ParticleRecord], FrameHeader>,
    sequence: u64,
    stats: PublishStats,
}

impl std::fmt::Debug for FramePublisher {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.debug_struct("FramePublisher")
            .field("name", &self.name)
            .field("stats", &self.stats)
            .finish_non_exhaustive()
    }
}

/// Nanoseconds since the Unix epoch.
pub fn unix_ns() -> u64 {
    SystemTime::now()
        .duration_since(UNIX_EPOCH)
        .map(|d| d.as_nanos() as u64)
        .unwrap_or(0)
}

impl FramePublisher {
    /// Open the service named by `spec` (see [`service::service_name`]) for frames of
    /// about `particles` records (the data segment grows when more are sent).
    pub fn open(spec: &str, particles: usize) -> Result<Self, IpcError> {
        Self::open_with(spec, particles, Delivery::Overflow)
    }

    /// [`Self::open`] with an explicit delivery mode. [`Delivery::Lossless`] creates the
    /// service and retries until every subscriber has room: for test tools, never for
    /// the solver.
    pub fn open_with(spec: &str, particles: usize, delivery: Delivery) -> Result<Self, IpcError> {
        let name = service::service_name(spec)?;
        let node = service::node(&name, false)?;
        let service = service::open(&node, &name, delivery)?;
        let strategy = match delivery {
            Delivery::Overflow => BackpressureStrategy::DiscardData,
            Delivery::Lossless => BackpressureStrategy::RetryUntilDelivered,
        };
        let publisher = service
            .publisher_builder()
            .initial_max_slice_len(particles.max(1))
            .allocation_strategy(AllocationStrategy::PowerOfTwo)
            .backpressure_strategy(strategy)
            .max_loaned_samples(1)
            .create()
            .map_err(|e| IpcError::Setup {
                service: name.clone(),
                what: "create a publisher",
                reason: format!("{e:?}"),
            })?;
        Ok(FramePublisher {
            name,
            node,
            service,
            publisher,
            sequence: 0,
            stats: PublishStats::default(),
        })
    }

    /// The full service name.
    pub fn name(&self) -> &str {
        &self.name
    }

    /// How a full subscriber queue is handled: [`BackpressureStrategy::DiscardData`]
    /// unless opened [`Delivery::Lossless`].
    pub fn backpressure(&self) -> BackpressureStrategy {
        self.publisher.backpressure_strategy()
    }

    /// Subscribers connected to the service now.
    pub fn subscribers(&self) -> usize {
        self.service.dynamic_config().number_of_subscribers()
    }

    /// Whether a frame would be built now (someone listens).
    pub fn wants_frame(&self) -> bool {
        self.subscribers() > 0
    }

    pub fn stats(&self) -> &PublishStats {
        &self.stats
    }

    /// Publish the current particles of `sim` (if anybody listens).
    pub fn publish(&mut self, sim: &AnySimulation) -> Outcome {
        self.publish_at(sim, sim.time())
    }

    /// Publish the current particles of `sim` stamped with `time` (an FMU's
    /// communication point, which includes the experiment's start time).
    pub fn publish_at(&mut self, sim: &AnySimulation, time: f64) -> Outcome {
        let (fine, coarse) = sim.particle_counts();
        let info = FrameInfo {
            time,
            step: sim.steps(),
            fine_count: fine,
            coarse_count: coarse,
            water_count: sim.water_count(),
            dimension: sim.dimension() as u32,
        };
        self.publish_with(&info, |out| sim.fill_particles(out))
    }

    /// Publish a copy of `records` (one memcpy into shared memory), if anybody listens.
    pub fn publish_slice(&mut self, info: &FrameInfo, records: &[ParticleRecord]) -> Outcome {
        debug_assert_eq!(
            records.len(),
            info.fine_count + info.coarse_count + info.water_count
        );
        self.publish_via(info, Fill::<NoFill>::Copy(records))
    }

    /// Publish a frame of `info.fine_count + info.coarse_count + info.water_count`
    /// records written by
    /// `fill` straight into shared memory (if anybody listens). The loaned slice
    /// starts zeroed.
    pub fn publish_with(
        &mut self,
        info: &FrameInfo,
        fill: impl FnOnce(&mut [ParticleRecord]),
    ) -> Outcome {
        self.publish_via(info, Fill::With(fill))
    }

    fn publish_via<F: FnOnce(&mut [ParticleRecord])>(
        &mut self,
        info: &FrameInfo,
        fill: Fill<'_, F>,
    ) -> Outcome {
        if self.sequence % CLEANUP_EVERY == CLEANUP_EVERY - 1 {
            // reclaim what subscribers that died still hold; never waits
            let _ = self.node.try_cleanup_dead_nodes();
        }
        let outcome = self.send(info, fill);
        match &outcome {
            Outcome::Sent(_) => self.stats.sent += 1,
            Outcome::NoSubscriber => self.stats.no_subscriber += 1,
            Outcome::Dropped(why) => {
                self.stats.dropped += 1;
                self.stats.first_drop.get_or_insert_with(|| why.clone());
            }
        }
        if !matches!(outcome, Outcome::NoSubscriber) {
            self.sequence += 1;
        }
        outcome
    }

    fn send<F: FnOnce(&mut [ParticleRecord])>(
        &mut self,
        info: &FrameInfo,
        fill: Fill<'_, F>,
    ) -> Outcome {
        if !self.wants_frame() {
            return Outcome::NoSubscriber;
        }
        let n = info.fine_count + info.coarse_count + info.water_count;
        let sample = match self.publisher.loan_slice_uninit(n) {
            Ok(s) => s,
            Err(e) => return Outcome::Dropped(format!("no sample to loan: {e:?}")),
        };
        let mut sample = match fill {
            Fill::Copy(records) if records.len() == n => sample.write_from_slice(records),
            Fill::Copy(records) => {
                return Outcome::Dropped(format!(
                    "header counts {n} particles, the frame has {}",
                    records.len()
                ))
            }
            Fill::With(f) => {
                let mut s = sample.write_from_fn(|_| ParticleRecord::default());
                f(s.payload_mut());
                s
            }
        };
        *sample.user_header_mut() = FrameHeader {
            time: info.time,
            step: info.step,
            sequence: self.sequence,
            sent_unix_ns: unix_ns(),
            fine_count: info.fine_count as u32,
            coarse_count: info.coarse_count as u32,
            dimension: info.dimension,
            schema_version: SCHEMA_VERSION,
            water_count: info.water_count as u32,
            reserved: 0,
        };
        match sample.send() {
            Ok(k) => Outcome::Sent(k),
            Err(e) => Outcome::Dropped(format!("send failed: {e:?}")),
        }
    }
}
