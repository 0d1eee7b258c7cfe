//! Reading a scene: `--set` overrides, strict parsing, rock fills expanded into bodies,
//! validation, the files that shapes name (meshes, terrain grids), where regions and
//! bodies lie, and what the build or the first step would refuse (a region holding no
//! particle, the water's start, a run that could not finish). What comes out is a
//! [`LoadedScene`] that nothing downstream needs to check again; every error names the
//! key and where its value came from (a line of the file, or a `--set` argument).

mod body_overlaps;
mod grid_probe;
mod placement;
mod rocks;
mod run_length;
mod water_start;

pub use run_length::{MAX_OUTPUTS, MAX_STEPS};

use crate::estimate;
use crate::scene::resolution::Resolution;
use crate::scene::{
    apply_overrides, attribute, parse, reattribute, validate, KeyError, Scene, SceneError,
    ShapeSpec,
};
use crate::shapes::assets::Assets;
use std::path::Path;

/// A parsed, validated scene together with the text it came from.
#[derive(Debug, Clone)]
pub struct LoadedScene {
    pub scene: Scene,
    /// The scene text after overrides (what was simulated).
    pub text: String,
    pub file: String,
    /// The text as the file holds it, before overrides.
    pub source: String,
    /// The `key.path=value` overrides applied.
    pub overrides: Vec<String>,
}

impl LoadedScene {
    /// The error at a scene key, located where its value came from: the `--set`
    /// argument that set it, else its line in the file as written.
    pub fn locate(&self, e: KeyError) -> SceneError {
        let line = crate::scene::locate(&self.text, &e.path);
        attribute(&self.source, &self.file, &self.overrides, e, line)
    }
}

/// Read and validate a scene file (a regular file of at most
/// [`MAX_SCENE_BYTES`](crate::numerics::capped_read::MAX_SCENE_BYTES)), applying `key.path=value`
/// overrides first.
pub fn load_scene_file(path: &Path, overrides: &[String]) -> Result<LoadedScene, SceneError> {
    let file = path.display().to_string();
    let cap = crate::numerics::capped_read::MAX_SCENE_BYTES;
    let text =
        crate::numerics::capped_read::read_capped_text(path, cap).map_err(|e| SceneError {
            file: file.clone(),
            path: String::new(),
            line: None,
            message: format!("cannot read scene file: {e}"),
        })?;
    let dir = path.parent().unwrap_or(Path::new("."));
    load_scene_in(&text, &file, overrides, dir)
}

/// Parse and validate scene text. `file` is used in error messages; files named by
/// shapes are read relative to the working directory.
pub fn load_scene_str(
    text: &str,
    file: &str,
    overrides: &[String],
) -> Result<LoadedScene, SceneError> {
    load_scene_in(text, file, overrides, Path::new("."))
}

/// Parse and validate scene text whose shape files live in `dir`.
pub fn load_scene_in(
    text: &str,
    file: &str,
    overrides: &[String],
    dir: &Path,
) -> Result<LoadedScene, SceneError> {
    let source = text;
    let text = apply_overrides(source, file, overrides)?;
    let mut scene = parse(&text, file).map_err(|e| reattribute(source, overrides, e))?;
    let fail = |e: KeyError| {
        let line = crate::scene::locate(&text, &e.path);
        attribute(source, file, overrides, e, line)
    };
    // dp, h and the skin, derived once for every check below
    let res = Resolution::of_scene(&scene);
    rocks::expand(&mut scene, res.dp).map_err(fail)?;
    validate(&scene).map_err(fail)?;
    scene.assets = read_assets(&scene, dir).map_err(fail)?;
    placement::check_regions(&scene).map_err(fail)?;
    body_overlaps::check_bodies(&scene, res.dp).map_err(fail)?;
    // a region that holds no particle at this dp, refused before what its spacing
    // would make of the time step
    if let Some(e) = estimate::empty_part(&scene, &estimate::estimate(&scene, &res)) {
        return Err(fail(e));
    }
    let water = water_start::check_water_start(&scene, &res).map_err(fail)?;
    run_length::check_run_length(&scene, &res, water.as_ref()).map_err(fail)?;
    Ok(LoadedScene {
        scene,
        text,
        file: file.to_string(),
        source: source.to_string(),
        overrides: overrides.to_vec(),
    })
}

/// Every shape of a scene with its key path.
fn shapes(scene: &Scene) -> Vec<(String, &ShapeSpec)> {
    let mut v = Vec::new();
    for (i, r) in scene.regions.iter().enumerate() {
        v.push((format!("regions[{i}].shape"), &r.shape));
    }
    for (i, w) in scene.walls.iter().enumerate() {
        v.push((format!("walls[{i}].shape"), &w.shape));
    }
    for (i, w) in scene.barriers.iter().enumerate() {
        v.push((format!("barriers[{i}].shape"), &w.shape));
    }
    for (i, b) in scene.bodies.iter().enumerate() {
        v.push((format!("bodies[{i}].shape"), &b.shape));
    }
    v
}

/// Read the files named by the scene's shapes, relative to `dir`; an error names the
/// key of the shape that names the file.
fn read_assets(scene: &Scene, dir: &Path) -> Result<Assets, KeyError> {
    let mut a = Assets::default();
    for (path, s) in shapes(scene) {
        let read = match s {
            ShapeSpec::Mesh { file, .. } => a.read_mesh(file, dir),
            ShapeSpec::Heightmap { file, .. } => a.read_grid(file, dir),
            _ => Ok(()),
        };
        read.map_err(|e| KeyError::new(format!("{path}.file"), e.to_string()))?;
    }
    Ok(a)
}

/// Every bundled scene (`models/scenes`), loaded, by file name: for the tests that
/// hold what runs before the build against the build.
#[cfg(test)]
pub(crate) fn bundled_scenes() -> Vec<(String, LoadedScene)> {
    let dir = Path::new(env!("CARGO_MANIFEST_DIR")).join("../models/scenes");
    let mut paths: Vec<_> = std::fs::read_dir(&dir)
        .expect("models/scenes")
        .map(|e| e.expect("a directory entry").path())
        .filter(|p| p.extension().is_some_and(|x| x == "toml"))
        .collect();
    paths.sort();
    paths
        .into_iter()
        .map(|p| {
            let name = p.file_name().unwrap_or_default().to_string_lossy().into();
            let loaded = load_scene_file(&p, &[]).unwrap_or_else(|e| panic!("{e}"));
            (name, loaded)
        })
        .collect()
}
