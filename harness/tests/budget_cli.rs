//! `granmix check` and `granmix run` refuse a scene over the memory budget at once, and
//! `check` estimates without building.

use std::path::PathBuf;
use std::process::Command;
use std::time::Instant;

const BIN: &str = env!("CARGO_BIN_EXE_granmix");

fn scene(name: &str) -> PathBuf {
    PathBuf::from(env!("CARGO_MANIFEST_DIR"))
        .join("../models/scenes")
        .join(name)
}

fn granmix(args: &[&str]) -> (i32, String, String, f64) {
    let t = Instant::now();
    let out = Command::new(BIN).args(args).output().expect("granmix runs");
    (
        out.status.code().unwrap_or(-1),
        String::from_utf8_lossy(&out.stdout).into_owned(),
        String::from_utf8_lossy(&out.stderr).into_owned(),
        t.elapsed().as_secs_f64(),
    )
}

#[test]
fn check_and_run_refuse_dp_1e_7_promptly() {
    let s = scene("column_collapse_3d.toml");
    let s = s.to_str().unwrap();
    let out = std::env::temp_dir().join(format!("granmix_budget_{}", std::process::id()));
    for args in [
        vec!["check", s, "--set", "simulation.dp=1e-7"],
        vec![
            "run",
            s,
            "--set",
            "simulation.dp=1e-7",
            "--quiet",
            "--no-vtk",
            "--out",
            out.to_str().unwrap(),
        ],
    ] {
        let (code, stdout, stderr, took) = granmix(&args);
        assert_eq!(code, 2, "{args:?}: {stdout}{stderr}");
        assert!(took < 5.0, "{args:?} took {took:.1} s");
        for part in [
            "dp = 1e-7 m",
            "particles",
            "memory budget",
            "--memory-budget",
        ] {
            assert!(
                stderr.contains(part),
                "{args:?}: `{part}` missing: {stderr}"
            );
        }
    }
    std::fs::remove_dir_all(&out).ok();
}

#[test]
fn check_estimates_and_the_flag_sets_the_budget() {
    let s = scene("fmu_barrier_2d.toml");
    let s = s.to_str().unwrap();
    let (code, stdout, stderr, _) = granmix(&["check", s]);
    assert_eq!(code, 0, "{stderr}");
    for part in [
        "region layer",
        "fine particles",
        "dummy particles",
        "memory ~",
        "Δt (Eq. 51, at rest)",
        "cost ~",
    ] {
        assert!(stdout.contains(part), "`{part}` missing: {stdout}");
    }
    let (code, stdout, stderr, _) = granmix(&["check", s, "--exact"]);
    assert_eq!(code, 0, "{stderr}");
    assert!(stdout.contains("200 fine particles"), "{stdout}");
    let (code, _, stderr, _) = granmix(&["check", s, "--memory-budget", "100kB"]);
    assert_eq!(code, 2);
    assert!(
        stderr.contains("over the memory budget of 97.7 KiB"),
        "{stderr}"
    );
    let (code, _, stderr, _) = granmix(&["check", s, "--memory-budget", "lots"]);
    assert_eq!(code, 2);
    assert!(stderr.contains("not a size"), "{stderr}");
}

/// `check` names the bound that sets the step: the acoustic one of a dry soil, the
/// seepage limit ρ_d k / (2 μ) of a soil of low permeability (issue 44: a bound other
/// than the acoustic one must be stated), with and without `--exact`.
#[test]
fn check_names_the_bound_that_sets_the_step() {
    let s = scene("seepage_column.toml");
    let s = s.to_str().unwrap();
    let (code, stdout, stderr, _) = granmix(&["check", s]);
    assert_eq!(code, 0, "{stderr}");
    assert!(stdout.contains("set by CFL · h / c0"), "{stdout}");
    for exact in [&[][..], &["--exact"][..]] {
        // the seepage drag is implicit on both sides: no permeability bounds the step
        let mut args = vec!["check", s, "--set", "materials.0.permeability=1e-12"];
        args.extend_from_slice(exact);
        let (code, stdout, stderr, _) = granmix(&args);
        assert_eq!(code, 0, "{stderr}");
        assert!(stdout.contains("set by CFL · h / c0"), "{stdout}");
        let mut args = vec!["check", s, "--set", "water.viscosity=300"];
        args.extend_from_slice(exact);
        let (code, stdout, stderr, _) = granmix(&args);
        assert_eq!(code, 0, "{stderr}");
        assert!(
            stdout.contains("set by the viscous limit h² ρ / (8 μ)")
                && stdout.contains("(`water.viscosity`)"),
            "{stdout}"
        );
    }
}

/// Issue 74: the estimate counts what an inflow lets in. A channel that starts dry and
/// fills from an inlet (1 m/s through a 0.1 m inlet for 0.2 s, dp = 0.01 m: 20 layers
/// of 10 particles) was estimated at no water, and its steps at the output interval's
/// (4 against the run's 594); the estimate now gives the particles the run ends with
/// (to a layer) and its steps at the water's Δt (within 25 %).
#[test]
fn check_counts_what_an_inflow_lets_in() {
    let dir = std::env::temp_dir().join(format!("granmix_inflow_{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    let path = dir.join("channel.toml");
    std::fs::write(
        &path,
        r#"[simulation]
name = "inflow_channel"
dimension = 2
gravity = [0.0, -9.81]
end_time = 0.2
dp = 0.01
output_interval = 0.05

[water]
density = 1000.0
viscosity = 1.0e-3

[[water.inflows]]
name = "inlet"
shape = { type = "box", min = [0.0, 0.0], max = [0.05, 0.1] }
direction = "+x"
speed = 1.0

[[containers]]
name = "channel"
min = [0.0, 0.0]
max = [1.0, 0.3]
open = ["+y"]
"#,
    )
    .unwrap();
    let p = path.to_str().unwrap();
    let (code, stdout, stderr, _) = granmix(&["check", p]);
    assert_eq!(code, 0, "{stdout}{stderr}");
    let number_after = |line: &str, key: &str| -> f64 {
        let rest = &line[line.find(key).unwrap() + key.len()..];
        rest.split_whitespace()
            .next()
            .unwrap()
            .trim_start_matches('~')
            .parse()
            .unwrap()
    };
    let inflow = stdout.lines().find(|l| l.contains("inflow inlet")).unwrap();
    let let_in = number_after(inflow, "inflow inlet");
    let dt = stdout.lines().find(|l| l.contains("steps to t")).unwrap();
    let steps = number_after(dt, "→");
    let out = dir.join("out");
    let o = out.to_str().unwrap();
    let (code, stdout, stderr, _) =
        granmix(&["run", p, "--quiet", "--no-vtk", "--no-plots", "--out", o]);
    assert_eq!(code, 0, "{stdout}{stderr}");
    let summary: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(out.join("summary.json")).unwrap()).unwrap();
    let water = summary["particles_water"].as_f64().unwrap();
    let run_steps = summary["steps_fine"].as_f64().unwrap();
    assert!(
        (let_in - water).abs() <= 10.0,
        "{let_in} estimated, {water} let in"
    );
    assert!(
        (steps / run_steps - 1.0).abs() < 0.25,
        "{steps} steps estimated, {run_steps} taken"
    );
    std::fs::remove_dir_all(&dir).ok();
}

/// `granmix check … | head -1`: a reader that has gone closes the pipe. The command ends
/// with the shell's status for SIGPIPE (141) and says nothing, where it panicked on
/// the broken pipe with a backtrace.
#[test]
fn check_into_a_closed_pipe_ends_quietly() {
    let (reader, writer) = std::io::pipe().expect("a pipe");
    drop(reader);
    let s = scene("fmu_barrier_2d.toml");
    let out = Command::new(BIN)
        .args(["check", s.to_str().expect("utf-8 path")])
        .stdout(writer)
        .output()
        .expect("granmix runs");
    let err = String::from_utf8_lossy(&out.stderr);
    assert_eq!(out.status.code(), Some(141), "{err}");
    assert!(err.is_empty(), "{err}");
}
