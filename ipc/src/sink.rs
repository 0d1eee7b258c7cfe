//! One interface for every bulk output of a run: the particle channel, MCAP
//! recordings and, in the CLI, the CSV series and VTK snapshots. The CLI runner and
//! the FMU hold their outputs as [`Sinks`] and feed them the same way: a sample at
//! every output time (CLI) or communication point (FMU), a call after every step, and
//! `finish` at the end.

use crate::publisher::FramePublisher;
use crate::recorder::Recorder;
use granmix_core::run::sample::Sample;
use granmix_core::AnySimulation;
use serde_json::{json, Value};
use std::time::Instant;

/// A sink that failed, with the error it met.
#[derive(Debug, thiserror::Error)]
#[error("{sink}: {source}")]
pub struct SinkError {
    /// The sink's name ([`Sink::name`]).
    pub sink: String,
    #[source]
    pub source: Box<dyn std::error::Error + Send + Sync>,
}

impl SinkError {
    pub fn new(sink: &str, source: impl Into<Box<dyn std::error::Error + Send + Sync>>) -> Self {
        SinkError {
            sink: sink.to_string(),
            source: source.into(),
        }
    }
}

/// A bulk output of a run.
pub trait Sink: Send {
    /// The name a run summary files the sink's [`report`](Sink::report) under, and
    /// errors name.
    fn name(&self) -> &str;
    /// The state at a sampling time, `sample.time` (an FMU's communication point,
    /// which includes the experiment's start time).
    fn sample(&mut self, sim: &AnySimulation, sample: &Sample) -> Result<(), SinkError>;
    /// The state after a step (streaming sinks); nothing by default.
    fn step(&mut self, _sim: &AnySimulation) -> Result<(), SinkError> {
        Ok(())
    }
    /// The state the stability guard stopped the run on (finite: it stops before
    /// NaNs), for a last look; nothing by default.
    fn blowup(&mut self, _sim: &AnySimulation) -> Result<(), SinkError> {
        Ok(())
    }
    /// Flush and close (writes summaries and indexes); nothing by default. Called once.
    fn finish(&mut self) -> Result<(), SinkError> {
        Ok(())
    }
    /// What the sink has done, for the run summary.
    fn report(&self) -> Option<Value> {
        None
    }
}

/// The outputs of one run, fed in the order they were added.
#[derive(Default)]
pub struct Sinks {
    sinks: Vec<Box<dyn Sink>>,
    /// Seconds spent in the sinks.
    pub seconds: f64,
}

impl Sinks {
    pub fn push(&mut self, sink: impl Sink + 'static) {
        self.sinks.push(Box::new(sink));
    }
    pub fn is_empty(&self) -> bool {
        self.sinks.is_empty()
    }
    /// Every sink's [`Sink::sample`]; the first error stops the round.
    pub fn sample(&mut self, sim: &AnySimulation, sample: &Sample) -> Result<(), SinkError> {
        self.timed(|s| s.sample(sim, sample))
    }
    /// Every sink's [`Sink::step`].
    pub fn step(&mut self, sim: &AnySimulation) -> Result<(), SinkError> {
        self.timed(|s| s.step(sim))
    }
    /// Every sink's [`Sink::blowup`].
    pub fn blowup(&mut self, sim: &AnySimulation) -> Result<(), SinkError> {
        self.timed(|s| s.blowup(sim))
    }
    /// Every sink's [`Sink::finish`] (all of them, even after an error; the first
    /// error is returned). The sinks are dropped: a second call does nothing.
    pub fn finish(&mut self) -> Result<(), SinkError> {
        let mut first = Ok(());
        for mut s in self.sinks.drain(..) {
            let r = s.finish();
            if first.is_ok() {
                first = r;
            }
        }
        first
    }
    /// The report of the sink named `name`, if there is one.
    pub fn report(&self, name: &str) -> Option<Value> {
        self.sinks
            .iter()
            .find(|s| s.name() == name)
            .and_then(|s| s.report())
    }
    fn timed(
        &mut self,
        mut f: impl FnMut(&mut dyn Sink) -> Result<(), SinkError>,
    ) -> Result<(), SinkError> {
        let t = Instant::now();
        let r = self.sinks.iter_mut().try_for_each(|s| f(s.as_mut()));
        self.seconds += t.elapsed().as_secs_f64();
        r
    }
}

impl Drop for Sinks {
    fn drop(&mut self) {
        let _ = self.finish();
    }
}

/// The particle channel as a sink. It publishes every `every` steps (the CLI's
/// `--publish-every`) or, without `every`, at every sample (the FMU's communication
/// points, stamped with the sample's time). Publishing never fails: a frame nobody
/// can take is dropped and counted.
pub struct ChannelSink {
    publisher: FramePublisher,
    every: Option<u64>,
    seconds: f64,
}

impl ChannelSink {
    pub fn new(publisher: FramePublisher, every: Option<u64>) -> Self {
        ChannelSink {
            publisher,
            every,
            seconds: 0.0,
        }
    }
    pub fn publisher(&self) -> &FramePublisher {
        &self.publisher
    }
}

impl Sink for ChannelSink {
    fn name(&self) -> &str {
        "publish"
    }
    fn sample(&mut self, sim: &AnySimulation, sample: &Sample) -> Result<(), SinkError> {
        if self.every.is_none() {
            let t = Instant::now();
            self.publisher.publish_at(sim, sample.time);
            self.seconds += t.elapsed().as_secs_f64();
        }
        Ok(())
    }
    fn step(&mut self, sim: &AnySimulation) -> Result<(), SinkError> {
        if let Some(k) = self.every {
            if sim.steps().is_multiple_of(k) {
                let t = Instant::now();
                self.publisher.publish(sim);
                self.seconds += t.elapsed().as_secs_f64();
            }
        }
        Ok(())
    }
    fn report(&self) -> Option<Value> {
        let st = self.publisher.stats();
        Some(json!({
            "service": self.publisher.name(),
            "every": self.every,
            "frames_sent": st.sent,
            "frames_dropped": st.dropped,
            "first_drop": st.first_drop,
            "no_subscriber": st.no_subscriber,
            "seconds": self.seconds,
        }))
    }
}

impl Sink for Recorder {
    fn name(&self) -> &str {
        "record"
    }
    fn sample(&mut self, sim: &AnySimulation, sample: &Sample) -> Result<(), SinkError> {
        self.record(sim, sample)
            .map_err(|e| SinkError::new("record", e))
    }
    fn finish(&mut self) -> Result<(), SinkError> {
        self.close()
            .map(|_| ())
            .map_err(|e| SinkError::new("record", e))
    }
    fn report(&self) -> Option<Value> {
        Some(json!({
            "path": self.path().display().to_string(),
            "messages": self.counts(),
        }))
    }
}
