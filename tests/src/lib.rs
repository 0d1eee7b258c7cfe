//! Shared helpers for the validation tests: load bundled scenes with overrides, or
//! scenes written in the test, and run them through the same run loop as the CLI.

use granmix_core::input::{load_scene_file, load_scene_str, LoadedScene};
use granmix_core::run::runner::{self, RunEnd};
use granmix_core::run::simulation::Sample;
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

/// Run `op` on a thread pool of its own: `GRANMIX_TEST_THREADS` worker threads (default
/// 1). `cargo test` runs two tests at a time on this two-core machine; two tests
/// sharing rayon's global pool of two workers spend about a seventh more CPU time than
/// the same tests on one thread each (the workers waking and yielding at every parallel
/// loop: the 2D SPHinXsys collapse at dp = 4 mm takes 17.3 s of CPU on one thread and
/// 19.9 s on two), and a small test beside a large one waits behind its loops. Set it
/// to 2 to run one test alone faster. Results are bitwise the same at any thread count.
pub fn on_own_pool<R: Send>(op: impl FnOnce() -> R + Send) -> R {
    let n = std::env::var("GRANMIX_TEST_THREADS")
        .ok()
        .and_then(|v| v.parse::<usize>().ok())
        .filter(|&n| n > 0)
        .unwrap_or(1);
    rayon::ThreadPoolBuilder::new()
        .num_threads(n)
        .build()
        .unwrap_or_else(|e| panic!("a pool of {n} thread(s): {e}"))
        .install(op)
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
    mut done: impl FnMut(&[Sample]) -> bool + Send,
) -> (Vec<Sample>, RunEnd, AnySimulation) {
    let loaded = load(name, set);
    on_own_pool(|| {
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
    })
}

/// Load and build a scene written in the test; `name` stands for its file in messages.
pub fn build_text(text: &str, name: &str) -> (LoadedScene, AnySimulation) {
    let loaded = load_scene_str(text, name, &[]).unwrap_or_else(|e| panic!("{e}"));
    let sim = AnySimulation::new(&loaded).unwrap_or_else(|e| panic!("{name}: {e}"));
    (loaded, sim)
}

/// Run a built scene to its end (or until settled), calling `on_sample` at t = 0 and at
/// every output time. A blow-up fails the test with the guard's diagnostic.
pub fn run_built(
    loaded: &LoadedScene,
    sim: &mut AnySimulation,
    mut on_sample: impl FnMut(&Sample) + Send,
) -> RunEnd {
    let end = on_own_pool(|| {
        runner::run(
            sim,
            &loaded.scene.simulation,
            |_, s| {
                on_sample(s);
                true
            },
            |_| {},
        )
    });
    assert!(
        !matches!(end, RunEnd::Blowup(_)),
        "{}: {end:?}",
        loaded.file
    );
    end
}

/// [`build_text`] then [`run_built`]: run a scene written in the test to its end.
pub fn run_text(text: &str, name: &str, on_sample: impl FnMut(&Sample) + Send) -> AnySimulation {
    let (loaded, mut sim) = build_text(text, name);
    run_built(&loaded, &mut sim, on_sample);
    sim
}

/// The message with which a scene written in the test is refused, when it is loaded
/// (`bad.toml` in the message) or built; the test fails if it is accepted.
pub fn refusal(text: &str) -> String {
    match load_scene_str(text, "bad.toml", &[]) {
        Err(e) => e.to_string(),
        Ok(l) => match AnySimulation::new(&l) {
            Err(e) => e.to_string(),
            Ok(_) => panic!("accepted:\n{text}"),
        },
    }
}

/// Relative error |a − b| / |b|.
pub fn rel(a: f64, b: f64) -> f64 {
    (a - b).abs() / b.abs()
}

/// The cases of a test: those that must pass, and with `GRANMIX_MUTATIONS=1` in the
/// environment also its mutation runs, that must fail (a wrong porosity, a wrong
/// permeability: proof that the test can fail). The mutation runs double a test's time,
/// so the suite leaves them out by default; run them after changing a test's physics
/// or tolerance: `GRANMIX_MUTATIONS=1 cargo test --release -p granmix-tests --test
/// validation saturated`.
pub fn with_mutations<T>(cases: Vec<(T, bool)>) -> Vec<(T, bool)> {
    let all = std::env::var("GRANMIX_MUTATIONS").is_ok_and(|v| v == "1");
    cases
        .into_iter()
        .filter(|(_, must_pass)| all || *must_pass)
        .collect()
}
