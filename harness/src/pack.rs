//! `granmix pack-fmu`: write an FMI 2.0 Co-Simulation FMU for a scene (the granular
//! model) or a structure file (`models/structures/*.toml`, a structural partner). The
//! work is [`granmix_fmu::package::write_fmu`]; this front finds the library.

use anyhow::{bail, Context, Result};
use std::path::PathBuf;

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

/// Write the FMU for `args.input`.
pub fn pack(args: &PackArgs) -> Result<()> {
    let lib = find_library(&args.lib)?;
    granmix_fmu::package::write_fmu(&args.input, &args.out, &lib, &args.set)
        .map_err(anyhow::Error::msg)
}
