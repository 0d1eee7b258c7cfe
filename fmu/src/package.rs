//! Writing an FMU archive: `modelDescription.xml` from the variable table, the shared
//! library under `binaries/linux64/<modelIdentifier>.so` and the model's resources.
//! `granmix pack-fmu` is the command-line front; tests call [`write_fmu`] directly.

use crate::error::{GranularError, ReadError, StructureError};
use crate::granular::{self, Granular};
use crate::model::Model;
use crate::structure::Structure;
use crate::xml::model_description;
use crate::zip::ZipWriter;
use granmix_core::input::load_scene_file;
use granmix_core::scene::{apply_overrides, Scene, ShapeSpec};
use std::path::{Path, PathBuf};

/// Why an FMU or its resources cannot be written; each names the file at fault.
#[derive(Debug, thiserror::Error)]
pub enum PackageError {
    #[error("output `{}` has no file name", out.display())]
    NoFileName { out: PathBuf },
    #[error("output `{}`: empty model identifier", out.display())]
    EmptyIdentifier { out: PathBuf },
    #[error(transparent)]
    Read(#[from] ReadError),
    #[error("--set applies to scenes, not structure files")]
    SetOnStructure,
    #[error(transparent)]
    Structure(#[from] StructureError),
    /// The scene does not load or take the overrides (granmix-core's message names the
    /// file and key).
    #[error("{0}")]
    Scene(String),
    /// Shape file `path` named by key `key` of scene file `scene` cannot be read.
    #[error("{scene}: {key}: cannot read {}: {error}", path.display())]
    Shape {
        scene: String,
        key: String,
        path: PathBuf,
        error: std::io::Error,
    },
    #[error(transparent)]
    Granular(#[from] GranularError),
    /// The FMU's shared library cannot be read.
    #[error(
        "FMU library {}: {error} (build it with `cargo build --release -p granmix-fmu`)",
        lib.display()
    )]
    Library { lib: PathBuf, error: std::io::Error },
    /// `path` (the FMU or a resource file) cannot be written.
    #[error("{}: {error}", path.display())]
    Write {
        path: PathBuf,
        error: std::io::Error,
    },
    #[error("cannot create {}: {error}", dir.display())]
    CreateDir { dir: PathBuf, error: std::io::Error },
}

/// Model identifier from the output name: letters, digits and `_`, not starting with a
/// digit.
pub fn model_identifier(out: &Path) -> Result<String, PackageError> {
    let stem =
        out.file_stem()
            .and_then(|s| s.to_str())
            .ok_or_else(|| PackageError::NoFileName {
                out: out.to_path_buf(),
            })?;
    let mut id: String = stem
        .chars()
        .map(|c| if c.is_ascii_alphanumeric() { c } else { '_' })
        .collect();
    if id.is_empty() {
        return Err(PackageError::EmptyIdentifier {
            out: out.to_path_buf(),
        });
    }
    if id.as_bytes()[0].is_ascii_digit() {
        id.insert(0, '_');
    }
    Ok(id)
}

/// Shape files a scene names, with the key path of each `file`.
fn shape_files(scene: &Scene) -> Vec<(String, String)> {
    let keyed = |key: &str, shapes: Vec<&ShapeSpec>| -> Vec<(String, ShapeSpec)> {
        shapes
            .into_iter()
            .enumerate()
            .map(|(i, s)| (format!("{key}[{i}].shape.file"), s.clone()))
            .collect()
    };
    let mut all = keyed("regions", scene.regions.iter().map(|r| &r.shape).collect());
    all.extend(keyed(
        "bodies",
        scene.bodies.iter().map(|b| &b.shape).collect(),
    ));
    all.extend(keyed(
        "walls",
        scene.walls.iter().map(|w| &w.shape).collect(),
    ));
    all.extend(keyed(
        "barriers",
        scene.barriers.iter().map(|w| &w.shape).collect(),
    ));
    all.into_iter()
        .filter_map(|(key, shape)| match shape {
            ShapeSpec::Mesh { file, .. } | ShapeSpec::Heightmap { file, .. } => Some((key, file)),
            _ => None,
        })
        .collect()
}

/// True when `text` is a structure file (a top-level `[structure]` table).
pub fn is_structure(text: &str) -> bool {
    text.parse::<toml::Table>()
        .map(|t| t.contains_key("structure"))
        .unwrap_or(false)
}

/// What an FMU holds besides its shared library.
pub struct Contents {
    /// `modelDescription.xml`.
    pub model_description: String,
    /// The GUID in the description, which `fmi2Instantiate` checks against the resources.
    pub guid: String,
    /// The files of `resources/`, by name.
    pub resources: Vec<(String, Vec<u8>)>,
}

/// The description and resources of the FMU with model identifier `id` for `input` (a
/// scene, with `sets` overrides, or a structure file). Errors name the file at fault.
pub fn contents(input: &Path, id: &str, sets: &[String]) -> Result<Contents, PackageError> {
    let text = ReadError::read_to_string(input.to_path_buf())?;
    let mut resources = Vec::new();
    let (info, xml) = if is_structure(&text) {
        if !sets.is_empty() {
            return Err(PackageError::SetOnStructure);
        }
        let s = Structure::new(&text, &input.display().to_string())?;
        resources.push(("structure.toml".to_string(), text.into_bytes()));
        let info = s.info(id);
        let xml = model_description(&info, s.variables());
        (info, xml)
    } else {
        let loaded =
            load_scene_file(input, sets).map_err(|e| PackageError::Scene(e.to_string()))?;
        let dir = input.parent().unwrap_or(Path::new("."));
        // Shape files travel in resources/ under flat names; the packed scene names them.
        let mut renames = Vec::new();
        for (n, (key, file)) in shape_files(&loaded.scene).into_iter().enumerate() {
            let src = dir.join(&file);
            let base = Path::new(&file)
                .file_name()
                .and_then(|s| s.to_str())
                .unwrap_or("shape");
            let flat = format!("shape_{n}_{base}");
            let data = std::fs::read(&src).map_err(|error| PackageError::Shape {
                scene: loaded.file.clone(),
                key: key.clone(),
                path: src.clone(),
                error,
            })?;
            resources.push((flat.clone(), data));
            renames.push(format!("{key}=\"{flat}\""));
        }
        let packed = apply_overrides(&loaded.text, &loaded.file, &renames)
            .map_err(|e| PackageError::Scene(e.to_string()))?;
        // The packed scene differs only in shape-file names, so the table is the same.
        let model = Granular::new(loaded, dir)?;
        let mut info = model.info(id);
        info.guid = granular::guid(&packed);
        resources.push(("scene.toml".to_string(), packed.into_bytes()));
        let xml = model_description(&info, model.variables());
        (info, xml)
    };
    Ok(Contents {
        model_description: xml,
        guid: info.guid,
        resources,
    })
}

/// Write the FMU for `input` (a scene, with `sets` overrides, or a structure file) to
/// `out`, with the shared library `lib`. Errors name the file at fault.
pub fn write_fmu(
    input: &Path,
    out: &Path,
    lib: &Path,
    sets: &[String],
) -> Result<(), PackageError> {
    let id = model_identifier(out)?;
    let c = contents(input, &id, sets)?;
    let so = std::fs::read(lib).map_err(|error| PackageError::Library {
        lib: lib.to_path_buf(),
        error,
    })?;
    let mut zip = ZipWriter::default();
    let io = |error| PackageError::Write {
        path: out.to_path_buf(),
        error,
    };
    for (name, data) in &c.resources {
        zip.add(&format!("resources/{name}"), data).map_err(io)?;
    }
    zip.add("modelDescription.xml", c.model_description.as_bytes())
        .map_err(io)?;
    zip.add(&format!("binaries/linux64/{id}.so"), &so)
        .map_err(io)?;
    if let Some(parent) = out.parent().filter(|p| !p.as_os_str().is_empty()) {
        std::fs::create_dir_all(parent).map_err(|error| PackageError::CreateDir {
            dir: parent.to_path_buf(),
            error,
        })?;
    }
    std::fs::write(out, zip.finish()).map_err(io)
}

/// Write the `resources/` of the FMU for `input` into the directory `dir` (as a master
/// unpacks it) and return the FMU's GUID: what [`crate::ffi::LocalInstance`] needs to
/// instantiate the FMU inside this process.
pub fn write_resources(input: &Path, sets: &[String], dir: &Path) -> Result<String, PackageError> {
    let c = contents(input, "granmix", sets)?;
    std::fs::create_dir_all(dir).map_err(|error| PackageError::CreateDir {
        dir: dir.to_path_buf(),
        error,
    })?;
    for (name, data) in &c.resources {
        let path = dir.join(name);
        std::fs::write(&path, data).map_err(|error| PackageError::Write { path, error })?;
    }
    Ok(c.guid)
}
