//! `granmix pack-fmu`: write an FMI 2.0 Co-Simulation FMU for a scene (the granular
//! model) or a structure file (`models/structures/*.toml`, a structural partner).

use crate::zip::ZipWriter;
use anyhow::{bail, Context, Result};
use granmix_core::scene::{apply_overrides, load_scene_file, ShapeSpec};
use granmix_fmu::granular::{self, Granular};
use granmix_fmu::model::Model;
use granmix_fmu::structure::Structure;
use granmix_fmu::xml::model_description;
use std::path::{Path, PathBuf};

/// Arguments of `granmix pack-fmu`.
#[derive(clap::Args, Debug)]
pub struct PackArgs {
    /// Scene file (TOML), or a structure file with a `[structure]` table.
    pub input: PathBuf,
    /// Output FMU; its file stem is the model identifier.
    #[arg(short, long)]
    pub out: PathBuf,
    /// The granmix-fmu shared library (default: libgranmix_fmu.so next to granmix).
    #[arg(long)]
    pub lib: Option<PathBuf>,
    /// Override a scene value before packing, e.g. --set simulation.dp=0.01.
    #[arg(long = "set", value_name = "KEY.PATH=VALUE")]
    pub set: Vec<String>,
}

/// Model identifier from the output name: letters, digits and `_`, not starting with a
/// digit.
pub fn model_identifier(out: &Path) -> Result<String> {
    let stem = out
        .file_stem()
        .and_then(|s| s.to_str())
        .with_context(|| format!("output `{}` has no file name", out.display()))?;
    let mut id: String = stem
        .chars()
        .map(|c| if c.is_ascii_alphanumeric() { c } else { '_' })
        .collect();
    if id.is_empty() {
        bail!("output `{}`: empty model identifier", out.display());
    }
    if id.as_bytes()[0].is_ascii_digit() {
        id.insert(0, '_');
    }
    Ok(id)
}

fn find_library(lib: &Option<PathBuf>) -> Result<PathBuf> {
    let path = match lib {
        Some(p) => p.clone(),
        None => std::env::current_exe()
            .context("cannot locate the granmix executable")?
            .with_file_name("libgranmix_fmu.so"),
    };
    if !path.is_file() {
        bail!(
            "FMU library {} not found: build it with `cargo build --release -p granmix-fmu` \
             or name it with --lib",
            path.display()
        );
    }
    Ok(path)
}

/// Shape files a scene names, with the key path of each `file`.
fn shape_files(scene: &granmix_core::scene::Scene) -> Vec<(String, String)> {
    let mut out = Vec::new();
    let shapes = scene
        .regions
        .iter()
        .enumerate()
        .map(|(i, r)| (format!("regions[{i}]"), &r.shape))
        .chain(
            scene
                .bodies
                .iter()
                .enumerate()
                .map(|(i, b)| (format!("bodies[{i}]"), &b.shape)),
        )
        .chain(
            scene
                .walls
                .iter()
                .enumerate()
                .map(|(i, w)| (format!("walls[{i}]"), &w.shape)),
        )
        .chain(
            scene
                .barriers
                .iter()
                .enumerate()
                .map(|(i, w)| (format!("barriers[{i}]"), &w.shape)),
        );
    for (key, shape) in shapes {
        if let ShapeSpec::Mesh { file, .. } | ShapeSpec::Heightmap { file, .. } = shape {
            out.push((format!("{key}.shape.file"), file.clone()));
        }
    }
    out
}

/// Write the FMU for `args.input`.
pub fn pack(args: &PackArgs) -> Result<()> {
    let id = model_identifier(&args.out)?;
    let lib = find_library(&args.lib)?;
    let text = std::fs::read_to_string(&args.input)
        .with_context(|| format!("cannot read {}", args.input.display()))?;
    let is_structure = text
        .parse::<toml::Table>()
        .map(|t| t.contains_key("structure"))
        .unwrap_or(false);
    let mut zip = ZipWriter::default();
    let xml = if is_structure {
        if !args.set.is_empty() {
            bail!("--set applies to scenes, not structure files");
        }
        let s =
            Structure::new(&text, &args.input.display().to_string()).map_err(anyhow::Error::msg)?;
        zip.add("resources/structure.toml", text.as_bytes())?;
        model_description(&s.info(&id), s.variables())
    } else {
        let loaded = load_scene_file(&args.input, &args.set).map_err(|e| anyhow::anyhow!("{e}"))?;
        let dir = args.input.parent().unwrap_or(Path::new("."));
        // Shape files travel in resources/ under flat names; the packed scene names them.
        let mut renames = Vec::new();
        for (n, (key, file)) in shape_files(&loaded.scene).into_iter().enumerate() {
            let src = dir.join(&file);
            let base = Path::new(&file)
                .file_name()
                .and_then(|s| s.to_str())
                .unwrap_or("shape");
            let flat = format!("shape_{n}_{base}");
            let data = std::fs::read(&src)
                .with_context(|| format!("{key}: cannot read {}", src.display()))?;
            zip.add(&format!("resources/{flat}"), &data)?;
            renames.push(format!("{key}=\"{flat}\""));
        }
        let packed = apply_overrides(&loaded.text, &loaded.file, &renames)
            .map_err(|e| anyhow::anyhow!("{e}"))?;
        // The packed scene differs only in shape-file names, so the table is the same.
        let model = Granular::new(loaded.clone(), dir).map_err(anyhow::Error::msg)?;
        zip.add("resources/scene.toml", packed.as_bytes())?;
        let mut info = model.info(&id);
        info.guid = granular::guid(&packed);
        model_description(&info, model.variables())
    };
    zip.add("modelDescription.xml", xml.as_bytes())?;
    let so = std::fs::read(&lib).with_context(|| format!("cannot read {}", lib.display()))?;
    zip.add(&format!("binaries/linux64/{id}.so"), &so)?;
    if let Some(parent) = args.out.parent().filter(|p| !p.as_os_str().is_empty()) {
        std::fs::create_dir_all(parent)
            .with_context(|| format!("cannot create {}", parent.display()))?;
    }
    std::fs::write(&args.out, zip.finish())
        .with_context(|| format!("cannot write {}", args.out.display()))?;
    Ok(())
}
