//! `granmix`: run, check and benchmark granular-mixture scenes.

mod bench;
mod check;
mod element;
mod ensemble;
mod pack;
mod pattern;
mod plot;
mod quicklook;
mod run;
mod series;
mod vtk;
mod watch;

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
        /// Skip the quick-look plot (plots/quicklook.png: barrier loads, energies, soil density,
        /// run-out against time).
        #[arg(long)]
        no_plots: bool,
        /// No progress bar or stage table.
        #[arg(long, short)]
        quiet: bool,
        /// Publish particle frames over iceoryx2 on `granmix/<SERVICE>/particles`
        /// (default SERVICE: the scene's file name), or on SERVICE itself if it has a `/`.
        #[arg(long, value_name = "SERVICE", num_args = 0..=1, default_missing_value = "")]
        publish: Option<String>,
        /// Publish a frame every N fine steps.
        #[arg(long, value_name = "N", default_value_t = 10)]
        publish_every: u64,
        /// Record the run to an MCAP file (particles, bodies, loads, energies, scene).
        #[arg(long, value_name = "FILE.mcap")]
        record: Option<PathBuf>,
        /// Refuse the scene if its estimated memory exceeds SIZE (e.g. 8GiB, 500MB,
        /// 4e9; default: 80 % of the available memory).
        #[arg(long, value_name = "SIZE", value_parser = parse_size)]
        memory_budget: Option<f64>,
        /// Run N members, each start perturbed (every soil and water particle moved by
        /// --epsilon dp, seeded), into OUT/member_NN, and write the spread of every
        /// output: OUT/ensemble.csv, ensemble.json and plots/ensemble.png.
        #[arg(long, value_name = "N")]
        ensemble: Option<usize>,
        /// The members' displacement as a fraction of dp, in (0, 0.5).
        #[arg(
            long,
            value_name = "EPS",
            default_value_t = 1e-6,
            requires = "ensemble"
        )]
        epsilon: f64,
        /// Member m's seed is SEED + m.
        #[arg(long, value_name = "SEED", default_value_t = 0, requires = "ensemble")]
        seed: u64,
    },
    /// Validate a scene and estimate its particle counts, memory, Δt and cost without
    /// building it; refuse it if over the memory budget.
    Check {
        scene: PathBuf,
        #[arg(long = "set", value_name = "KEY.PATH=VALUE")]
        set: Vec<String>,
        /// Build the scene and print exact counts (and the coarse step Δt_c).
        #[arg(long)]
        exact: bool,
        /// Refuse the scene if its estimated memory exceeds SIZE (e.g. 8GiB, 500MB,
        /// 4e9; default: 80 % of the available memory).
        #[arg(long, value_name = "SIZE", value_parser = parse_size)]
        memory_budget: Option<f64>,
    },
    /// Run benchmark cases at several resolutions; writes JSON and a PNG.
    Bench(bench::BenchArgs),
    /// Drive one material point of a scene's soil through a drained triaxial
    /// compression or a simple shear: peak and end stresses against Mohr–Coulomb,
    /// element.csv and element.png.
    Element(element::ElementArgs),
    /// Package a scene (or a structure file) as an FMI 2.0 Co-Simulation FMU.
    PackFmu(pack::PackArgs),
    /// Subscribe to a particle service: frame rate, particle count, latency; can record.
    Watch(watch::WatchArgs),
    /// Measure the particle channel: publish cost against memcpy, solver overhead.
    BenchIpc(bench::ipc::BenchIpcArgs),
    /// Publish a checkable test pattern on a new service (for the channel tests).
    #[command(hide = true)]
    IpcPattern(pattern::PatternArgs),
}

fn main() -> ExitCode {
    quiet_on_a_closed_pipe();
    let cli = Cli::parse();
    // The whole command runs on a worker of the pool: a parallel loop started from a
    // worker begins at once on that thread, while one started from outside the pool
    // is handed over to a sleeping worker and back (two thread switches per loop; on
    // one thread an eighth of a 5,000-particle run went to the scheduler).
    let n = match (cli.threads, std::thread::available_parallelism()) {
        (Some(n), Ok(cores)) if n > cores.get() => {
            eprintln!(
                "warning: --threads {n} is more than this machine's {cores} cores; using {cores} \
                 (results are identical for any count)"
            );
            cores.get()
        }
        (n, _) => n.unwrap_or(0),
    };
    if let Err(e) = rayon::ThreadPoolBuilder::new()
        .num_threads(n)
        .stack_size(WORKER_STACK)
        .build_global()
    {
        eprintln!("error: cannot set {n} threads: {e}");
        return ExitCode::from(2);
    }
    let mut result = None;
    rayon::scope(|_| result = Some(run_cli(cli.command)));
    match result.expect("the pool ran the command") {
        Ok(code) => code,
        Err(e) => {
            eprintln!("error: {e:#}");
            ExitCode::from(2)
        }
    }
}

/// Stack of the pool's threads, which run the whole command (the main thread's size).
const WORKER_STACK: usize = 8 << 20;

fn parse_size(text: &str) -> Result<f64, granmix_core::estimate::budget::SizeError> {
    granmix_core::estimate::budget::parse_bytes(text)
}

fn run_cli(cmd: Command) -> anyhow::Result<ExitCode> {
    match cmd {
        Command::Run {
            scene,
            out,
            set,
            no_vtk,
            no_plots,
            quiet,
            publish,
            publish_every,
            record,
            memory_budget,
            ensemble,
            epsilon,
            seed,
        } => {
            let out = out.unwrap_or_else(|| {
                PathBuf::from("out").join(
                    scene
                        .file_stem()
                        .map(|s| s.to_os_string())
                        .unwrap_or_default(),
                )
            });
            let publish = publish.map(|p| {
                if p.is_empty() {
                    scene
                        .file_stem()
                        .map(|s| s.to_string_lossy().into_owned())
                        .unwrap_or_else(|| "granmix".into())
                } else {
                    p
                }
            });
            let opts = run::RunOptions {
                scene,
                out: out.clone(),
                set,
                interactive: !quiet,
                vtk: !no_vtk,
                plots: !no_plots,
                publish,
                publish_every,
                record,
                memory_budget,
            };
            if let Some(members) = ensemble {
                return run_ensemble(
                    &opts,
                    ensemble::Ensemble {
                        members,
                        epsilon,
                        seed,
                    },
                );
            }
            let rep = run::run(&opts)?;
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
        Command::Check {
            scene,
            set,
            exact,
            memory_budget,
        } => {
            check::check(&scene, &set, exact, memory_budget)?;
            Ok(ExitCode::SUCCESS)
        }
        Command::Bench(args) => bench::bench(&args),
        Command::Element(args) => {
            element::element(&args)?;
            Ok(ExitCode::SUCCESS)
        }
        Command::PackFmu(args) => {
            pack::pack(&args)?;
            Ok(ExitCode::SUCCESS)
        }
        Command::Watch(args) => {
            watch::watch(&args)?;
            Ok(ExitCode::SUCCESS)
        }
        Command::BenchIpc(args) => {
            bench::ipc::bench_ipc(&args)?;
            Ok(ExitCode::SUCCESS)
        }
        Command::IpcPattern(args) => {
            pattern::pattern(&args)?;
            Ok(ExitCode::SUCCESS)
        }
    }
}

/// `granmix run --ensemble`: the members, then exit 3 if any blew up or failed.
fn run_ensemble(opts: &run::RunOptions, e: ensemble::Ensemble) -> anyhow::Result<ExitCode> {
    if opts.publish.is_some() || opts.record.is_some() {
        anyhow::bail!(
            "--ensemble runs its members side by side: --publish and --record take one run \
             (run a member alone with --set simulation.perturbation.seed=SEED)"
        );
    }
    let reports = ensemble::run(opts, &e)?;
    let blown = reports
        .iter()
        .any(|r| r.as_ref().map_or(true, |r| r.blowup.is_some()));
    Ok(if blown {
        ExitCode::from(3)
    } else {
        ExitCode::SUCCESS
    })
}

/// A reader that stops early (`granmix check … | head`) closes the pipe, and `println!`
/// then panics on the broken pipe. The command's output is no longer wanted: end
/// quietly with the status a shell gives a process its SIGPIPE stopped (128 + 13),
/// instead of a panic message and a backtrace. Every other panic keeps the default
/// report.
fn quiet_on_a_closed_pipe() {
    let default = std::panic::take_hook();
    std::panic::set_hook(Box::new(move |info| {
        let msg = info
            .payload()
            .downcast_ref::<String>()
            .map(String::as_str)
            .or_else(|| info.payload().downcast_ref::<&str>().copied())
            .unwrap_or("");
        if msg.starts_with("failed printing to std") && msg.contains("Broken pipe") {
            std::process::exit(141);
        }
        default(info);
    }));
}
