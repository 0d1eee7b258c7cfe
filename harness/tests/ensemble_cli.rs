//! `granmix run SCENE --ensemble N`: the members' statistics against the members' own
//! series, a member rerun alone, and the refusals naming the argument at fault.

use std::path::{Path, PathBuf};
use std::process::Command;

const BIN: &str = env!("CARGO_BIN_EXE_granmix");

fn scene(name: &str) -> String {
    PathBuf::from(env!("CARGO_MANIFEST_DIR"))
        .join("../models/scenes")
        .join(name)
        .display()
        .to_string()
}

fn granmix(args: &[&str]) -> (i32, String) {
    let out = Command::new(BIN).args(args).output().expect("granmix runs");
    let text =
        String::from_utf8_lossy(&out.stdout).into_owned() + &String::from_utf8_lossy(&out.stderr);
    (out.status.code().unwrap_or(-1), text)
}

/// Column `name` of a series.csv (its heading carries a unit).
fn column(path: &Path, name: &str) -> Vec<f64> {
    let text = std::fs::read_to_string(path).unwrap();
    let mut lines = text.lines();
    let head: Vec<&str> = lines.next().unwrap().split(',').collect();
    let k = head
        .iter()
        .position(|h| h.split(" [").next() == Some(name))
        .unwrap_or_else(|| panic!("no column {name} in {}", path.display()));
    lines
        .map(|l| l.split(',').nth(k).unwrap().parse().unwrap())
        .collect()
}

fn tmp(tag: &str) -> PathBuf {
    std::env::temp_dir().join(format!("granmix_ensemble_{tag}_{}", std::process::id()))
}

#[test]
fn the_spread_is_that_of_the_members_series_and_a_member_reruns_alone() {
    let out = tmp("run");
    let s = scene("debris_flow_saturated.toml");
    let o = out.display().to_string();
    let base = [
        "--set",
        "simulation.end_time=0.1",
        "--no-vtk",
        "--no-plots",
        "--quiet",
    ];
    let mut args = vec!["run", &s, "--ensemble", "3", "--seed", "5", "--out", &o];
    args.extend(base);
    let (code, text) = granmix(&args);
    assert_eq!(code, 0, "{text}");
    // each member's peak of the boulder's load, from its own series (9 digits)
    let col = "boulder_1.force.x";
    let peaks: Vec<f64> = (0..3)
        .map(|m| {
            let x = column(&out.join(format!("member_{m:02}/series.csv")), col);
            x.into_iter().fold(f64::NEG_INFINITY, f64::max)
        })
        .collect();
    assert!(
        peaks[0] != peaks[1] && peaks[1] != peaks[2],
        "the members' starts differ: {peaks:?}"
    );
    let n = peaks.len() as f64;
    let mean = peaks.iter().sum::<f64>() / n;
    let sd = (peaks.iter().map(|p| (p - mean).powi(2)).sum::<f64>() / (n - 1.0)).sqrt();
    let mut o3 = peaks.clone();
    o3.sort_by(f64::total_cmp);
    // 0.95 (N − 1) = 1.9: 10 % of the way from the 2nd to the 3rd
    let p95 = o3[1] + 0.9 * (o3[2] - o3[1]);
    let table = std::fs::read_to_string(out.join("ensemble.csv")).unwrap();
    let row: Vec<&str> = table
        .lines()
        .find(|l| l.starts_with(&format!("{col},peak,")))
        .unwrap_or_else(|| panic!("no {col} peak row: {table}"))
        .split(',')
        .collect();
    assert_eq!(row[3], "3", "{row:?}");
    let got: Vec<f64> = row[4..9].iter().map(|v| v.parse().unwrap()).collect();
    for (name, g, want, scale) in [
        ("mean", got[0], mean, mean.abs()),
        ("sd", got[1], sd, mean.abs()),
        ("min", got[2], o3[0], mean.abs()),
        ("max", got[3], o3[2], mean.abs()),
        ("p95", got[4], p95, mean.abs()),
    ] {
        assert!(
            (g - want).abs() <= 1e-8 * scale,
            "{name}: {g} against {want} from the members' series"
        );
    }
    let json: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(out.join("ensemble.json")).unwrap()).unwrap();
    assert_eq!(json["runs"][1]["seed"], 6);
    assert_eq!(json["finished"], 3);
    // member 1 alone, by its seed: the same series, bitwise
    let alone = tmp("alone");
    let a = alone.display().to_string();
    let mut args = vec![
        "run",
        &s,
        "--set",
        "simulation.perturbation.seed=6",
        "--set",
        "simulation.perturbation.amplitude=1e-6",
        "--out",
        &a,
    ];
    args.extend(base);
    let (code, text) = granmix(&args);
    assert_eq!(code, 0, "{text}");
    assert_eq!(
        std::fs::read(alone.join("series.csv")).unwrap(),
        std::fs::read(out.join("member_01/series.csv")).unwrap(),
        "member 1 rerun alone"
    );
    std::fs::remove_dir_all(&out).ok();
    std::fs::remove_dir_all(&alone).ok();
}

#[test]
fn bad_ensembles_name_the_argument() {
    let s = scene("debris_flow_saturated.toml");
    let out = tmp("bad");
    let o = out.display().to_string();
    for (args, words) in [
        (
            vec!["--ensemble", "1"],
            "--ensemble 1: an ensemble needs at least 2 members",
        ),
        (
            vec!["--ensemble", "4", "--epsilon", "0.5"],
            "--epsilon 0.5: must lie in (0, 0.5)",
        ),
        (
            vec!["--ensemble", "4", "--epsilon", "0"],
            "--epsilon 0.0: must lie in (0, 0.5)",
        ),
        (
            vec!["--ensemble", "4", "--set", "simulation.perturbation.seed=2"],
            "--ensemble sets simulation.perturbation for each member",
        ),
        (vec!["--epsilon", "1e-3"], "--ensemble"),
    ] {
        let mut a = vec!["run", &s, "--quiet", "--no-vtk", "--out", &o];
        a.extend(args.iter().copied());
        let (code, text) = granmix(&a);
        assert_eq!(code, 2, "{args:?}: {text}");
        assert!(text.contains(words), "{args:?}: `{words}` missing: {text}");
    }
    std::fs::remove_dir_all(&out).ok();
}
