//! `granmix element`: one material point of a scene's soil driven through a drained
//! triaxial compression or a simple shear (granmix_core::fine::element), for
//! calibrating a material against laboratory tests: a table of peak and end values
//! against Mohr–Coulomb, element.csv and element.png.

use crate::plot::{panels, Curve, Panel};
use anyhow::{bail, Context, Result};
use clap::{Args, ValueEnum};
use granmix_core::fine::element::{simple_shear, triaxial_compression};
use granmix_core::fine::material::FineMaterial;
use granmix_core::input::load_scene_file;
use granmix_core::scene::MaterialSpec;
use std::fmt::Write as _;
use std::path::PathBuf;

#[derive(Clone, Copy, Debug, ValueEnum)]
pub enum Path {
    /// Drained triaxial compression: lateral stress held at each --confining value.
    Triaxial,
    /// Simple shear from an isotropic state at each --confining value.
    Shear,
}

#[derive(Args)]
pub struct ElementArgs {
    /// Scene file (TOML) holding the material.
    scene: PathBuf,
    /// The `[[materials]]` entry (default: the first).
    #[arg(long)]
    material: Option<String>,
    /// The strain path.
    #[arg(long, value_enum, default_value_t = Path::Triaxial)]
    path: Path,
    /// Confining stresses σ3 (triaxial) or initial pressures (shear), Pa,
    /// comma-separated.
    #[arg(long, value_delimiter = ',', default_values_t = [50e3, 100e3, 150e3])]
    confining: Vec<f64>,
    /// Final axial strain (triaxial) or engineering shear strain γ (shear).
    #[arg(long, default_value_t = 0.3)]
    strain: f64,
    /// Increments along the path.
    #[arg(long, default_value_t = 30_000)]
    steps: usize,
    /// Shear rate γ̇ (1/s) of the shear path: only μ(I) depends on it.
    #[arg(long, default_value_t = 1.0)]
    rate: f64,
    /// Override a scene value, e.g. --set materials.0.friction_angle=28.6 (repeatable).
    #[arg(long = "set", value_name = "KEY.PATH=VALUE")]
    set: Vec<String>,
    /// Output directory for element.csv and element.png (default: out/element).
    #[arg(long)]
    out: Option<PathBuf>,
}

/// One curve of the run: (strain, stress measure, second measure) per increment.
struct Run {
    confining: f64,
    points: Vec<(f64, f64, f64)>,
    peak: (f64, f64),
    end: f64,
}

/// `granmix element`: the material's single-element tests (drained triaxial
/// compression or simple shear) at each confining stress, printed against the yield
/// surface's reference and written to element.csv and element.png.
pub fn element(a: &ElementArgs) -> Result<()> {
    let loaded = load_scene_file(&a.scene, &a.set)?;
    let spec = material(a, &loaded.scene.materials)?;
    check(a)?;
    let m = FineMaterial::from_spec(spec);
    let runs = run(a, &m);
    print_table(a, &m, &runs);
    write_outputs(a, &m, &runs)
}

/// The material `--material` names (the scene's first without it).
fn material<'a>(a: &ElementArgs, specs: &'a [MaterialSpec]) -> Result<&'a MaterialSpec> {
    Ok(match &a.material {
        None => specs
            .first()
            .with_context(|| format!("{}: no [[materials]] entry", a.scene.display()))?,
        Some(name) => specs.iter().find(|m| &m.name == name).with_context(|| {
            let known: Vec<_> = specs.iter().map(|m| m.name.as_str()).collect();
            format!(
                "--material: {} has no material `{name}` (known: {})",
                a.scene.display(),
                known.join(", ")
            )
        })?,
    })
}

/// Refuse confining stresses, strains, step counts and rates that name no test.
fn check(a: &ElementArgs) -> Result<()> {
    if a.confining.is_empty() || a.confining.iter().any(|c| !(*c > 0.0 && c.is_finite())) {
        bail!(
            "--confining: give positive stresses in Pa, found {:?}",
            a.confining
        );
    }
    if !(a.strain > 0.0 && a.strain.is_finite()) || a.steps == 0 {
        bail!("--strain must be positive and --steps at least 1");
    }
    if !(a.rate > 0.0 && a.rate.is_finite()) {
        bail!(
            "--rate must be a positive shear rate in 1/s, found {}",
            a.rate
        );
    }
    Ok(())
}

/// One test per confining stress along the chosen path.
fn run(a: &ElementArgs, m: &FineMaterial) -> Vec<Run> {
    a.confining
        .iter()
        .map(|&s3| match a.path {
            Path::Triaxial => {
                let p = triaxial_compression(m, s3, a.strain, a.steps);
                let pts: Vec<_> = p
                    .iter()
                    .map(|s| (s.axial_strain, s.q, s.volumetric_strain))
                    .collect();
                summarise(s3, pts)
            }
            Path::Shear => {
                let dt = a.strain / (a.steps as f64 * a.rate);
                let p = simple_shear(m, s3, a.strain, a.steps, dt);
                let pts: Vec<_> = p
                    .iter()
                    .map(|s| (s.gamma, s.shear_stress, s.shear_stress / s.p))
                    .collect();
                summarise(s3, pts)
            }
        })
        .collect()
}

/// The measured stress and its unit.
fn measure(path: Path) -> &'static str {
    match path {
        Path::Triaxial => "q [kPa]",
        Path::Shear => "√J2 [kPa]",
    }
}

/// The material, and per run its peak and end against the reference.
fn print_table(a: &ElementArgs, m: &FineMaterial, runs: &[Run]) {
    let phi = m.phi;
    let (s, t) = (phi.sin(), phi.tan());
    println!(
        "material `{}`: φ = {:.2}° on the `{}` cone{}{}",
        m.name,
        phi.to_degrees(),
        m.surface.name(),
        if m.hardening.is_some() {
            ", with hardening (φ at ε_p = 0)"
        } else {
            ""
        },
        if m.mu_i.is_some() {
            ", μ(I) (φ = atan μ_s)"
        } else {
            ""
        }
    );
    let (measure, reference) = (
        measure(a.path),
        match a.path {
            Path::Triaxial => "Mohr–Coulomb q = 2 sin φ σ3/(1 − sin φ)",
            Path::Shear => "√J2 = tan φ p (the shear cone)",
        },
    );
    println!(
        "{:>10} {:>14} {:>12} {:>14} {:>16}",
        "σ3 [kPa]",
        format!("peak {measure}"),
        "at strain",
        format!("end {measure}"),
        "reference [kPa]"
    );
    for r in runs {
        let want = match a.path {
            Path::Triaxial => 2.0 * s * r.confining / (1.0 - s),
            Path::Shear => t * r.confining,
        };
        println!(
            "{:>10.1} {:>14.2} {:>12.4} {:>14.2} {:>16.2}",
            r.confining / 1e3,
            r.peak.1 / 1e3,
            r.peak.0,
            r.end / 1e3,
            want / 1e3
        );
    }
    println!("reference: {reference} at the static φ");
}

/// element.csv and element.png in `--out`.
fn write_outputs(a: &ElementArgs, m: &FineMaterial, runs: &[Run]) -> Result<()> {
    let out = a
        .out
        .clone()
        .unwrap_or_else(|| PathBuf::from("out/element"));
    std::fs::create_dir_all(&out).with_context(|| format!("create {}", out.display()))?;
    let (xname, yname, zname) = match a.path {
        Path::Triaxial => ("axial_strain", "q [Pa]", "volumetric_strain"),
        Path::Shear => ("gamma", "sqrt_j2 [Pa]", "sqrt_j2_over_p"),
    };
    let mut csv = format!("confining [Pa],{xname},{yname},{zname}\n");
    for r in runs {
        for (x, y, z) in &r.points {
            writeln!(csv, "{:e},{x:e},{y:e},{z:e}", r.confining)?;
        }
    }
    let csv_path = out.join("element.csv");
    std::fs::write(&csv_path, csv).with_context(|| format!("write {}", csv_path.display()))?;
    // per run, (strain, y(point)) against the strain
    let curves = |y: fn(&(f64, f64, f64)) -> f64| -> Vec<Curve> {
        runs.iter()
            .map(|r| Curve {
                label: format!("σ3 = {:.0} kPa", r.confining / 1e3),
                points: r.points.iter().map(|p| (p.0, y(p))).collect(),
            })
            .collect()
    };
    let (title, xlabel, second) = match a.path {
        Path::Triaxial => (
            "drained triaxial compression",
            "axial strain",
            ("volumetric strain (compression > 0)", "ε_v"),
        ),
        Path::Shear => (
            "simple shear",
            "shear strain γ",
            ("stress ratio", "√J2 / p"),
        ),
    };
    let png = out.join("element.png");
    panels(
        &png,
        &format!("material `{}`: {title}", m.name),
        xlabel,
        &[
            Panel {
                title: "stress against strain".into(),
                ylabel: measure(a.path).into(),
                curves: curves(|p| p.1 * 1e-3),
                include: Some((0.0, 0.0)),
            },
            Panel {
                title: second.0.into(),
                ylabel: second.1.into(),
                curves: curves(|p| p.2),
                include: None,
            },
        ],
    )?;
    println!("wrote {} and {}", csv_path.display(), png.display());
    Ok(())
}

/// The run's peak (strain, value) and end value.
fn summarise(confining: f64, points: Vec<(f64, f64, f64)>) -> Run {
    let peak = points.iter().fold(
        (0.0, f64::MIN),
        |b, p| if p.1 > b.1 { (p.0, p.1) } else { b },
    );
    let end = points.last().map(|p| p.1).unwrap_or(0.0);
    Run {
        confining,
        points,
        peak,
        end,
    }
}
