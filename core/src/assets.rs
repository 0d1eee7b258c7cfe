//! Files that shapes refer to (meshes, terrain grids), read once at scene load with
//! paths relative to the scene file. Errors name the key and the file.

use crate::heightmap::Heightmap;
use crate::mesh::TriMesh;
use crate::scene::{Scene, ShapeSpec};
use std::collections::BTreeMap;
use std::path::Path;
use std::sync::Arc;

/// Parsed files, keyed by the `file` string as written in the scene.
#[derive(Clone, Debug, Default)]
pub struct Assets {
    pub meshes: BTreeMap<String, Arc<TriMesh>>,
    pub grids: BTreeMap<String, Arc<Heightmap>>,
}

/// Every shape of a scene with its key path.
pub fn shapes(scene: &Scene) -> Vec<(String, &ShapeSpec)> {
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

/// Read the files named by the scene's shapes, relative to `dir`.
pub fn load(scene: &Scene, dir: &Path) -> Result<Assets, (String, String)> {
    let mut a = Assets::default();
    for (path, s) in shapes(scene) {
        match s {
            ShapeSpec::Mesh { file, .. } if !a.meshes.contains_key(file) => {
                let m = TriMesh::load(&dir.join(file)).map_err(|e| (format!("{path}.file"), e))?;
                a.meshes.insert(file.clone(), Arc::new(m));
            }
            ShapeSpec::Heightmap { file, .. } if !a.grids.contains_key(file) => {
                let g =
                    Heightmap::load(&dir.join(file)).map_err(|e| (format!("{path}.file"), e))?;
                a.grids.insert(file.clone(), Arc::new(g));
            }
            _ => {}
        }
    }
    Ok(a)
}
