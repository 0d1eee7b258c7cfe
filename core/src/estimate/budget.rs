//! The memory budget: a scene whose estimated memory ([`estimate`](crate::estimate))
//! exceeds it is refused before any particle is allocated.
//!
//! The budget is `simulation.memory_budget` (bytes) when it is positive, else 80 % of
//! the memory the machine has available (`MemAvailable` in `/proc/meminfo`; where that
//! cannot be read, 80 % of 4 GiB). A set budget beyond the machine's memory (RAM and
//! swap, `MemTotal` + `SwapTotal`) is cut to it: no allocation beyond it can succeed,
//! and an allocation that fails aborts the process, the FMU's host included.

use crate::estimate::{estimate, Estimate};
use crate::numerics::math::Real;
use crate::numerics::neighbors::MAX_CELLS;
use crate::scene::resolution::Resolution;
use crate::scene::Scene;

/// Share of the available memory a scene may use by default.
pub const DEFAULT_SHARE: Real = 0.8;
/// Memory assumed available where `/proc/meminfo` cannot be read.
pub const FALLBACK_AVAILABLE: Real = 4.0 * GIB;
const GIB: Real = 1024.0 * 1024.0 * 1024.0;

/// A budget in bytes and where it came from.
#[derive(Clone, Debug, PartialEq)]
pub struct Budget {
    pub bytes: Real,
    pub origin: String,
}

/// The budget that applies to `scene`.
pub fn budget(scene: &Scene) -> Budget {
    let set = scene.simulation.memory_budget;
    if set > 0.0 {
        let name = scene
            .simulation
            .memory_budget_origin
            .clone()
            .unwrap_or_else(|| "simulation.memory_budget".into());
        return match machine_bytes() {
            Some(m) if set > m => Budget {
                bytes: m,
                origin: format!(
                    "this machine's {} of memory and swap: {name} = {} is beyond it",
                    human_bytes(m),
                    human_bytes(set)
                ),
            },
            _ => Budget {
                bytes: set,
                origin: name,
            },
        };
    }
    match available_bytes() {
        Some(a) => Budget {
            bytes: DEFAULT_SHARE * a,
            origin: format!("80 % of the {} available", human_bytes(a)),
        },
        None => Budget {
            bytes: DEFAULT_SHARE * FALLBACK_AVAILABLE,
            origin: "80 % of 4 GiB (available memory unknown)".into(),
        },
    }
}

/// `MemAvailable` of `/proc/meminfo`, in bytes.
pub fn available_bytes() -> Option<Real> {
    meminfo(&["MemAvailable"])
}

/// The machine's memory and swap (`MemTotal` + `SwapTotal` of `/proc/meminfo`), in
/// bytes: more than any process can allocate.
pub fn machine_bytes() -> Option<Real> {
    meminfo(&["MemTotal", "SwapTotal"])
}

/// The sum of `fields` of `/proc/meminfo` (each `Name: <n> kB`), in bytes.
fn meminfo(fields: &[&str]) -> Option<Real> {
    let text = std::fs::read_to_string("/proc/meminfo").ok()?;
    fields.iter().try_fold(0.0, |sum, f| {
        let line = text
            .lines()
            .find(|l| l.strip_prefix(f).is_some_and(|r| r.starts_with(':')))?;
        let mut it = line.split_whitespace().skip(1);
        let kib: Real = it.next()?.parse().ok()?;
        (it.next() == Some("kB")).then_some(sum + kib * 1024.0)
    })
}

/// A scene refused for its memory: its estimate and the budget it exceeds.
#[derive(Debug, Clone, thiserror::Error)]
#[error("{}", over_budget(.estimate, .budget))]
pub struct OverBudget {
    pub estimate: Box<Estimate>,
    pub budget: Budget,
}

/// Estimate `scene` and refuse it when the estimate exceeds its budget. The error
/// names dp, the estimated particles and bytes, the budget and how to change it.
pub fn enforce(scene: &Scene, res: &Resolution) -> Result<Estimate, OverBudget> {
    let estimate = estimate(scene, res);
    let budget = budget(scene);
    if !passes(&estimate, &budget) {
        return Err(OverBudget {
            estimate: Box::new(estimate),
            budget,
        });
    }
    Ok(estimate)
}

/// Whether estimate `e` passes budget `b`: its bytes are a number no larger than the
/// budget (a NaN or infinite estimate never passes) and its cell grid fits the `u32`
/// cell index ([`MAX_CELLS`]).
pub fn passes(e: &Estimate, b: &Budget) -> bool {
    e.bytes <= b.bytes && e.cells <= MAX_CELLS as Real
}

/// A size that [`parse_bytes`] cannot read.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum SizeError {
    #[error("`{0}` is not a size; write e.g. 8GiB, 500MB or 4e9")]
    NotASize(String),
    #[error("unknown unit `{unit}` in `{text}`; use B, kB, MB, GB, TB, KiB, MiB, GiB or TiB")]
    UnknownUnit { unit: String, text: String },
    #[error("`{0}`: the budget must be a positive size")]
    NotPositive(String),
}

/// The refusal message: dp, the estimated particles, grid cells and bytes, what they
/// exceed, and the advice that fits the case (raising the budget helps only a finite
/// estimate over it; a grid beyond its cell index needs the parts closer together or a
/// coarser dp).
pub fn over_budget(e: &Estimate, b: &Budget) -> String {
    let head = format!(
        "dp = {:?} m gives an estimated {:.3e} particles ({:.3e} fine, {:.3e} water, {:.3e} wall, \
         {:.3e} coarse) and {:.3e} grid cells needing about {} ({:.3e} bytes)",
        e.dp,
        e.particles(),
        e.fine(),
        e.water(),
        e.walls,
        e.coarse(),
        e.cells,
        human_bytes(e.bytes),
        e.bytes,
    );
    let mut parts = vec![head];
    if e.bytes.is_nan() || e.bytes > b.bytes {
        let advice = if e.bytes.is_finite() {
            "coarsen simulation.dp or raise the budget (`--memory-budget 8GiB` on the command \
             line, simulation.memory_budget in bytes in the scene, the FMU parameter \
             memory_budget)"
        } else {
            "no budget holds that: coarsen simulation.dp"
        };
        parts.push(format!(
            "over the memory budget of {} ({}); {advice}",
            human_bytes(b.bytes),
            b.origin
        ));
    }
    if e.cells.is_nan() || e.cells > MAX_CELLS as Real {
        parts.push(format!(
            "its neighbour grid of {:.3e} cells ({} of them) is beyond the {MAX_CELLS:.3e} a \
             cell index holds: the scene's parts lie far apart for this spacing (a region far \
             from every container still spans the grid); bring them closer together or \
             coarsen simulation.dp",
            e.cells,
            human_bytes(e.grid_bytes)
        ));
    }
    parts.join(", ")
}

/// Bytes with a binary unit: `512 B`, `3.4 GiB`, `1.2e6 EiB`.
pub fn human_bytes(b: Real) -> String {
    const UNITS: [&str; 7] = ["B", "KiB", "MiB", "GiB", "TiB", "PiB", "EiB"];
    let mut v = b;
    let mut u = 0;
    while v >= 1024.0 && u + 1 < UNITS.len() {
        v /= 1024.0;
        u += 1;
    }
    if u == 0 {
        format!("{v:.0} B")
    } else if v < 1e4 {
        format!("{v:.1} {}", UNITS[u])
    } else {
        format!("{v:.2e} {}", UNITS[u])
    }
}

/// Parse a size: a number of bytes (`8e9`) or a number with a unit, decimal (kB, MB,
/// GB, TB) or binary (KiB, MiB, GiB, TiB); case-insensitive, spaces allowed.
pub fn parse_bytes(text: &str) -> Result<Real, SizeError> {
    let t = text.trim();
    let split = t
        .find(|c: char| c.is_ascii_alphabetic() && c != 'e' && c != 'E')
        .unwrap_or(t.len());
    let (num, unit) = t.split_at(split);
    let value: Real = num
        .trim()
        .parse()
        .map_err(|_| SizeError::NotASize(text.to_string()))?;
    let factor = match unit.trim().to_ascii_lowercase().as_str() {
        "" | "b" => 1.0,
        "kb" | "k" => 1e3,
        "mb" | "m" => 1e6,
        "gb" | "g" => 1e9,
        "tb" | "t" => 1e12,
        "kib" => 1024.0,
        "mib" => 1024.0 * 1024.0,
        "gib" => GIB,
        "tib" => GIB * 1024.0,
        u => {
            return Err(SizeError::UnknownUnit {
                unit: u.to_string(),
                text: text.to_string(),
            })
        }
    };
    let bytes = value * factor;
    if !(bytes.is_finite() && bytes > 0.0) {
        return Err(SizeError::NotPositive(text.to_string()));
    }
    Ok(bytes)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn sizes_parse_with_decimal_and_binary_units() {
        assert_eq!(parse_bytes("8GiB").unwrap(), 8.0 * GIB);
        assert_eq!(parse_bytes(" 500 MB ").unwrap(), 5e8);
        assert_eq!(parse_bytes("4e9").unwrap(), 4e9);
        assert_eq!(parse_bytes("1.5kib").unwrap(), 1536.0);
        assert!(parse_bytes("8 parsecs").is_err());
        assert!(parse_bytes("-1GB").is_err());
        assert!(parse_bytes("GB").is_err());
    }

    #[test]
    fn the_machine_holds_its_available_memory() {
        let (m, a) = (machine_bytes().unwrap(), available_bytes().unwrap());
        assert!(m >= a && a > 0.0, "machine {m} B, available {a} B");
    }

    #[test]
    fn human_bytes_picks_the_unit() {
        assert_eq!(human_bytes(512.0), "512 B");
        assert_eq!(human_bytes(3.5 * GIB), "3.5 GiB");
    }
}
