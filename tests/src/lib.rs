//! Shared helpers for the validation tests: load bundled scenes with overrides and run
//! them through the same run loop as the CLI.

use granmix_core::runner::{self, RunEnd};
use granmix_core::scene::{load_scene_file, LoadedScene};
use granmix_core::simulation::Sample;
use granmix_core::AnySimulation;
use std::path::PathBuf;

/// Path of a bundled scene.
pub fn scene_path(name: &str) -> PathBuf {
    PathBuf::from(env!("CARGO_MANIFEST_DIR"))
        .join("../models/scenes")
        .join(name)
}

/// Load a bundled scene with `key=value` overrides.
pub fn load(name: &str, set: &[&str]) -> LoadedScene {
    let set: Vec<String> = set.iter().map(|s| s.to_string()).collect();
    load_scene_file(&scene_path(name), &set).unwrap_or_else(|e| panic!("{e}"))
}

/// Run a scene to its end (or until settled) and return every sample.
pub fn run(name: &str, set: &[&str]) -> (Vec<Sample>, RunEnd, AnySimulation) {
    run_until(name, set, |_| false)
}

/// Run a scene like [`run`], but stop early (`RunEnd::Stopped`) as soon as `done`,
/// shown every sample so far, says the observable of interest has stopped changing.
pub fn run_until(
    name: &str,
    set: &[&str],
    mut done: impl FnMut(&[Sample]) -> bool,
) -> (Vec<Sample>, RunEnd, AnySimulation) {
    let loaded = load(name, set);
    let mut sim = AnySimulation::new(&loaded).unwrap_or_else(|e| panic!("{e}"));
    let mut samples = Vec::new();
    let end = runner::run(
        &mut sim,
        &loaded.scene.simulation,
        |_, s| {
            samples.push(s.clone());
            !done(&samples)
        },
        |_| {},
    );
    (samples, end, sim)
}

/// Relative error |a − b| / |b|.
pub fn rel(a: f64, b: f64) -> f64 {
    (a - b).abs() / b.abs()
}
