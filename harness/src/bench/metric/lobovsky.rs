//! The dam break of Lobovský et al. (2014), H = 0.3 m (issue 42): the water levels at
//! the four stations H1–H4 and the pressures of sensors 1–4 on the opposite wall of
//! `lobovsky_dam_break.toml`, against the digitised series of the experiment.
//!
//! L. Lobovský, E. Botia-Vera, F. Castellana, J. Mas-Soler, A. Souto-Iglesias,
//! "Experimental investigation of dynamic pressure loads during dam break", J. Fluids
//! Struct. 48 (2014) 407–434, Figs. 16 (levels) and 18 (pressures, one impact event).
//! The files are read where they lie, in `shared/reference/lobovsky2014/` beside the
//! project (or the directory `GRANMIX_REFERENCE` names); nothing is copied.
//!
//! Time is t* = t √(g/H), levels h/H, pressures p/(ρ g H).
//! - levels: the RMS difference over t* ≤ 6 against the mean of the experiment's
//!   records at each station; the score is the largest of the four;
//! - sensor 1's arrival: the first t* at which p/(ρgH) reaches 0.1, in both;
//! - each sensor's mean pressure over 3 ≤ t* ≤ 6 and its peak, beside the data's.

use anyhow::{anyhow, Context, Result};
use granmix_core::run::simulation::Sample;
use serde_json::{json, Value};
use std::path::{Path, PathBuf};

/// Column height H (m), gravity and density of the experiment.
pub(crate) const H: f64 = 0.3;
const G: f64 = 9.81;
const RHO: f64 = 1000.0;
/// The level comparison ends here (t*).
const LEVELS_UNTIL: f64 = 6.0;
/// Sensor 1 has arrived when p/(ρgH) first reaches this.
const ARRIVAL: f64 = 0.1;
/// The window of the mean pressure (t*).
const MEAN_WINDOW: (f64, f64) = (3.0, 6.0);

/// The stations: gauge name and the records of its level (Fig. 16).
const LEVELS: [(&str, &[&str]); 4] = [
    ("H1", &["Fig16_WaterLevels_H1_2.dat"]),
    (
        "H2",
        &["Fig16_WaterLevels_H2_3.dat", "Fig16_WaterLevels_H2_4.dat"],
    ),
    (
        "H3",
        &["Fig16_WaterLevels_H3_3.dat", "Fig16_WaterLevels_H3_4.dat"],
    ),
    (
        "H4",
        &["Fig16_WaterLevels_H4_4.dat", "Fig16_WaterLevels_H4_5.dat"],
    ),
];

/// The sensors: probe name, height (mm) and its record (Fig. 18; the README of the
/// data maps the file numbers to the sensors).
const SENSORS: [(&str, f64, &str); 4] = [
    ("sensor1", 3.0, "Fig18_peak_event_5_sensors_5.dat"),
    ("sensor2", 15.0, "Fig18_peak_event_5_sensors_4.dat"),
    ("sensor3", 30.0, "Fig18_peak_event_5_sensors_2.dat"),
    ("sensor4", 80.0, "Fig18_peak_event_5_sensors_1.dat"),
];

/// A digitised series (t*, value).
#[derive(Clone, Debug, Default)]
pub(crate) struct Series {
    pub(crate) t: Vec<f64>,
    pub(crate) v: Vec<f64>,
}

impl Series {
    /// Two whitespace-separated columns; lines starting with `#` are comments, and a
    /// first line of column names (`time\tlength`) is a header.
    pub(crate) fn read(path: &Path) -> Result<Series> {
        let text = std::fs::read_to_string(path)
            .with_context(|| format!("reading the reference series {}", path.display()))?;
        let mut s = Series::default();
        for (n, line) in text.lines().enumerate() {
            let line = line.trim();
            if line.is_empty() || line.starts_with('#') {
                continue;
            }
            let mut it = line.split_whitespace().map(str::parse::<f64>);
            match (it.next(), it.next()) {
                (Some(Ok(t)), Some(Ok(v))) => {
                    s.t.push(t);
                    s.v.push(v);
                }
                _ if n == 0 && !line.starts_with(|c: char| c.is_ascii_digit() || c == '-') => {}
                _ => {
                    return Err(anyhow!(
                        "{}:{}: expected two numbers, found {line:?}",
                        path.display(),
                        n + 1
                    ))
                }
            }
        }
        Ok(s)
    }

    /// Linear interpolation at `t` (the end values outside).
    pub(crate) fn at(&self, t: f64) -> f64 {
        let k = self.t.partition_point(|&x| x < t);
        if k == 0 {
            return self.v[0];
        }
        if k == self.t.len() {
            return self.v[k - 1];
        }
        let (t0, t1) = (self.t[k - 1], self.t[k]);
        let f = if t1 > t0 { (t - t0) / (t1 - t0) } else { 0.0 };
        self.v[k - 1] + f * (self.v[k] - self.v[k - 1])
    }

    /// The first t* at which the value reaches `level`.
    fn first_reaching(&self, level: f64) -> Option<f64> {
        let k = self.v.iter().position(|&v| v >= level)?;
        if k == 0 {
            return Some(self.t[0]);
        }
        let (v0, v1) = (self.v[k - 1], self.v[k]);
        Some(self.t[k - 1] + (level - v0) / (v1 - v0) * (self.t[k] - self.t[k - 1]))
    }

    /// The mean over `lo ≤ t* ≤ hi` (trapezoidal in time).
    fn mean(&self, (lo, hi): (f64, f64)) -> Option<f64> {
        let mut area = 0.0;
        for k in 1..self.t.len() {
            let (a, b) = (self.t[k - 1].max(lo), self.t[k].min(hi));
            if b > a {
                area += (b - a) * 0.5 * (self.at(a) + self.at(b));
            }
        }
        (self.t.first()? <= &lo && self.t.last()? >= &hi).then(|| area / (hi - lo))
    }

    fn peak(&self) -> f64 {
        self.v.iter().copied().fold(f64::NEG_INFINITY, f64::max)
    }
}

/// Series by name (a gauge's or a probe's).
type Named = Vec<(String, Series)>;

/// The experiment's series: each station's records and each sensor's.
pub(crate) struct Lobovsky {
    pub(crate) levels: Vec<(&'static str, Vec<Series>)>,
    pub(crate) pressures: Vec<(&'static str, f64, Series)>,
}

/// Where the reference data lie: `GRANMIX_REFERENCE`, else `shared/reference` beside
/// the working directory's project or beside the project of `scenes`; the first of
/// these that holds the experiment's folder `set` (e.g. `lobovsky2014`).
pub(crate) fn reference_dir(scenes: &Path, set: &str) -> Result<PathBuf> {
    let mut tried = Vec::new();
    let mut candidates: Vec<PathBuf> = Vec::new();
    if let Some(d) = std::env::var_os("GRANMIX_REFERENCE") {
        candidates.push(PathBuf::from(d));
    }
    candidates.push(PathBuf::from("../shared/reference"));
    if let Ok(s) = scenes.canonicalize() {
        // <project>/models/scenes → <project>/../shared/reference
        if let Some(p) = s.parent().and_then(Path::parent).and_then(Path::parent) {
            candidates.push(p.join("shared/reference"));
        }
    }
    for c in candidates {
        if c.join(set).is_dir() {
            return Ok(c);
        }
        tried.push(c.display().to_string());
    }
    Err(anyhow!(
        "the experiments' reference data ({set}/) are not in {}: set \
         GRANMIX_REFERENCE to the directory that holds them",
        tried.join(", ")
    ))
}

impl Lobovsky {
    /// Read the series from `dir`/lobovsky2014.
    pub(crate) fn load(dir: &Path) -> Result<Self> {
        let d = dir.join("lobovsky2014");
        let levels = LEVELS
            .iter()
            .map(|(name, files)| {
                let s = files
                    .iter()
                    .map(|f| Series::read(&d.join(f)))
                    .collect::<Result<Vec<_>>>()?;
                Ok((*name, s))
            })
            .collect::<Result<Vec<_>>>()?;
        let pressures = SENSORS
            .iter()
            .map(|(name, y, f)| Ok((*name, *y, Series::read(&d.join(f))?)))
            .collect::<Result<Vec<_>>>()?;
        Ok(Lobovsky { levels, pressures })
    }

    /// The run's level at gauge `name` (h/H) and pressure at probe `name` (p/ρgH)
    /// against t*.
    fn simulated(samples: &[Sample]) -> (Named, Named) {
        let ts = (G / H).sqrt();
        let mut levels: Named = Vec::new();
        let mut pressures: Named = Vec::new();
        for s in samples {
            for (k, (name, d)) in s.gauges.iter().enumerate() {
                if levels.len() <= k {
                    levels.push((name.clone(), Series::default()));
                }
                levels[k].1.t.push(s.time * ts);
                levels[k].1.v.push(d / H);
            }
            for (k, (name, p)) in s.probes.iter().enumerate() {
                if pressures.len() <= k {
                    pressures.push((name.clone(), Series::default()));
                }
                pressures[k].1.t.push(s.time * ts);
                pressures[k]
                    .1
                    .v
                    .push(p.water_pressure.unwrap_or(0.0) / (RHO * G * H));
            }
        }
        (levels, pressures)
    }

    /// The comparison of a run: per station the RMS over t* ≤ 6 against the mean of
    /// its records, per sensor the mean over 3 ≤ t* ≤ 6 and the peak, sensor 1's
    /// arrival; `score` is the largest level RMS (None if a gauge is missing).
    pub(crate) fn report(&self, samples: &[Sample]) -> Value {
        let (levels, pressures) = Self::simulated(samples);
        let find = |v: &[(String, Series)], n: &str| {
            v.iter().find(|(name, _)| name == n).map(|(_, s)| s.clone())
        };
        let mut stations = Vec::new();
        let mut score: Option<f64> = Some(0.0);
        for (name, records) in &self.levels {
            let Some(sim) = find(&levels, name).filter(|s| !s.t.is_empty()) else {
                score = None;
                continue;
            };
            let base = &records[0];
            let (mut sum, mut n) = (0.0, 0);
            for &t in base.t.iter().filter(|&&t| t <= LEVELS_UNTIL) {
                if t > *sim.t.last().unwrap() {
                    break;
                }
                let data = records.iter().map(|r| r.at(t)).sum::<f64>() / records.len() as f64;
                sum += (sim.at(t) - data).powi(2);
                n += 1;
            }
            let rms = (n > 0).then(|| (sum / n as f64).sqrt());
            score = score.zip(rms).map(|(a, b)| a.max(b));
            stations.push(json!({"gauge": name, "rms": rms, "records": records.len()}));
        }
        let mut sensors = Vec::new();
        for (name, y, data) in &self.pressures {
            let sim = find(&pressures, name).unwrap_or_default();
            let (ms, md) = (sim.mean(MEAN_WINDOW), data.mean(MEAN_WINDOW));
            sensors.push(json!({
                "sensor": name, "height_mm": y,
                "mean": ms, "mean_data": md,
                "mean_rel_error": ms.zip(md).map(|(a, b)| (a - b) / b),
                "peak": (!sim.t.is_empty()).then(|| sim.peak()), "peak_data": data.peak(),
                "arrival": sim.first_reaching(ARRIVAL),
                "arrival_data": data.first_reaching(ARRIVAL),
            }));
        }
        json!({"score": score, "stations": stations, "sensors": sensors})
    }

    /// The figure: the four levels and the four pressures against the data.
    pub(crate) fn plot(&self, samples: &[Sample], png: &Path, title: &str) -> Result<()> {
        use crate::plot::{Curve, Panel};
        let (levels, pressures) = Self::simulated(samples);
        let pts = |s: &Series, until: f64| -> Vec<(f64, f64)> {
            s.t.iter()
                .zip(&s.v)
                .filter(|(t, _)| **t <= until)
                .map(|(t, v)| (*t, *v))
                .collect()
        };
        let until = levels
            .iter()
            .chain(&pressures)
            .filter_map(|(_, s)| s.t.last().copied())
            .fold(0.0, f64::max);
        let ours = |named: &Named, name: &str| -> Vec<Curve> {
            named
                .iter()
                .filter(|(n, _)| n == name)
                .map(|(_, s)| Curve {
                    label: "granmix".into(),
                    points: pts(s, until),
                })
                .collect()
        };
        let mut panels = Vec::new();
        for (name, records) in &self.levels {
            // granmix first: the same colour in every panel
            let mut curves = ours(&levels, name);
            curves.extend(records.iter().enumerate().map(|(k, r)| Curve {
                label: format!("experiment, record {}", k + 1),
                points: pts(r, until),
            }));
            panels.push(Panel {
                title: format!("water level at {name}"),
                ylabel: "h/H".into(),
                curves,
                include: Some((0.0, 0.5)),
            });
        }
        for (name, y, data) in &self.pressures {
            let mut curves = ours(&pressures, name);
            curves.push(Curve {
                label: "experiment (one impact)".into(),
                points: pts(data, until),
            });
            panels.push(Panel {
                title: format!("pressure, {name} (y = {y} mm)"),
                ylabel: "p/(ρgH)".into(),
                curves,
                include: Some((0.0, 1.0)),
            });
        }
        crate::plot::panels(png, title, "t √(g/H)", &panels)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The interpolation, the first crossing and the windowed mean of a ramp v = t.
    #[test]
    fn series_of_a_ramp() {
        let s = Series {
            t: vec![0.0, 1.0, 2.0, 4.0],
            v: vec![0.0, 1.0, 2.0, 4.0],
        };
        assert_eq!(s.at(1.5), 1.5);
        assert_eq!(s.at(9.0), 4.0);
        assert!((s.first_reaching(2.5).unwrap() - 2.5).abs() < 1e-12);
        assert!((s.mean((1.0, 3.0)).unwrap() - 2.0).abs() < 1e-12);
        assert_eq!(s.mean((1.0, 5.0)), None);
    }
}
