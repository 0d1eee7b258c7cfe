//! Names of scene entries (materials, regions, bodies, walls, probes, …; not the
//! free-text `simulation.name`): they become
//! CSV column headers (`<probe>.pressure`), FMU variable names (`<body>.force.x`) and
//! parts of file names, so they are limited to characters safe in all three: ASCII
//! letters, digits, `_` and `-`. A comma, quote, newline or NUL would break a header
//! into columns or rows of different widths.

use super::validate::{fail, Check};
use super::Scene;

/// Longest name (a column header holds the name and a suffix such as `.sigma_xx`).
pub const MAX_NAME_CHARS: usize = 64;

/// Why `name` is not a safe name, if it is not.
pub fn unsafe_name(name: &str) -> Option<String> {
    if name.is_empty() {
        return Some("a name must not be empty".into());
    }
    if name.chars().count() > MAX_NAME_CHARS {
        return Some(format!(
            "a name holds at most {MAX_NAME_CHARS} characters, this one {}",
            name.chars().count()
        ));
    }
    let bad = name
        .chars()
        .find(|c| !(c.is_ascii_alphanumeric() || *c == '_' || *c == '-'))?;
    Some(format!(
        "{:?} holds {:?}; names become CSV headers, FMU variable names and file names, so \
         they take only ASCII letters, digits, `_` and `-`",
        name, bad
    ))
}

/// Every name in the scene, with its key path.
fn names(s: &Scene) -> Vec<(String, &str)> {
    fn of<'a, T>(
        key: &str,
        list: &'a [T],
        name: impl Fn(&'a T) -> &'a str,
    ) -> Vec<(String, &'a str)> {
        list.iter()
            .enumerate()
            .map(|(i, x)| (format!("{key}[{i}].name"), name(x)))
            .collect()
    }
    let mut v = Vec::new();
    v.extend(of("materials", &s.materials, |m| &m.name));
    v.extend(of("regions", &s.regions, |m| &m.name));
    v.extend(of("solids", &s.solids, |m| &m.name));
    v.extend(of("bodies", &s.bodies, |m| &m.name));
    v.extend(of("rock_fills", &s.rock_fills, |m| &m.name));
    v.extend(of("walls", &s.walls, |m| &m.name));
    v.extend(of("barriers", &s.barriers, |m| &m.name));
    v.extend(of("containers", &s.containers, |m| &m.name));
    v.extend(of("probes", &s.probes, |m| &m.name));
    v.extend(of("gauges", &s.gauges, |m| &m.name));
    if let Some(w) = &s.water {
        v.extend(of("water.regions", &w.regions, |m| &m.name));
        v.extend(of("water.inflows", &w.inflows, |m| &m.name));
        v.extend(of("water.outflows", &w.outflows, |m| &m.name));
    }
    v
}

/// The first segments of the series' own columns that have parts (`water.max_speed`,
/// `momentum.x`, `kinetic_energy.water`, `steps.fine`, `density_ratio.mean`): an output
/// name equal to one could share a column. The observables' test checks the list.
pub const RESERVED: [&str; 5] = [
    "water",
    "momentum",
    "kinetic_energy",
    "steps",
    "density_ratio",
];

/// The families whose names begin output columns and FMU variables
/// (`<probe>.pressure`, `<barrier>.force.x`, `<body>.position.x`, `<gauge>.level`):
/// one namespace across them all.
const OUTPUT_FAMILIES: [&str; 6] = [
    "probes",
    "gauges",
    "bodies",
    "barriers",
    "walls",
    "containers",
];

/// Refuse the first unsafe name, then the first output name used twice (within one
/// family or across them) or taken by the series' own columns.
pub(super) fn validate_names(s: &Scene) -> Check {
    let all = names(s);
    for (key, name) in &all {
        if let Some(why) = unsafe_name(name) {
            return fail(key.clone(), why);
        }
    }
    let mut seen: std::collections::HashMap<&str, &str> = std::collections::HashMap::new();
    let outputs = all.iter().filter(|(key, _)| {
        OUTPUT_FAMILIES
            .iter()
            .any(|f| key.strip_prefix(f).is_some_and(|r| r.starts_with('[')))
    });
    for (key, name) in outputs {
        if RESERVED.contains(name) {
            return fail(
                key.clone(),
                format!(
                    "`{name}` is the name of the series' own columns ({name}.…); rename it \
                     (reserved: {})",
                    RESERVED.join(", ")
                ),
            );
        }
        if let Some(first) = seen.insert(name, key) {
            return fail(
                key.clone(),
                format!(
                    "`{name}` is also {first}: probes, gauges, bodies, barriers, walls and \
                     containers share one namespace, since their names begin the columns of \
                     series.csv and the FMU's variables; rename one"
                ),
            );
        }
    }
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::unsafe_name;

    #[test]
    fn only_csv_and_file_safe_names_pass() {
        for ok in ["column", "post_left", "tank-2", "A1"] {
            assert_eq!(unsafe_name(ok), None, "{ok}");
        }
        for bad in ["", "a,b", "a\nb", "a\0b", "a b", "a/b", "a.b", "\"q\""] {
            assert!(unsafe_name(bad).is_some(), "{bad:?}");
        }
        assert!(unsafe_name(&"x".repeat(65)).is_some());
    }
}
