//! The CSV time series: energies, run-out, speeds, barrier and panel loads, probes and
//! bodies. Each column is named `name [unit]` (no bracket where dimensionless); the
//! units of loads and energies follow the dimension (per metre of width in 2D).
//! Counts (steps, κ, contacts, water particles) are written as integers, everything
//! else as `{:.9e}`. docs/scenes.md lists every column with its definition.

use granmix_core::run::sample;
use granmix_core::run::simulation::Sample;
use granmix_core::AnySimulation;
use granmix_ipc::{Sink, SinkError};
use std::io::Write;

const AX: [&str; 3] = ["x", "y", "z"];
const SIG: [&str; 6] = ["xx", "yy", "zz", "xy", "xz", "yz"];

/// Which families and objects a scene has: what the columns are built from.
#[derive(Clone, Debug, Default)]
pub struct Layout {
    pub dim: usize,
    /// The scene has fine grains (soil).
    pub fine: bool,
    /// The scene has `[water]`.
    pub water: bool,
    /// Barrier names with their panel counts (empty: one panel, no panel columns).
    pub barriers: Vec<(String, Vec<usize>)>,
    pub probes: Vec<String>,
    pub gauges: Vec<String>,
    pub bodies: Vec<String>,
}

impl Layout {
    /// The layout of a built simulation.
    pub fn of(sim: &AnySimulation) -> Self {
        Layout {
            dim: sim.dimension(),
            fine: sim.fine_count() > 0,
            water: sim.has_water(),
            barriers: sim
                .barrier_names()
                .into_iter()
                .zip(sim.barrier_panels())
                .collect(),
            probes: sim.probe_names(),
            gauges: sim.gauge_names(),
            bodies: sim.body_names(),
        }
    }
    /// Grains (fine or coarse) whose deposit has a run-out.
    fn grains(&self) -> bool {
        self.fine || !self.bodies.is_empty()
    }
}

/// A physical unit that depends on the dimension.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Unit {
    /// N/m in 2D (per metre of width), N in 3D.
    Force,
    /// N·m/m = N in 2D, N·m in 3D.
    Moment,
    /// J/m in 2D, J in 3D.
    Energy,
    /// N·s/m in 2D, N·s in 3D.
    Momentum,
    /// The same in 2D and 3D; "" is dimensionless.
    Fixed(&'static str),
}

impl Unit {
    /// The unit's symbol in a `dim`-dimensional scene ("" when dimensionless).
    pub fn symbol(self, dim: usize) -> &'static str {
        let two = dim == 2;
        match self {
            Unit::Force => {
                if two {
                    "N/m"
                } else {
                    "N"
                }
            }
            Unit::Moment => {
                if two {
                    "N"
                } else {
                    "N m"
                }
            }
            Unit::Energy => {
                if two {
                    "J/m"
                } else {
                    "J"
                }
            }
            Unit::Momentum => {
                if two {
                    "N s/m"
                } else {
                    "N s"
                }
            }
            Unit::Fixed(u) => u,
        }
    }
}

/// One column: its name, its unit and whether it holds a count.
#[derive(Clone, Debug, PartialEq)]
pub struct Column {
    pub name: String,
    pub unit: Unit,
    pub integer: bool,
}

impl Column {
    fn real(name: impl Into<String>, unit: Unit) -> Self {
        Column {
            name: name.into(),
            unit,
            integer: false,
        }
    }
    fn count(name: impl Into<String>) -> Self {
        Column {
            name: name.into(),
            unit: Unit::Fixed(""),
            integer: true,
        }
    }
    /// `name [unit]`, or the name alone where dimensionless.
    pub fn heading(&self, dim: usize) -> String {
        match self.unit.symbol(dim) {
            "" => self.name.clone(),
            u => format!("{} [{u}]", self.name),
        }
    }
}

/// One cell of a row.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Cell {
    Real(f64),
    Count(u64),
    /// A value that does not exist at this row (the front of water that has all left):
    /// an empty cell, never ±inf or NaN.
    Empty,
}

impl Cell {
    /// A real that may not exist.
    fn maybe(v: Option<f64>) -> Cell {
        v.map_or(Cell::Empty, Cell::Real)
    }

    fn text(self) -> String {
        match self {
            Cell::Real(v) => format!("{v:.9e}"),
            Cell::Count(n) => n.to_string(),
            Cell::Empty => String::new(),
        }
    }
}

const S: Unit = Unit::Fixed("s");
const M: Unit = Unit::Fixed("m");
const MS: Unit = Unit::Fixed("m/s");
const PA: Unit = Unit::Fixed("Pa");
/// The summaries of the fine grains' ρ/ρ0 (`granmix_core::run::sample::DensityRatio`).
const DENSITY_RATIO: [&str; 3] = ["median", "p10", "min"];

/// Columns for a scene of this layout, in row order.
pub fn header(l: &Layout) -> Vec<Column> {
    let d = l.dim;
    let axes = |h: &mut Vec<Column>, q: &str, u: Unit| push_axes(h, d, q, u);
    let mut h = vec![
        Column::real("time", S),
        Column::count("steps"),
        Column::real("dt", S),
    ];
    if l.fine {
        h.extend(fine_columns());
    }
    if l.grains() {
        h.push(Column::real("runout", M));
    }
    h.push(Column::real("kinetic_energy_total", Unit::Energy));
    if !l.bodies.is_empty() {
        for c in [
            "kinetic_energy_coarse",
            "potential_energy_coarse",
            "strain_energy",
            "contact_energy",
        ] {
            h.push(Column::real(c, Unit::Energy));
        }
        h.push(Column::real("max_speed_coarse", MS));
        h.push(Column::count("steps_coarse"));
        h.push(Column::count("kappa"));
        axes(&mut h, "momentum", Unit::Momentum);
    }
    if l.water {
        h.push(Column::count("water.particles"));
        h.push(Column::real("water.kinetic_energy", Unit::Energy));
        h.push(Column::real("water.potential_energy", Unit::Energy));
        h.push(Column::real("water.front", M));
        h.push(Column::real("water.max_speed", MS));
        axes(&mut h, "water.momentum", Unit::Momentum);
        h.push(Column::real("water.min_pressure", PA));
    }
    for (b, panels) in &l.barriers {
        barrier_columns(&mut h, (d, l.water), b, panels);
    }
    for p in &l.probes {
        for s in SIG.iter().take(if d == 2 { 4 } else { 6 }) {
            h.push(Column::real(format!("{p}.sigma_{s}"), PA));
        }
        h.push(Column::real(format!("{p}.pressure"), PA));
        axes(&mut h, &format!("{p}.velocity"), MS);
        if l.water {
            h.push(Column::real(format!("{p}.water_pressure"), PA));
            axes(&mut h, &format!("{p}.water_velocity"), MS);
        }
    }
    for g in &l.gauges {
        h.push(Column::real(format!("{g}.level"), M));
    }
    for b in &l.bodies {
        body_columns(&mut h, (d, l.water), b);
    }
    h
}

/// The `d` components of quantity `q` along the axes.
fn push_axes(h: &mut Vec<Column>, d: usize, q: &str, u: Unit) {
    for a in AX.iter().take(d) {
        h.push(Column::real(format!("{q}.{a}"), u));
    }
}

/// The components of rotation `q`: the z component alone in 2D.
fn push_rot(h: &mut Vec<Column>, d: usize, q: &str, u: Unit) {
    for a in if d == 2 { &AX[2..] } else { &AX[..] } {
        h.push(Column::real(format!("{q}.{a}"), u));
    }
}

/// The columns of barrier `b` with `panels` panels per direction: its load (split
/// into water and grains with water), moment and peak, then each panel's load.
fn barrier_columns(h: &mut Vec<Column>, (d, water): (usize, bool), b: &str, panels: &[usize]) {
    let axes = |h: &mut Vec<Column>, q: &str, u: Unit| push_axes(h, d, q, u);
    let rot = |h: &mut Vec<Column>, q: &str, u: Unit| push_rot(h, d, q, u);
    axes(h, &format!("{b}.force"), Unit::Force);
    if water {
        axes(h, &format!("{b}.force_water"), Unit::Force);
        axes(h, &format!("{b}.force_grains"), Unit::Force);
    }
    rot(h, &format!("{b}.moment"), Unit::Moment);
    h.push(Column::real(format!("{b}.peak_force"), Unit::Force));
    for p in panel_labels(panels) {
        axes(h, &format!("{b}.{p}.force"), Unit::Force);
        if water {
            axes(h, &format!("{b}.{p}.force_water"), Unit::Force);
            axes(h, &format!("{b}.{p}.force_grains"), Unit::Force);
        }
    }
}

/// The columns of body `b`: its pose, velocities, loads (the water's with water),
/// torque and contacts.
fn body_columns(h: &mut Vec<Column>, (d, water): (usize, bool), b: &str) {
    let axes = |h: &mut Vec<Column>, q: &str, u: Unit| push_axes(h, d, q, u);
    let rot = |h: &mut Vec<Column>, q: &str, u: Unit| push_rot(h, d, q, u);
    axes(h, &format!("{b}.position"), M);
    axes(h, &format!("{b}.velocity"), MS);
    for q in ["w", "x", "y", "z"] {
        h.push(Column::real(
            format!("{b}.orientation.{q}"),
            Unit::Fixed(""),
        ));
    }
    rot(h, &format!("{b}.angular_velocity"), Unit::Fixed("rad/s"));
    axes(h, &format!("{b}.force"), Unit::Force);
    axes(h, &format!("{b}.fine_force"), Unit::Force);
    if water {
        axes(h, &format!("{b}.water_force"), Unit::Force);
    }
    rot(h, &format!("{b}.torque"), Unit::Moment);
    h.push(Column::count(format!("{b}.contacts")));
}

/// The fine grains' columns: energies, largest speed and ρ/ρ0.
fn fine_columns() -> Vec<Column> {
    let mut h = vec![
        Column::real("kinetic_energy", Unit::Energy),
        Column::real("potential_energy", Unit::Energy),
        Column::real("max_speed", MS),
    ];
    for q in DENSITY_RATIO {
        h.push(Column::real(format!("density_ratio.{q}"), Unit::Fixed("")));
    }
    h
}

/// The labels of a barrier's panels ([`sample::panel_labels`]), none for a count the
/// scene's check refuses.
pub fn panel_labels(counts: &[usize]) -> Vec<String> {
    sample::panel_labels(counts).unwrap_or_default()
}

/// Σ ½ m v² of every family present: fine, coarse and water (J, or J/m in 2D).
pub fn total_kinetic_energy(s: &Sample) -> f64 {
    s.kinetic_energy + s.coarse_kinetic_energy + s.water.as_ref().map_or(0.0, |w| w.kinetic_energy)
}

/// Cells of one row, matching [`header`].
pub fn row(l: &Layout, s: &Sample) -> Vec<Cell> {
    let d = l.dim;
    let mut r = vec![Cell::Real(s.time), Cell::Count(s.steps), Cell::Real(s.dt)];
    let reals = |r: &mut Vec<Cell>, v: &[f64]| r.extend(v.iter().map(|x| Cell::Real(*x)));
    let rot = |r: &mut Vec<Cell>, v: &[f64; 3]| {
        r.extend(
            v[if d == 2 { 2 } else { 0 }..]
                .iter()
                .map(|x| Cell::Real(*x)),
        )
    };
    if l.fine {
        reals(&mut r, &[s.kinetic_energy, s.potential_energy, s.max_speed]);
        let d = s.density_ratio.unwrap_or_default();
        reals(&mut r, &[d.median, d.p10, d.min]);
    }
    if l.grains() {
        r.push(Cell::Real(s.runout));
    }
    r.push(Cell::Real(total_kinetic_energy(s)));
    if !l.bodies.is_empty() {
        reals(
            &mut r,
            &[
                s.coarse_kinetic_energy,
                s.coarse_potential_energy,
                s.strain_energy,
                s.contact_energy,
                s.coarse_max_speed,
            ],
        );
        r.push(Cell::Count(s.steps_coarse));
        r.push(Cell::Count(s.kappa as u64));
        reals(&mut r, &s.momentum[..d]);
    }
    if l.water {
        let w = s.water.clone().unwrap_or_default();
        r.push(Cell::Count(w.particles as u64));
        reals(&mut r, &[w.kinetic_energy, w.potential_energy]);
        r.push(Cell::maybe(w.front));
        r.push(Cell::Real(w.max_speed));
        reals(&mut r, &w.momentum[..d]);
        r.push(Cell::Real(w.min_pressure));
    }
    for (b, (_, panels)) in s.barriers.iter().zip(&l.barriers) {
        reals(&mut r, &b.force[..d]);
        if l.water {
            reals(&mut r, &b.force_water[..d]);
            reals(&mut r, &b.force_grains[..d]);
        }
        rot(&mut r, &b.moment);
        r.push(Cell::Real(b.peak_force));
        for p in 0..panel_labels(panels).len() {
            let f = b.panels.get(p).copied().unwrap_or_default();
            reals(&mut r, &f[..d]);
            if l.water {
                let fw = b.panels_water.get(p).copied().unwrap_or_default();
                reals(&mut r, &fw[..d]);
                let fg = b.panels_grains.get(p).copied().unwrap_or_default();
                reals(&mut r, &fg[..d]);
            }
        }
    }
    for (_, p) in &s.probes {
        reals(&mut r, &p.stress.0[..if d == 2 { 4 } else { 6 }]);
        r.push(Cell::Real(-p.stress.trace() / 3.0));
        reals(&mut r, &p.velocity[..d]);
        if l.water {
            // gauge pressure: 0 where no water reaches the probe
            r.push(Cell::Real(p.water_pressure.unwrap_or(0.0)));
            reals(&mut r, &p.water_velocity.unwrap_or_default()[..d]);
        }
    }
    for (_, depth) in &s.gauges {
        r.push(Cell::Real(*depth));
    }
    for b in &s.bodies {
        reals(&mut r, &b.position[..d]);
        reals(&mut r, &b.velocity[..d]);
        reals(&mut r, &b.orientation);
        rot(&mut r, &b.angular_velocity);
        reals(&mut r, &b.force[..d]);
        reals(&mut r, &b.fine_force[..d]);
        if l.water {
            reals(&mut r, &b.water_force[..d]);
        }
        rot(&mut r, &b.torque);
        r.push(Cell::Count(b.contacts as u64));
    }
    r
}

/// A CSV file written row by row.
pub struct CsvSeries {
    out: std::io::BufWriter<std::fs::File>,
    layout: Layout,
}

impl CsvSeries {
    /// A series of samples of a scene with this layout.
    pub fn create(path: &std::path::Path, layout: Layout) -> std::io::Result<Self> {
        let mut out = std::io::BufWriter::new(std::fs::File::create(path)?);
        let names: Vec<String> = header(&layout)
            .iter()
            .map(|c| c.heading(layout.dim))
            .collect();
        writeln!(out, "{}", names.join(","))?;
        Ok(CsvSeries { out, layout })
    }
    pub fn write(&mut self, cells: &[Cell]) -> std::io::Result<()> {
        let line: Vec<String> = cells.iter().map(|c| c.text()).collect();
        writeln!(self.out, "{}", line.join(","))?;
        self.out.flush()
    }
}

impl Sink for CsvSeries {
    fn name(&self) -> &str {
        "series.csv"
    }
    fn sample(&mut self, _sim: &AnySimulation, s: &Sample) -> Result<(), SinkError> {
        self.write(&row(&self.layout, s))
            .map_err(|e| SinkError::new("series.csv", e))
    }
}

#[cfg(test)]
mod tests {
    use super::*;
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

    /// Every row has one cell per column, in 2D and 3D, with and without water.
    #[test]
    fn rows_match_the_header() {
        for dim in [2, 3] {
            for water in [false, true] {
                let l = layout(dim, water);
                let s = sample(water);
                assert_eq!(
                    header(&l).len(),
                    row(&l, &s).len(),
                    "dim {dim}, water {water}"
                );
            }
        }
    }

    /// Issue 39: declared panels appear as columns, loads carry units, counts are integers.
    #[test]
    fn issue_39_panels_units_and_integers() {
        let l = layout(2, true);
        let names: Vec<String> = header(&l).iter().map(|c| c.heading(2)).collect();
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
        let h3: Vec<String> = header(&layout(3, false))
            .iter()
            .map(|c| c.heading(3))
            .collect();
        assert!(h3.iter().any(|c| c == "barrier.force.z [N]"));
        let cells = row(&l, &sample(true));
        let text: Vec<String> = cells.iter().map(|c| c.text()).collect();
        assert_eq!(text[1], "270");
    }
}
