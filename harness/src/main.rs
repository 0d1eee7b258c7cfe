//! `granmix`: run, check and benchmark granular-mixture scenes.

mod accuracy;
mod bench;
mod check;
mod pack;
mod plot;
mod run;
mod scale;
mod series;
mod stability;
mod vtk;

use clap::{Parser, Subcommand};
use std::path::PathBuf;
use std::process::ExitCode;

#[derive(Parser)]
#[command(
    name = "granmix",
    version,
    about = "SPH simulation of binary granular mixtures hitting barriers"
)]
struct Cli {
    /// Worker threads (default: all cores). Results are identical for any count.
    #[arg(long, global = true)]
    threads: Option<usize>,
    #[command(subcommand)]
    command: Command,
}

#[derive(Subcommand)]
enum Command {
    /// Run a scene to its end time; writes VTK, series.csv and summary.json.
    Run {
        /// Scene file (TOML).
        scene: PathBuf,
        /// Output directory (default: out/<scene name>).
        #[arg(long)]
        out: Option<PathBuf>,
        /// Override a scene value, e.g. --set simulation.dp=0.004 (repeatable).
        #[arg(long = "set", value_name = "KEY.PATH=VALUE")]
        set: Vec<String>,
        /// Skip VTK snapshots.
        #[arg(long)]
        no_vtk: bool,
        /// No progress bar or stage table.
        #[arg(long, short)]
        quiet: bool,
    },
    /// Validate a scene and print particle counts, Δt and estimated cost.
    Check {
        scene: PathBuf,
        #[arg(long = "set", value_name = "KEY.PATH=VALUE")]
        set: Vec<String>,
    },
    /// Run benchmark cases at several resolutions; writes JSON and a PNG.
    Bench(bench::BenchArgs),
    /// Package a scene (or a structure file) as an FMI 2.0 Co-Simulation FMU.
    PackFmu(pack::PackArgs),
}

fn main() -> ExitCode {
    let cli = Cli::parse();
    if let Some(n) = cli.threads {
        if let Err(e) = rayon::ThreadPoolBuilder::new()
            .num_threads(n)
            .build_global()
        {
            eprintln!("error: cannot set {n} threads: {e}");
            return ExitCode::from(2);
        }
    }
    match run_cli(cli.command) {
        Ok(code) => code,
        Err(e) => {
            eprintln!("error: {e:#}");
            ExitCode::from(2)
        }
    }
}

fn run_cli(cmd: Command) -> anyhow::Result<ExitCode> {
    match cmd {
        Command::Run {
            scene,
            out,
            set,
            no_vtk,
            quiet,
        } => {
            let out = out.unwrap_or_else(|| {
                PathBuf::from("out").join(
                    scene
                        .file_stem()
                        .map(|s| s.to_os_string())
                        .unwrap_or_default(),
                )
            });
            let rep = run::run(&run::RunOptions {
                scene,
                out: out.clone(),
                set,
                interactive: !quiet,
                vtk: !no_vtk,
            })?;
            if let Some(b) = rep.blowup {
                eprintln!("error: {b}");
                if !no_vtk {
                    eprintln!(
                        "the state at the blow-up is the last snapshot in {}",
                        out.display()
                    );
                }
                return Ok(ExitCode::from(3));
            }
            Ok(ExitCode::SUCCESS)
        }
        Command::Check { scene, set } => {
            check::check(&scene, &set)?;
            Ok(ExitCode::SUCCESS)
        }
        Command::Bench(args) => bench::bench(&args),
        Command::PackFmu(args) => {
            pack::pack(&args)?;
            Ok(ExitCode::SUCCESS)
        }
    }
}
