//! `granmix watch`: subscribe to a particle service, print frame rate, particle count
//! and latency once a second, and optionally record what arrives to MCAP.

use anyhow::{Context, Result};
use granmix_ipc::publisher::unix_ns;
use granmix_ipc::{FrameHeader, FrameSubscriber, Recorder, SceneInfo};
use std::io::Write;
use std::path::PathBuf;
use std::time::{Duration, Instant};

#[derive(clap::Args)]
pub struct WatchArgs {
    /// Service: an instance name (`run1` → `granmix/run1/particles`) or a full name.
    pub service: String,
    /// Record the received particle frames to this MCAP file.
    #[arg(long)]
    pub record: Option<PathBuf>,
    /// Stop after this many frames.
    #[arg(long)]
    pub frames: Option<u64>,
    /// Stop when no frame has arrived for this many seconds (default: never).
    #[arg(long)]
    pub timeout: Option<f64>,
    /// Subscribe but never take a frame (a stalled subscriber, for tests).
    #[arg(long, hide = true)]
    pub stall: bool,
}

/// Frame statistics over one report interval.
#[derive(Default)]
struct Window {
    frames: u64,
    latency_sum: f64,
    latency_max: f64,
}

/// Frames received so far, the sequence numbers missed, and the statistics of the
/// current report interval.
struct Tally {
    total: u64,
    gaps: u64,
    next_seq: Option<u64>,
    win: Window,
    window_start: Instant,
}

impl Tally {
    /// Nothing received yet; the first interval starts now.
    fn new() -> Self {
        Tally {
            total: 0,
            gaps: 0,
            next_seq: None,
            win: Window::default(),
            window_start: Instant::now(),
        }
    }

    /// Count the frame of header `h`, received `latency` seconds after it was sent;
    /// print the first frame, then frame rate, latency and missed frames once a second.
    fn count(&mut self, h: &FrameHeader, latency: f64) {
        if let Some(s) = self.next_seq {
            self.gaps += h.sequence.saturating_sub(s);
        }
        self.next_seq = Some(h.sequence + 1);
        self.total += 1;
        let win = &mut self.win;
        win.frames += 1;
        win.latency_sum += latency;
        win.latency_max = win.latency_max.max(latency);
        let el = self.window_start.elapsed().as_secs_f64();
        if self.total == 1 {
            println!(
                "first frame: t = {:.6} s  step {}  {} + {} particles  latency {:.3} ms",
                h.time,
                h.step,
                h.fine_count,
                h.coarse_count,
                1e3 * latency
            );
        } else if el >= 1.0 {
            println!(
                "t = {:.6} s  step {}  {} + {} particles  {:.1} frames/s  latency mean {:.3} ms max {:.3} ms  missed {}",
                h.time,
                h.step,
                h.fine_count,
                h.coarse_count,
                win.frames as f64 / el.max(1e-9),
                1e3 * win.latency_sum / win.frames as f64,
                1e3 * win.latency_max,
                self.gaps
            );
        }
        if self.total == 1 || el >= 1.0 {
            std::io::stdout().flush().ok();
            self.win = Window::default();
            self.window_start = Instant::now();
        }
    }
}

/// The MCAP recorder of `--record`, if asked for, labelled with the service of `sub`.
fn recorder(a: &WatchArgs, sub: &FrameSubscriber) -> Result<Option<Recorder>> {
    Ok(match &a.record {
        Some(p) => Some(Recorder::create(
            p,
            &SceneInfo {
                text: String::new(),
                file: format!("iceoryx2 service {}", sub.name()),
                name: None,
                dimension: 3,
                water: false,
            },
        )?),
        None => None,
    })
}

/// Subscribe to the service of `a`, report what arrives and record it if asked, until
/// the frame count or the timeout is reached or the run is interrupted.
pub fn watch(a: &WatchArgs) -> Result<()> {
    let sub = FrameSubscriber::open_interruptible(&a.service)?;
    println!("ready: subscribed to {}", sub.name());
    std::io::stdout().flush().ok();
    let mut recorder = recorder(a, &sub)?;
    let timeout = a.timeout.map(Duration::from_secs_f64);
    let mut last_frame = Instant::now();
    let mut tally = Tally::new();
    loop {
        if timeout.is_some_and(|t| last_frame.elapsed() > t) {
            println!(
                "no frame for {:.1} s: stopping",
                last_frame.elapsed().as_secs_f64()
            );
            break;
        }
        if a.stall {
            if !sub.idle(Duration::from_millis(50)) {
                break;
            }
            continue;
        }
        let Some(frame) = sub.receive()? else {
            // Ctrl-C or SIGTERM: stop, and close the recording properly
            if !sub.idle(Duration::from_micros(500)) {
                println!("interrupted");
                break;
            }
            continue;
        };
        let h = *frame.header();
        let latency = unix_ns().saturating_sub(h.sent_unix_ns) as f64 * 1e-9;
        if let Some(r) = recorder.as_mut() {
            r.write_particles(h.time, frame.records())
                .context("recording a frame")?;
        }
        drop(frame);
        last_frame = Instant::now();
        tally.count(&h, latency);
        if a.frames.is_some_and(|n| tally.total >= n) {
            break;
        }
    }
    println!("{} frames received, {} missed", tally.total, tally.gaps);
    if let Some(r) = recorder {
        let path = r.path().to_path_buf();
        let c = r.finish()?;
        println!("recorded {} frames to {}", c.particles, path.display());
    }
    Ok(())
}
