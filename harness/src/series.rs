//! The CSV time series: energies, run-out, speed, barrier loads and probes.

use granmix_core::simulation::Sample;
use granmix_core::AnySimulation;
use granmix_ipc::{Sink, SinkError};
use std::io::Write;

const AX: [&str; 3] = ["x", "y", "z"];
const SIG: [&str; 6] = ["xx", "yy", "zz", "xy", "xz", "yz"];

/// Column names for a scene of dimension `dim`.
pub fn header(
    dim: usize,
    barriers: &[String],
    probes: &[String],
    bodies: &[String],
    water: bool,
) -> Vec<String> {
    let body_forces: &[&str] = if water {
        &["force", "fine_force", "water_force"]
    } else {
        &["force", "fine_force"]
    };
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
    if !bodies.is_empty() {
        for c in [
            "kinetic_energy_coarse",
            "potential_energy_coarse",
            "strain_energy",
            "contact_energy",
            "steps_coarse",
            "kappa",
        ] {
            h.push(c.to_string());
        }
        for a in AX.iter().take(dim) {
            h.push(format!("momentum.{a}"));
        }
    }
    if water {
        for c in [
            "water.kinetic_energy",
            "water.potential_energy",
            "water.front",
            "water.max_speed",
        ] {
            h.push(c.to_string());
        }
    }
    for b in barriers {
        for a in AX.iter().take(dim) {
            h.push(format!("{b}.force.{a}"));
        }
        if water {
            for q in ["force_water", "force_grains"] {
                for a in AX.iter().take(dim) {
                    h.push(format!("{b}.{q}.{a}"));
                }
            }
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
        if water {
            h.push(format!("{p}.water_pressure"));
            for a in AX.iter().take(dim) {
                h.push(format!("{p}.water_velocity.{a}"));
            }
        }
    }
    for b in bodies {
        for q in ["position", "velocity"] {
            for a in AX.iter().take(dim) {
                h.push(format!("{b}.{q}.{a}"));
            }
        }
        for q in ["w", "x", "y", "z"] {
            h.push(format!("{b}.orientation.{q}"));
        }
        rot_cols(&mut h, dim, b, "angular_velocity");
        for q in body_forces {
            for a in AX.iter().take(dim) {
                h.push(format!("{b}.{q}.{a}"));
            }
        }
        rot_cols(&mut h, dim, b, "torque");
        h.push(format!("{b}.contacts"));
    }
    h
}

/// Rotational columns: z only in 2D.
fn rot_cols(h: &mut Vec<String>, dim: usize, b: &str, q: &str) {
    if dim == 2 {
        h.push(format!("{b}.{q}.z"));
    } else {
        for a in AX {
            h.push(format!("{b}.{q}.{a}"));
        }
    }
}

fn rot_vals(r: &mut Vec<f64>, dim: usize, v: &[f64; 3]) {
    if dim == 2 {
        r.push(v[2]);
    } else {
        r.extend_from_slice(v);
    }
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
    if !s.bodies.is_empty() {
        r.extend_from_slice(&[
            s.coarse_kinetic_energy,
            s.coarse_potential_energy,
            s.strain_energy,
            s.contact_energy,
            s.steps_coarse as f64,
            s.kappa as f64,
        ]);
        r.extend_from_slice(&s.momentum[..dim]);
    }
    if let Some(w) = &s.water {
        // no front without water: an empty cell
        let front = w.front.unwrap_or(f64::NAN);
        r.extend_from_slice(&[w.kinetic_energy, w.potential_energy, front, w.max_speed]);
    }
    for b in &s.barriers {
        r.extend_from_slice(&b.force[..dim]);
        if s.water.is_some() {
            r.extend_from_slice(&b.force_water[..dim]);
            for a in 0..dim {
                r.push(b.force[a] - b.force_water[a]);
            }
        }
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
        if s.water.is_some() {
            // gauge pressure: 0 where no water reaches the probe
            r.push(p.water_pressure.unwrap_or(0.0));
            r.extend_from_slice(&p.water_velocity.unwrap_or_default()[..dim]);
        }
    }
    for b in &s.bodies {
        r.extend_from_slice(&b.position[..dim]);
        r.extend_from_slice(&b.velocity[..dim]);
        r.extend_from_slice(&b.orientation);
        rot_vals(&mut r, dim, &b.angular_velocity);
        r.extend_from_slice(&b.force[..dim]);
        r.extend_from_slice(&b.fine_force[..dim]);
        if s.water.is_some() {
            r.extend_from_slice(&b.water_force[..dim]);
        }
        rot_vals(&mut r, dim, &b.torque);
        r.push(b.contacts as f64);
    }
    r
}

/// A CSV file written row by row.
pub struct CsvSeries {
    out: std::io::BufWriter<std::fs::File>,
    /// The scene's dimension (columns per vector).
    dim: usize,
}

impl CsvSeries {
    /// A series of `dim`-dimensional samples with columns `header`.
    pub fn create(
        path: &std::path::Path,
        dim: usize,
        header: Vec<String>,
    ) -> std::io::Result<Self> {
        let mut out = std::io::BufWriter::new(std::fs::File::create(path)?);
        writeln!(out, "{}", header.join(","))?;
        Ok(CsvSeries { out, dim })
    }
    /// Write one row; a value that does not exist (NaN, e.g. the front of no water)
    /// is an empty cell.
    pub fn write(&mut self, values: &[f64]) -> std::io::Result<()> {
        let line: Vec<String> = values
            .iter()
            .map(|v| {
                if v.is_nan() {
                    String::new()
                } else {
                    format!("{v:.9e}")
                }
            })
            .collect();
        writeln!(self.out, "{}", line.join(","))?;
        self.out.flush()
    }
}

impl Sink for CsvSeries {
    fn name(&self) -> &str {
        "series.csv"
    }
    fn sample(&mut self, _sim: &AnySimulation, s: &Sample) -> Result<(), SinkError> {
        self.write(&row(self.dim, s))
            .map_err(|e| SinkError::new("series.csv", e))
    }
}
