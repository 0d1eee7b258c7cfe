//! The variable table of a granular scene: the outputs are the observables core gives
//! an FMU variable ([`observables::all`], [`Observable::fmu`]), expanded in this order:
//! each barrier (its outputs, its panels' outputs, its inputs when driven), each body,
//! the energies and step counts; then one [`Param`] per parameter of a material or a
//! solid ([`Params`]), then the simulation settings. The value reference of a variable
//! is its index in the table; variability follows from causality and base type
//! ([`crate::xml`]).

use crate::error::GranularError;
use crate::variables::{Causality, Kind, Variable};
use granmix_core::input::LoadedScene;
use granmix_core::run::observables::{self, Layout, Observable, Owner};
use granmix_core::scene::{BarrierInput, MaterialSpec, SimulationSpec, SolidSpec};
use granmix_core::AnySimulation;

const AXES: [&str; 3] = ["x", "y", "z"];

/// Where a variable's value lives.
#[derive(Clone, Debug, PartialEq)]
pub enum Slot {
    /// Observable `k` of [`Table::outputs`].
    Output(usize),
    /// Component `k` of the input of driven barrier `b`.
    BarrierInput(usize, usize),
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
    /// The observables behind the outputs ([`Slot::Output`]).
    pub outputs: Vec<Observable>,
    /// Input mode of each barrier (None: not driven).
    pub inputs: Vec<Option<BarrierInput>>,
}

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

/// The table as it is built.
struct Builder {
    /// Dimension of the scene.
    d: usize,
    table: Table,
    /// Every observable of the scene; those with an FMU variable are taken as outputs.
    observables: Vec<Observable>,
}

impl Builder {
    fn push(&mut self, variable: Variable, slot: Slot) {
        self.table.variables.push(variable);
        self.table.slots.push(slot);
    }

    /// The outputs of `owner`, in the observables' order.
    fn outputs(&mut self, owner: Owner) {
        let (mine, rest) = std::mem::take(&mut self.observables)
            .into_iter()
            .partition(|o| o.fmu.as_ref().is_some_and(|f| f.owner == owner));
        self.observables = rest;
        for o in mine {
            let f = o.fmu.as_ref().expect("an FMU output");
            let kind = if o.integer { Kind::Integer } else { Kind::Real };
            let v = Variable::output(f.name.clone(), o.unit.fmi(self.d), f.description.clone())
                .of_kind(kind);
            self.push(v, Slot::Output(self.table.outputs.len()));
            self.table.outputs.push(o);
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

    /// The outputs of barrier `b` named `name` (its panels' among them), and its inputs
    /// when it is driven in `mode`.
    fn barrier(&mut self, b: usize, name: &str, mode: Option<BarrierInput>) {
        self.outputs(Owner::Barrier(b));
        let (key, unit, what) = match mode {
            Some(BarrierInput::Displacement) => (
                "displacement",
                "m",
                "rigid displacement from the initial place, reached at the end of the step",
            ),
            Some(BarrierInput::Velocity) => ("velocity", "m/s", "rigid velocity during the step"),
            None => return,
        };
        for (k, axis) in AXES.iter().enumerate().take(self.d) {
            let variable = Variable {
                causality: Causality::Input,
                start: Some(0.0),
                ..Variable::output(
                    format!("{name}.{key}.{axis}"),
                    Some(unit),
                    format!("barrier `{name}`: {what}, {axis} component"),
                )
            };
            self.push(variable, Slot::BarrierInput(b, k));
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
        table: Table {
            variables: Vec::new(),
            slots: Vec::new(),
            outputs: Vec::new(),
            inputs: Vec::new(),
        },
        observables: observables::all(&Layout::of(sim)),
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
        panel_labels(name, &counts, t.d)?;
        t.barrier(b, name, mode);
    }
    for b in 0..sim.body_names().len() {
        t.outputs(Owner::Body(b));
    }
    t.outputs(Owner::Totals);
    t.params(&MATERIALS, &scene.materials);
    t.params(&SOLIDS, &scene.solids);
    t.settings(&scene.simulation);
    Ok(t.table)
}

#[cfg(test)]
mod tests {
    use super::build_table;
    use granmix_core::input::load_scene_str;
    use granmix_core::AnySimulation;

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
