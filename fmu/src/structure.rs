//! Structural partner models for coupling with granmix (`models/structures/*.toml`):
//! a single-DOF mass–spring–damper post and a flexible barrier of N posts coupled by
//! springs. Each communication step is integrated exactly for the force held constant
//! over the step: y(t + h) = exp(A h) y(t) on the state augmented with the forcing.

use crate::envelope::{self, Encoding, ModelKind};
use crate::error::{ModelError, ReadError, StateError, StepError, StructureError};
use crate::model::bytes::{Reader, Writer};
use crate::model::{check_step, Model};
use crate::state::Place;
use crate::variables::{Causality, Variable};
use crate::xml::{self, ModelInfo};
use nalgebra::{DMatrix, DVector};
use serde::Deserialize;
use std::path::Path;
use std::sync::Arc;

/// `[structure]` of a structure file.
#[derive(Debug, Clone, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct StructureSpec {
    /// Model name shown by importers.
    pub name: String,
    /// `"post"`: one mass–spring–damper; `"chain"`: `posts` masses, each held by its own
    /// spring and damper and coupled to its neighbours by `coupling_stiffness`.
    pub kind: StructureKind,
    /// Mass of each post (kg; kg/m when coupled to a 2D scene).
    pub mass: f64,
    /// Spring stiffness to the ground (N/m; N/m per metre in 2D).
    pub stiffness: f64,
    /// Viscous damping to the ground (N·s/m).
    pub damping: f64,
    /// Chain only: number of posts (≥ 2).
    #[serde(default)]
    pub posts: Option<usize>,
    /// Chain only: stiffness of the springs between neighbouring posts (N/m).
    #[serde(default)]
    pub coupling_stiffness: Option<f64>,
    /// Default experiment: stop time and communication step (s).
    pub stop_time: f64,
    pub step_size: f64,
}

/// Which structural model.
#[derive(Debug, Clone, Copy, Deserialize, PartialEq, Eq)]
#[serde(rename_all = "lowercase")]
pub enum StructureKind {
    Post,
    Chain,
}

/// A structure file: one `[structure]` table.
#[derive(Debug, Clone, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct StructureFile {
    pub structure: StructureSpec,
}

impl StructureFile {
    /// Parse and check a structure file; errors name the file and key.
    pub fn parse(text: &str, file: &str) -> Result<Self, StructureError> {
        let f: StructureFile = toml::from_str(text).map_err(|error| StructureError::Toml {
            file: file.to_string(),
            error,
        })?;
        let s = &f.structure;
        let bad = |key: &'static str, why: &'static str| {
            Err(StructureError::Key {
                file: file.to_string(),
                key,
                why,
            })
        };
        for (key, v) in [
            ("mass", s.mass),
            ("stop_time", s.stop_time),
            ("step_size", s.step_size),
        ] {
            if !(v > 0.0 && v.is_finite()) {
                return bad(key, "must be positive");
            }
        }
        for (key, v) in [("stiffness", s.stiffness), ("damping", s.damping)] {
            if !(v >= 0.0 && v.is_finite()) {
                return bad(key, "must be zero or positive");
            }
        }
        match s.kind {
            StructureKind::Post => {
                if s.posts.is_some() || s.coupling_stiffness.is_some() {
                    return bad(
                        "kind",
                        "`posts` and `coupling_stiffness` belong to kind = \"chain\"",
                    );
                }
            }
            StructureKind::Chain => {
                if !s.posts.is_some_and(|n| (2..=64).contains(&n)) {
                    return bad("posts", "a chain needs 2 to 64 posts");
                }
                if !s
                    .coupling_stiffness
                    .is_some_and(|k| k >= 0.0 && k.is_finite())
                {
                    return bad("coupling_stiffness", "a chain needs a stiffness ≥ 0");
                }
            }
        }
        Ok(f)
    }

    /// Number of degrees of freedom.
    pub fn dofs(&self) -> usize {
        self.structure.posts.unwrap_or(1)
    }
}

/// Parameter slots after the per-post variables: m, k, c (and k_coupling for chains).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
enum Param {
    Mass,
    Stiffness,
    Damping,
    Coupling,
}

struct Layout {
    variables: Vec<Variable>,
    /// Value reference of each post's force input, displacement, velocity and impulse.
    force: Vec<usize>,
    disp: Vec<usize>,
    vel: Vec<usize>,
    impulse: Vec<usize>,
    params: Vec<(usize, Param)>,
}

fn layout(f: &StructureFile) -> Layout {
    let n = f.dofs();
    let s = &f.structure;
    let mut l = Layout {
        variables: Vec::new(),
        force: Vec::new(),
        disp: Vec::new(),
        vel: Vec::new(),
        impulse: Vec::new(),
        params: Vec::new(),
    };
    for i in 0..n {
        let p = if n == 1 {
            String::new()
        } else {
            format!("post_{i}.")
        };
        let who = if n == 1 {
            "the post".to_string()
        } else {
            format!("post {i}")
        };
        l.force.push(l.variables.len());
        l.variables.push(Variable::input(
            format!("{p}force"),
            Some("N"),
            format!("load on {who}, held constant over the step"),
            0.0,
        ));
        l.disp.push(l.variables.len());
        l.variables.push(Variable::output(
            format!("{p}displacement"),
            Some("m"),
            format!("displacement of {who}"),
        ));
        l.vel.push(l.variables.len());
        l.variables.push(Variable::output(
            format!("{p}velocity"),
            Some("m/s"),
            format!("velocity of {who}"),
        ));
        l.impulse.push(l.variables.len());
        l.variables.push(Variable::output(
            format!("{p}impulse"),
            Some("N.s"),
            format!("impulse received by {who} from its force input since the start"),
        ));
    }
    let mut param = |name: &str, unit, what: &str, v: f64, p: Param| {
        l.params.push((l.variables.len(), p));
        l.variables
            .push(Variable::parameter(name, Some(unit), what, v));
    };
    param("m", "kg", "mass of each post", s.mass, Param::Mass);
    param(
        "k",
        "N/m",
        "stiffness of each post's spring to the ground",
        s.stiffness,
        Param::Stiffness,
    );
    param(
        "c",
        "N.s/m",
        "damping of each post to the ground",
        s.damping,
        Param::Damping,
    );
    if let Some(kc) = s.coupling_stiffness {
        param(
            "k_coupling",
            "N/m",
            "stiffness of the springs between neighbouring posts",
            kc,
            Param::Coupling,
        );
    }
    l
}

/// A structural model instance.
#[derive(Clone)]
pub struct Structure {
    file: Arc<StructureFile>,
    text: Arc<String>,
    layout: Arc<Layout>,
    values: Vec<f64>,
    x: Vec<f64>,
    v: Vec<f64>,
    impulse: Vec<f64>,
    time: f64,
    initialised: bool,
}

/// GUID of a structural FMU: derived from the structure file.
pub fn guid(text: &str) -> String {
    let mut content = format!("granmix-structure {}\n", env!("CARGO_PKG_VERSION")).into_bytes();
    content.extend_from_slice(text.as_bytes());
    xml::guid_of(&content)
}

impl Structure {
    /// Load `structure.toml` from the FMU's resources directory.
    pub fn from_resources(dir: &Path) -> Result<Self, StructureError> {
        let path = dir.join("structure.toml");
        let file = path.display().to_string();
        let text = ReadError::read_to_string(path)?;
        Self::new(&text, &file)
    }

    /// Build from the text of structure file `file` (named in errors).
    pub fn new(text: &str, file: &str) -> Result<Self, StructureError> {
        let f = StructureFile::parse(text, file)?;
        let layout = layout(&f);
        let n = f.dofs();
        Ok(Structure {
            values: layout
                .variables
                .iter()
                .map(|v| v.start.unwrap_or(0.0))
                .collect(),
            layout: Arc::new(layout),
            file: Arc::new(f),
            text: Arc::new(text.to_string()),
            x: vec![0.0; n],
            v: vec![0.0; n],
            impulse: vec![0.0; n],
            time: 0.0,
            initialised: false,
        })
    }

    pub fn info(&self, model_identifier: &str) -> ModelInfo {
        let s = &self.file.structure;
        ModelInfo {
            model_name: s.name.clone(),
            model_identifier: model_identifier.to_string(),
            guid: guid(&self.text),
            description: match s.kind {
                StructureKind::Post => "single-DOF mass-spring-damper post".to_string(),
                StructureKind::Chain => format!(
                    "flexible barrier: {} posts coupled by springs",
                    self.file.dofs()
                ),
            },
            stop_time: s.stop_time,
            step_size: s.step_size,
        }
    }

    fn param(&self, p: Param) -> f64 {
        let (i, _) = self
            .layout
            .params
            .iter()
            .find(|(_, q)| *q == p)
            .copied()
            .unwrap_or((usize::MAX, p));
        self.values.get(i).copied().unwrap_or(0.0)
    }

    /// exp(A h) of the system augmented with the constant forcing: state (x, v, 1).
    fn propagator(&self, h: f64) -> DMatrix<f64> {
        let n = self.x.len();
        let (m, k, c, kc) = (
            self.param(Param::Mass),
            self.param(Param::Stiffness),
            self.param(Param::Damping),
            self.param(Param::Coupling),
        );
        let mut a = DMatrix::<f64>::zeros(2 * n + 1, 2 * n + 1);
        for i in 0..n {
            a[(i, n + i)] = 1.0;
            let mut kii = k;
            for j in [i.wrapping_sub(1), i + 1] {
                if j < n {
                    kii += kc;
                    a[(n + i, j)] = kc / m;
                }
            }
            a[(n + i, i)] = -kii / m;
            a[(n + i, n + i)] = -c / m;
            a[(n + i, 2 * n)] = self.values[self.layout.force[i]] / m;
        }
        (a * h).exp()
    }
}

impl Model for Structure {
    fn variables(&self) -> &[Variable] {
        &self.layout.variables
    }

    fn get(&mut self, vr: u32) -> Result<f64, ModelError> {
        let i = vr as usize;
        let l = &self.layout;
        let find = |list: &[usize]| list.iter().position(|&j| j == i);
        Ok(if let Some(p) = find(&l.disp) {
            self.x[p]
        } else if let Some(p) = find(&l.vel) {
            self.v[p]
        } else if let Some(p) = find(&l.impulse) {
            self.impulse[p]
        } else {
            self.values[i]
        })
    }

    fn check(&self, vr: u32, value: f64) -> Result<(), ModelError> {
        let v = &self.layout.variables[vr as usize];
        if !value.is_finite() {
            return Err(ModelError::NotFinite {
                name: v.name.clone(),
                value,
            });
        }
        if v.causality == Causality::Parameter {
            let p = self
                .layout
                .params
                .iter()
                .find(|(j, _)| *j == vr as usize)
                .map(|(_, p)| *p);
            let ok = match p {
                Some(Param::Mass) => value > 0.0,
                _ => value >= 0.0,
            };
            if !ok {
                return Err(ModelError::OutOfRange {
                    name: v.name.clone(),
                    value,
                });
            }
        }
        Ok(())
    }

    fn values_mut(&mut self) -> &mut [f64] {
        &mut self.values
    }

    fn exit_initialization(&mut self) -> Result<(), ModelError> {
        self.initialised = true;
        Ok(())
    }

    fn set_start_time(&mut self, start: f64) -> Result<(), ModelError> {
        self.time = start;
        Ok(())
    }

    fn initialised(&self) -> bool {
        self.initialised
    }

    fn do_step(&mut self, t: f64, h: f64) -> Result<(), StepError> {
        check_step(t, h, self.time)?;
        let n = self.x.len();
        let e = self.propagator(h);
        let mut y = DVector::<f64>::zeros(2 * n + 1);
        for i in 0..n {
            y[i] = self.x[i];
            y[n + i] = self.v[i];
        }
        y[2 * n] = 1.0;
        let y = e * y;
        for i in 0..n {
            self.x[i] = y[i];
            self.v[i] = y[n + i];
            self.impulse[i] += self.values[self.layout.force[i]] * h;
        }
        if y.iter().any(|z| !z.is_finite()) {
            return Err(StepError::Failed(
                StructureError::NonFinite {
                    name: self.file.structure.name.clone(),
                    t: t + h,
                }
                .into(),
            ));
        }
        self.time = t + h;
        Ok(())
    }

    fn time(&self) -> f64 {
        self.time
    }

    fn reset(&mut self) -> Result<(), ModelError> {
        *self = Structure::new(&self.text, "structure.toml")?;
        Ok(())
    }

    fn snapshot(&self) -> Box<dyn Model> {
        Box::new(self.clone())
    }

    fn to_bytes(&self, place: &Place) -> Result<Vec<u8>, ModelError> {
        let mut w = Writer::default();
        w.f64(self.time);
        for list in [&self.values, &self.x, &self.v, &self.impulse] {
            w.u64(list.len() as u64);
            for &x in list.iter() {
                w.f64(x);
            }
        }
        Ok(envelope::seal(
            ModelKind::Structure,
            &guid(&self.text),
            Encoding::Raw,
            place,
            &w.0,
        )?)
    }

    fn restore_bytes(&self, bytes: &[u8]) -> Result<(Box<dyn Model>, Option<Place>), ModelError> {
        let opened = envelope::open(bytes, ModelKind::Structure, &guid(&self.text))?;
        let payload = opened.payload;
        let mut r = Reader::new(&payload);
        let mut m = self.clone();
        m.time = r.f64()?;
        for list in [&mut m.values, &mut m.x, &mut m.v, &mut m.impulse] {
            let n = r.u64()? as usize;
            if n != list.len() {
                return Err(StateError::ListLength {
                    found: n,
                    expected: list.len(),
                }
                .into());
            }
            for x in list.iter_mut() {
                *x = r.f64()?;
            }
        }
        Ok((Box::new(m), opened.place))
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    const POST: &str = r#"
[structure]
name = "post"
kind = "post"
mass = 2.0
stiffness = 800.0
damping = 0.0
stop_time = 1.0
step_size = 0.01
"#;

    #[test]
    fn post_matches_the_undamped_oscillator() {
        let mut s = Structure::new(POST, "post.toml").unwrap();
        s.set(0, 40.0).unwrap(); // force → static deflection F/k = 0.05 m
        let (h, steps) = (0.01, 37);
        for i in 0..steps {
            s.do_step(i as f64 * h, h).unwrap();
        }
        let w = (800.0f64 / 2.0).sqrt();
        let t = steps as f64 * h;
        let x = 0.05 * (1.0 - (w * t).cos());
        assert!((s.x[0] - x).abs() < 1e-12, "{} vs {x}", s.x[0]);
        assert!((s.impulse[0] - 40.0 * t).abs() < 1e-12);
    }

    #[test]
    fn free_mass_receives_the_impulse() {
        let text = POST.replace("800.0", "0.0");
        let mut s = Structure::new(&text, "post.toml").unwrap();
        let mut t = 0.0;
        for (i, f) in [3.0, -1.0, 7.5, 0.25].iter().enumerate() {
            s.set(0, *f).unwrap();
            let h = 0.003 * (i + 1) as f64;
            s.do_step(t, h).unwrap();
            t += h;
        }
        let p = 2.0 * s.v[0];
        assert!((p - s.impulse[0]).abs() <= 1e-12 * s.impulse[0].abs());
    }

    #[test]
    fn chain_statics() {
        let text = POST
            .replace(
                "kind = \"post\"",
                "kind = \"chain\"\nposts = 3\ncoupling_stiffness = 400.0",
            )
            .replace("damping = 0.0", "damping = 200.0");
        let mut s = Structure::new(&text, "chain.toml").unwrap();
        s.set(0, 10.0).unwrap(); // post_0.force
        for i in 0..2000 {
            s.do_step(i as f64 * 0.01, 0.01).unwrap();
        }
        // K x = F with K = [[k+kc, -kc, 0], [-kc, k+2kc, -kc], [0, -kc, k+kc]]
        let (k, kc) = (800.0, 400.0);
        let km = nalgebra::Matrix3::new(k + kc, -kc, 0.0, -kc, k + 2.0 * kc, -kc, 0.0, -kc, k + kc);
        let x = km.try_inverse().unwrap() * nalgebra::Vector3::new(10.0, 0.0, 0.0);
        for i in 0..3 {
            assert!(
                (s.x[i] - x[i]).abs() < 1e-9,
                "post {i}: {} vs {}",
                s.x[i],
                x[i]
            );
        }
    }
}
