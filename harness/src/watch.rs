//! `granmix watch`: subscribe to a particle service, print frame rate, particle count
//! and latency once a second, and optionally record what arrives to MCAP.

use anyhow::{Context, Result};
use granmix_ipc::publisher::unix_ns;
use granmix_ipc::{FrameSubscriber, Recorder, SceneInfo};
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

pub fn watch(a: &WatchArgs) -> Result<()> {
    let sub = FrameSubscriber::open_interruptible(&a.service)?;
    println!("ready: subscribed to {}", sub.name());
    std::io::stdout().flush().ok();
    let mut recorder = match &a.record {
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
    };
    let timeout = a.timeout.map(Duration::from_secs_f64);
    let mut last_frame = Instant::now();
    let mut window_start = Instant::now();
    let mut win = Window::default();
    let (mut total, mut gaps) = (0u64, 0u64);
    let mut next_seq: Option<u64> = None;
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
        if let Some(s) = next_seq {
            gaps += h.sequence.saturating_sub(s);
        }
        next_seq = Some(h.sequence + 1);
        total += 1;
        win.frames += 1;
        win.latency_sum += latency;
        win.latency_max = win.latency_max.max(latency);
        last_frame = Instant::now();
        let el = window_start.elapsed().as_secs_f64();
        if total == 1 {
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
                gaps
            );
        }
        if total == 1 || el >= 1.0 {
            std::io::stdout().flush().ok();
            win = Window::default();
            window_start = Instant::now();
        }
        if a.frames.is_some_and(|n| total >= n) {
            break;
        }
    }
    println!("{total} frames received, {gaps} missed");
    if let Some(r) = recorder {
        let path = r.path().to_path_buf();
        let c = r.finish()?;
        println!("recorded {} frames to {}", c.particles, path.display());
    }
    Ok(())
}
