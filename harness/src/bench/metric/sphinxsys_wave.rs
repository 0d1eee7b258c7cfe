//! SPHinXsys's 2D standing wave (`sphinxsys_standing_wave.toml`, issue 73): the water
//! scheme's numerical dissipation against another SPH code's on the same set-up, a
//! code-to-code reference.
//!
//! SPHinXsys (github.com/Xiangyu-Hu/SPHinXsys, `tests/2d_examples/test_2d_standing_wave`)
//! records the free-surface height at the centre antinode of a tank 2 m long, water
//! 1 m deep, released from rest at η = 1 + 0.1 cos(πx). Its regression record lies in
//! the project, `models/reference/sphinxsys_standing_wave/probe.csv`, with its source
//! and how its times were reconstructed. Both series, granmix's gauge `probe` at the
//! same place and SPHinXsys's probe, are fitted the same way over the same 10 s: the
//! height about its mean, from its first crossing of the mean on, by its zero crossings
//! (the period) and the slope of the log of its extrema (the decay; [`damped`]). The
//! score is the difference of the log decrements per period.

use anyhow::{anyhow, Context, Result};
use granmix_core::run::oscillation::{damped, Oscillation};
use granmix_core::run::simulation::Sample;
use serde_json::{json, Value};
use std::path::{Path, PathBuf};

/// The record, under the project's reference folder (`models/reference`).
const RECORD: &str = "sphinxsys_standing_wave/probe.csv";
/// The gauge of the scene at the centre antinode.
const GAUGE: &str = "probe";

/// SPHinXsys's probe record: (time s, surface height m).
pub(crate) struct SphinxsysWave {
    record: Vec<(f64, f64)>,
}

/// Period and decay of a probe's height `h(t)` about its mean, from its first crossing
/// of the mean on (the record starts at a trough, where [`damped`] expects a zero).
pub(crate) fn fit(series: &[(f64, f64)]) -> Option<Oscillation> {
    let about = about_mean(series);
    let first = about
        .windows(2)
        .position(|w| w[0].1.signum() != w[1].1.signum())?;
    damped(&about[first + 1..])
}

/// The series `h(t)` less its mean.
fn about_mean(series: &[(f64, f64)]) -> Vec<(f64, f64)> {
    let mean = series.iter().map(|p| p.1).sum::<f64>() / series.len().max(1) as f64;
    series.iter().map(|&(t, h)| (t, h - mean)).collect()
}

/// Where the record lies: `models/reference` beside the scenes folder `scenes`.
fn record_path(scenes: &Path) -> PathBuf {
    scenes.join("..").join("reference").join(RECORD)
}

impl SphinxsysWave {
    /// The record beside the scenes folder `scenes`: a header `time,height`, then one
    /// `t,h` pair per line.
    pub(crate) fn load(scenes: &Path) -> Result<Self> {
        let path = record_path(scenes);
        let text = std::fs::read_to_string(&path)
            .with_context(|| format!("reading SPHinXsys's probe record {}", path.display()))?;
        let mut lines = text.lines();
        if lines.next().map(str::trim) != Some("time,height") {
            return Err(anyhow!(
                "{}: the first line must be the header `time,height`",
                path.display()
            ));
        }
        let mut record = Vec::new();
        for (n, line) in lines.enumerate() {
            let pair = line.split_once(',').and_then(|(t, h)| {
                Some((t.trim().parse::<f64>().ok()?, h.trim().parse::<f64>().ok()?))
            });
            match pair {
                Some((t, h)) if t.is_finite() && h.is_finite() => record.push((t, h)),
                _ => {
                    return Err(anyhow!(
                        "{} line {}: `{line}` is not a pair of finite numbers `t,h`",
                        path.display(),
                        n + 2
                    ))
                }
            }
        }
        if fit(&record).is_none() {
            return Err(anyhow!(
                "{}: the record holds no oscillation to fit ({} samples)",
                path.display(),
                record.len()
            ));
        }
        Ok(SphinxsysWave { record })
    }

    /// granmix's gauge `probe` over the run: (time, depth).
    fn simulated(samples: &[Sample]) -> Vec<(f64, f64)> {
        samples
            .iter()
            .filter_map(|s| {
                let level = s.gauges.iter().find(|g| g.0 == GAUGE)?.1;
                Some((s.time, level))
            })
            .collect()
    }

    /// Both fits, their periods against linear theory and the score (the difference of
    /// the decrements), printed as a line and returned for the record.
    pub(crate) fn report(&self, samples: &[Sample]) -> Value {
        let theirs = fit(&self.record).expect("checked at load");
        let ours = fit(&Self::simulated(samples));
        let linear = linear_period();
        let Some(ours) = ours else {
            println!("{:<27} the gauge `{GAUGE}` holds no oscillation to fit", "");
            return json!({ "score": null, "sphinxsys_decrement": theirs.decrement() });
        };
        let score = (ours.decrement() - theirs.decrement()).abs();
        println!(
            "{:<27} log decrement {:.4} per period against SPHinXsys's {:.4} (difference {:.4}, \
             asked ≤ 0.01); period {:.4} s against {:.4} s ({:.4} s of linear theory)",
            "",
            ours.decrement(),
            theirs.decrement(),
            score,
            ours.period,
            theirs.period,
            linear
        );
        json!({
            "score": score,
            "decrement": ours.decrement(), "period_s": ours.period,
            "half_periods": ours.half_periods,
            "sphinxsys_decrement": theirs.decrement(), "sphinxsys_period_s": theirs.period,
            "period_linear_s": linear,
        })
    }

    /// Both heights about their means against time, in one panel.
    pub(crate) fn plot(&self, samples: &[Sample], png: &Path, title: &str) -> Result<()> {
        use crate::plot::{Curve, Panel};
        let curves = vec![
            Curve {
                label: "granmix, gauge at x = 1 m".into(),
                points: about_mean(&Self::simulated(samples)),
            },
            Curve {
                label: "SPHinXsys, probe at x = 1 m".into(),
                points: about_mean(&self.record),
            },
        ];
        let panel = Panel {
            title: "surface height at the centre antinode, about its mean".into(),
            ylabel: "η − η̄ [m]".into(),
            curves,
            include: Some((-0.1, 0.1)),
        };
        crate::plot::panels(png, title, "t [s]", &[panel])
    }
}

/// The period of the mode of linear theory, 2π/√(g k tanh kH) with k = π (a wavelength
/// of 2 m, the tank's length), H = 1 m: 1.134 s.
fn linear_period() -> f64 {
    let k = std::f64::consts::PI;
    2.0 * std::f64::consts::PI / (9.81 * k * (k * 1.0_f64).tanh()).sqrt()
}

#[cfg(test)]
mod tests {
    use super::*;

    fn scenes() -> PathBuf {
        Path::new(env!("CARGO_MANIFEST_DIR")).join("../models/scenes")
    }

    /// SPHinXsys's record, fitted as granmix's series is: a period of 1.148 s (1.2 %
    /// above linear theory) and a decrement of 0.016 per period, as a least-squares
    /// damped cosine over the same 10 s gives (0.0161; docs/method.md §Water).
    #[test]
    fn sphinxsys_record_decays_as_its_regression_data_say() {
        let w = SphinxsysWave::load(&scenes()).expect("the record in the tree");
        let f = fit(&w.record).expect("an oscillation");
        assert!((f.period - 1.148).abs() < 0.01, "period {}", f.period);
        assert!(
            (f.decrement() - 0.016).abs() < 0.004,
            "decrement {}",
            f.decrement()
        );
        assert!(
            (linear_period() - 1.134).abs() < 1e-3,
            "{}",
            linear_period()
        );
    }

    /// The fit reads a known damped cosine sampled as the record is (every 0.0987 s,
    /// starting at a trough): the period within 1 %, the decrement within 10 %.
    #[test]
    fn fit_recovers_a_damped_cosine() {
        let (period, delta) = (1.15, 0.05);
        let w = 2.0 * std::f64::consts::PI / period;
        let gamma = delta / period;
        let series: Vec<(f64, f64)> = (0..102)
            .map(|n| {
                let t = n as f64 * 0.0987;
                (t, 1.0 - 0.1 * (-gamma * t).exp() * (w * t).cos())
            })
            .collect();
        let f = fit(&series).expect("an oscillation");
        assert!((f.period / period - 1.0).abs() < 0.01, "{}", f.period);
        assert!(
            (f.decrement() / delta - 1.0).abs() < 0.1,
            "{}",
            f.decrement()
        );
    }

    /// A record that is not `time,height` pairs is refused with its file and line.
    #[test]
    fn a_broken_record_names_its_line() {
        let dir = std::env::temp_dir().join(format!("granmix-sphx-{}", std::process::id()));
        let scenes = dir.join("scenes");
        let rec = dir.join("reference/sphinxsys_standing_wave");
        std::fs::create_dir_all(&scenes).unwrap();
        std::fs::create_dir_all(&rec).unwrap();
        std::fs::write(rec.join("probe.csv"), "time,height\n0.0,0.89\n0.1,x\n").unwrap();
        let err = SphinxsysWave::load(&scenes)
            .err()
            .expect("refused")
            .to_string();
        assert!(err.contains("probe.csv line 3"), "{err}");
        std::fs::remove_dir_all(&dir).unwrap();
    }
}
