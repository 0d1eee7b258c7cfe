//! The particle counts written beside `dp` in the bundled scenes' headers
//! (`dp = 0.01  # 2500 water particles`) are the counts `granmix check --exact` builds.

use granmix_core::input::load_scene_file;
use granmix_core::AnySimulation;
use std::path::PathBuf;

/// The comment of the `dp = …` line of a scene, if it counts particles.
fn stated(text: &str) -> Option<String> {
    let line = text.lines().find(|l| l.trim_start().starts_with("dp ="))?;
    let comment = line.split_once('#')?.1;
    let upto = &comment[..comment.rfind("particles")?];
    // a ratio before a colon (`a/40: …`) is not a count
    Some(upto.rsplit(':').next().unwrap_or(upto).to_string())
}

/// The sum of the whole numbers in `text`.
fn sum_of_counts(text: &str) -> usize {
    text.split(|c: char| !c.is_ascii_digit())
        .filter(|s| !s.is_empty())
        .map(|s| s.parse::<usize>().unwrap())
        .sum()
}

#[test]
fn header_particle_counts_match_the_built_scenes() {
    let dir = PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("../models/scenes");
    let mut paths: Vec<PathBuf> = std::fs::read_dir(&dir)
        .unwrap()
        .map(|e| e.unwrap().path())
        .filter(|p| p.extension().is_some_and(|e| e == "toml"))
        .collect();
    paths.sort();
    let mut checked = 0;
    for path in paths {
        let text = std::fs::read_to_string(&path).unwrap();
        let Some(counts) = stated(&text) else {
            continue;
        };
        let loaded = load_scene_file(&path, &[]).unwrap();
        let sim = AnySimulation::new(&loaded).unwrap();
        let built = sim.fine_count() + sim.water_count();
        let said = sum_of_counts(&counts);
        assert_eq!(
            said,
            built,
            "{}: the header says `{}` particles, the build has {} fine and {} water",
            path.display(),
            counts.trim(),
            sim.fine_count(),
            sim.water_count()
        );
        checked += 1;
    }
    assert!(checked >= 10, "only {checked} headers count particles");
}
