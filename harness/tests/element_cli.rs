//! `granmix element`: a scene's soil driven through a drained triaxial compression
//! prints its peak against Mohr–Coulomb and writes element.csv and element.png; a
//! wrong material name is refused with the known ones.

use std::path::PathBuf;
use std::process::Command;

const BIN: &str = env!("CARGO_BIN_EXE_granmix");

fn scene(name: &str) -> String {
    PathBuf::from(env!("CARGO_MANIFEST_DIR"))
        .join("../models/scenes")
        .join(name)
        .to_string_lossy()
        .into_owned()
}

/// φ = 28.6° on the compression cone at σ3 = 50 kPa: the peak deviator is Mohr–Coulomb's
/// 2 sin φ σ3/(1 − sin φ) = 91.83 kPa (seed 004's table: 91.8), to 0.1 %.
#[test]
fn triaxial_peak_is_printed_and_written() {
    let out = std::env::temp_dir().join(format!("granmix_element_{}", std::process::id()));
    let run = Command::new(BIN)
        .args([
            "element",
            &scene("column_collapse_2d.toml"),
            "--set",
            "materials.0.friction_angle=28.6",
            "--set",
            "materials.0.yield_surface=compression_cone",
            "--confining",
            "50e3",
            "--strain",
            "0.05",
            "--steps",
            "5000",
            "--out",
            out.to_str().unwrap(),
        ])
        .output()
        .expect("granmix runs");
    let stdout = String::from_utf8_lossy(&run.stdout);
    assert!(
        run.status.success(),
        "{stdout}{}",
        String::from_utf8_lossy(&run.stderr)
    );
    let row = stdout
        .lines()
        .find(|l| l.trim_start().starts_with("50.0"))
        .unwrap_or_else(|| panic!("no σ3 = 50 kPa row: {stdout}"));
    let cols: Vec<f64> = row.split_whitespace().map(|c| c.parse().unwrap()).collect();
    let (peak, reference) = (cols[1], cols[4]);
    let s = 28.6_f64.to_radians().sin();
    let mc = 2.0 * s * 50.0 / (1.0 - s);
    assert!((reference - mc).abs() < 0.01, "{row}");
    assert!(
        (peak / mc - 1.0).abs() < 1e-3,
        "peak {peak} kPa against {mc}: {stdout}"
    );
    assert!(stdout.contains("compression_cone"), "{stdout}");
    let csv = std::fs::read_to_string(out.join("element.csv")).expect("element.csv");
    assert_eq!(csv.lines().count(), 1 + 5001, "header and 5001 states");
    assert!(
        out.join("element.png")
            .metadata()
            .expect("element.png")
            .len()
            > 10_000
    );
    std::fs::remove_dir_all(&out).ok();
}

#[test]
fn an_unknown_material_is_refused_with_the_known_ones() {
    let run = Command::new(BIN)
        .args([
            "element",
            &scene("column_collapse_2d.toml"),
            "--material",
            "clay",
        ])
        .output()
        .expect("granmix runs");
    let stderr = String::from_utf8_lossy(&run.stderr);
    assert_eq!(run.status.code(), Some(2), "{stderr}");
    assert!(
        stderr.contains("--material") && stderr.contains("clay"),
        "{stderr}"
    );
    assert!(stderr.contains("known: "), "{stderr}");
}
