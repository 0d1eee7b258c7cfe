//! Bitwise record of the physics: bundled scenes run 25–925 steps through the CLI,
//! and their `series.csv` and the deterministic part of `summary.json` (observables,
//! bodies, step counts, time steps, particle counts, status) must equal, byte for byte,
//! the record in `harness/tests/golden/`. A refactoring that changes no physics leaves
//! every file equal; a change of physics shows here first, scene by scene.
//!
//! The scenes cover 2D and 3D soil, rigid and elastic coarse bodies, a barrier with
//! panels, cohesion with rocks, a barrier moving at a prescribed speed, and one driven
//! through its displacement input as an FMU master drives it; water in a dam break, a
//! periodic channel, around a boulder and against an FMU barrier; saturated soil in a
//! seepage column and a debris flow with boulders.
//! The record holds for this machine's floating point (x86-64, glibc's libm); the
//! results are the same at any thread count (`determinism.rs`) and on both
//! instruction sets of the lane passes (AVX2 and the baseline, `GRANMIX_SIMD=scalar`).
//!
//! After an intended change of physics, rewrite the record with
//! `GRANMIX_BLESS=1 cargo test --release --workspace --test cli golden` and say in the
//! commit why the numbers moved.

use granmix_core::input::load_scene_file;
use granmix_core::AnySimulation;
use serde_json::Value;
use std::fmt::Write as _;
use std::path::{Path, PathBuf};
use std::process::Command;

const BIN: &str = env!("CARGO_BIN_EXE_granmix");

/// Scene, end time (s) and the other overrides that keep it to a few hundred steps at
/// most; every case writes five samples after t = 0.
const CASES: &[(&str, f64, &[&str])] = &[
    ("column_collapse_2d.toml", 0.02, &["simulation.dp=0.008"]),
    ("column_collapse_3d.toml", 0.01, &["simulation.dp=0.01"]),
    ("impact_crater.toml", 0.002, &["simulation.dp=0.006"]),
    ("blocks_impact.toml", 0.01, &["simulation.dp=0.005"]),
    ("debris_barrier.toml", 0.05, &[]),
    ("srm_slope.toml", 0.02, &["simulation.dp=1.0"]),
    ("rubber_rings.toml", 0.0005, &[]),
    ("incline_block.toml", 0.02, &[]),
    ("active_earth_pressure_2d.toml", 0.02, &[]),
    (
        "fmu_barrier_2d.toml",
        0.02,
        &["barriers[0].panels=[4]", "regions[0].velocity=[2.0, 0.0]"],
    ),
    ("geostatic_layer.toml", 0.01, &[]),
    // water and saturated soil (issue 40: recorded before the families are refactored)
    ("dam_break_2d.toml", 0.02, &[]),
    ("boulder_in_water.toml", 0.01, &[]),
    ("poiseuille_2d.toml", 5.0, &[]),
    ("seepage_column.toml", 0.03, &[]),
    ("debris_flow_saturated.toml", 0.05, &[]),
    ("fmu_water_barrier_2d.toml", 0.05, &[]),
];

/// The keys of summary.json that depend on the physics alone (not on timing, threads,
/// paths or memory layout).
const SUMMARY_KEYS: &[&str] = &[
    "blowup",
    "bodies",
    "dimension",
    "dt_coarse",
    "dt_fine",
    "kappa",
    "name",
    "neighbor_builds",
    "observables",
    "particles",
    "particles_coarse",
    "status",
    "steps_coarse",
    "steps_fine",
    "wall_particles",
];

fn root() -> PathBuf {
    PathBuf::from(env!("CARGO_MANIFEST_DIR"))
}

/// Run one case into `out` on the instruction set `simd` asks for (`GRANMIX_SIMD`:
/// `auto` or `scalar`) and return (series.csv, the physics part of summary.json).
fn run_case(scene: &str, (end, set): (f64, &[&str]), simd: &str, out: &Path) -> (String, String) {
    let path = root().join("../models/scenes").join(scene);
    let mut cmd = Command::new(BIN);
    cmd.env(granmix_core::numerics::pairs::quad::ENV, simd);
    cmd.arg("run")
        .arg(&path)
        .args(["--quiet", "--no-vtk", "--out"])
        .arg(out);
    cmd.args(["--set", &format!("simulation.end_time={end}")]);
    cmd.args([
        "--set",
        &format!("simulation.output_interval={}", end / 5.0),
    ]);
    for s in set {
        cmd.args(["--set", s]);
    }
    let o = cmd.output().expect("granmix runs");
    assert!(
        o.status.success(),
        "{scene}: granmix run failed:\n{}",
        String::from_utf8_lossy(&o.stderr)
    );
    let series = std::fs::read_to_string(out.join("series.csv")).expect("series.csv");
    let summary: Value = serde_json::from_str(
        &std::fs::read_to_string(out.join("summary.json")).expect("summary.json"),
    )
    .expect("summary.json is JSON");
    if simd == "scalar" {
        assert_eq!(
            summary["simd"], "scalar",
            "{scene}: GRANMIX_SIMD=scalar did not select the baseline lanes"
        );
    }
    let kept: serde_json::Map<String, Value> = SUMMARY_KEYS
        .iter()
        .map(|k| {
            let v = summary
                .get(*k)
                .unwrap_or_else(|| panic!("{scene}: summary.json has no `{k}`"));
            (k.to_string(), v.clone())
        })
        .collect();
    let mut summary = serde_json::to_string_pretty(&Value::Object(kept)).unwrap();
    summary.push('\n');
    (series, summary)
}

/// fmu_barrier_2d with four panels, its barrier driven as an FMU master drives it: a
/// displacement input set before each 1 ms communication step (a ramp and a
/// half-sine). Every sample's loads, panel forces and energies, printed exactly ({:?}
/// round-trips an f64).
fn input_driven_barrier() -> String {
    let scene = root().join("../models/scenes/fmu_barrier_2d.toml");
    let set = ["barriers[0].panels=[4]".to_string()];
    let loaded = load_scene_file(&scene, &set).unwrap_or_else(|e| panic!("{e}"));
    let mut sim = AnySimulation::new(&loaded).unwrap_or_else(|e| panic!("{e}"));
    let mut text = String::from("time,displacement.x,force,moment,peak_force,panels,ke\n");
    let h = 1e-3;
    for n in 0..20u32 {
        let t = f64::from(n) * h;
        let x = 2e-5 * f64::from(n) + 1e-4 * (t * std::f64::consts::PI / 0.02).sin();
        let d = sim.barrier_displacement(0);
        sim.drive_barrier(0, [(x - d[0]) / h, -d[1] / h, -d[2] / h])
            .unwrap_or_else(|e| panic!("{e}"));
        sim.advance_to(t + h).unwrap_or_else(|e| panic!("{e}"));
        let s = sim.sample();
        let b = &s.barriers[0];
        writeln!(
            text,
            "{:?},{:?},{:?},{:?},{:?},{:?},{:?}",
            s.time, x, b.force, b.moment, b.peak_force, b.panels, s.kinetic_energy
        )
        .unwrap();
    }
    text
}

/// First line at which two texts differ, for the failure message.
fn first_difference(a: &str, b: &str) -> String {
    for (i, (x, y)) in a.lines().zip(b.lines()).enumerate() {
        if x != y {
            let cut = |s: &str| s.chars().take(300).collect::<String>();
            return format!(
                "line {}:\n  record: {}\n  now:    {}",
                i + 1,
                cut(x),
                cut(y)
            );
        }
    }
    format!(
        "{} lines recorded, {} now",
        a.lines().count(),
        b.lines().count()
    )
}

#[test]
fn golden_outputs_are_bitwise_unchanged() {
    compare_with_record("auto");
}

/// The same record on the baseline instruction set (`GRANMIX_SIMD=scalar`, the path
/// of an x86-64 without AVX2): the cluster-pair passes give the same bits on both
/// levels (`pairs::quad`), so every scene's files equal the record. The input-driven
/// barrier runs in this process, on the level it detected, and is left to the test
/// above.
#[test]
fn golden_outputs_are_the_same_on_the_scalar_path() {
    compare_with_record("scalar");
}

/// Run every case on `simd` and compare its files with the record (or rewrite the
/// record, with `GRANMIX_BLESS=1`, on the detected level only).
fn compare_with_record(simd: &str) {
    let bless = simd == "auto" && std::env::var_os("GRANMIX_BLESS").is_some();
    let tmp = std::env::temp_dir().join(format!("granmix_golden_{simd}_{}", std::process::id()));
    let mut records = Vec::new();
    for (scene, end, set) in CASES {
        let stem = scene.trim_end_matches(".toml");
        let (series, summary) = run_case(scene, (*end, set), simd, &tmp.join(stem));
        records.push((format!("{stem}/series.csv"), series));
        records.push((format!("{stem}/summary.json"), summary));
    }
    if simd == "auto" {
        records.push((
            "fmu_barrier_2d_driven/loads.csv".to_string(),
            input_driven_barrier(),
        ));
    }
    let _ = std::fs::remove_dir_all(&tmp);
    let mut failures = Vec::new();
    for (name, now) in &records {
        let file = root().join("tests/golden").join(name);
        let dir = file.parent().unwrap();
        if bless {
            std::fs::create_dir_all(dir).unwrap();
            std::fs::write(&file, now).unwrap();
            continue;
        }
        match std::fs::read_to_string(&file) {
            Ok(record) if record == *now => {}
            Ok(record) => failures.push(format!(
                "{name} differs from the record, {}",
                first_difference(&record, now)
            )),
            Err(e) => failures.push(format!(
                "{}: {e} (record it with GRANMIX_BLESS=1)",
                file.display()
            )),
        }
    }
    assert!(
        failures.is_empty(),
        "GRANMIX_SIMD={simd}: {} golden file(s) changed:\n{}",
        failures.len(),
        failures.join("\n")
    );
}
