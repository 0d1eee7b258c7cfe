//! Hostile scene files (issue 38, point 7): every case, written in the test as a small
//! variant of a bundled scene, is refused by plain `granmix check` and by `granmix run`
//! with a non-zero exit and a message naming the file (or the `--set` argument) and the
//! key or line, within 5 s and 100 MB. A case that hangs is killed and fails the test.

use std::io::Read;
use std::path::{Path, PathBuf};
use std::process::{Command, Stdio};
use std::time::{Duration, Instant};

const BIN: &str = env!("CARGO_BIN_EXE_granmix");

/// What each case may take: the bounds.
const MAX_SECONDS: f64 = 5.0;
const MAX_BYTES: f64 = 100e6;
/// A case still running after this is killed (a hang fails the test instead of CI).
const KILL_AFTER: Duration = Duration::from_secs(20);
/// A case holding more than this is killed at once (a runaway read or allocation).
const KILL_ABOVE: f64 = 1e9;

fn bundled(name: &str) -> String {
    let p = PathBuf::from(env!("CARGO_MANIFEST_DIR"))
        .join("../models/scenes")
        .join(name);
    std::fs::read_to_string(&p).unwrap_or_else(|e| panic!("{}: {e}", p.display()))
}

/// Replace `from` (which must occur) by `to`.
fn edit(text: &str, from: &str, to: &str) -> String {
    assert!(text.contains(from), "`{from}` not in the scene");
    text.replacen(from, to, 1)
}

/// One hostile input: a scene text, `--set` arguments and the parts its refusal must
/// name (besides the file).
struct Case {
    name: &'static str,
    text: String,
    set: Vec<String>,
    expect: Vec<&'static str>,
}

fn case(name: &'static str, text: String, set: &[&str], expect: &[&'static str]) -> Case {
    Case {
        name,
        text,
        set: set.iter().map(|s| s.to_string()).collect(),
        expect: expect.to_vec(),
    }
}

/// Exit code (None: killed by a signal), stdout, stderr, seconds and peak resident bytes.
struct Outcome {
    code: Option<i32>,
    stdout: String,
    stderr: String,
    seconds: f64,
    peak: f64,
    killed: Option<String>,
}

/// Peak resident memory of a running process (`VmHWM`), in bytes.
fn peak_rss(pid: u32) -> Option<f64> {
    let s = std::fs::read_to_string(format!("/proc/{pid}/status")).ok()?;
    let line = s.lines().find(|l| l.starts_with("VmHWM:"))?;
    let kib: f64 = line.split_whitespace().nth(1)?.parse().ok()?;
    Some(kib * 1024.0)
}

/// Run granmix with `args`, polling its peak memory every 2 ms until it exits; kill it
/// past [`KILL_AFTER`] or [`KILL_ABOVE`].
fn granmix(args: &[String], dir: &Path) -> Outcome {
    let t = Instant::now();
    let mut child = Command::new(BIN)
        .args(args)
        .current_dir(dir)
        .stdin(Stdio::null())
        .stdout(Stdio::piped())
        .stderr(Stdio::piped())
        .spawn()
        .expect("granmix starts");
    // drain the pipes on threads so that a chatty child never blocks on them
    let mut out = child.stdout.take().expect("piped");
    let mut err = child.stderr.take().expect("piped");
    let so = std::thread::spawn(move || {
        let mut s = String::new();
        out.read_to_string(&mut s).ok();
        s
    });
    let se = std::thread::spawn(move || {
        let mut s = String::new();
        err.read_to_string(&mut s).ok();
        s
    });
    let (mut peak, mut killed) = (0.0f64, None);
    let status = loop {
        if let Some(p) = peak_rss(child.id()) {
            peak = peak.max(p);
        }
        if let Some(s) = child.try_wait().expect("wait") {
            break s;
        }
        if t.elapsed() > KILL_AFTER || peak > KILL_ABOVE {
            killed = Some(format!(
                "killed after {:.1} s at {:.0} MB",
                t.elapsed().as_secs_f64(),
                peak / 1e6
            ));
            child.kill().ok();
            break child.wait().expect("wait");
        }
        std::thread::sleep(Duration::from_millis(2));
    };
    Outcome {
        code: status.code(),
        stdout: so.join().unwrap_or_default(),
        stderr: se.join().unwrap_or_default(),
        seconds: t.elapsed().as_secs_f64(),
        peak,
        killed,
    }
}

/// The cases of issue 38, point 7, and the `check` cases of its point 4.
fn cases() -> Vec<Case> {
    let col3 = bundled("column_collapse_3d.toml");
    let col2 = bundled("column_collapse_2d.toml");
    let tank = bundled("hydrostatic_tank.toml");
    let sat = bundled("saturated_collapse_2d.toml");
    let srm = bundled("srm_slope.toml");
    let fmu = bundled("fmu_barrier_2d.toml");
    let boulder = bundled("boulder_in_water.toml");
    let wall = |kind: &str, file: &str| {
        format!(
            "{col3}\n[[walls]]\nname = \"m\"\nshape = {{ type = \"{kind}\", file = \"{file}\" }}\n"
        )
    };
    let box2 = "shape = { type = \"box\", min = [0.0, 0.0], max = [0.2, 0.1] }";
    let polygon = |v: &str| {
        edit(
            &col2,
            box2,
            &format!("shape = {{ type = \"polygon\", vertices = {v} }}"),
        )
    };
    let water_speed = |extra: &str| {
        edit(
            &edit(
                &tank,
                "viscosity = 1.0e-3",
                &format!("viscosity = 1.0e-3\n{extra}"),
            ),
            "max = [0.5, 0.5] }",
            "max = [0.5, 0.5] }\nvelocity = [5.0, 0.0]",
        )
    };
    let deep = format!("{}=1", vec!["a"; 3000].join("."));
    let mut probes = tank.clone();
    for i in 0..250_000 {
        probes.push_str(&format!(
            "[[probes]]\nname = \"p{i}\"\nposition = [0.25, 0.25]\n"
        ));
    }
    vec![
        // files that never end or never come
        case("mesh_dev_zero", wall("mesh", "/dev/zero"), &[], &["walls[0].shape.file", "regular file"]),
        case("mesh_fifo", wall("mesh", "fifo.obj"), &[], &["walls[0].shape.file", "regular file"]),
        case("heightmap_dev_zero", wall("heightmap", "/dev/zero"), &[], &["walls[0].shape.file", "regular file"]),
        case("heightmap_fifo", wall("heightmap", "fifo.asc"), &[], &["walls[0].shape.file", "regular file"]),
        // memory
        case(
            "region_far_from_containers",
            col2.clone(),
            &["regions[0].shape.min=[1000.0, 0.0]", "regions[0].shape.max=[1000.2, 0.1]"],
            &["simulation.dp", "cells"],
        ),
        case(
            "region_30_m_away_priced_with_its_grid",
            col2.clone(),
            &["regions[0].shape.min=[30.0, 0.0]", "regions[0].shape.max=[30.2, 0.1]", "simulation.memory_budget=100e6"],
            &["simulation.dp", "memory budget"],
        ),
        case(
            "rock_fill_of_10_um_rocks",
            srm.clone(),
            &["rock_fills[0].size=1e-5", "rock_fills[0].clearance=0.0"],
            &["rock_fills[0].size"],
        ),
        case("probes_250k", probes, &[], &["MiB"]),
        // steps and outputs
        case("permeability_1e-30", sat.clone(), &["materials[0].permeability=1e-30"], &["materials[0].permeability", "impermeable"]),
        case("cfl_1e-308", col2.clone(), &["simulation.cfl=1e-308"], &["simulation.cfl"]),
        case("output_interval_1e-308", col2.clone(), &["simulation.output_interval=1e-308"], &["simulation.output_interval"]),
        case("end_time_1e308", col2.clone(), &["simulation.end_time=1e308"], &["simulation.end_time"]),
        // accepted with nonsense
        case(
            "outflow_removing_all_water",
            format!("{tank}\n[[water.outflows]]\nname = \"drain\"\npoint = [0.0, 1.0]\nnormal = [0.0, -1.0]\n"),
            &[],
            &["water.outflows[0]", "removes"],
        ),
        case(
            "self_intersecting_polygon",
            polygon("[[0.0, 0.0], [0.2, 0.1], [0.2, 0.0], [0.0, 0.05]]"),
            &[],
            &["regions[0].shape.vertices", "intersect"],
        ),
        case(
            "symmetric_self_intersecting_polygon",
            polygon("[[0.0, 0.0], [0.2, 0.1], [0.2, 0.0], [0.0, 0.1]]"),
            &[],
            &["regions[0].shape.vertices", "intersect"],
        ),
        case("probe_name_comma_newline", edit(&tank, "name = \"mid\"", "name = \"a,b\\nc\""), &[], &["probes[0].name"]),
        case("probe_name_nul", edit(&tank, "name = \"mid\"", "name = \"a\\u0000b\""), &[], &["probes[0].name"]),
        case("region_name_comma", edit(&col2, "name = \"column\"", "name = \"col,umn\""), &[], &["regions[0].name"]),
        case("body_name_newline", edit(&boulder, "name = \"disc\"", "name = \"di\\nsc\""), &[], &["bodies[0].name"]),
        case("set_empty_key_segment", col2.clone(), &["simulation..dp=0.01"], &["--set simulation..dp=0.01", "empty"]),
        // check said valid, the run refused at step 0 or 1
        case("water_density_1e308", tank.clone(), &["water.density=1e308"], &["water.density"]),
        case("water_density_1e-308", tank.clone(), &["water.density=1e-308"], &["water.density"]),
        case("soil_density_1e308", col2.clone(), &["materials[0].density=1e308"], &["materials[0].density"]),
        case("soil_density_1e-308", col2.clone(), &["materials[0].density=1e-308"], &["materials[0].density"]),
        case("viscosity_1e308", tank.clone(), &["water.viscosity=1e308"], &["water.viscosity"]),
        case("gravity_1e308", col2.clone(), &["simulation.gravity=[0.0, -1e308]"], &["simulation.gravity"]),
        case("sound_speed_1e308", tank.clone(), &["water.sound_speed=1e308"], &["water.sound_speed"]),
        case(
            "grain_size_1e-308",
            edit(&sat, "permeability = 1.0e-8 ", "grain_size = 1e-308 "),
            &[],
            &["materials[0].grain_size"],
        ),
        case("speed_scale_below_the_initial_speed", water_speed("speed_scale = 0.1"), &[], &["water.speed_scale"]),
        case(
            "body_inside_a_wall",
            format!("{boulder}\n[[walls]]\nname = \"block\"\nshape = {{ type = \"box\", min = [0.2, 0.2], max = [0.4, 0.4] }}\n"),
            &["bodies[0].shape.center=[0.21, 0.3]"],
            &["bodies[0]", "block"],
        ),
        // check said valid, `--exact` and the run refused
        case("sound_speed_below_the_flow_speed", water_speed("sound_speed = 1.0"), &[], &["water.sound_speed"]),
        case(
            "inlet_outside_the_domain",
            format!(
                "{tank}\n[[water.inflows]]\nname = \"in\"\nshape = {{ type = \"box\", min = [5.0, 5.0], max = [5.1, 5.1] }}\ndirection = \"+x\"\nspeed = 1.0\n"
            ),
            &[],
            &["water.inflows[0].shape"],
        ),
        case("no_gravity_with_water", tank.clone(), &["simulation.gravity=[-0.0, -0.0]"], &["water.sound_speed"]),
        case("dp_1e308", col2.clone(), &["simulation.dp=1e308"], &["regions[0].shape", "no particle"]),
        case("dp_1e308_fmu_scene", fmu.clone(), &["simulation.dp=1e308"], &["regions[0].shape"]),
        // sizes (issue 38, point 4)
        case("dp_1e-160", fmu.clone(), &["simulation.dp=1e-160"], &["simulation.dp", "coarsen"]),
        case("dp_subnormal", col2.clone(), &["simulation.dp=1e-310"], &["simulation.dp"]),
        case("box_of_subnormal_size", col2.clone(), &["regions[0].shape.max=[1e-310, 0.1]"], &["regions[0].shape"]),
        // messages
        case(
            "duplicate_key",
            edit(&col2, "dp = 0.002 ", "dp = 0.002\ndp = 0.003 "),
            &[],
            &["`dp`", "column_collapse_2d.toml:14"],
        ),
        // issue 74: check said valid, the first step blew up, or the run went on in nonsense
        case("set_key_path_3000_deep", col2.clone(), &[deep.as_str()], &["segments"]),
        case("region_faster_than_max_speed", col2.clone(), &["regions[0].velocity=[200.0, 0.0]"], &["regions[0].velocity", "max_speed"]),
        case("water_region_faster_than_max_speed", tank.clone(), &["water.regions[0].velocity=[0.0, 200.0]"], &["water.regions[0].velocity", "max_speed"]),
        case(
            "two_identical_regions",
            format!("{col2}\n[[regions]]\nname = \"again\"\nmaterial = \"aluminium_bars\"\n{box2}\n"),
            &[],
            &["regions[1].shape", "column", "again", "overlap"],
        ),
        case(
            "two_identical_water_regions",
            format!("{tank}\n[[water.regions]]\nname = \"again\"\nshape = {{ type = \"box\", min = [0.0, 0.0], max = [0.5, 0.5] }}\n"),
            &[],
            &["water.regions[1].shape", "overlap"],
        ),
        case("friction_angle_1e-300", col2.clone(), &["materials[0].friction_angle=1e-300"], &["materials[0].friction_angle"]),
        case("body_holding_no_particle", boulder.clone(), &["bodies[0].shape.radius=0.001"], &["bodies[0].shape", "particle"]),
        case(
            "two_overlapping_bodies",
            format!("{boulder}\n[[bodies]]\nname = \"twin\"\nmaterial = \"float\"\nmodel = \"rigid\"\nshape = {{ type = \"sphere\", center = [0.32, 0.3], radius = 0.05 }}\n"),
            &[],
            &["bodies[1].shape", "disc", "twin", "overlapping"],
        ),
        case(
            "plane_normal_of_length_1e200",
            format!("{col2}\n[[walls]]\nname = \"slope\"\nshape = {{ type = \"plane\", point = [0.5, 0.0], normal = [1e200, 1e200], half_extent = 0.5 }}\n"),
            &[],
            &["walls[0].shape.normal", "length"],
        ),
        case(
            "outflow_normal_of_length_1e200",
            format!("{tank}\n[[water.outflows]]\nname = \"drain\"\npoint = [0.5, 0.0]\nnormal = [1e200, 1e200]\n"),
            &[],
            &["water.outflows[0].normal", "length"],
        ),
        case("negative_wall_friction", col2.clone(), &["numerics.wall_friction=-0.5"], &["numerics.wall_friction"]),
        case(
            "two_probes_of_one_name",
            format!("{tank}\n[[probes]]\nname = \"mid\"\nposition = [0.25, 0.1]\n"),
            &[],
            &["probes[1].name", "probes[0].name"],
        ),
        case(
            "a_probe_named_as_a_body",
            format!("{boulder}\n[[probes]]\nname = \"disc\"\nposition = [0.1, 0.1]\n"),
            &[],
            &["`disc`", "bodies[0].name", "namespace"],
        ),
        case("a_probe_named_water", edit(&tank, "name = \"mid\"", "name = \"water\""), &[], &["probes[0].name", "series' own columns"]),
        case("set_value_out_of_range", col2.clone(), &["simulation.dp=-1"], &["--set simulation.dp=-1"]),
        case("set_value_of_wrong_type", col2, &["simulation.cfl=\"x\""], &["--set simulation.cfl=\"x\""]),
    ]
}

#[test]
fn hostile_scene_files_are_refused_promptly_and_named() {
    let dir = std::env::temp_dir().join(format!("granmix_hostile_{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    for fifo in ["fifo.obj", "fifo.asc"] {
        let ok = Command::new("mkfifo")
            .arg(dir.join(fifo))
            .status()
            .is_ok_and(|s| s.success());
        assert!(ok, "mkfifo {fifo}");
    }
    let mut table = Vec::new();
    let mut failures = Vec::new();
    for c in cases() {
        // the duplicate-key case names the bundled file's line: keep its name
        let file = if c.name == "duplicate_key" {
            "column_collapse_2d.toml".to_string()
        } else {
            format!("{}.toml", c.name)
        };
        std::fs::write(dir.join(&file), &c.text).unwrap();
        for cmd in ["check", "run"] {
            let mut args = vec![cmd.to_string(), file.clone()];
            for s in &c.set {
                args.push("--set".into());
                args.push(s.clone());
            }
            if cmd == "run" {
                for a in ["--quiet", "--no-vtk", "--out"] {
                    args.push(a.into());
                }
                args.push(format!("out_{}", c.name));
            }
            let o = granmix(&args, &dir);
            let first = o.stderr.lines().next().unwrap_or("").to_string();
            table.push(format!(
                "{:<40} {cmd:<5} exit {:>4} {:>6.3} s {:>6.1} MB  {}",
                c.name,
                o.code.map_or("sig".to_string(), |c| c.to_string()),
                o.seconds,
                o.peak / 1e6,
                first.chars().take(300).collect::<String>()
            ));
            let mut fail = |why: String| failures.push(format!("{} ({cmd}): {why}", c.name));
            if let Some(k) = &o.killed {
                fail(k.clone());
                continue;
            }
            match o.code {
                None => fail("ended by a signal (abort or crash)".into()),
                Some(0) => fail(format!("accepted (exit 0):\n{}", o.stdout)),
                Some(_) => {}
            }
            // the file, or the `--set` argument the error's value came from
            let named = o.stderr.contains(&file)
                || c.set
                    .iter()
                    .any(|s| o.stderr.contains(&format!("--set {s}")));
            if !named {
                fail(format!("the message does not name {file}: {}", o.stderr));
            }
            for part in &c.expect {
                if !o.stderr.contains(part) {
                    fail(format!("`{part}` missing from: {}", o.stderr));
                }
            }
            if o.seconds > MAX_SECONDS {
                fail(format!("took {:.2} s", o.seconds));
            }
            if o.peak > MAX_BYTES {
                fail(format!("held {:.0} MB", o.peak / 1e6));
            }
        }
    }
    println!("{}", table.join("\n"));
    std::fs::remove_dir_all(&dir).ok();
    assert!(failures.is_empty(), "{}", failures.join("\n\n"));
}

/// A region 30 m from its container: the run's peak memory is mostly the steppers'
/// cell grids over the sparse domain, and the estimate that `check` and the budget use
/// prices them (it said 54 MiB for a run of 169 MB before they were counted).
#[test]
fn a_sparse_domain_is_priced_with_its_cell_grids() {
    let dir = std::env::temp_dir().join(format!("granmix_sparse_{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    let scene =
        PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("../models/scenes/column_collapse_2d.toml");
    let set: Vec<String> = [
        "regions[0].shape.min=[30.0, 0.0]",
        "regions[0].shape.max=[30.2, 0.1]",
        "simulation.end_time=0.0002",
    ]
    .iter()
    .map(|s| s.to_string())
    .collect();
    let loaded = granmix_core::input::load_scene_file(&scene, &set).unwrap();
    let res = granmix_core::scene::resolution::Resolution::of_scene(&loaded.scene);
    let e = granmix_core::estimate::estimate(&loaded.scene, &res);
    let mut args = vec!["run".to_string(), scene.to_string_lossy().into_owned()];
    for s in &set {
        args.push("--set".into());
        args.push(s.clone());
    }
    for a in ["--quiet", "--no-vtk", "--out", "out"] {
        args.push(a.into());
    }
    let o = granmix(&args, &dir);
    std::fs::remove_dir_all(&dir).ok();
    assert_eq!(o.code, Some(0), "{}", o.stderr);
    println!(
        "estimated {:.1} MB ({:.1} MB in grids of {:.3e} cells), the run peaked at {:.1} MB",
        e.bytes / 1e6,
        e.grid_bytes / 1e6,
        e.cells,
        o.peak / 1e6
    );
    // the grids dominate, and the run holds the estimate plus the program (≤ 20 MB)
    assert!(
        e.grid_bytes > 0.9 * e.bytes,
        "{} of {}",
        e.grid_bytes,
        e.bytes
    );
    assert!(
        o.peak > 0.9 * e.bytes && o.peak < e.bytes + 20e6,
        "estimated {:.1} MB, the run peaked at {:.1} MB",
        e.bytes / 1e6,
        o.peak / 1e6
    );
}

/// Issue 74: `check` refuses everything the first steps of `run` would, across the
/// bundled scenes: every scene plain `check` passes runs its first 20 µs (a few steps,
/// the build and its checks included) with exit 0.
#[test]
fn every_bundled_scene_check_passes_takes_its_first_steps() {
    let dir = std::env::temp_dir().join(format!("granmix_first_steps_{}", std::process::id()));
    let scenes = PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("../models/scenes");
    let mut files: Vec<PathBuf> = std::fs::read_dir(&scenes)
        .unwrap()
        .map(|e| e.unwrap().path())
        .filter(|p| p.extension().is_some_and(|e| e == "toml"))
        .collect();
    files.sort();
    assert!(files.len() >= 30, "{} bundled scenes", files.len());
    let mut failed = Vec::new();
    for f in &files {
        let s = f.to_str().unwrap().to_string();
        let check = Command::new(BIN).args(["check", &s]).output().unwrap();
        if !check.status.success() {
            failed.push(format!("{s}: check refused it"));
            continue;
        }
        let out = dir.join(f.file_stem().unwrap());
        let run = Command::new(BIN)
            .args([
                "run",
                &s,
                "--set",
                "simulation.end_time=2e-5",
                "--quiet",
                "--no-vtk",
            ])
            .args(["--no-plots", "--out", out.to_str().unwrap()])
            .output()
            .unwrap();
        if !run.status.success() {
            let e = String::from_utf8_lossy(&run.stderr).into_owned();
            failed.push(format!(
                "{s}: check passed, run exited {:?}: {e}",
                run.status.code()
            ));
        }
    }
    std::fs::remove_dir_all(&dir).ok();
    assert!(failed.is_empty(), "{}", failed.join("\n"));
}
