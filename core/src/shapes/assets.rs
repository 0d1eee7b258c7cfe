//! Files that shapes refer to (meshes, terrain grids), read once at scene load with
//! paths relative to the scene file ([`input`](crate::input) names the key at fault).

use crate::shapes::heightmap::Heightmap;
use crate::shapes::mesh::TriMesh;
use crate::shapes::shape_file::ShapeFileError;
use std::collections::BTreeMap;
use std::path::Path;
use std::sync::Arc;

/// Parsed files, keyed by the `file` string as written in the scene.
#[derive(Clone, Debug, Default)]
pub struct Assets {
    pub meshes: BTreeMap<String, Arc<TriMesh>>,
    pub grids: BTreeMap<String, Arc<Heightmap>>,
}

impl Assets {
    /// Read the mesh `file` (relative to `dir`) unless it is read already.
    pub fn read_mesh(&mut self, file: &str, dir: &Path) -> Result<(), ShapeFileError> {
        if !self.meshes.contains_key(file) {
            let m = TriMesh::load(&dir.join(file))?;
            self.meshes.insert(file.to_string(), Arc::new(m));
        }
        Ok(())
    }

    /// Read the terrain grid `file` (relative to `dir`) unless it is read already.
    pub fn read_grid(&mut self, file: &str, dir: &Path) -> Result<(), ShapeFileError> {
        if !self.grids.contains_key(file) {
            let g = Heightmap::load(&dir.join(file))?;
            self.grids.insert(file.to_string(), Arc::new(g));
        }
        Ok(())
    }
}
