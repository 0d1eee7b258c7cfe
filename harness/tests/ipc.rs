//! The particle channel between processes and the MCAP recording, driven through the
//! `granmix` binary: pattern frames bit for bit, a run that a stalled or killed
//! subscriber cannot stop or change, and a recording read back with the Rust reader.

use granmix_ipc::foxglove::messages::{FrameTransforms, PointCloud, SceneUpdate};
use granmix_ipc::foxglove::{Decode, Encode};
use granmix_ipc::pattern::{pattern_info, pattern_record};
use granmix_ipc::payload::record_bytes;
use granmix_ipc::FrameSubscriber;
use std::collections::BTreeMap;
use std::io::{BufRead, BufReader};
use std::path::{Path, PathBuf};
use std::process::{Child, Command, Stdio};
use std::time::{Duration, Instant};

const BIN: &str = env!("CARGO_BIN_EXE_granmix");

fn root() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("..")
}

/// A service name no earlier (possibly killed) test run has used.
fn unique(tag: &str) -> String {
    let t = std::time::SystemTime::now()
        .duration_since(std::time::UNIX_EPOCH)
        .unwrap()
        .as_nanos();
    format!("test-{tag}-{}-{t}", std::process::id())
}

/// A child process killed when the test ends, whatever happens.
struct Proc(Child);

impl Drop for Proc {
    fn drop(&mut self) {
        let _ = self.0.kill();
        let _ = self.0.wait();
    }
}

/// Start `granmix args…` and wait for its `ready` line; further lines go to `lines`.
fn start(args: &[&str]) -> (Proc, std::sync::mpsc::Receiver<String>) {
    let mut child = Command::new(BIN)
        .args(args)
        .stdout(Stdio::piped())
        .stderr(Stdio::inherit())
        .spawn()
        .expect("granmix starts");
    let out = child.stdout.take().unwrap();
    let (tx, rx) = std::sync::mpsc::channel();
    std::thread::spawn(move || {
        for l in BufReader::new(out).lines().map_while(Result::ok) {
            let _ = tx.send(l);
        }
    });
    let first = rx
        .recv_timeout(Duration::from_secs(60))
        .expect("a ready line");
    assert!(first.starts_with("ready"), "{args:?} printed {first}");
    (Proc(child), rx)
}

#[test]
fn two_processes_exchange_100_frames_of_100k_particles_bit_for_bit() {
    let svc = unique("pattern");
    let n = 100_000;
    let (mut publisher, _) = start(&[
        "ipc-pattern",
        &svc,
        "--particles",
        &n.to_string(),
        "--frames",
        "100",
        "--timeout",
        "60",
    ]);
    let sub = FrameSubscriber::open(&svc).unwrap();
    let deadline = Instant::now() + Duration::from_secs(120);
    let mut k = 0u64;
    while k < 100 {
        assert!(Instant::now() < deadline, "only {k} frames arrived");
        let Some(frame) = sub.receive().unwrap() else {
            std::thread::sleep(Duration::from_micros(200));
            continue;
        };
        let h = frame.header();
        let info = pattern_info(k, n);
        assert_eq!(h.sequence, k);
        assert_eq!(h.time.to_bits(), info.time.to_bits());
        assert_eq!(h.step, info.step);
        assert_eq!(h.fine_count as usize, info.fine_count);
        assert_eq!(h.coarse_count as usize, info.coarse_count);
        let expected: Vec<_> = (0..n).map(|i| pattern_record(k, i)).collect();
        assert!(
            record_bytes(frame.records()) == record_bytes(&expected),
            "frame {k} differs"
        );
        k += 1;
    }
    drop(sub);
    let status = publisher.0.wait().unwrap();
    assert!(status.success());
}

fn read_series(dir: &Path) -> String {
    std::fs::read_to_string(dir.join("series.csv")).unwrap()
}

fn summary(dir: &Path) -> serde_json::Value {
    serde_json::from_str(&std::fs::read_to_string(dir.join("summary.json")).unwrap()).unwrap()
}

fn run(scene: &str, out: &Path, extra: &[&str]) -> std::process::ExitStatus {
    let scene = root().join("models/scenes").join(scene);
    Command::new(BIN)
        .arg("run")
        .arg(&scene)
        .arg("--out")
        .arg(out)
        .args(["--no-vtk", "--quiet"])
        .args(extra)
        .status()
        .unwrap()
}

#[test]
fn stalled_and_killed_subscribers_neither_stop_nor_change_the_run() {
    let tmp = std::env::temp_dir().join(unique("stall"));
    let svc = unique("stall");
    let sets = [
        "--set",
        "simulation.end_time=0.02",
        "--set",
        "simulation.output_interval=0.005",
    ];
    // reference without publishing
    let plain = tmp.join("plain");
    assert!(run("column_collapse_2d.toml", &plain, &sets).success());
    // one subscriber that never takes a frame, one that is killed mid-run
    let (_stalled, _) = start(&["watch", &svc, "--stall", "--timeout", "120"]);
    let (mut victim, lines) = start(&["watch", &svc, "--timeout", "120"]);
    let published = tmp.join("published");
    let mut args: Vec<&str> = sets.to_vec();
    args.extend(["--publish", &svc, "--publish-every", "1"]);
    let scene = root().join("models/scenes/column_collapse_2d.toml");
    let mut runner = Proc(
        Command::new(BIN)
            .arg("run")
            .arg(&scene)
            .arg("--out")
            .arg(&published)
            .args(["--no-vtk", "--quiet"])
            .args(&args)
            .spawn()
            .unwrap(),
    );
    // kill the live subscriber once it has a frame (or the run ended first)
    let _ = lines.recv_timeout(Duration::from_secs(120));
    victim.0.kill().unwrap();
    let status = runner.0.wait().unwrap();
    assert!(status.success(), "the run failed: {status}");
    let (a, b) = (summary(&plain), summary(&published));
    assert_eq!(a["steps_fine"], b["steps_fine"], "all steps ran");
    assert_eq!(read_series(&plain), read_series(&published), "same results");
    let p = &b["publish"];
    assert_eq!(p["every"], 1);
    assert!(p["frames_sent"].as_u64().unwrap() > 0, "{p}");
    let _ = std::fs::remove_dir_all(&tmp);
}

#[test]
fn recording_reads_back_with_the_rust_reader() {
    let tmp = std::env::temp_dir().join(unique("record"));
    let mcap_path = tmp.join("run.mcap");
    let status = run(
        "blocks_impact.toml",
        &tmp,
        &[
            "--set",
            "simulation.end_time=0.002",
            "--set",
            "simulation.output_interval=0.0005",
            "--record",
            mcap_path.to_str().unwrap(),
        ],
    );
    assert!(status.success());
    let s = summary(&tmp);
    let samples = read_series(&tmp).lines().count() as u64 - 1;
    let counts = &s["record"]["messages"];
    assert_eq!(counts["particles"].as_u64(), Some(samples));
    let bytes = std::fs::read(&mcap_path).unwrap();
    let mut per_topic: BTreeMap<String, u64> = BTreeMap::new();
    let particles = s["particles"].as_u64().unwrap() + s["particles_coarse"].as_u64().unwrap();
    for m in mcap::MessageStream::new(&bytes).unwrap() {
        let m = m.unwrap();
        *per_topic.entry(m.channel.topic.clone()).or_default() += 1;
        let schema = m.channel.schema.as_ref().unwrap();
        match m.channel.topic.as_str() {
            "/particles" => {
                let fox = PointCloud::get_schema().unwrap();
                assert_eq!(schema.name, "foxglove.PointCloud");
                assert_eq!(schema.encoding, "protobuf");
                assert_eq!(&schema.data[..], &fox.data[..], "foxglove's descriptor");
                let pc = PointCloud::decode(&m.data[..]).unwrap();
                assert_eq!(pc.point_stride, 56);
                assert_eq!(pc.data.len() as u64, 56 * particles);
            }
            "/bodies" => {
                let fox = FrameTransforms::get_schema().unwrap();
                assert_eq!(schema.name, "foxglove.FrameTransforms");
                assert_eq!(&schema.data[..], &fox.data[..]);
                let ft = FrameTransforms::decode(&m.data[..]).unwrap();
                assert_eq!(ft.transforms.len(), 3);
            }
            "/walls" => {
                // the geometry, once: every wall particle as x, y, z and its object
                assert_eq!(schema.name, "foxglove.PointCloud");
                let pc = PointCloud::decode(&m.data[..]).unwrap();
                assert_eq!(pc.point_stride, 16);
                let walls = s["wall_particles"].as_u64().unwrap();
                assert_eq!(pc.data.len() as u64, 16 * walls);
            }
            "/geometry" => {
                // the walls' solids, once (nothing moves): one entity per wall object
                assert_eq!(schema.name, "foxglove.SceneUpdate");
                let fox = SceneUpdate::get_schema().unwrap();
                assert_eq!(&schema.data[..], &fox.data[..]);
                let su = SceneUpdate::decode(&m.data[..]).unwrap();
                let objects: Vec<&str> = su.entities.iter().map(|e| e.id.as_str()).collect();
                assert_eq!(objects, ["tank.left", "tank.bottom"]);
            }
            "/barriers" | "/energy" => {
                assert_eq!(schema.encoding, "jsonschema");
                assert_eq!(m.channel.message_encoding, "json");
                let v: serde_json::Value = serde_json::from_slice(&m.data).unwrap();
                assert!(v["time"].is_number());
            }
            t => panic!("unexpected topic {t}"),
        }
    }
    for (topic, key) in [
        ("/particles", "particles"),
        ("/bodies", "bodies"),
        ("/barriers", "barriers"),
        ("/energy", "energy"),
    ] {
        assert_eq!(per_topic.get(topic).copied(), Some(samples), "{topic}");
        assert_eq!(counts[key].as_u64(), Some(samples), "{key}");
    }
    assert_eq!(per_topic.get("/walls").copied(), Some(1));
    assert_eq!(counts["walls"].as_u64(), Some(1));
    assert_eq!(per_topic.get("/geometry").copied(), Some(1));
    assert_eq!(counts["geometry"].as_u64(), Some(1));
    let summary = mcap::Summary::read(&bytes).unwrap().unwrap();
    let scene_text = std::fs::read_to_string(tmp.join("scene.toml")).unwrap();
    let idx = &summary.attachment_indexes;
    assert_eq!(idx.len(), 1);
    let att = mcap::read::attachment(&bytes, &idx[0]).unwrap();
    assert_eq!(att.name, "scene.toml");
    assert_eq!(&att.data[..], scene_text.as_bytes());
    let _ = std::fs::remove_dir_all(&tmp);
}

/// A water scene's recording carries the water on its own `/water` topic, every record
/// of family 2 and as many as the run's water particles.
#[test]
fn water_is_recorded_on_its_own_topic() {
    let tmp = std::env::temp_dir().join(unique("water"));
    let mcap_path = tmp.join("run.mcap");
    let status = run(
        "fmu_water_barrier_2d.toml",
        &tmp,
        &[
            "--set",
            "simulation.end_time=0.004",
            "--set",
            "simulation.output_interval=0.002",
            "--record",
            mcap_path.to_str().unwrap(),
        ],
    );
    assert!(status.success());
    let s = summary(&tmp);
    let water = s["particles_water"].as_u64().unwrap();
    assert!(water > 0);
    let samples = read_series(&tmp).lines().count() as u64 - 1;
    assert_eq!(s["record"]["messages"]["water"].as_u64(), Some(samples));
    let bytes = std::fs::read(&mcap_path).unwrap();
    let mut seen = 0;
    for m in mcap::MessageStream::new(&bytes).unwrap() {
        let m = m.unwrap();
        if m.channel.topic == "/water" {
            let pc = PointCloud::decode(&m.data[..]).unwrap();
            assert_eq!(pc.point_stride, 56);
            assert_eq!(pc.data.len() as u64, 56 * water);
            for r in pc.data.chunks(56) {
                assert_eq!(&r[40..44], &2u32.to_le_bytes(), "family of a water record");
            }
            seen += 1;
        }
    }
    assert_eq!(seen, samples);
}
