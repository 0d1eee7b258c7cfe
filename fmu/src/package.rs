//! Writing an FMU archive: `modelDescription.xml` from the variable table, the shared
//! library under `binaries/linux64/<modelIdentifier>.so` and the model's resources.
//! `granmix pack-fmu` is the command-line front; tests call [`write_fmu`] directly.

use crate::granular::{self, Granular};
use crate::model::Model;
use crate::structure::Structure;
use crate::xml::model_description;
use crate::zip::ZipWriter;
use granmix_core::scene::{apply_overrides, load_scene_file, Scene, ShapeSpec};
use std::path::Path;

/// Model identifier from the output name: letters, digits and `_`, not starting with a
/// digit.
pub fn model_identifier(out: &Path) -> Result<String, String> {
    let stem = out
        .file_stem()
        .and_then(|s| s.to_str())
        .ok_or_else(|| format!("output `{}` has no file name", out.display()))?;
    let mut id: String = stem
        .chars()
        .map(|c| if c.is_ascii_alphanumeric() { c } else { '_' })
        .collect();
    if id.is_empty() {
        return Err(format!(
            "output `{}`: empty model identifier",
            out.display()
        ));
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

/// Write the FMU for `input` (a scene, with `sets` overrides, or a structure file) to
/// `out`, with the shared library `lib`. Errors name the file at fault.
pub fn write_fmu(input: &Path, out: &Path, lib: &Path, sets: &[String]) -> Result<(), String> {
    let id = model_identifier(out)?;
    let text = std::fs::read_to_string(input)
        .map_err(|e| format!("cannot read {}: {e}", input.display()))?;
    let so = std::fs::read(lib).map_err(|e| {
        format!(
            "FMU library {}: {e} (build it with `cargo build --release -p granmix-fmu`)",
            lib.display()
        )
    })?;
    let mut zip = ZipWriter::default();
    let io = |e: std::io::Error| format!("{}: {e}", out.display());
    let xml = if is_structure(&text) {
        if !sets.is_empty() {
            return Err("--set applies to scenes, not structure files".into());
        }
        let s = Structure::new(&text, &input.display().to_string())?;
        zip.add("resources/structure.toml", text.as_bytes())
            .map_err(io)?;
        model_description(&s.info(&id), s.variables())
    } else {
        let loaded = load_scene_file(input, sets).map_err(|e| e.to_string())?;
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
            let data = std::fs::read(&src).map_err(|e| {
                format!("{}: {key}: cannot read {}: {e}", loaded.file, src.display())
            })?;
            zip.add(&format!("resources/{flat}"), &data).map_err(io)?;
            renames.push(format!("{key}=\"{flat}\""));
        }
        let packed =
            apply_overrides(&loaded.text, &loaded.file, &renames).map_err(|e| e.to_string())?;
        // The packed scene differs only in shape-file names, so the table is the same.
        let model = Granular::new(loaded, dir)?;
        zip.add("resources/scene.toml", packed.as_bytes())
            .map_err(io)?;
        let mut info = model.info(&id);
        info.guid = granular::guid(&packed);
        model_description(&info, model.variables())
    };
    zip.add("modelDescription.xml", xml.as_bytes())
        .map_err(io)?;
    zip.add(&format!("binaries/linux64/{id}.so"), &so)
        .map_err(io)?;
    if let Some(parent) = out.parent().filter(|p| !p.as_os_str().is_empty()) {
        std::fs::create_dir_all(parent)
            .map_err(|e| format!("cannot create {}: {e}", parent.display()))?;
    }
    std::fs::write(out, zip.finish()).map_err(io)
}
