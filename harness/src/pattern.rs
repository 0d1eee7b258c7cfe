//! `granmix ipc-pattern` (hidden): publish the test pattern of
//! [`granmix_ipc::pattern`] losslessly, for the cross-process and cross-language
//! channel tests.

use anyhow::{bail, Result};
use granmix_ipc::pattern::{pattern_info, pattern_record};
use granmix_ipc::service::Delivery;
use granmix_ipc::{FramePublisher, Outcome};
use std::time::{Duration, Instant};

#[derive(clap::Args)]
pub struct PatternArgs {
    /// Service (instance name or full name); must not exist yet.
    pub service: String,
    /// Records per frame.
    #[arg(long, default_value_t = 100_000)]
    pub particles: usize,
    /// Frames to send.
    #[arg(long, default_value_t = 100)]
    pub frames: u64,
    /// Wait for this many subscribers before sending.
    #[arg(long, default_value_t = 1)]
    pub subscribers: usize,
    /// Give up waiting for subscribers (to connect, then to leave) after this long (s).
    #[arg(long, default_value_t = 60.0)]
    pub timeout: f64,
}

pub fn pattern(a: &PatternArgs) -> Result<()> {
    let mut p = FramePublisher::open_with(&a.service, a.particles, Delivery::Lossless)?;
    println!("ready: publishing on {}", p.name());
    let deadline = Instant::now() + Duration::from_secs_f64(a.timeout);
    while p.subscribers() < a.subscribers {
        if Instant::now() > deadline {
            bail!(
                "only {} of {} subscribers connected within {} s",
                p.subscribers(),
                a.subscribers,
                a.timeout
            );
        }
        std::thread::sleep(Duration::from_millis(10));
    }
    for k in 0..a.frames {
        let info = pattern_info(k, a.particles);
        let records: Vec<_> = (0..a.particles).map(|i| pattern_record(k, i)).collect();
        let out = p.publish_slice(&info, &records);
        if !matches!(out, Outcome::Sent(_)) {
            bail!("frame {k}: {out:?}");
        }
    }
    println!("sent {} frames of {} records", a.frames, a.particles);
    // stay until the subscribers have taken everything and left
    let deadline = Instant::now() + Duration::from_secs_f64(a.timeout);
    while p.subscribers() > 0 && Instant::now() < deadline {
        std::thread::sleep(Duration::from_millis(10));
    }
    Ok(())
}
