//! The memory budget: particle counts and memory estimated without building a particle
//! (core/src/estimate/mod.rs), checked against the built scenes; a scene over the budget is
//! refused before any allocation.

use granmix_core::estimate::{estimate, fine_bytes_per_particle};
use granmix_core::input::load_scene_file;
use granmix_core::scene::resolution::Resolution;
use granmix_core::AnySimulation;
use std::path::PathBuf;
use std::time::Instant;

fn scene(name: &str) -> PathBuf {
    PathBuf::from(env!("CARGO_MANIFEST_DIR"))
        .join("../models/scenes")
        .join(name)
}

fn scenes() -> Vec<PathBuf> {
    let dir = scene("");
    let mut v: Vec<PathBuf> = std::fs::read_dir(&dir)
        .unwrap()
        .map(|e| e.unwrap().path())
        .filter(|p| p.extension().and_then(|e| e.to_str()) == Some("toml"))
        .collect();
    v.sort();
    v
}

/// Relative error of an estimate against a built count (0 against 0 is exact).
fn rel(est: f64, built: usize) -> f64 {
    if built == 0 {
        return if est.abs() < 0.5 { 0.0 } else { f64::INFINITY };
    }
    est / built as f64 - 1.0
}

/// Fine particles of a region and dummy wall particles lie on the lattice that fills the
/// shape, so their count is the volume over dp^d up to the lattice's boundary layer:
/// with the lattice offset at random against a curved or slanted surface a boundary
/// lattice point is in or out with equal chance, an error of order dp × area / volume,
/// a few per cent at the bundled spacings (a region 30 spacings thick: ~3 %). Coarse
/// bodies are small (a rock fill's rocks hold tens of particles) and their lattice is
/// placed to fit the surface, so their boundary error is larger, up to one layer of
/// a few-particle body; their total is held to 20 %.
const REGION_TOL: f64 = 0.05;
const WALL_TOL: f64 = 0.05;
const COARSE_TOL: f64 = 0.20;

#[test]
fn estimates_match_the_built_counts_of_every_bundled_scene() {
    let mut report = Vec::new();
    for path in scenes() {
        let name = path.file_name().unwrap().to_string_lossy().to_string();
        let loaded = load_scene_file(&path, &[]).unwrap();
        let t = Instant::now();
        let e = estimate(&loaded.scene, &Resolution::of_scene(&loaded.scene));
        let te = t.elapsed().as_secs_f64();
        let sim = AnySimulation::new(&loaded).unwrap();
        let (walls, coarse) = (sim.wall_count(), sim.coarse_count());
        report.push(format!(
            "{name:<28} estimate {te:.3} s  fine {:+.3}  walls {:+.3}  coarse {:+.3}",
            rel(e.fine(), sim.fine_count()),
            rel(e.walls, walls),
            rel(e.coarse(), coarse)
        ));
        assert!(te < 1.0, "{name}: the estimate took {te:.3} s");
        for ((n, c), (_, b)) in e.regions.iter().zip(sim.region_counts()) {
            let r = rel(*c, b);
            assert!(
                r.abs() < REGION_TOL,
                "{name}: region {n}: {c:.0} for {b} ({r:+.3})"
            );
        }
        let r = rel(e.walls, walls);
        assert!(
            r.abs() < WALL_TOL,
            "{name}: walls {:.0} for {walls} ({r:+.3})",
            e.walls
        );
        let r = rel(e.coarse(), coarse);
        assert!(
            r.abs() < COARSE_TOL,
            "{name}: coarse {:.0} for {coarse} ({r:+.3})",
            e.coarse()
        );
    }
    println!("{}", report.join("\n"));
}

/// The bytes per fine particle the estimate uses against what a built simulation holds
/// once its lists are built (`fine_bytes`: particle arrays and the stepper's scratch,
/// measured from the capacities of the real vectors), on bulk scenes. The built solver's
/// cell grids (dense over the domain, so their bytes go with its cells, not its
/// particles) are compared with the estimate's grid bytes, shared over the particles.
#[test]
fn fine_bytes_per_particle_match_the_built_solver() {
    for (file, dim) in [
        ("column_collapse_2d.toml", 2),
        ("column_collapse_3d.toml", 3),
    ] {
        let loaded = load_scene_file(&scene(file), &[]).unwrap();
        let mut sim = AnySimulation::new(&loaded).unwrap();
        sim.step(f64::INFINITY).unwrap();
        let measured = sim.fine_bytes() as f64 / sim.fine_count() as f64;
        let n = &loaded.scene.numerics;
        let per_particle = if dim == 2 {
            fine_bytes_per_particle::<2>(n.smoothing_ratio, n.neighbor_skin)
        } else {
            fine_bytes_per_particle::<3>(n.smoothing_ratio, n.neighbor_skin)
        };
        let e = estimate(&loaded.scene, &Resolution::of_scene(&loaded.scene));
        let grids = e.grid_bytes / sim.fine_count() as f64;
        let est = per_particle + grids;
        println!(
            "{file}: estimated {est:.0} bytes per fine particle ({per_particle:.0} and \
             {grids:.0} of cell grids), built {measured:.0}"
        );
        assert!(
            (est / measured - 1.0).abs() < 0.10,
            "{file}: estimated {est:.0} bytes per fine particle, built {measured:.0}"
        );
    }
}

/// dp = 1e-7 would need far more than any machine: the build refuses it at once, with
/// an error naming dp, the count and the budget, before allocating a particle.
#[test]
fn a_scene_over_the_budget_is_refused_before_building() {
    for file in [
        "fmu_barrier_2d.toml",
        "column_collapse_3d.toml",
        "debris_barrier.toml",
    ] {
        let loaded = load_scene_file(&scene(file), &["simulation.dp=1e-7".to_string()]).unwrap();
        let t = Instant::now();
        let err = match AnySimulation::new(&loaded) {
            Ok(_) => panic!("{file}: dp = 1e-7 was built"),
            Err(e) => e.to_string(),
        };
        let took = t.elapsed().as_secs_f64();
        println!("{file}: refused in {took:.3} s: {err}");
        assert!(took < 1.0, "{file}: took {took:.3} s to refuse");
        for part in [
            "`simulation.dp`",
            "dp = 1e-7 m",
            "particles",
            "memory budget",
            "--memory-budget",
        ] {
            assert!(err.contains(part), "{file}: `{part}` missing from: {err}");
        }
    }
}

/// `simulation.memory_budget` sets the budget: the small 2D scene (≈ 0.3 MB) builds under
/// the default and under 1 GB, and is refused under 100 kB.
#[test]
fn the_budget_can_be_set() {
    let path = scene("fmu_barrier_2d.toml");
    let ok = load_scene_file(&path, &["simulation.memory_budget=1e9".to_string()]).unwrap();
    let e = estimate(&ok.scene, &Resolution::of_scene(&ok.scene));
    assert!(e.bytes > 1e5 && e.bytes < 1e7, "{} bytes", e.bytes);
    AnySimulation::new(&ok).unwrap();
    let low = load_scene_file(&path, &["simulation.memory_budget=1e5".to_string()]).unwrap();
    let err = AnySimulation::new(&low).err().expect("refused").to_string();
    assert!(err.contains("97.7 KiB (simulation.memory_budget)"), "{err}");
    let neg = load_scene_file(&path, &["simulation.memory_budget=-1".to_string()]);
    assert!(neg.unwrap_err().to_string().contains("memory_budget"));
}
