//! Reading a scene: `--set` overrides, strict parsing, rock fills expanded into bodies,
//! validation, the files that shapes name (meshes, terrain grids) and where regions
//! lie. What comes out is a [`LoadedScene`] that nothing downstream needs to check again.

mod placement;
mod rocks;

use crate::assets::Assets;
use crate::scene::{apply_overrides, at, parse, validate, KeyError, Scene, SceneError, ShapeSpec};
use std::path::Path;

/// A parsed, validated scene together with the text it came from.
#[derive(Debug, Clone)]
pub struct LoadedScene {
    pub scene: Scene,
    /// The scene text after overrides (what was simulated).
    pub text: String,
    pub file: String,
}

/// Read and validate a scene file, applying `key.path=value` overrides first.
pub fn load_scene_file(path: &Path, overrides: &[String]) -> Result<LoadedScene, SceneError> {
    let file = path.display().to_string();
    let text = std::fs::read_to_string(path).map_err(|e| SceneError {
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
    let text = apply_overrides(text, file, overrides)?;
    let mut scene = parse(&text, file)?;
    let fail = |e| at(&text, file, e);
    rocks::expand(&mut scene).map_err(fail)?;
    validate(&scene).map_err(fail)?;
    scene.assets = read_assets(&scene, dir).map_err(fail)?;
    placement::check_regions(&scene).map_err(fail)?;
    Ok(LoadedScene {
        scene,
        text,
        file: file.to_string(),
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
