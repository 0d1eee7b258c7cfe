//! The observables of a sample, written once: each with its name, its unit and how it
//! is read from a [`Sample`]. The CSV series takes its header and its rows from the
//! same table ([`observables`]), so the two cannot fall out of step, and the summary
//! and the quick-look plot read the same derived values ([`total_kinetic_energy`]).
//!
//! The table follows the scene's [`Layout`]: the families and objects it has. Units of
//! loads and energies follow the dimension (per metre of width in 2D). Counts (steps,
//! κ, contacts, water particles) are integers.
//!
//! The FMU's outputs are observables of the same table ([`all`]): an observable the FMU
//! exposes carries its [`Fmu`] variable (name, owner, description). A few are the
//! FMU's alone (a body's step-averaged load, its angle in 2D, the energies of families
//! a scene lacks): they are not part of the series ([`Observable::series`]).

use crate::numerics::math::Real;
use crate::run::any::AnySimulation;
use crate::run::sample::{self, BarrierSample, BodySample, ProbeValue, Sample};

const AX: [&str; 3] = ["x", "y", "z"];
const SIG: [&str; 6] = ["xx", "yy", "zz", "xy", "xz", "yz"];
/// The summaries of the fine grains' ρ/ρ0 ([`sample::DensityRatio`]).
const DENSITY_RATIO: [&str; 3] = ["median", "p10", "min"];

/// Which families and objects a scene has: what the observables are built from.
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
    /// Resting fine grains sleep (`numerics.sleep`): the series carries their awake
    /// share.
    pub sleep: bool,
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
            sleep: sim.sleeps(),
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
        match (self, two) {
            (Unit::Force, true) => "N/m",
            (Unit::Force, false) => "N",
            (Unit::Moment, true) => "N",
            (Unit::Moment, false) => "N m",
            (Unit::Energy, true) => "J/m",
            (Unit::Energy, false) => "J",
            (Unit::Momentum, true) => "N s/m",
            (Unit::Momentum, false) => "N s",
            (Unit::Fixed(u), _) => u,
        }
    }

    /// The unit's name in an FMU's model description: the symbol, with `N.m` for a
    /// moment in 3D (None when dimensionless).
    pub fn fmi(self, dim: usize) -> Option<&'static str> {
        match self.symbol(dim) {
            "" => None,
            "N m" => Some("N.m"),
            u => Some(u),
        }
    }
}

const S: Unit = Unit::Fixed("s");
const M: Unit = Unit::Fixed("m");
const MS: Unit = Unit::Fixed("m/s");
const PA: Unit = Unit::Fixed("Pa");
const NONE: Unit = Unit::Fixed("");

/// One value of a sample.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Cell {
    Real(Real),
    Count(u64),
    /// A value that does not exist in this sample (the front of water that has all
    /// left): an empty cell, never ±inf or NaN.
    Empty,
}

impl Cell {
    /// A real that may not exist.
    fn maybe(v: Option<Real>) -> Cell {
        v.map_or(Cell::Empty, Cell::Real)
    }
}

/// How an observable is read from a sample.
type Read = Box<dyn Fn(&Sample) -> Cell + Send + Sync>;

/// The entity an FMU output belongs to: its variables are listed with that entity's.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Owner {
    Barrier(usize),
    Body(usize),
    /// The energies and step counts.
    Totals,
}

/// The FMU output variable of an observable.
#[derive(Clone, Debug, PartialEq)]
pub struct Fmu {
    /// Structured name (`barrier.force.x`; a 2D rotation has no `.z`).
    pub name: String,
    pub owner: Owner,
    pub description: String,
}

/// One observable: its name, its unit, whether it is a count, and its value in a sample.
pub struct Observable {
    pub name: String,
    pub unit: Unit,
    pub integer: bool,
    /// The run's summary gives its final value.
    pub summary: bool,
    /// The CSV series (and the summary) carry it; false for the FMU's own outputs.
    pub series: bool,
    /// Its FMU output variable, if the FMU exposes it.
    pub fmu: Option<Fmu>,
    /// Its component suffix (`x`, `y`, `z`, `w`), "" for a scalar.
    axis: &'static str,
    /// The name its FMU variable takes (a 2D rotation drops the `.z`).
    fmu_name: String,
    read: Read,
}

impl Observable {
    /// Its value in sample `s`.
    pub fn value(&self, s: &Sample) -> Cell {
        (self.read)(s)
    }

    /// Its value in sample `s` as a real (a count converted, an empty cell 0).
    pub fn real(&self, s: &Sample) -> Real {
        match self.value(s) {
            Cell::Real(v) => v,
            Cell::Count(c) => c as Real,
            Cell::Empty => 0.0,
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

/// The table under construction, for a scene of dimension `d`.
struct Table {
    d: usize,
    rows: Vec<Observable>,
}

impl Table {
    /// The last `n` observables go into the run's summary.
    fn in_summary(&mut self, n: usize) {
        let k = self.rows.len() - n;
        for o in &mut self.rows[k..] {
            o.summary = true;
        }
    }

    /// The last `n` observables are the FMU's alone: not in the series.
    fn fmu_only(&mut self, n: usize) {
        let k = self.rows.len() - n;
        for o in &mut self.rows[k..] {
            o.series = false;
        }
    }

    /// The last `n` observables are FMU outputs of `owner`; `what` describes the one of
    /// component suffix `axis` ("" for a scalar).
    fn expose(&mut self, n: usize, owner: Owner, what: impl Fn(&str) -> String) {
        let k = self.rows.len() - n;
        for o in &mut self.rows[k..] {
            o.fmu = Some(Fmu {
                name: o.fmu_name.clone(),
                owner,
                description: what(o.axis),
            });
        }
    }

    fn push(&mut self, name: impl Into<String>, (unit, integer): (Unit, bool), read: Read) {
        let name = name.into();
        self.rows.push(Observable {
            fmu_name: name.clone(),
            name,
            unit,
            integer,
            summary: false,
            series: true,
            fmu: None,
            axis: "",
            read,
        });
    }

    /// The last observable is the FMU's total `fmu`, described by `what`.
    fn total(&mut self, fmu: &str, what: &str) {
        self.component("", fmu.to_string());
        self.expose(1, Owner::Totals, |_| what.to_string());
    }

    /// The FMU names of the last `n` observables, which start with `from`, start with
    /// `to` instead.
    fn rename(&mut self, n: usize, from: &str, to: &str) {
        let k = self.rows.len() - n;
        for o in &mut self.rows[k..] {
            if let Some(rest) = o.fmu_name.strip_prefix(from) {
                o.fmu_name = format!("{to}{rest}");
            }
        }
    }

    /// The last observable's component suffix, and its FMU variable's name.
    fn component(&mut self, axis: &'static str, fmu_name: String) {
        let o = self.rows.last_mut().expect("a row was pushed");
        o.axis = axis;
        o.fmu_name = fmu_name;
    }

    fn real(
        &mut self,
        name: impl Into<String>,
        unit: Unit,
        f: impl Fn(&Sample) -> Real + Send + Sync + 'static,
    ) {
        self.push(name, (unit, false), Box::new(move |s| Cell::Real(f(s))));
    }

    /// A real that some samples lack (an empty cell there).
    fn maybe(
        &mut self,
        name: impl Into<String>,
        unit: Unit,
        f: impl Fn(&Sample) -> Option<Real> + Send + Sync + 'static,
    ) {
        self.push(name, (unit, false), Box::new(move |s| Cell::maybe(f(s))));
    }

    fn count(
        &mut self,
        name: impl Into<String>,
        f: impl Fn(&Sample) -> u64 + Send + Sync + 'static,
    ) {
        self.push(name, (NONE, true), Box::new(move |s| Cell::Count(f(s))));
    }

    /// The `d` components `q.x`, `q.y` (, `q.z`) of the vector `f` reads.
    fn axes<F>(&mut self, q: &str, unit: Unit, f: F)
    where
        F: Fn(&Sample) -> [Real; 3] + Clone + Send + Sync + 'static,
    {
        for (a, name) in AX.iter().enumerate().take(self.d) {
            let f = f.clone();
            self.real(format!("{q}.{name}"), unit, move |s| f(s)[a]);
            self.component(name, format!("{q}.{name}"));
        }
    }

    /// The components of the rotation `f` reads: its z component alone in 2D (whose
    /// FMU variable is named without suffix).
    fn rotation<F>(&mut self, q: &str, unit: Unit, f: F)
    where
        F: Fn(&Sample) -> [Real; 3] + Clone + Send + Sync + 'static,
    {
        let from = if self.d == 2 { 2 } else { 0 };
        for (a, name) in AX.iter().enumerate().skip(from) {
            let f = f.clone();
            self.real(format!("{q}.{name}"), unit, move |s| f(s)[a]);
            let fmu = if self.d == 2 {
                q.to_string()
            } else {
                format!("{q}.{name}")
            };
            self.component(name, fmu);
        }
    }
}

/// The observables the series and the summary carry, of a scene of this layout, in
/// order: time and steps, the fine grains, the run-out, the energies, the coarse grains,
/// the water, each barrier and its panels, each probe, each gauge, each body.
pub fn observables(l: &Layout) -> Vec<Observable> {
    all(l).into_iter().filter(|o| o.series).collect()
}

/// Every observable of a scene of this layout: the series' ([`observables`]) and the
/// FMU's own ([`Observable::fmu`], [`Observable::series`]).
pub fn all(l: &Layout) -> Vec<Observable> {
    let mut t = Table {
        d: l.dim,
        rows: Vec::new(),
    };
    t.real("time", S, |s| s.time);
    t.in_summary(1);
    t.count("steps", |s| s.steps);
    t.total("steps.fine", "fine solver steps taken so far");
    t.real("dt", S, |s| s.dt);
    fine(&mut t, l.fine, l.sleep);
    if l.grains() {
        t.real("runout", M, |s| s.runout);
        t.in_summary(1);
    }
    t.real("kinetic_energy_total", Unit::Energy, total_kinetic_energy);
    t.in_summary(1);
    coarse(&mut t, !l.bodies.is_empty());
    if l.water {
        water(&mut t);
    }
    for (k, (b, panels)) in l.barriers.iter().enumerate() {
        barrier(&mut t, (k, b), panels, l.water);
    }
    for (k, p) in l.probes.iter().enumerate() {
        probe(&mut t, (k, p), l.water);
    }
    for (k, g) in l.gauges.iter().enumerate() {
        t.real(format!("{g}.level"), M, move |s| {
            s.gauges.get(k).map_or(0.0, |g| g.1)
        });
    }
    for (k, b) in l.bodies.iter().enumerate() {
        body(&mut t, (k, b), l.water);
    }
    t.rows
}

/// The values of `table` in sample `s`, in order.
pub fn row(table: &[Observable], s: &Sample) -> Vec<Cell> {
    table.iter().map(|o| o.value(s)).collect()
}

/// Σ ½ m v² of every family present: fine, coarse and water (J, or J/m in 2D).
pub fn total_kinetic_energy(s: &Sample) -> Real {
    s.kinetic_energy + s.coarse_kinetic_energy + s.water.as_ref().map_or(0.0, |w| w.kinetic_energy)
}

/// The fine grains: energies, largest speed, ρ/ρ0 and, where they sleep (`sleep`),
/// the share awake (`shown`: the scene has them; otherwise only the FMU's kinetic
/// energy, zero).
fn fine(t: &mut Table, shown: bool, sleep: bool) {
    t.real("kinetic_energy", Unit::Energy, |s| s.kinetic_energy);
    t.total("kinetic_energy.fine", "kinetic energy of the fine grains");
    if !shown {
        t.fmu_only(1);
        return;
    }
    t.in_summary(1);
    t.real("potential_energy", Unit::Energy, |s| s.potential_energy);
    t.real("max_speed", MS, |s| s.max_speed);
    t.in_summary(1);
    for (k, q) in DENSITY_RATIO.iter().enumerate() {
        // none without fine particles
        let ratio = move |s: &Sample| s.density_ratio.map(|d| [d.median, d.p10, d.min][k]);
        t.maybe(format!("density_ratio.{q}"), NONE, ratio);
    }
    t.in_summary(DENSITY_RATIO.len());
    if sleep {
        t.maybe("awake_fine", NONE, |s| s.awake_fine);
        t.in_summary(1);
    }
}

/// The coarse grains: energies, largest speed, sub-steps, κ and momentum (`shown`: the
/// scene has bodies; otherwise only the FMU's kinetic energy and sub-steps, zero).
fn coarse(t: &mut Table, shown: bool) {
    let steps = |t: &mut Table| {
        t.count("steps_coarse", |s| s.steps_coarse);
        t.total("steps.coarse", "coarse sub-steps taken so far");
    };
    t.real("kinetic_energy_coarse", Unit::Energy, |s| {
        s.coarse_kinetic_energy
    });
    t.total(
        "kinetic_energy.coarse",
        "kinetic energy of the coarse grains",
    );
    if !shown {
        steps(t);
        t.fmu_only(2);
        return;
    }
    t.in_summary(1);
    t.real("potential_energy_coarse", Unit::Energy, |s| {
        s.coarse_potential_energy
    });
    t.real("strain_energy", Unit::Energy, |s| s.strain_energy);
    t.real("contact_energy", Unit::Energy, |s| s.contact_energy);
    t.real("max_speed_coarse", MS, |s| s.coarse_max_speed);
    t.in_summary(1);
    steps(t);
    t.count("kappa", |s| s.kappa as u64);
    t.axes("momentum", Unit::Momentum, |s| s.momentum);
}

/// The water: particles, energies, front, largest speed, momentum, least pressure.
fn water(t: &mut Table) {
    let w = |s: &Sample| s.water.clone().unwrap_or_default();
    t.count("water.particles", move |s| w(s).particles as u64);
    t.real("water.kinetic_energy", Unit::Energy, move |s| {
        w(s).kinetic_energy
    });
    t.total("kinetic_energy.water", "kinetic energy of the water");
    t.in_summary(2);
    t.real("water.potential_energy", Unit::Energy, move |s| {
        w(s).potential_energy
    });
    t.maybe("water.front", M, move |s| w(s).front);
    t.real("water.max_speed", MS, move |s| w(s).max_speed);
    t.in_summary(2);
    t.axes("water.momentum", Unit::Momentum, move |s| w(s).momentum);
    t.real("water.min_pressure", PA, move |s| w(s).min_pressure);
    t.in_summary(1);
}

/// Barrier `k` named `b` with `panels` panels per direction: its load (split into
/// water and grains with water), moment and peak, then each panel's load.
fn barrier(t: &mut Table, (k, b): (usize, &str), panels: &[usize], water: bool) {
    let (d, owner) = (t.d, Owner::Barrier(k));
    let of =
        move |s: &Sample, f: fn(&BarrierSample) -> [Real; 3]| s.barriers.get(k).map_or([0.0; 3], f);
    t.axes(&format!("{b}.force"), Unit::Force, move |s| {
        of(s, |b| b.force)
    });
    t.expose(d, owner, |a| {
        format!("load on barrier `{b}`, impulse over the step / step, {a} component")
    });
    t.in_summary(d);
    if water {
        t.axes(&format!("{b}.force_water"), Unit::Force, move |s| {
            of(s, |b| b.force_water)
        });
        t.expose(d, owner, |a| {
            format!(
                "the water's part of the load on barrier `{b}` (pressure and viscous \
                 traction), impulse over the step / step, {a} component"
            )
        });
        t.axes(&format!("{b}.force_grains"), Unit::Force, move |s| {
            of(s, |b| b.force_grains)
        });
        t.expose(d, owner, |a| {
            format!(
                "the grains' part of the load on barrier `{b}` (fine and coarse), impulse \
                 over the step / step, {a} component"
            )
        });
        t.in_summary(2 * d);
    }
    t.rotation(&format!("{b}.moment"), Unit::Moment, move |s| {
        of(s, |b| b.moment)
    });
    t.expose(rotations(d), owner, |_| {
        format!("moment on barrier `{b}` about its reference point, step-averaged")
    });
    t.real(format!("{b}.peak_force"), Unit::Force, move |s| {
        s.barriers.get(k).map_or(0.0, |b| b.peak_force)
    });
    t.expose(1, owner, |_| {
        format!(
            "largest resultant load on barrier `{b}` of any solver step within the \
             communication step"
        )
    });
    let labels = sample::panel_labels(panels).unwrap_or_default();
    for (p, label) in labels.iter().enumerate() {
        panel(t, (k, b), (p, label), water);
    }
}

/// Panel `p` labelled `label` of barrier `k` named `b`: its load (split into water and
/// grains with water).
fn panel(t: &mut Table, (k, b): (usize, &str), (p, label): (usize, &str), water: bool) {
    let (d, owner) = (t.d, Owner::Barrier(k));
    // panel p's load in `f` of barrier k
    let at = move |s: &Sample, f: fn(&BarrierSample) -> &[[Real; 3]]| {
        s.barriers
            .get(k)
            .and_then(|b| f(b).get(p).copied())
            .unwrap_or_default()
    };
    t.axes(&format!("{b}.{label}.force"), Unit::Force, move |s| {
        at(s, |b| &b.panels)
    });
    t.expose(d, owner, |a| {
        format!("load on panel {label} of barrier `{b}`, step-averaged, {a} component")
    });
    t.in_summary(d);
    if water {
        let q = format!("{b}.{label}.force_water");
        t.axes(&q, Unit::Force, move |s| at(s, |b| &b.panels_water));
        t.expose(d, owner, |a| {
            format!(
                "the water's part of the load on panel {label} of barrier `{b}`, \
                 step-averaged, {a} component"
            )
        });
        let q = format!("{b}.{label}.force_grains");
        t.axes(&q, Unit::Force, move |s| at(s, |b| &b.panels_grains));
        t.expose(d, owner, |a| {
            format!(
                "the grains' part of the load on panel {label} of barrier `{b}`, \
                 step-averaged, {a} component"
            )
        });
    }
}

/// The components of a rotation in dimension `d`: z alone in 2D.
fn rotations(d: usize) -> usize {
    if d == 2 {
        1
    } else {
        3
    }
}

/// Probe `k` named `p`: its stress, pressure and velocity, and the water's there.
fn probe(t: &mut Table, (k, p): (usize, &str), water: bool) {
    let of = move |s: &Sample, f: fn(&ProbeValue) -> Real| s.probes.get(k).map_or(0.0, |p| f(&p.1));
    let vec = move |s: &Sample, f: fn(&ProbeValue) -> [Real; 3]| {
        s.probes.get(k).map_or([0.0; 3], |p| f(&p.1))
    };
    let parts = if t.d == 2 { 4 } else { 6 };
    for (c, name) in SIG.iter().enumerate().take(parts) {
        let sigma = move |s: &Sample| s.probes.get(k).map_or(0.0, |p| p.1.stress.0[c]);
        t.real(format!("{p}.sigma_{name}"), PA, sigma);
    }
    t.real(format!("{p}.pressure"), PA, move |s| {
        of(s, |p| -p.stress.trace() / 3.0)
    });
    t.axes(&format!("{p}.velocity"), MS, move |s| {
        vec(s, |p| p.velocity)
    });
    if water {
        // gauge pressure: 0 where no water reaches the probe
        let q = format!("{p}.water_pressure");
        t.real(q, PA, move |s| of(s, |p| p.water_pressure.unwrap_or(0.0)));
        let q = format!("{p}.water_velocity");
        t.axes(&q, MS, move |s| {
            vec(s, |p| p.water_velocity.unwrap_or_default())
        });
    }
}

/// Body `k` named `b`: its pose, velocities, loads (the water's with water), torque
/// and contacts; and the FMU's own: its angle in 2D, its step-averaged load and torque.
fn body(t: &mut Table, (k, b): (usize, &str), water: bool) {
    let (d, owner) = (t.d, Owner::Body(k));
    let of = move |s: &Sample, f: fn(&BodySample) -> [Real; 3]| s.bodies.get(k).map_or([0.0; 3], f);
    t.axes(&format!("{b}.position"), M, move |s| of(s, |b| b.position));
    t.expose(d, owner, |_| format!("body `{b}`: centre of mass"));
    t.axes(&format!("{b}.velocity"), MS, move |s| of(s, |b| b.velocity));
    t.expose(d, owner, |_| {
        format!("body `{b}`: velocity of the centre of mass")
    });
    let quaternion = move |s: &Sample| s.bodies.get(k).map_or([0.0; 4], |b| b.orientation);
    for (c, q) in ["w", "x", "y", "z"].iter().enumerate() {
        t.real(format!("{b}.orientation.{q}"), NONE, move |s| {
            quaternion(s)[c]
        });
        t.component(q, format!("{b}.orientation.{q}"));
    }
    if d == 3 {
        t.expose(4, owner, |_| format!("body `{b}`: unit quaternion"));
    } else {
        // the rotation about z of the quaternion (w, 0, 0, z)
        t.real(format!("{b}.angle"), Unit::Fixed("rad"), move |s| {
            let [w, _, _, z] = quaternion(s);
            2.0 * z.atan2(w)
        });
        t.expose(1, owner, |_| format!("body `{b}`: rotation angle about z"));
        t.fmu_only(1);
    }
    let rad = Unit::Fixed("rad/s");
    t.rotation(&format!("{b}.angular_velocity"), rad, move |s| {
        of(s, |b| b.angular_velocity)
    });
    t.expose(rotations(d), owner, |_| {
        format!("body `{b}`: angular velocity")
    });
    t.axes(&format!("{b}.force"), Unit::Force, move |s| {
        of(s, |b| b.force)
    });
    t.axes(&format!("{b}.fine_force"), Unit::Force, move |s| {
        of(s, |b| b.fine_force)
    });
    if water {
        t.axes(&format!("{b}.water_force"), Unit::Force, move |s| {
            of(s, |b| b.water_force)
        });
    }
    t.rotation(&format!("{b}.torque"), Unit::Moment, move |s| {
        of(s, |b| b.torque)
    });
    t.count(format!("{b}.contacts"), move |s| {
        s.bodies.get(k).map_or(0, |b| b.contacts as u64)
    });
    // the FMU's: the load and torque averaged over the communication step
    t.axes(&format!("{b}.mean_force"), Unit::Force, move |s| {
        of(s, |b| b.mean_force)
    });
    t.rename(d, &format!("{b}.mean_force"), &format!("{b}.force"));
    t.expose(d, owner, |_| {
        format!(
            "body `{b}`: load from grains and contacts, impulse over the step / step, \
             gravity excluded"
        )
    });
    t.rotation(&format!("{b}.mean_torque"), Unit::Moment, move |s| {
        of(s, |b| b.mean_torque)
    });
    let (from, to) = (format!("{b}.mean_torque"), format!("{b}.torque"));
    t.rename(rotations(d), &from, &to);
    t.expose(rotations(d), owner, |_| {
        format!("body `{b}`: torque about the centre of mass, step-averaged")
    });
    t.fmu_only(d + rotations(d));
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::scene::names_check::RESERVED;

    /// Every column of the series' own (no barrier, probe, gauge or body) that has
    /// parts begins with a name the scene reserves, so no output name can share it.
    #[test]
    fn the_series_own_columns_with_parts_begin_with_reserved_names() {
        for dim in [2, 3] {
            let l = Layout {
                dim,
                fine: true,
                water: true,
                barriers: Vec::new(),
                probes: Vec::new(),
                gauges: Vec::new(),
                bodies: Vec::new(),
                sleep: true,
            };
            for o in all(&l) {
                let fmu = o.fmu.as_ref().map(|f| f.name.clone());
                for name in std::iter::once(o.name.clone()).chain(fmu) {
                    if let Some((first, _)) = name.split_once('.') {
                        assert!(RESERVED.contains(&first), "{name}: `{first}` not reserved");
                    }
                }
            }
        }
    }
}
