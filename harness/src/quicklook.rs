//! The quick-look plot `granmix run` writes (`plots/quicklook.png`; `--no-plots` turns
//! it off): an engineer's first questions after a run, answered without a script.
//! Panels against time: the barrier loads split into water and grains, the kinetic
//! energy of each family and their total, the run-out of the grains with the water's
//! front, the water levels of the gauges, and the soil's density against its
//! material's (median, 10th percentile and minimum of ρ/ρ0). The curves are the rows of series.csv.

use crate::plot::{self, Curve, Panel};
use crate::series::{self, Layout, Unit};
use anyhow::Result;
use granmix_core::run::simulation::Sample;
use std::path::Path;

/// |v| of the first `dim` components.
fn norm(v: &[f64; 3], dim: usize) -> f64 {
    v[..dim].iter().map(|x| x * x).sum::<f64>().sqrt()
}

/// A curve of `f(sample)` against time.
fn curve(label: impl Into<String>, samples: &[Sample], f: impl Fn(&Sample) -> f64) -> Curve {
    Curve {
        label: label.into(),
        points: samples.iter().map(|s| (s.time, f(s))).collect(),
    }
}

/// Barrier loads: the resultant of each barrier, and with water its water and grain
/// parts (magnitudes of the impulse-averaged forces).
fn loads(l: &Layout, samples: &[Sample]) -> Vec<Curve> {
    let d = l.dim;
    let mut c = Vec::new();
    for (k, (name, _)) in l.barriers.iter().enumerate() {
        let at = |s: &Sample| s.barriers.get(k).cloned().unwrap_or_default();
        c.push(curve(format!("{name}: total"), samples, |s| {
            norm(&at(s).force, d)
        }));
        if l.water {
            c.push(curve(format!("{name}: water"), samples, |s| {
                norm(&at(s).force_water, d)
            }));
            c.push(curve(format!("{name}: grains"), samples, |s| {
                norm(&at(s).force_grains, d)
            }));
        }
    }
    c
}

/// Kinetic energy by family and in total.
fn energies(l: &Layout, samples: &[Sample]) -> Vec<Curve> {
    let mut c = Vec::new();
    if l.fine {
        c.push(curve("fine grains", samples, |s| s.kinetic_energy));
    }
    if !l.bodies.is_empty() {
        c.push(curve("coarse grains", samples, |s| s.coarse_kinetic_energy));
    }
    if l.water {
        c.push(curve("water", samples, |s| {
            s.water.as_ref().map_or(0.0, |w| w.kinetic_energy)
        }));
    }
    c.push(curve("total", samples, series::total_kinetic_energy));
    c
}

/// Run-out of the grains and front of the water.
fn fronts(l: &Layout, samples: &[Sample]) -> Vec<Curve> {
    let mut c = Vec::new();
    if l.fine || !l.bodies.is_empty() {
        c.push(curve("run-out (grains)", samples, |s| s.runout));
    }
    if l.water {
        // no point while there is no water (all of it gone through an outflow)
        c.push(Curve {
            label: "water front (largest x)".into(),
            points: samples
                .iter()
                .filter_map(|s| Some((s.time, s.water.as_ref()?.front?)))
                .collect(),
        });
    }
    c
}

/// The fine grains' ρ/ρ0: median, 10th percentile and minimum (empty without them).
fn densities(samples: &[Sample]) -> Vec<Curve> {
    type Pick = fn(&granmix_core::run::sample::DensityRatio) -> f64;
    let picks: [(&str, Pick); 3] = [
        ("median", |d| d.median),
        ("10th percentile", |d| d.p10),
        ("minimum", |d| d.min),
    ];
    picks
        .iter()
        .map(|(label, pick)| Curve {
            label: (*label).into(),
            points: samples
                .iter()
                .filter_map(|s| Some((s.time, pick(&s.density_ratio?))))
                .collect(),
        })
        .filter(|c| !c.points.is_empty())
        .collect()
}

/// Write the quick-look PNG of a run's samples to `path`.
pub fn write(path: &Path, title: &str, l: &Layout, samples: &[Sample]) -> Result<()> {
    let d = l.dim;
    let mut panels = Vec::new();
    let load = loads(l, samples);
    if !load.is_empty() {
        panels.push(Panel {
            title: "barrier load (impulse-averaged resultant)".into(),
            ylabel: format!("force [{}]", Unit::Force.symbol(d)),
            curves: load,
            include: None,
        });
    }
    panels.push(Panel {
        title: "kinetic energy".into(),
        ylabel: format!("energy [{}]", Unit::Energy.symbol(d)),
        curves: energies(l, samples),
        include: None,
    });
    let front = fronts(l, samples);
    if !front.is_empty() {
        panels.push(Panel {
            title: "run-out".into(),
            ylabel: "distance [m]".into(),
            curves: front,
            include: None,
        });
    }
    if !l.gauges.is_empty() {
        panels.push(Panel {
            title: "water levels (gauges)".into(),
            ylabel: "depth [m]".into(),
            curves: l
                .gauges
                .iter()
                .enumerate()
                .map(|(k, g)| {
                    curve(g.clone(), samples, |s| {
                        s.gauges.get(k).map_or(f64::NAN, |x| x.1)
                    })
                })
                .collect(),
            include: Some((0.0, 0.0)),
        });
    }
    let density = densities(samples);
    if !density.is_empty() {
        panels.push(Panel {
            title: "soil density".into(),
            ylabel: "ρ/ρ0".into(),
            curves: density,
            // ρ0 ± 5 %: a soil that keeps its density draws flat at 1
            include: Some((0.95, 1.05)),
        });
    }
    plot::panels(path, title, "time [s]", &panels)
}
