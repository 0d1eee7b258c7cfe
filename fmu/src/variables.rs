//! The value-reference table: one list of variables drives both `modelDescription.xml`
//! ([`crate::xml`]) and the run-time lookups of the FFI layer.

/// FMI 2.0 base type of a scalar variable.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Kind {
    Real,
    Integer,
    Boolean,
    String,
}

/// FMI 2.0 causality (the subset granmix uses).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Causality {
    /// Set before initialisation (variability `fixed`).
    Parameter,
    /// Set by the master between communication steps (variability `continuous`).
    Input,
    /// Computed by the FMU.
    Output,
}

/// One scalar variable. Its value reference is its index in the table.
#[derive(Clone, Debug, PartialEq)]
pub struct Variable {
    /// Structured name (`barrier.force.x`); segments that are not identifiers are quoted
    /// by [`crate::xml`].
    pub name: String,
    pub kind: Kind,
    pub causality: Causality,
    /// SI unit, e.g. `N/m`; `None` for dimensionless values.
    pub unit: Option<&'static str>,
    pub description: String,
    /// Start value: required for parameters and inputs, absent for outputs
    /// (String variables use [`Variable::start_text`]).
    pub start: Option<f64>,
    /// Start value of a String parameter.
    pub start_text: Option<String>,
}

impl Variable {
    /// A Real output.
    pub fn output(
        name: impl Into<String>,
        unit: Option<&'static str>,
        description: impl Into<String>,
    ) -> Self {
        Variable {
            name: name.into(),
            kind: Kind::Real,
            causality: Causality::Output,
            unit,
            description: description.into(),
            start: None,
            start_text: None,
        }
    }
    /// A Real input with start value `start`.
    pub fn input(
        name: impl Into<String>,
        unit: Option<&'static str>,
        description: impl Into<String>,
        start: f64,
    ) -> Self {
        Variable::output(name, unit, description).settable(Causality::Input, start)
    }
    /// A Real parameter with start value `start`.
    pub fn parameter(
        name: impl Into<String>,
        unit: Option<&'static str>,
        description: impl Into<String>,
        start: f64,
    ) -> Self {
        Variable::output(name, unit, description).settable(Causality::Parameter, start)
    }
    /// The same variable as one the master sets (`causality`), starting at `start`.
    fn settable(self, causality: Causality, start: f64) -> Self {
        Variable {
            causality,
            start: Some(start),
            ..self
        }
    }
    /// A String parameter with start value `start`.
    pub fn text_parameter(
        name: impl Into<String>,
        description: impl Into<String>,
        start: &str,
    ) -> Self {
        Variable {
            kind: Kind::String,
            causality: Causality::Parameter,
            start_text: Some(start.to_string()),
            ..Variable::output(name, None, description)
        }
    }
    /// The same variable with another base type.
    pub fn of_kind(self, kind: Kind) -> Self {
        Variable { kind, ..self }
    }
}

/// A value reference the table does not have, or has with another base type.
#[derive(Clone, Debug, PartialEq, Eq, thiserror::Error)]
pub enum LookupError {
    #[error("unknown value reference {vr} (the model has {count})")]
    Unknown { vr: u32, count: usize },
    #[error("value reference {vr} (`{name}`) is {kind:?}, not {wanted:?}")]
    WrongKind {
        vr: u32,
        name: String,
        kind: Kind,
        wanted: Kind,
    },
}

/// Find variable `vr` of base type `kind`, or say why not.
pub fn lookup(table: &[Variable], vr: u32, kind: Kind) -> Result<&Variable, LookupError> {
    let v = table.get(vr as usize).ok_or(LookupError::Unknown {
        vr,
        count: table.len(),
    })?;
    if v.kind != kind {
        return Err(LookupError::WrongKind {
            vr,
            name: v.name.clone(),
            kind: v.kind,
            wanted: kind,
        });
    }
    Ok(v)
}
