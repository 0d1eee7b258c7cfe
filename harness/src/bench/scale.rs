//! `granmix bench --suite scale`: throughput and memory against problem size. The 3D
//! column collapse (and the 2D one, for bytes per particle) is built at spacings that
//! give about 10 k to 2 M fine particles; each is timed over a fixed number of fine
//! steps after a warm-up, smallest first, so the process's peak resident set after a
//! size is that size's peak. Reports particle-steps per second, its spread over the
//! sizes (the cost per particle-step should not grow with N), bytes per particle (the
//! solver's arrays and the peak RSS) and the largest 3D scene this machine's memory
//! holds at that rate.

use crate::run::load;
use anyhow::Result;
use granmix_core::AnySimulation;
use serde_json::{json, Value};
use std::path::Path;
use std::time::Instant;

/// Peak resident set size of this process (VmHWM), bytes; None off Linux.
pub fn peak_rss() -> Option<u64> {
    let s = std::fs::read_to_string("/proc/self/status").ok()?;
    let line = s.lines().find(|l| l.starts_with("VmHWM:"))?;
    let kb: u64 = line.split_whitespace().nth(1)?.parse().ok()?;
    Some(kb * 1024)
}

/// Total physical memory (MemTotal), bytes.
fn mem_total() -> Option<u64> {
    let s = std::fs::read_to_string("/proc/meminfo").ok()?;
    let line = s.lines().find(|l| l.starts_with("MemTotal:"))?;
    let kb: u64 = line.split_whitespace().nth(1)?.parse().ok()?;
    Some(kb * 1024)
}

struct Size {
    dim: usize,
    scene: &'static str,
    /// Fine particles wanted.
    target: f64,
    /// Particles and spacing of the scene as bundled.
    n0: f64,
    dp0: f64,
}

fn sizes(quick: bool) -> Vec<Size> {
    let three = |target| Size {
        dim: 3,
        scene: "column_collapse_3d.toml",
        target,
        n0: 25_280.0,
        dp0: 0.005,
    };
    let two = |target| Size {
        dim: 2,
        scene: "column_collapse_2d.toml",
        target,
        n0: 5_000.0,
        dp0: 0.002,
    };
    if quick {
        return vec![two(2e3), three(2e3)];
    }
    vec![
        two(1e4),
        two(1e5),
        three(1e4),
        three(3e4),
        three(1e5),
        three(3e5),
        three(1e6),
        three(2e6),
    ]
}

/// Run the scale suite, write `scale.json` and `scale.md` (and the Markdown to
/// `report`); returns the JSON document.
pub fn scale(scenes: &Path, out: &Path, quick: bool, report: Option<&Path>) -> Result<Value> {
    std::fs::create_dir_all(out)?;
    let (warm, timed) = if quick { (2, 5) } else { (5, 30) };
    println!(
        "{:>3} {:>10} {:>10} {:>9} {:>10} {:>12} {:>10} {:>10}",
        "dim", "dp [m]", "fine", "walls", "setup [s]", "Mpart-st/s", "B/part", "RSS B/part"
    );
    let mut runs = Vec::new();
    let base = peak_rss().unwrap_or(0);
    for s in sizes(quick) {
        let dp = s.dp0 * (s.n0 / s.target).powf(1.0 / s.dim as f64);
        let set = vec![format!("simulation.dp={dp:.6}")];
        let t0 = Instant::now();
        let loaded = load(&scenes.join(s.scene), &set)?;
        let mut sim = AnySimulation::new(&loaded).map_err(|e| anyhow::anyhow!("{e}"))?;
        for _ in 0..warm {
            sim.step(f64::INFINITY)
                .map_err(|b| anyhow::anyhow!("{}: {b}", s.scene))?;
        }
        let setup = t0.elapsed().as_secs_f64();
        let t1 = Instant::now();
        for _ in 0..timed {
            sim.step(f64::INFINITY)
                .map_err(|b| anyhow::anyhow!("{}: {b}", s.scene))?;
        }
        let wall = t1.elapsed().as_secs_f64();
        let n = sim.fine_count();
        let rate = (n * timed) as f64 / wall;
        let bytes = sim.fine_bytes() as f64 / n as f64;
        let rss = peak_rss().map(|r| r.saturating_sub(base) as f64 / n as f64);
        println!(
            "{:>3} {:>10.6} {:>10} {:>9} {:>10.1} {:>12.3} {:>10.0} {:>10}",
            s.dim,
            dp,
            n,
            sim.wall_count(),
            setup,
            rate / 1e6,
            bytes,
            rss.map(|r| format!("{r:.0}")).unwrap_or("-".into())
        );
        runs.push(json!({
            "dimension": s.dim, "scene": s.scene, "dp": dp, "particles": n,
            "wall_particles": sim.wall_count(), "setup_s": setup, "steps_timed": timed,
            "wall_time_s": wall, "particle_steps_per_s": rate,
            "bytes_per_particle": bytes, "peak_rss_bytes_per_particle": rss,
        }));
        drop(sim);
    }
    let rates: Vec<f64> = runs
        .iter()
        .filter(|r| r["dimension"] == 3)
        .filter_map(|r| r["particle_steps_per_s"].as_f64())
        .collect();
    let spread = if rates.len() > 1 {
        let hi = rates.iter().copied().fold(0.0, f64::max);
        let lo = rates.iter().copied().fold(f64::INFINITY, f64::min);
        Some(hi / lo - 1.0)
    } else {
        None
    };
    let per3 = runs.iter().rfind(|r| r["dimension"] == 3).and_then(|r| {
        r["peak_rss_bytes_per_particle"]
            .as_f64()
            .or(r["bytes_per_particle"].as_f64())
    });
    let largest = match (per3, mem_total()) {
        (Some(b), Some(m)) if b > 0.0 => Some(0.8 * m as f64 / b),
        _ => None,
    };
    if let Some(s) = spread {
        println!(
            "3D cost per particle-step: largest/smallest throughput − 1 = {:.1} % (bound 30 %)",
            100.0 * s
        );
    }
    if let Some(l) = largest {
        println!(
            "largest 3D scene in 80 % of this machine's memory: about {:.1} M fine particles",
            l / 1e6
        );
    }
    let doc = json!({
        "suite": "scale", "quick": quick, "threads": rayon::current_num_threads(),
        "runs": runs, "throughput_spread_3d": spread,
        "largest_3d_particles": largest, "memory_total_bytes": mem_total(),
    });
    let path = out.join("scale.json");
    std::fs::write(&path, serde_json::to_string_pretty(&doc)?)?;
    println!("wrote {}", path.display());
    let md = markdown(&doc);
    std::fs::write(out.join("scale.md"), &md)?;
    if let Some(r) = report {
        std::fs::write(r, &md)?;
        println!("wrote {}", r.display());
    }
    Ok(doc)
}

/// The scale report as Markdown, generated from the suite's JSON.
pub fn markdown(doc: &Value) -> String {
    let mut s = format!(
        "# Scale report\n\n\
         Generated by `granmix bench --suite scale` from `scale.json`; do not edit.\n\
         Column collapse (VALIDATION §2 and §3 material) at spacings giving 10 k to 2 M fine\n\
         particles, {} thread(s); each size is timed over a fixed number of fine steps from\n\
         rest after a warm-up. *Bytes/particle* counts the fine-grain solver's arrays\n\
         (particle state, neighbour records, step buffers, neighbour lists, cell grids) per\n\
         fine particle; *peak RSS/particle* is the process's peak resident set over the\n\
         suite's baseline per fine particle, so it also carries the wall particles (2.5 to 7\n\
         per fine particle in this scene's wide floor) and everything else the run holds.\n\n\
         | dim | dp [m] | fine particles | wall particles | set-up [s] | Mparticle-steps/s | bytes/particle | peak RSS/particle |\n\
         |---|---|---|---|---|---|---|---|\n",
        doc["threads"]
    );
    for r in doc["runs"].as_array().cloned().unwrap_or_default() {
        s += &format!(
            "| {} | {:.6} | {} | {} | {:.1} | {:.3} | {:.0} | {} |\n",
            r["dimension"],
            r["dp"].as_f64().unwrap_or(0.0),
            r["particles"],
            r["wall_particles"],
            r["setup_s"].as_f64().unwrap_or(0.0),
            r["particle_steps_per_s"].as_f64().unwrap_or(0.0) / 1e6,
            r["bytes_per_particle"].as_f64().unwrap_or(0.0),
            r["peak_rss_bytes_per_particle"]
                .as_f64()
                .map(|x| format!("{x:.0}"))
                .unwrap_or("–".into()),
        );
    }
    if let Some(x) = doc["throughput_spread_3d"].as_f64() {
        s += &format!(
            "\n3D throughput, largest over smallest − 1: {:.1} % (bound: 30 %).\n",
            100.0 * x
        );
    }
    let last3 = doc["runs"]
        .as_array()
        .and_then(|r| r.iter().rfind(|r| r["dimension"] == 3).cloned());
    if let Some(r) = last3 {
        if let Some(b) = r["peak_rss_bytes_per_particle"].as_f64() {
            s += &format!(
                "3D memory at {} fine particles: {b:.0} bytes of peak RSS per fine particle \
                 (bound: 1 KB).\n",
                r["particles"]
            );
        }
    }
    if let Some(x) = doc["largest_3d_particles"].as_f64() {
        s += &format!(
            "Largest 3D scene in 80 % of this machine's {:.1} GiB at the largest size's peak \
             RSS per particle: about {:.1} M fine particles.\n",
            doc["memory_total_bytes"].as_f64().unwrap_or(0.0) / (1u64 << 30) as f64,
            x / 1e6
        );
    }
    s
}
