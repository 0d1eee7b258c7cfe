//! `modelDescription.xml` generated from a variable table (FMI 2.0 Co-Simulation).

use crate::variables::{Causality, Kind, Variable};
use std::fmt::Write;

/// Model-level facts written into the description.
#[derive(Clone, Debug)]
pub struct ModelInfo {
    pub model_name: String,
    /// Name of the shared library in `binaries/linux64/` (without `.so`).
    pub model_identifier: String,
    pub guid: String,
    pub description: String,
    /// Default experiment: stop time and communication step (s).
    pub stop_time: f64,
    pub step_size: f64,
}

/// Exponents of kg, m, s, rad of the units granmix uses.
fn base_unit(unit: &str) -> [i32; 4] {
    match unit {
        "m" => [0, 1, 0, 0],
        "m/s" => [0, 1, -1, 0],
        "s" => [0, 0, 1, 0],
        "kg" => [1, 0, 0, 0],
        "kg/m" => [1, -1, 0, 0],
        "kg/m3" => [1, -3, 0, 0],
        "kg/m2" => [1, -2, 0, 0],
        "N" | "J/m" | "N.m/m" => [1, 1, -2, 0],
        "N/m" => [1, 0, -2, 0],
        "N/m2" | "Pa" => [1, -1, -2, 0],
        "N.m" | "J" => [1, 2, -2, 0],
        "N.s" => [1, 1, -1, 0],
        "N.s/m" => [1, 0, -1, 0],
        "N.s/m2" => [1, -1, -1, 0],
        "N/m/m" => [1, -1, -2, 0],
        "rad" => [0, 0, 0, 1],
        "rad/s" => [0, 0, -1, 1],
        "deg" => [0, 0, 0, 1],
        other => panic!("unit `{other}` missing from the unit table in xml.rs"),
    }
}

/// Quote a structured-name segment unless it is a plain identifier.
fn segment(s: &str) -> String {
    let ident = s
        .chars()
        .next()
        .is_some_and(|c| c.is_ascii_alphabetic() || c == '_')
        && s.chars().all(|c| c.is_ascii_alphanumeric() || c == '_');
    if ident {
        s.to_string()
    } else {
        format!("'{}'", s.replace('\\', "\\\\").replace('\'', "\\'"))
    }
}

/// A variable name under the `structured` naming convention.
pub fn structured_name(name: &str) -> String {
    name.split('.').map(segment).collect::<Vec<_>>().join(".")
}

fn esc(s: &str) -> String {
    s.replace('&', "&amp;")
        .replace('<', "&lt;")
        .replace('>', "&gt;")
        .replace('"', "&quot;")
}

/// Shortest decimal that reads back to the same f64.
fn num(x: f64) -> String {
    format!("{x:?}")
}

/// The whole `modelDescription.xml`.
pub fn model_description(info: &ModelInfo, table: &[Variable]) -> String {
    let mut x = String::new();
    let w = &mut x;
    let _ = writeln!(w, r#"<?xml version="1.0" encoding="UTF-8"?>"#);
    let _ = writeln!(
        w,
        r#"<fmiModelDescription fmiVersion="2.0" modelName="{}" guid="{}" description="{}" generationTool="granmix {}" variableNamingConvention="structured" numberOfEventIndicators="0">"#,
        esc(&info.model_name),
        esc(&info.guid),
        esc(&info.description),
        env!("CARGO_PKG_VERSION"),
    );
    let _ = writeln!(
        w,
        r#"  <CoSimulation modelIdentifier="{}" canHandleVariableCommunicationStepSize="true" canInterpolateInputs="false" canGetAndSetFMUstate="true" canSerializeFMUstate="true" canNotUseMemoryManagementFunctions="true"/>"#,
        esc(&info.model_identifier)
    );
    unit_definitions(w, table);
    let _ = writeln!(
        w,
        r#"  <DefaultExperiment startTime="0.0" stopTime="{}" stepSize="{}"/>"#,
        num(info.stop_time),
        num(info.step_size)
    );
    let _ = writeln!(w, "  <ModelVariables>");
    for (vr, v) in table.iter().enumerate() {
        scalar_variable(w, vr, v);
    }
    let _ = writeln!(w, "  </ModelVariables>");
    model_structure(w, table);
    let _ = writeln!(w, "</fmiModelDescription>");
    x
}

/// `<UnitDefinitions>`: each unit of the table once, in sorted order (none: no element).
fn unit_definitions(w: &mut String, table: &[Variable]) {
    let mut units: Vec<&str> = table.iter().filter_map(|v| v.unit).collect();
    units.sort();
    units.dedup();
    if units.is_empty() {
        return;
    }
    let _ = writeln!(w, "  <UnitDefinitions>");
    for u in units {
        let [kg, m, s, rad] = base_unit(u);
        let mut attrs = String::new();
        for (k, e) in [("kg", kg), ("m", m), ("s", s), ("rad", rad)] {
            if e != 0 {
                let _ = write!(attrs, r#" {k}="{e}""#);
            }
        }
        let factor = if u == "deg" {
            format!(r#" factor="{}""#, num(std::f64::consts::PI / 180.0))
        } else {
            String::new()
        };
        let _ = writeln!(
            w,
            r#"    <Unit name="{}"><BaseUnit{attrs}{factor}/></Unit>"#,
            esc(u)
        );
    }
    let _ = writeln!(w, "  </UnitDefinitions>");
}

/// The `<ScalarVariable>` of variable `v` with value reference `vr`.
fn scalar_variable(w: &mut String, vr: usize, v: &Variable) {
    let (causality, variability) = match (v.causality, v.kind) {
        (Causality::Parameter, _) => ("parameter", "fixed"),
        (Causality::Input, Kind::Real) => ("input", "continuous"),
        (Causality::Input, _) => ("input", "discrete"),
        (Causality::Output, Kind::Real) => ("output", "continuous"),
        (Causality::Output, _) => ("output", "discrete"),
    };
    let _ = writeln!(
        w,
        r#"    <!-- {} -->
    <ScalarVariable name="{}" valueReference="{vr}" causality="{causality}" variability="{variability}" description="{}">"#,
        vr + 1,
        esc(&structured_name(&v.name)),
        esc(&v.description)
    );
    let mut attrs = String::new();
    if let Some(u) = v.unit {
        let _ = write!(attrs, r#" unit="{}""#, esc(u));
    }
    if let Some(s) = v.start {
        let s = match v.kind {
            Kind::Real => num(s),
            Kind::Integer => format!("{}", s as i64),
            Kind::Boolean => (if s != 0.0 { "true" } else { "false" }).to_string(),
            Kind::String => String::new(),
        };
        let _ = write!(attrs, r#" start="{s}""#);
    }
    let tag = match v.kind {
        Kind::Real => "Real",
        Kind::Integer => {
            attrs.clear(); // no units on integers
            if let Some(s) = v.start {
                let _ = write!(attrs, r#" start="{}""#, s as i64);
            }
            "Integer"
        }
        Kind::Boolean => "Boolean",
        Kind::String => {
            attrs.clear(); // no units on strings
            let text = v.start_text.as_deref().unwrap_or("");
            let _ = write!(attrs, r#" start="{}""#, esc(text));
            "String"
        }
    };
    let _ = writeln!(w, "      <{tag}{attrs}/>\n    </ScalarVariable>");
}

/// `<ModelStructure>`: every output is an output and an initial unknown.
fn model_structure(w: &mut String, table: &[Variable]) {
    let _ = writeln!(w, "  <ModelStructure>");
    let outputs: Vec<usize> = table
        .iter()
        .enumerate()
        .filter(|(_, v)| v.causality == Causality::Output)
        .map(|(i, _)| i + 1)
        .collect();
    for section in ["Outputs", "InitialUnknowns"] {
        if outputs.is_empty() {
            continue;
        }
        let _ = writeln!(w, "    <{section}>");
        for i in &outputs {
            let _ = writeln!(w, r#"      <Unknown index="{i}"/>"#);
        }
        let _ = writeln!(w, "    </{section}>");
    }
    let _ = writeln!(w, "  </ModelStructure>");
}

/// GUID derived from `content`: 128-bit FNV-1a, written as a braced UUID.
pub fn guid_of(content: &[u8]) -> String {
    let mut h: u128 = 0x6c62272e07bb014262b821756295c58d;
    let prime: u128 = 0x0000000001000000000000000000013B;
    for &b in content {
        h ^= b as u128;
        h = h.wrapping_mul(prime);
    }
    let hex = format!("{h:032x}");
    format!(
        "{{{}-{}-{}-{}-{}}}",
        &hex[0..8],
        &hex[8..12],
        &hex[12..16],
        &hex[16..20],
        &hex[20..32]
    )
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn names_quote_non_identifiers() {
        assert_eq!(structured_name("barrier.force.x"), "barrier.force.x");
        assert_eq!(structured_name("my-wall.force.x"), "'my-wall'.force.x");
        assert_eq!(structured_name("post_1.force"), "post_1.force");
    }

    #[test]
    fn guid_depends_on_content() {
        assert_eq!(guid_of(b"a"), guid_of(b"a"));
        assert_ne!(guid_of(b"a"), guid_of(b"b"));
        assert_eq!(guid_of(b"a").len(), 38);
    }
}
