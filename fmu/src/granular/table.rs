//! The variable table of a granular scene, built from data: one [`Row`] per kind of
//! variable of a barrier, a panel or a body, and one [`Param`] per parameter of a
//! material or a solid ([`Params`]), expanded over the scene's entities in this order: each barrier
//! (its outputs, its panels' outputs, its inputs when driven), each body, the energies
//! and step counts, each fine-grain material, each coarse-grain solid, then the
//! simulation settings. The value reference of a variable is its index in the table;
//! variability follows from causality and base type ([`crate::xml`]).

use crate::error::GranularError;
use crate::variables::{Causality, Kind, Variable};
use granmix_core::input::LoadedScene;
use granmix_core::scene::{BarrierInput, MaterialSpec, SimulationSpec, SolidSpec};
use granmix_core::AnySimulation;

const AXES: [&str; 3] = ["x", "y", "z"];

/// Body quantity behind an output.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum BodyQ {
    Position,
    /// Quaternion component (3D) w, x, y, z.
    Orientation,
    /// Rotation angle about z (2D).
    Angle,
    Velocity,
    AngularVelocity,
    Force,
    Torque,
}

/// Where a variable's value lives.
#[derive(Clone, Debug, PartialEq)]
pub enum Slot {
    BarrierForce(usize, usize),
    BarrierMoment(usize, usize),
    BarrierPeak(usize),
    /// Component `k` of the water's part of the load on barrier `b`.
    BarrierForceWater(usize, usize),
    /// Component `k` of the grains' part of the load on barrier `b`.
    BarrierForceGrains(usize, usize),
    /// Component `k` of the force on panel `p` of barrier `b`.
    PanelForce(usize, usize, usize),
    /// The water's part of a panel's load (barrier, panel, axis).
    PanelForceWater(usize, usize, usize),
    /// The grains' part of a panel's load (barrier, panel, axis).
    PanelForceGrains(usize, usize, usize),
    /// Component `k` of the input of driven barrier `b`.
    BarrierInput(usize, usize),
    Body(usize, BodyQ, usize),
    KineticFine,
    KineticCoarse,
    KineticWater,
    StepsFine,
    StepsCoarse,
    /// A scene value set through an override `key.path=value`.
    SceneValue(String),
    MultiRate,
    /// Publish particle frames at every communication point.
    IpcEnabled,
    /// The particle service (String).
    IpcService,
    /// MCAP file to record to (String; empty: no recording).
    RecordPath,
}

/// The variable table of a scene, with what each entry is bound to.
pub struct Table {
    pub variables: Vec<Variable>,
    pub slots: Vec<Slot>,
    /// Input mode of each barrier (None: not driven).
    pub inputs: Vec<Option<BarrierInput>>,
}

/// The components a [`Row`] expands to.
#[derive(Clone, Copy, Debug)]
enum Comps {
    /// One variable, named without suffix.
    One,
    /// One per axis of the scene: `.x`, `.y` and, in 3D, `.z`.
    Axes,
    /// About z alone in 2D (named without suffix); `.x`, `.y`, `.z` in 3D.
    Rotation,
    /// The unit quaternion's `.w`, `.x`, `.y`, `.z`.
    Quaternion,
}

impl Comps {
    /// Component index and name suffix of each variable, in dimension `d`.
    fn of(self, d: usize) -> Vec<(usize, Option<&'static str>)> {
        let axes = |n: usize| (0..n).map(|k| (k, Some(AXES[k]))).collect();
        match self {
            Comps::One => vec![(0, None)],
            Comps::Axes => axes(d),
            Comps::Rotation if d == 2 => vec![(2, None)],
            Comps::Rotation => axes(3),
            Comps::Quaternion => ["w", "x", "y", "z"]
                .into_iter()
                .enumerate()
                .map(|(k, c)| (k, Some(c)))
                .collect(),
        }
    }
}

/// A unit that may depend on the dimension: 2D scenes are per metre of depth.
#[derive(Clone, Copy, Debug)]
enum Unit {
    /// N/m in 2D, N in 3D.
    Force,
    /// N in 2D, N.m in 3D.
    Moment,
    /// J/m in 2D, J in 3D.
    Energy,
    /// The same in 2D and 3D (None: dimensionless).
    Fixed(Option<&'static str>),
}

impl Unit {
    fn of(self, d: usize) -> Option<&'static str> {
        let per_m = d == 2;
        match self {
            Unit::Force => Some(if per_m { "N/m" } else { "N" }),
            Unit::Moment => Some(if per_m { "N" } else { "N.m" }),
            Unit::Energy => Some(if per_m { "J/m" } else { "J" }),
            Unit::Fixed(u) => u,
        }
    }
}

/// Which entity a [`Row`] is expanded for: barrier or body `entity`, and for panel rows
/// panel `panel` of barrier `entity`.
#[derive(Clone, Copy, Debug)]
struct At {
    entity: usize,
    panel: usize,
}

/// One kind of Real variable of a barrier, a panel or a body.
struct Row {
    /// Name after the entity's: `force` gives `<barrier>.force.x`.
    key: &'static str,
    /// Output, or input (start value 0).
    causality: Causality,
    comps: Comps,
    unit: Unit,
    /// Description: `{name}` stands for the barrier's or body's name, `{label}` for a
    /// panel's label, `{axis}` for the component's suffix.
    what: &'static str,
    /// Only in scenes of this dimension (None: in both).
    dimension: Option<usize>,
    /// The slot of component `k`.
    slot: fn(At, usize) -> Slot,
}

impl Row {
    const fn output(
        key: &'static str,
        comps: Comps,
        unit: Unit,
        what: &'static str,
        slot: fn(At, usize) -> Slot,
    ) -> Row {
        Row {
            key,
            causality: Causality::Output,
            comps,
            unit,
            what,
            dimension: None,
            slot,
        }
    }

    /// The same row as inputs (start value 0).
    const fn input(self) -> Row {
        Row {
            causality: Causality::Input,
            ..self
        }
    }

    /// The same row, only in scenes of dimension `dimension`.
    const fn only_in(self, dimension: usize) -> Row {
        Row {
            dimension: Some(dimension),
            ..self
        }
    }
}

const METRE: Unit = Unit::Fixed(Some("m"));

/// The outputs of every barrier.
const BARRIER: &[Row] = &[
    Row::output(
        "force",
        Comps::Axes,
        Unit::Force,
        "load on barrier `{name}`, impulse over the step / step, {axis} component",
        |at, k| Slot::BarrierForce(at.entity, k),
    ),
    Row::output(
        "moment",
        Comps::Rotation,
        Unit::Moment,
        "moment on barrier `{name}` about its reference point, step-averaged",
        |at, k| Slot::BarrierMoment(at.entity, k),
    ),
    Row::output(
        "peak_force",
        Comps::One,
        Unit::Force,
        "largest resultant load on barrier `{name}` of any solver step within the \
         communication step",
        |at, _| Slot::BarrierPeak(at.entity),
    ),
];

/// The outputs of every barrier of a scene with water: the load split into the water's
/// part and the grains'.
const WATER_BARRIER: &[Row] = &[
    Row::output(
        "force_water",
        Comps::Axes,
        Unit::Force,
        "the water's part of the load on barrier `{name}` (pressure and viscous traction), \
         impulse over the step / step, {axis} component",
        |at, k| Slot::BarrierForceWater(at.entity, k),
    ),
    Row::output(
        "force_grains",
        Comps::Axes,
        Unit::Force,
        "the grains' part of the load on barrier `{name}` (fine and coarse), impulse over \
         the step / step, {axis} component",
        |at, k| Slot::BarrierForceGrains(at.entity, k),
    ),
];

/// The outputs of every panel of a barrier (named `<barrier>.<label>.…`).
const PANEL: &[Row] = &[Row::output(
    "force",
    Comps::Axes,
    Unit::Force,
    "load on panel {label} of barrier `{name}`, step-averaged, {axis} component",
    |at, k| Slot::PanelForce(at.entity, at.panel, k),
)];

/// The outputs of every panel in a scene with water: its load split as the barrier's.
const WATER_PANEL: &[Row] = &[
    Row::output(
        "force_water",
        Comps::Axes,
        Unit::Force,
        "the water's part of the load on panel {label} of barrier `{name}`, step-averaged, \
         {axis} component",
        |at, k| Slot::PanelForceWater(at.entity, at.panel, k),
    ),
    Row::output(
        "force_grains",
        Comps::Axes,
        Unit::Force,
        "the grains' part of the load on panel {label} of barrier `{name}`, step-averaged, \
         {axis} component",
        |at, k| Slot::PanelForceGrains(at.entity, at.panel, k),
    ),
];

/// The inputs of a barrier driven by displacement.
const DISPLACEMENT_INPUT: Row = Row::output(
    "displacement",
    Comps::Axes,
    METRE,
    "barrier `{name}`: rigid displacement from the initial place, reached at the end of \
     the step, {axis} component",
    |at, k| Slot::BarrierInput(at.entity, k),
)
.input();

/// The inputs of a barrier driven by velocity.
const VELOCITY_INPUT: Row = Row::output(
    "velocity",
    Comps::Axes,
    Unit::Fixed(Some("m/s")),
    "barrier `{name}`: rigid velocity during the step, {axis} component",
    |at, k| Slot::BarrierInput(at.entity, k),
)
.input();

/// The outputs of every body.
const BODY: &[Row] = &[
    Row::output(
        "position",
        Comps::Axes,
        METRE,
        "body `{name}`: centre of mass",
        |at, k| Slot::Body(at.entity, BodyQ::Position, k),
    ),
    Row::output(
        "angle",
        Comps::Rotation,
        Unit::Fixed(Some("rad")),
        "body `{name}`: rotation angle about z",
        |at, k| Slot::Body(at.entity, BodyQ::Angle, k),
    )
    .only_in(2),
    Row::output(
        "orientation",
        Comps::Quaternion,
        Unit::Fixed(None),
        "body `{name}`: unit quaternion",
        |at, k| Slot::Body(at.entity, BodyQ::Orientation, k),
    )
    .only_in(3),
    Row::output(
        "velocity",
        Comps::Axes,
        Unit::Fixed(Some("m/s")),
        "body `{name}`: velocity of the centre of mass",
        |at, k| Slot::Body(at.entity, BodyQ::Velocity, k),
    ),
    Row::output(
        "angular_velocity",
        Comps::Rotation,
        Unit::Fixed(Some("rad/s")),
        "body `{name}`: angular velocity",
        |at, k| Slot::Body(at.entity, BodyQ::AngularVelocity, k),
    ),
    Row::output(
        "force",
        Comps::Axes,
        Unit::Force,
        "body `{name}`: load from grains and contacts, impulse over the step / step, \
         gravity excluded",
        |at, k| Slot::Body(at.entity, BodyQ::Force, k),
    ),
    Row::output(
        "torque",
        Comps::Rotation,
        Unit::Moment,
        "body `{name}`: torque about the centre of mass, step-averaged",
        |at, k| Slot::Body(at.entity, BodyQ::Torque, k),
    ),
];

/// One Real parameter of every material or solid of type `T`: the scene key it
/// overrides and its value in the scene.
struct Param<T> {
    key: &'static str,
    unit: Option<&'static str>,
    what: &'static str,
    /// The start value; None where the key does not apply (a μ(I) material has no
    /// `friction_angle`): no variable.
    value: fn(&T) -> Option<f64>,
}

impl<T> Param<T> {
    const fn new(
        key: &'static str,
        unit: Option<&'static str>,
        what: &'static str,
        value: fn(&T) -> Option<f64>,
    ) -> Self {
        Param {
            key,
            unit,
            what,
            value,
        }
    }
}

/// The parameters of every entry of a scene list: `<list>.<name>.<key>`, overriding
/// `<list>[<index>].<key>`.
struct Params<T: 'static> {
    list: &'static str,
    /// What an entry is, for the descriptions.
    who: &'static str,
    name: fn(&T) -> &str,
    params: &'static [Param<T>],
}

/// The parameters of every fine-grain material.
const MATERIALS: Params<MaterialSpec> = Params {
    list: "materials",
    who: "fine-grain material",
    name: |m| &m.name,
    params: &[
        Param::new("density", Some("kg/m3"), "initial density", |m| {
            Some(m.density)
        }),
        Param::new("youngs_modulus", Some("Pa"), "Young's modulus", |m| {
            Some(m.youngs_modulus)
        }),
        Param::new("poisson_ratio", None, "Poisson's ratio", |m| {
            Some(m.poisson_ratio)
        }),
        Param::new("friction_angle", Some("deg"), "friction angle", |m| {
            m.friction_angle
        }),
        Param::new("cohesion", Some("Pa"), "cohesion", |m| Some(m.cohesion)),
        Param::new("dilation_angle", Some("deg"), "dilation angle", |m| {
            Some(m.dilation_angle)
        }),
    ],
};

/// The parameters of every coarse-grain solid.
const SOLIDS: Params<SolidSpec> = Params {
    list: "solids",
    who: "coarse-grain solid",
    name: |s| &s.name,
    params: &[
        Param::new("density", Some("kg/m3"), "density", |s| Some(s.density)),
        Param::new("youngs_modulus", Some("Pa"), "Young's modulus", |s| {
            Some(s.youngs_modulus)
        }),
        Param::new("poisson_ratio", None, "Poisson's ratio", |s| {
            Some(s.poisson_ratio)
        }),
    ],
};

/// `template` with each `{key}` of `values` replaced by its value, in one pass (a
/// replaced value is not searched again, so names may hold braces).
fn fill(template: &str, values: &[(&str, &str)]) -> String {
    let mut out = String::with_capacity(template.len() + 32);
    let mut rest = template;
    while let Some(open) = rest.find('{') {
        out.push_str(&rest[..open]);
        let after = &rest[open + 1..];
        let value = after.find('}').and_then(|close| {
            let key = &after[..close];
            let (_, v) = values.iter().find(|(k, _)| *k == key)?;
            Some((*v, close))
        });
        match value {
            Some((v, close)) => {
                out.push_str(v);
                rest = &after[close + 1..];
            }
            None => {
                out.push('{');
                rest = after;
            }
        }
    }
    out.push_str(rest);
    out
}

/// The table as it is built.
struct Builder {
    /// Dimension of the scene.
    d: usize,
    /// The scene has water: barriers split their loads, the water has its energy.
    water: bool,
    table: Table,
}

impl Builder {
    fn push(&mut self, variable: Variable, slot: Slot) {
        self.table.variables.push(variable);
        self.table.slots.push(slot);
    }

    /// The variables of `rows` for the entity named `prefix` at `at`; `names` fills the
    /// descriptions.
    fn rows<'a>(
        &mut self,
        rows: impl IntoIterator<Item = &'a Row>,
        prefix: &str,
        at: At,
        names: &[(&str, &str)],
    ) {
        let d = self.d;
        for row in rows {
            if row.dimension.is_some_and(|only| only != d) {
                continue;
            }
            for (k, axis) in row.comps.of(d) {
                let name = match axis {
                    Some(axis) => format!("{prefix}.{}.{axis}", row.key),
                    None => format!("{prefix}.{}", row.key),
                };
                let mut values = names.to_vec();
                values.push(("axis", axis.unwrap_or("")));
                let variable = Variable {
                    name,
                    kind: Kind::Real,
                    causality: row.causality,
                    unit: row.unit.of(d),
                    description: fill(row.what, &values),
                    start: (row.causality != Causality::Output).then_some(0.0),
                    start_text: None,
                };
                self.push(variable, (row.slot)(at, k));
            }
        }
    }

    /// The parameters of `family` for each entry of `specs` (the scene's list).
    fn params<T>(&mut self, family: &Params<T>, specs: &[T]) {
        let Params {
            list, who, params, ..
        } = family;
        for (i, spec) in specs.iter().enumerate() {
            let name = (family.name)(spec);
            for p in params.iter() {
                let Some(value) = (p.value)(spec) else {
                    continue;
                };
                let variable = Variable::parameter(
                    format!("{list}.{name}.{}", p.key),
                    p.unit,
                    format!("{who} `{name}`: {}", p.what),
                    value,
                );
                self.push(variable, Slot::SceneValue(format!("{list}[{i}].{}", p.key)));
            }
        }
    }

    /// The outputs of barrier `b` named `name`, those of its panels (`counts` per
    /// direction, empty: none) and its inputs when it is driven in `mode`.
    fn barrier(
        &mut self,
        b: usize,
        name: &str,
        counts: &[usize],
        mode: Option<BarrierInput>,
    ) -> Result<(), GranularError> {
        let at = At {
            entity: b,
            panel: 0,
        };
        self.rows(BARRIER, name, at, &[("name", name)]);
        if self.water {
            self.rows(WATER_BARRIER, name, at, &[("name", name)]);
        }
        for (p, label) in panel_labels(name, counts, self.d)?.iter().enumerate() {
            let at = At {
                entity: b,
                panel: p,
            };
            let prefix = format!("{name}.{label}");
            self.rows(PANEL, &prefix, at, &[("name", name), ("label", label)]);
            if self.water {
                self.rows(
                    WATER_PANEL,
                    &prefix,
                    at,
                    &[("name", name), ("label", label)],
                );
            }
        }
        let inputs = match mode {
            Some(BarrierInput::Displacement) => Some(&DISPLACEMENT_INPUT),
            Some(BarrierInput::Velocity) => Some(&VELOCITY_INPUT),
            None => None,
        };
        self.rows(inputs, name, at, &[("name", name)]);
        Ok(())
    }

    /// The energies and step counts.
    fn totals(&mut self) {
        let energy = Unit::Energy.of(self.d);
        let totals = [
            (
                Variable::output(
                    "kinetic_energy.fine",
                    energy,
                    "kinetic energy of the fine grains",
                ),
                Slot::KineticFine,
            ),
            (
                Variable::output(
                    "kinetic_energy.coarse",
                    energy,
                    "kinetic energy of the coarse grains",
                ),
                Slot::KineticCoarse,
            ),
            (
                Variable::output("steps.fine", None, "fine solver steps taken so far")
                    .of_kind(Kind::Integer),
                Slot::StepsFine,
            ),
            (
                Variable::output("steps.coarse", None, "coarse sub-steps taken so far")
                    .of_kind(Kind::Integer),
                Slot::StepsCoarse,
            ),
        ];
        for (v, s) in totals {
            self.push(v, s);
        }
        if self.water {
            let v = Variable::output(
                "kinetic_energy.water",
                energy,
                "kinetic energy of the water",
            );
            self.push(v, Slot::KineticWater);
        }
    }

    /// The simulation settings a master may change before initialisation.
    fn settings(&mut self, s: &SimulationSpec) {
        let scene = |path: &str| Slot::SceneValue(path.to_string());
        let multi = (s.time_stepping_name() == "multi-rate") as u8 as f64;
        let settings = [
            (
                Variable::parameter(
                    "particle_spacing",
                    Some("m"),
                    "initial particle spacing dp",
                    s.dp,
                ),
                scene("simulation.dp"),
            ),
            (
                Variable::parameter(
                    "memory_budget",
                    None,
                    "memory budget in bytes: a scene estimated to need more is refused at \
                     initialisation (0: 80 % of the available memory)",
                    s.memory_budget,
                ),
                scene("simulation.memory_budget"),
            ),
            (
                Variable::parameter(
                    "cfl",
                    None,
                    "CFL number of the fine time step, Eq. (51)",
                    s.cfl,
                ),
                scene("simulation.cfl"),
            ),
            (
                Variable::parameter(
                    "multi_rate",
                    None,
                    "multi-rate stepping (true) or one Δt for all grains (false)",
                    multi,
                )
                .of_kind(Kind::Boolean),
                Slot::MultiRate,
            ),
            (
                Variable::parameter(
                    "ipc.enabled",
                    None,
                    "publish every particle at each communication point over iceoryx2 \
                     (docs/ipc.md)",
                    0.0,
                )
                .of_kind(Kind::Boolean),
                Slot::IpcEnabled,
            ),
            (
                Variable::text_parameter(
                    "ipc.service",
                    "particle service: an instance name (granmix/<name>/particles) or a full \
                     service name; empty: the FMU instance name",
                    "",
                ),
                Slot::IpcService,
            ),
            (
                Variable::text_parameter(
                    "record.path",
                    "record particles, bodies, loads and energies at each communication \
                     point to this MCAP file; empty: no recording",
                    "",
                ),
                Slot::RecordPath,
            ),
        ];
        for (v, slot) in settings {
            self.push(v, slot);
        }
    }
}

/// The labels of the panels of barrier `barrier` with `counts` panels per direction
/// ([`panel_labels`](granmix_core::run::sample::panel_labels)).
fn panel_labels(barrier: &str, counts: &[usize], d: usize) -> Result<Vec<String>, GranularError> {
    granmix_core::run::sample::panel_labels(counts).ok_or_else(|| GranularError::PanelCounts {
        barrier: barrier.to_string(),
        counts: d - 1,
    })
}

/// The variable table of `loaded`, built as `sim`.
pub fn build_table(loaded: &LoadedScene, sim: &AnySimulation) -> Result<Table, GranularError> {
    let scene = &loaded.scene;
    let mut t = Builder {
        d: sim.dimension(),
        water: sim.has_water(),
        table: Table {
            variables: Vec::new(),
            slots: Vec::new(),
            inputs: Vec::new(),
        },
    };
    for (b, name) in sim.barrier_names().iter().enumerate() {
        let spec = scene.barriers.iter().find(|w| &w.name == name);
        let mode = spec.and_then(|w| w.input);
        if mode.is_some() != sim.barrier_driven(b) {
            return Err(GranularError::InputFlag {
                barrier: name.clone(),
            });
        }
        t.table.inputs.push(mode);
        let counts = spec.and_then(|w| w.panels.clone()).unwrap_or_default();
        t.barrier(b, name, &counts, mode)?;
    }
    for (i, name) in sim.body_names().iter().enumerate() {
        let at = At {
            entity: i,
            panel: 0,
        };
        t.rows(BODY, name, at, &[("name", name)]);
    }
    t.totals();
    t.params(&MATERIALS, &scene.materials);
    t.params(&SOLIDS, &scene.solids);
    t.settings(&scene.simulation);
    Ok(t.table)
}

#[cfg(test)]
mod tests {
    use super::{build_table, fill};
    use granmix_core::input::load_scene_str;
    use granmix_core::AnySimulation;

    #[test]
    fn fill_replaces_known_keys_once() {
        let v = [("name", "a {axis} b"), ("axis", "x")];
        assert_eq!(
            fill("`{name}` {axis} {other}", &v),
            "`a {axis} b` x {other}"
        );
        assert_eq!(fill("{", &v), "{");
        assert_eq!(fill("{name", &v), "{name");
    }

    /// A μ(I) material has no friction angle to tune: its table carries no
    /// `friction_angle` parameter (setting one would make the scene invalid), and a
    /// Drucker–Prager material's does.
    #[test]
    fn a_mu_i_material_has_no_friction_angle_parameter() {
        let text = |material: &str| {
            format!(
                "[simulation]\ndimension = 2\ngravity = [0.0, -9.81]\nend_time = 0.1\n\
                 dp = 0.01\noutput_interval = 0.01\n\n[[materials]]\nname = \"soil\"\n\
                 density = 1500.0\nyoungs_modulus = 1e6\npoisson_ratio = 0.3\n{material}\n\n\
                 [[regions]]\nname = \"block\"\nmaterial = \"soil\"\n\
                 shape = {{ type = \"box\", min = [0.0, 0.0], max = [0.05, 0.05] }}\n"
            )
        };
        for (material, has) in [
            ("friction_angle = 30.0", true),
            (
                "mu_i = { mu_s = 0.383, mu_2 = 0.643, i_0 = 0.279, grain_diameter = 5e-4, \
                 grain_density = 2500.0 }",
                false,
            ),
        ] {
            let loaded = load_scene_str(&text(material), "soil.toml", &[]).unwrap();
            let sim = AnySimulation::new(&loaded).unwrap();
            let table = build_table(&loaded, &sim).unwrap();
            let names: Vec<_> = table.variables.iter().map(|v| v.name.as_str()).collect();
            assert_eq!(
                names.contains(&"materials.soil.friction_angle"),
                has,
                "{material}: {names:?}"
            );
            assert!(names.contains(&"materials.soil.density"), "{names:?}");
        }
    }
}
