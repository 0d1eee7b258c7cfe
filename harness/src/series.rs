//! The CSV time series: one column per observable of the scene
//! ([`observables`], written once in core with its name and unit, so the header and
//! the rows come from the same table). Each column is named `name [unit]` (no bracket
//! where dimensionless). Counts (steps, κ, contacts, water particles) are written as
//! integers, everything else as `{:.9e}`; a value that does not exist in a sample (the
//! front of water that has all left) as an empty cell. docs/scenes.md lists every
//! column with its definition.

use granmix_core::run::observables::{observables, Cell, Observable};
pub use granmix_core::run::observables::{total_kinetic_energy, Layout, Unit};
use granmix_core::run::simulation::Sample;
use granmix_core::AnySimulation;
use granmix_ipc::{Sink, SinkError};
use std::io::Write;

/// A cell as the CSV writes it.
fn text(c: Cell) -> String {
    match c {
        Cell::Real(v) => format!("{v:.9e}"),
        Cell::Count(n) => n.to_string(),
        Cell::Empty => String::new(),
    }
}

/// A CSV file written row by row.
pub struct CsvSeries {
    out: std::io::BufWriter<std::fs::File>,
    table: Vec<Observable>,
}

impl CsvSeries {
    /// A series of samples of a scene with this layout.
    pub fn create(path: &std::path::Path, layout: Layout) -> std::io::Result<Self> {
        let mut out = std::io::BufWriter::new(std::fs::File::create(path)?);
        let table = observables(&layout);
        let names: Vec<String> = table.iter().map(|c| c.heading(layout.dim)).collect();
        writeln!(out, "{}", names.join(","))?;
        Ok(CsvSeries { out, table })
    }
    /// One row: the value of every column in sample `s`.
    pub fn write(&mut self, s: &Sample) -> std::io::Result<()> {
        let line: Vec<String> = self.table.iter().map(|o| text(o.value(s))).collect();
        writeln!(self.out, "{}", line.join(","))?;
        self.out.flush()
    }
}

impl Sink for CsvSeries {
    fn name(&self) -> &str {
        "series.csv"
    }
    fn sample(&mut self, _sim: &AnySimulation, s: &Sample) -> Result<(), SinkError> {
        self.write(s).map_err(|e| SinkError::new("series.csv", e))
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use granmix_core::run::observables::row;
    use granmix_core::run::sample::{BarrierSample, WaterSample};

    fn layout(dim: usize, water: bool) -> Layout {
        Layout {
            dim,
            fine: true,
            water,
            barriers: vec![("barrier".into(), vec![3])],
            probes: vec!["p".into()],
            gauges: vec!["g".into()],
            bodies: vec!["b".into()],
            sleep: false,
        }
    }

    fn sample(water: bool) -> Sample {
        Sample {
            steps: 270,
            kappa: 4,
            barriers: vec![BarrierSample {
                panels: vec![[1.0; 3]; 3],
                ..Default::default()
            }],
            probes: vec![("p".into(), Default::default())],
            gauges: vec![("g".into(), 0.1)],
            bodies: vec![Default::default()],
            water: water.then(WaterSample::default),
            ..Default::default()
        }
    }

    /// Every column reads its own value, in 2D and 3D, with and without water.
    #[test]
    fn each_column_reads_its_value() {
        for dim in [2, 3] {
            for water in [false, true] {
                let l = layout(dim, water);
                let mut s = sample(water);
                s.barriers[0].force = [1.5, -2.5, 3.5];
                s.barriers[0].panels[2] = [0.25, 0.5, 0.75];
                s.bodies[0].contacts = 7;
                s.bodies[0].torque = [0.0, 0.0, -4.0];
                s.gauges[0].1 = 0.125;
                let table = observables(&l);
                let cells = row(&table, &s);
                let at = |name: &str| {
                    let k = table.iter().position(|o| o.name == name).expect(name);
                    cells[k]
                };
                assert_eq!(at("barrier.force.y"), Cell::Real(-2.5), "dim {dim}");
                assert_eq!(at("barrier.panel_2.force.x"), Cell::Real(0.25));
                assert_eq!(at("b.contacts"), Cell::Count(7));
                assert_eq!(at("b.torque.z"), Cell::Real(-4.0));
                assert_eq!(at("g.level"), Cell::Real(0.125));
                assert_eq!(at("steps"), Cell::Count(270));
            }
        }
    }

    /// Issue 39: declared panels appear as columns, loads carry units, counts are integers.
    #[test]
    fn issue_39_panels_units_and_integers() {
        let l = layout(2, true);
        let names: Vec<String> = observables(&l).iter().map(|c| c.heading(2)).collect();
        for n in [
            "barrier.force.x [N/m]",
            "barrier.moment.z [N]",
            "barrier.panel_2.force_water.y [N/m]",
            "barrier.panel_0.force.x [N/m]",
            "steps",
            "kappa",
            "time [s]",
            "kinetic_energy_total [J/m]",
        ] {
            assert!(names.iter().any(|c| c == n), "no column `{n}` in {names:?}");
        }
        let h3: Vec<String> = observables(&layout(3, false))
            .iter()
            .map(|c| c.heading(3))
            .collect();
        assert!(h3.iter().any(|c| c == "barrier.force.z [N]"));
        let cells = row(&observables(&l), &sample(true));
        assert_eq!(text(cells[1]), "270");
    }
}
