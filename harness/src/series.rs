//! The CSV time series: energies, run-out, speed, barrier loads and probes.

use granmix_core::simulation::Sample;
use std::io::Write;

const AX: [&str; 3] = ["x", "y", "z"];
const SIG: [&str; 6] = ["xx", "yy", "zz", "xy", "xz", "yz"];

/// Column names for a scene of dimension `dim`.
pub fn header(dim: usize, barriers: &[String], probes: &[String]) -> Vec<String> {
    let mut h: Vec<String> = [
        "time",
        "steps",
        "dt",
        "kinetic_energy",
        "potential_energy",
        "runout",
        "max_speed",
    ]
    .iter()
    .map(|s| s.to_string())
    .collect();
    for b in barriers {
        for a in AX.iter().take(dim) {
            h.push(format!("{b}.force.{a}"));
        }
        if dim == 2 {
            h.push(format!("{b}.moment.z"));
        } else {
            for a in AX {
                h.push(format!("{b}.moment.{a}"));
            }
        }
        h.push(format!("{b}.peak_force"));
    }
    for p in probes {
        for s in SIG.iter().take(if dim == 2 { 4 } else { 6 }) {
            h.push(format!("{p}.sigma_{s}"));
        }
        h.push(format!("{p}.pressure"));
        for a in AX.iter().take(dim) {
            h.push(format!("{p}.velocity.{a}"));
        }
    }
    h
}

/// Values of one row, matching [`header`].
pub fn row(dim: usize, s: &Sample) -> Vec<f64> {
    let mut r = vec![
        s.time,
        s.steps as f64,
        s.dt,
        s.kinetic_energy,
        s.potential_energy,
        s.runout,
        s.max_speed,
    ];
    for b in &s.barriers {
        r.extend_from_slice(&b.force[..dim]);
        if dim == 2 {
            r.push(b.moment[2]);
        } else {
            r.extend_from_slice(&b.moment);
        }
        r.push(b.peak_force);
    }
    for (_, p) in &s.probes {
        r.extend_from_slice(&p.stress.0[..if dim == 2 { 4 } else { 6 }]);
        r.push(-p.stress.trace() / 3.0);
        r.extend_from_slice(&p.velocity[..dim]);
    }
    r
}

/// A CSV file written row by row.
pub struct CsvSeries {
    out: std::io::BufWriter<std::fs::File>,
}

impl CsvSeries {
    pub fn create(path: &std::path::Path, header: Vec<String>) -> std::io::Result<Self> {
        let mut out = std::io::BufWriter::new(std::fs::File::create(path)?);
        writeln!(out, "{}", header.join(","))?;
        Ok(CsvSeries { out })
    }
    pub fn write(&mut self, values: &[f64]) -> std::io::Result<()> {
        let line: Vec<String> = values.iter().map(|v| format!("{v:.9e}")).collect();
        writeln!(self.out, "{}", line.join(","))?;
        self.out.flush()
    }
}
