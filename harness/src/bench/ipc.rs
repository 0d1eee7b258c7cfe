//! `granmix bench-ipc`: what the particle channel costs.
//!
//! 1. Publishing one frame of `--particles` records (loan, fill, send to a subscriber
//!    in another process) against a plain memcpy of the same bytes.
//! 2. Solver step time of a scene in three modes: without a publisher, publishing
//!    with no subscriber (no frame is built), and publishing to a subscriber in
//!    another process. One simulation takes one step in each mode in turn, the first
//!    mode rotating, so noise, drifts and memory layout hit all three alike; the
//!    publish call inside the step is also timed on its own.

use crate::run::load;
use anyhow::{bail, Context, Result};
use granmix_core::AnySimulation;
use granmix_ipc::pattern::{pattern_info, pattern_record};
use granmix_ipc::{FramePublisher, Outcome, ParticleRecord};
use serde_json::{json, Value};
use std::io::{BufRead, BufReader};
use std::path::PathBuf;
use std::process::{Child, Command, Stdio};
use std::time::Instant;

#[derive(clap::Args)]
pub struct BenchIpcArgs {
    /// Records per frame for the publish-cost measurement.
    #[arg(long, default_value_t = 1_000_000)]
    particles: usize,
    /// Frames timed for the publish cost.
    #[arg(long, default_value_t = 40)]
    frames: u64,
    /// Scene for the solver-overhead measurement.
    #[arg(long, default_value = "models/scenes/column_collapse_3d.toml")]
    scene: PathBuf,
    /// Scene overrides for it (repeatable).
    #[arg(long = "set", value_name = "KEY.PATH=VALUE")]
    set: Vec<String>,
    /// Timed solver steps per configuration.
    #[arg(long, default_value_t = 20)]
    steps: u64,
    /// Output directory for bench_ipc.json.
    #[arg(long, default_value = "out/bench")]
    out: PathBuf,
}

/// A `granmix watch` child process subscribed to `service`; killed on drop.
struct Watcher(Child);

impl Watcher {
    fn start(service: &str) -> Result<Self> {
        let exe = std::env::current_exe().context("locating the granmix binary")?;
        let mut child = Command::new(exe)
            .args(["watch", service, "--timeout", "120"])
            .stdout(Stdio::piped())
            .stderr(Stdio::null())
            .spawn()
            .context("starting `granmix watch`")?;
        let out = child.stdout.take().context("watch stdout")?;
        let mut lines = BufReader::new(out).lines();
        match lines.next() {
            Some(Ok(l)) if l.starts_with("ready") => {}
            other => bail!("`granmix watch` did not start: {other:?}"),
        }
        // drain the rest so the child never blocks on a full pipe
        std::thread::spawn(move || for _ in lines {});
        Ok(Watcher(child))
    }
}

impl Drop for Watcher {
    fn drop(&mut self) {
        let _ = self.0.kill();
        let _ = self.0.wait();
    }
}

fn median(mut v: Vec<f64>) -> f64 {
    v.sort_by(f64::total_cmp);
    if v.is_empty() {
        return f64::NAN;
    }
    v[v.len() / 2]
}

fn mean(v: &[f64]) -> f64 {
    v.iter().sum::<f64>() / v.len().max(1) as f64
}

pub fn bench_ipc(a: &BenchIpcArgs) -> Result<()> {
    let tag = format!("bench-{}", std::process::id());
    let publish = publish_cost(a, &tag)?;
    let solver = solver_overhead(a, &tag)?;
    std::fs::create_dir_all(&a.out)?;
    let report = json!({
        "publish": publish.json(),
        "solver": solver.json(a),
    });
    let path = a.out.join("bench_ipc.json");
    std::fs::write(&path, serde_json::to_string_pretty(&report)?)?;
    println!("written {}", path.display());
    Ok(())
}

/// Part 1: the median time to publish one frame to a subscriber process, copied in and
/// filled in place, against a memcpy of the same bytes.
struct PublishCost {
    particles: usize,
    bytes: usize,
    /// Frames published (loan, copy, send) and sent.
    frames: usize,
    /// Medians (s): memcpy, publish (loan, copy, send), publish into a loan zeroed and
    /// filled in place.
    medians: [f64; 3],
}

impl PublishCost {
    fn json(&self) -> Value {
        let [m_copy, m_pub, m_fill] = self.medians;
        json!({
            "particles": self.particles,
            "bytes": self.bytes,
            "frames": self.frames,
            "publish_copy_ms_median": 1e3 * m_pub,
            "publish_fill_ms_median": 1e3 * m_fill,
            "memcpy_ms_median": 1e3 * m_copy,
            "ratio_copy": m_pub / m_copy,
            "ratio_fill": m_fill / m_copy,
        })
    }
}

/// Part 1, measured and printed.
fn publish_cost(a: &BenchIpcArgs, tag: &str) -> Result<PublishCost> {
    let n = a.particles;
    let src: Vec<ParticleRecord> = (0..n).map(|i| pattern_record(0, i)).collect();
    let mut dst = vec![ParticleRecord::default(); n];
    let mut memcpy = Vec::new();
    for _ in 0..a.frames {
        let t = Instant::now();
        dst.copy_from_slice(&src);
        memcpy.push(t.elapsed().as_secs_f64());
        std::hint::black_box(&dst);
    }
    let mut publisher = FramePublisher::open(&format!("{tag}-frames"), n)?;
    let watcher = Watcher::start(publisher.name())?;
    let (mut publish, mut publish_fill) = (Vec::new(), Vec::new());
    for k in 0..a.frames {
        let info = pattern_info(k, n);
        let t = Instant::now();
        let out = publisher.publish_slice(&info, &src);
        let dt = t.elapsed().as_secs_f64();
        if let Outcome::Sent(_) = out {
            publish.push(dt);
        }
        let t = Instant::now();
        let out = publisher.publish_with(&info, |recs| recs.copy_from_slice(&src));
        let dt = t.elapsed().as_secs_f64();
        if let Outcome::Sent(_) = out {
            publish_fill.push(dt);
        }
    }
    drop(watcher);
    let bytes = n * std::mem::size_of::<ParticleRecord>();
    let frames = publish.len();
    let medians = [median(memcpy), median(publish), median(publish_fill)];
    let [m_copy, m_pub, m_fill] = medians;
    println!(
        "publish {} records ({:.1} MB) to a subscriber process, median per frame: {:.3} ms (loan, copy, send; {} frames), {:.3} ms (loan zeroed, fill in place, send); memcpy of the same bytes {:.3} ms ({:.2}x and {:.2}x)",
        n,
        bytes as f64 / 1e6,
        1e3 * m_pub,
        frames,
        1e3 * m_fill,
        1e3 * m_copy,
        m_pub / m_copy,
        m_fill / m_copy
    );
    Ok(PublishCost {
        particles: n,
        bytes,
        frames,
        medians,
    })
}

/// Part 2: a scene's step times without a publisher, publishing with no subscriber
/// and publishing to a subscriber process, and the publish call on its own.
struct SolverOverhead {
    particles: usize,
    /// Seconds per step in each mode: plain, no subscriber, subscriber.
    times: [Vec<f64>; 3],
    /// Median seconds of a publish call that sent its frame.
    frame: f64,
    /// Median seconds of a memcpy of one frame's bytes.
    copy: f64,
    sent: u64,
    dropped: u64,
}

/// Part 2, measured: one step in each mode in turn, the first mode rotating, so noise,
/// drifts and memory layout hit all three alike.
fn solver_overhead(a: &BenchIpcArgs, tag: &str) -> Result<SolverOverhead> {
    let loaded = load(&a.scene, &a.set)?;
    let mut sim = AnySimulation::new(&loaded).map_err(|e| anyhow::anyhow!("{e}"))?;
    for _ in 0..2 {
        sim.step(f64::INFINITY)
            .map_err(|e| anyhow::anyhow!("{e}"))?;
    }
    let (f, c) = sim.particle_counts();
    let mut quiet = FramePublisher::open(&format!("{tag}-quiet"), f + c)?;
    let mut loud = FramePublisher::open(&format!("{tag}-loud"), f + c)?;
    let watcher = Watcher::start(loud.name())?;
    let mut times: [Vec<f64>; 3] = Default::default();
    let mut frame_times = Vec::new();
    for block in 0..a.steps as usize {
        // one step in each mode per block, the first mode rotating, so slow drifts
        // and periodic work (neighbour rebuilds) spread over all three
        for j in 0..3 {
            let k = (block + j) % 3;
            let t = Instant::now();
            sim.step(f64::INFINITY)
                .map_err(|e| anyhow::anyhow!("{e}"))?;
            match k {
                1 => {
                    quiet.publish(&sim);
                }
                2 => {
                    let tp = Instant::now();
                    if let Outcome::Sent(_) = loud.publish(&sim) {
                        frame_times.push(tp.elapsed().as_secs_f64());
                    }
                }
                _ => {}
            }
            times[k].push(t.elapsed().as_secs_f64());
        }
    }
    drop(watcher);
    // memcpy of one frame's bytes of this scene, for scale
    let sim_bytes = (f + c) * std::mem::size_of::<ParticleRecord>();
    let (from, mut to) = (vec![0u8; sim_bytes], vec![0u8; sim_bytes]);
    let mut sim_copy = Vec::new();
    for _ in 0..a.steps {
        let t = Instant::now();
        to.copy_from_slice(&from);
        sim_copy.push(t.elapsed().as_secs_f64());
        std::hint::black_box(&to);
    }
    let s = SolverOverhead {
        particles: f + c,
        times,
        frame: median(frame_times.clone()),
        copy: median(sim_copy),
        sent: loud.stats().sent,
        dropped: loud.stats().dropped,
    };
    s.print(a, sim_bytes, frame_times.len());
    Ok(s)
}

impl SolverOverhead {
    /// Medians of the three modes (a neighbour rebuild makes a few steps much longer).
    fn medians(&self) -> [f64; 3] {
        self.times.clone().map(median)
    }

    fn print(&self, a: &BenchIpcArgs, bytes: usize, frames: usize) {
        let [plain, no_sub, with_sub] = self.medians();
        let overhead = |x: f64| 100.0 * (x - plain) / plain;
        println!(
            "publish from the solver's arrays ({} particles, {:.1} MB): {:.3} ms per frame (median of {}); memcpy of the same bytes {:.3} ms ({:.2}x)",
            self.particles,
            bytes as f64 / 1e6,
            1e3 * self.frame,
            frames,
            1e3 * self.copy,
            self.frame / self.copy
        );
        println!(
            "publishing one frame per step costs {:.3} % of a step without publisher (measured inside the step)",
            100.0 * self.frame / plain
        );
        println!(
            "solver, {} particles, {} steps in each mode, median: {:.2} ms/step without publisher; {:.2} ms ({:+.2} %) publishing with no subscriber; {:.2} ms ({:+.2} %) publishing every step to a subscriber ({} frames sent)",
            self.particles,
            a.steps,
            1e3 * plain,
            1e3 * no_sub,
            overhead(no_sub),
            1e3 * with_sub,
            overhead(with_sub),
            self.sent
        );
    }

    fn json(&self, a: &BenchIpcArgs) -> Value {
        let [plain, no_sub, with_sub] = self.medians();
        let [plain_mean, no_sub_mean, with_sub_mean] = self.times.clone().map(|v| mean(&v));
        let overhead = |x: f64| 100.0 * (x - plain) / plain;
        let ms = |v: &[f64]| v.iter().map(|t| 1e3 * t).collect::<Vec<_>>();
        json!({
            "scene": a.scene.display().to_string(),
            "set": a.set,
            "particles": self.particles,
            "steps": a.steps,
            "ms_per_step_plain": 1e3 * plain,
            "ms_per_step_mean": [1e3 * plain_mean, 1e3 * no_sub_mean, 1e3 * with_sub_mean],
            "ms_per_step_no_subscriber": 1e3 * no_sub,
            "ms_per_step_subscriber": 1e3 * with_sub,
            "overhead_no_subscriber_percent": overhead(no_sub),
            "overhead_subscriber_percent": overhead(with_sub),
            "publish_from_solver_ms_median": 1e3 * self.frame,
            "publish_share_of_step_percent": 100.0 * self.frame / plain,
            "memcpy_same_bytes_ms_median": 1e3 * self.copy,
            "frames_sent": self.sent,
            "step_ms": {
                "plain": ms(&self.times[0]),
                "no_subscriber": ms(&self.times[1]),
                "subscriber": ms(&self.times[2]),
            },
            "frames_dropped": self.dropped,
        })
    }
}
