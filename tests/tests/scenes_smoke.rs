//! Every bundled scene loads, builds and takes a few steps.

use granmix_core::input::load_scene_file;
use granmix_core::AnySimulation;

#[test]
fn all_bundled_scenes_step() {
    let dir = std::path::PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("../models/scenes");
    let mut n = 0;
    for entry in std::fs::read_dir(&dir).unwrap() {
        let path = entry.unwrap().path();
        if path.extension().and_then(|e| e.to_str()) != Some("toml") {
            continue;
        }
        let loaded = load_scene_file(&path, &[]).unwrap_or_else(|e| panic!("{e}"));
        let mut sim =
            AnySimulation::new(&loaded).unwrap_or_else(|e| panic!("{}: {e}", path.display()));
        assert!(sim.fine_count() + sim.coarse_count() + sim.water_count() > 0);
        for _ in 0..5 {
            sim.step(f64::INFINITY)
                .unwrap_or_else(|e| panic!("{}: {e}", path.display()));
        }
        n += 1;
    }
    assert!(n >= 5, "expected the bundled scenes, found {n}");
}
