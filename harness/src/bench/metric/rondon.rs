//! The submerged collapses of Rondon, Pouliquen & Aussillous (2011) (issue 44, item 4):
//! the front and the basal excess pore pressure of `submerged_collapse_dense.toml` and
//! `submerged_collapse_loose.toml` against the digitised series of the experiment.
//!
//! L. Rondon, O. Pouliquen, P. Aussillous, "Granular collapse in a fluid: role of the
//! initial volume fraction", Phys. Fluids 23 (2011) 073301. The series are read where
//! they lie, in `shared/reference/rondon2011/` beside the project (or the directory
//! `GRANMIX_REFERENCE` names); nothing is copied.
//!
//! - front: the run-out from the left wall (`observe.runout_origin`), against the
//!   data at 2, 5 and 10 s (dense) or 1 and 2 s (loose), and at the data's last time
//!   (the final run-out); the score is the largest relative error of these;
//! - basal excess pore pressure: the mean of the probes `p2` and `p3` (2 and 3 cm from
//!   the wall, 1 mm above the floor) less the hydrostatic pressure below the fluid's
//!   surface at 8 cm (the scenes'); its extreme
//!   (the least for the dense column, the greatest for the loose one) against the
//!   data's, and whether it has relaxed to within a tenth of it by 30 s (dense) or
//!   20 s (loose).

use crate::bench::metric::lobovsky::Series;
use anyhow::Result;
use granmix_core::run::simulation::Sample;
use serde_json::{json, Value};
use std::path::Path;

/// The basal pressure probes, their height (m), the fluid's surface (m) and density
/// (kg/m³) in both scenes, and gravity.
const PROBES: [&str; 2] = ["p2", "p3"];
const PROBE_Y: f64 = 0.001;
const SURFACE: f64 = 0.08;
const RHO_F: f64 = 1010.0;
const G: f64 = 9.81;

/// Which of the two columns.
#[derive(Clone, Copy, Debug, PartialEq)]
pub(crate) enum Column {
    /// φ0 ≈ 0.60, H0 = 4.2 cm: creeps, negative excess pressure.
    Dense,
    /// φ0 ≈ 0.55, H0 = 4.8 cm: runs, positive excess pressure.
    Loose,
}

impl Column {
    fn name(self) -> &'static str {
        match self {
            Column::Dense => "dense",
            Column::Loose => "loose",
        }
    }

    /// The times (s) at which the front is compared.
    fn checkpoints(self) -> &'static [f64] {
        match self {
            Column::Dense => &[2.0, 5.0, 10.0],
            Column::Loose => &[1.0, 2.0],
        }
    }

    /// By when (s) the excess pressure should have relaxed to a tenth of its extreme.
    fn relaxed_by(self) -> f64 {
        match self {
            Column::Dense => 30.0,
            Column::Loose => 20.0,
        }
    }

    /// The extreme of a pressure series: its least (dense) or greatest (loose) value.
    fn extreme(self, v: &[f64]) -> Option<f64> {
        let it = v.iter().copied();
        match self {
            Column::Dense => it.reduce(f64::min),
            Column::Loose => it.reduce(f64::max),
        }
    }
}

/// The experiment's series of one column: front (cm) and basal excess pressure (Pa)
/// against time (s).
pub(crate) struct Rondon {
    column: Column,
    front: Series,
    pressure: Series,
}

impl Rondon {
    /// Read `dir`/rondon2011/{dense,loose}_{front,pressure}.tsv.
    pub(crate) fn load(dir: &Path, column: Column) -> Result<Self> {
        let d = dir.join("rondon2011");
        let read = |what: &str| Series::read(&d.join(format!("{}_{what}.tsv", column.name())));
        Ok(Rondon {
            column,
            front: read("front")?,
            pressure: read("pressure")?,
        })
    }

    /// The run's front (cm) and basal excess pressure (Pa) against time.
    fn simulated(samples: &[Sample]) -> (Series, Series) {
        let (mut front, mut pressure) = (Series::default(), Series::default());
        let hydrostatic = RHO_F * G * (SURFACE - PROBE_Y);
        for s in samples {
            front.t.push(s.time);
            front.v.push(100.0 * s.runout);
            let p: Vec<f64> = PROBES
                .iter()
                .filter_map(|n| {
                    s.probes
                        .iter()
                        .find(|(name, _)| name == n)?
                        .1
                        .water_pressure
                })
                .collect();
            if p.len() == PROBES.len() {
                pressure.t.push(s.time);
                pressure
                    .v
                    .push(p.iter().sum::<f64>() / p.len() as f64 - hydrostatic);
            }
        }
        (front, pressure)
    }

    /// The comparison of a run (see the module's notes); `score` is the largest
    /// relative front error, None if the run ended before a checkpoint.
    pub(crate) fn report(&self, samples: &[Sample]) -> Value {
        let (front, pressure) = Self::simulated(samples);
        let end = front.t.last().copied().unwrap_or(0.0);
        let last = *self.front.t.last().unwrap_or(&0.0);
        let mut score: Option<f64> = Some(0.0);
        let mut fronts = Vec::new();
        for &t in self
            .column
            .checkpoints()
            .iter()
            .chain(std::iter::once(&last))
        {
            let (sim, data) = (front.at(t), self.front.at(t));
            let err = (end >= t).then(|| (sim - data).abs() / data);
            score = score.zip(err).map(|(a, b)| a.max(b));
            fronts.push(json!({"t": t, "front_cm": sim, "front_data_cm": data, "rel_error": err}));
        }
        let ext = self.column.extreme(&pressure.v);
        let ext_data = self.column.extreme(&self.pressure.v);
        let when = |s: &Series, e: Option<f64>| {
            e.and_then(|e| s.v.iter().position(|&v| v == e).map(|k| s.t[k]))
        };
        let by = self.column.relaxed_by();
        let relaxed = ext
            .filter(|_| end >= by)
            .map(|e| pressure.at(by).abs() <= 0.1 * e.abs());
        json!({
            "column": self.column.name(),
            "score": score,
            "fronts": fronts,
            "pressure_extreme_pa": ext, "pressure_extreme_at_s": when(&pressure, ext),
            "pressure_extreme_data_pa": ext_data,
            "pressure_extreme_data_at_s": when(&self.pressure, ext_data),
            "pressure_sign_right": ext.zip(ext_data).map(|(a, b)| a * b > 0.0),
            "pressure_rel_error": ext.zip(ext_data).map(|(a, b)| (a - b).abs() / b.abs()),
            "relaxed_by_s": by, "relaxed": relaxed,
        })
    }

    /// The figure: the front and the basal excess pressure against the data.
    pub(crate) fn plot(&self, samples: &[Sample], png: &Path, title: &str) -> Result<()> {
        use crate::plot::{Curve, Panel};
        let (front, pressure) = Self::simulated(samples);
        let pts = |s: &Series| -> Vec<(f64, f64)> {
            s.t.iter().copied().zip(s.v.iter().copied()).collect()
        };
        let panel = |name: &str, unit: &str, ours: &Series, data: &Series| Panel {
            title: name.into(),
            ylabel: unit.into(),
            curves: vec![
                Curve {
                    label: "granmix".into(),
                    points: pts(ours),
                },
                Curve {
                    label: "Rondon et al. (2011)".into(),
                    points: pts(data),
                },
            ],
            include: Some((0.0, 0.0)),
        };
        let panels = [
            panel("front from the left wall", "cm", &front, &self.front),
            panel(
                "basal excess pore pressure",
                "Pa",
                &pressure,
                &self.pressure,
            ),
        ];
        crate::plot::panels(png, title, "t (s)", &panels)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The extremes and checkpoints of each column.
    #[test]
    fn columns_pick_their_extreme() {
        let v = [-10.0, -126.0, 3.0, 144.0];
        assert_eq!(Column::Dense.extreme(&v), Some(-126.0));
        assert_eq!(Column::Loose.extreme(&v), Some(144.0));
        assert_eq!(Column::Dense.extreme(&[]), None);
        assert_eq!(Column::Dense.checkpoints(), &[2.0, 5.0, 10.0]);
        assert_eq!(Column::Loose.relaxed_by(), 20.0);
    }
}
