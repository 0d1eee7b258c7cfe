//! Checks on the soil materials' pore keys (`porosity`, `permeability`, `grain_size`,
//! `saturated`), after the rest of the scene (`scene::validate`).

use super::validate::{fail, Check};
use super::Scene;

/// The pore keys of every `[[materials]]` entry.
pub(super) fn validate_pores(s: &Scene) -> Check {
    for (i, m) in s.materials.iter().enumerate() {
        let p = format!("materials[{i}]");
        if let Some(n) = m.porosity {
            if !(n > 0.0 && n < 1.0) {
                return fail(
                    format!("{p}.porosity"),
                    format!("must lie in (0, 1) (the pore fraction of the volume), found {n:?}"),
                );
            }
        }
        if let Some(k) = m.permeability {
            if !(k > 0.0 && k.is_finite()) {
                return fail(
                    format!("{p}.permeability"),
                    format!(
                        "must be a positive intrinsic permeability in m² (k = k_h μ / (ρ_w g) \
                         for a hydraulic conductivity k_h), found {k:?}"
                    ),
                );
            }
        }
        if let Some(d) = m.grain_size {
            if !(d > 0.0 && d.is_finite()) {
                return fail(
                    format!("{p}.grain_size"),
                    format!("must be a positive grain diameter in m, found {d:?}"),
                );
            }
            if m.permeability.is_some() {
                return fail(
                    format!("{p}.grain_size"),
                    "give `permeability` or `grain_size` (Kozeny–Carman), not both",
                );
            }
        }
        let seeps = m.permeability.is_some() || m.grain_size.is_some();
        if (seeps || m.saturated) && m.porosity.is_none() {
            let key = if m.saturated && !seeps {
                "saturated"
            } else if m.permeability.is_some() {
                "permeability"
            } else {
                "grain_size"
            };
            return fail(
                format!("{p}.porosity"),
                format!(
                    "`{key}` needs the soil's porosity n (`porosity`, in (0, 1)): it sets the \
                     buoyancy (1 − n) ∇p on the grains"
                ),
            );
        }
        if m.saturated && !seeps {
            return fail(
                format!("{p}.saturated"),
                "a saturated soil needs `permeability` (m²) or `grain_size` (m) for the \
                 seepage force between its grains and its pore water",
            );
        }
        if m.saturated && s.simulation.gravity_norm() == 0.0 {
            return fail(
                format!("{p}.saturated"),
                "a saturated soil starts at the hydrostatic pore pressure below its top, \
                 which needs gravity: set `simulation.gravity`",
            );
        }
    }
    Ok(())
}
