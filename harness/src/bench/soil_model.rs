//! The soil models the models suite compares (issue 43), and how one is put on a scene:
//! on every `[[materials]]` entry, after the case's own overrides, written beside the run
//! as `model_scene.toml`.

use anyhow::{anyhow, bail, Context, Result};
use std::path::{Path, PathBuf};

/// A soil model of the suite.
#[derive(Clone, Copy, PartialEq, Eq, Debug)]
pub(crate) enum Model {
    /// A Drucker–Prager cone fitted to the scene's φ (the `yield_surface` key).
    Cone(&'static str),
    /// μ(I) on the shear cone with μ_s = tan φ of the scene (see [`MU_I_RULE`]).
    MuI,
}

/// The models, in the report's column order.
pub(crate) const MODELS: [Model; 5] = [
    Model::Cone("plane_strain"),
    Model::Cone("compression_cone"),
    Model::Cone("extension_cone"),
    Model::Cone("shear"),
    Model::MuI,
];

/// μ(I) for a scene that gives a friction angle φ and a bulk density ρ, one rule for
/// every case (no per-case tuning): μ_s = tan φ, μ_2 = μ_s + 0.26 and I_0 = 0.279 (the
/// increment and I_0 of Jop, Forterre & Pouliquen 2006's glass beads), d = 1 mm, and
/// grains of ρ/0.6 (a solid fraction of 0.6).
pub(crate) const MU_I_RULE: &str = "μ_s = tan φ, μ_2 = μ_s + 0.26, I_0 = 0.279 (Jop et al. \
     2006's increment), d = 1 mm, ρ_s = ρ/0.6";

impl Model {
    pub(crate) fn name(self) -> &'static str {
        match self {
            Model::Cone(n) => n,
            Model::MuI => "mu_i",
        }
    }

    pub(crate) fn formula(self) -> &'static str {
        match self {
            Model::Cone("plane_strain") => {
                "seed 000 Eq. (6): α = tan φ/√(9 + 12 tan²φ); Mohr–Coulomb in plane strain (today's default)"
            }
            Model::Cone("compression_cone") => {
                "α = 2 sin φ/(√3 (3 − sin φ)); Mohr–Coulomb in triaxial compression (seed 004)"
            }
            Model::Cone("extension_cone") => {
                "α = 2 sin φ/(√3 (3 + sin φ)); Mohr–Coulomb in triaxial extension"
            }
            Model::Cone(_) => "√J2 = tan φ · p: φ is the ratio of shear stress to pressure",
            Model::MuI => MU_I_RULE,
        }
    }

    /// The scene text with this model on every material.
    pub(crate) fn apply(self, text: &str, file: &str) -> Result<String> {
        let mut doc: toml_edit::DocumentMut =
            text.parse().with_context(|| format!("{file}: not TOML"))?;
        let Some(mats) = doc
            .get_mut("materials")
            .and_then(|m| m.as_array_of_tables_mut())
        else {
            bail!(
                "{file}: no [[materials]] to apply the soil model {} to",
                self.name()
            );
        };
        for (k, m) in mats.iter_mut().enumerate() {
            match self {
                Model::Cone(name) => {
                    m.insert("yield_surface", toml_edit::value(name));
                }
                Model::MuI => {
                    let number = |key: &str| {
                        m.get(key)
                            .and_then(|v| v.as_float().or(v.as_integer().map(|i| i as f64)))
                            .ok_or_else(|| {
                                anyhow!("{file}: materials[{k}].{key} is needed for μ(I)")
                            })
                    };
                    let (phi, rho) = (number("friction_angle")?, number("density")?);
                    let mu_s = phi.to_radians().tan();
                    let mut t = toml_edit::InlineTable::new();
                    t.insert("mu_s", mu_s.into());
                    t.insert("mu_2", (mu_s + 0.26).into());
                    t.insert("i_0", 0.279.into());
                    t.insert("grain_diameter", 1e-3.into());
                    t.insert("grain_density", (rho / 0.6).into());
                    m.remove("friction_angle");
                    m.remove("yield_surface");
                    m.insert("mu_i", toml_edit::value(t));
                }
            }
        }
        Ok(doc.to_string())
    }

    /// `scene` with the overrides `common` and this model on every material, written to
    /// `dir/model_scene.toml` (the directory is made); its path.
    pub(crate) fn write_variant(
        self,
        scene: &Path,
        common: &[String],
        dir: &Path,
    ) -> Result<PathBuf> {
        std::fs::create_dir_all(dir).with_context(|| format!("creating {}", dir.display()))?;
        let file = scene.display().to_string();
        let text = std::fs::read_to_string(scene).with_context(|| format!("reading {file}"))?;
        let text = granmix_core::scene::apply_overrides(&text, &file, common)
            .map_err(|e| anyhow!("{e}"))?;
        let variant = dir.join("model_scene.toml");
        std::fs::write(&variant, self.apply(&text, &file)?)
            .with_context(|| format!("writing {}", variant.display()))?;
        Ok(variant)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    const SCENE: &str = "[[materials]]\nname = \"sand\"\ndensity = 1500.0\nyoungs_modulus = 1e6\n\
        poisson_ratio = 0.3\nfriction_angle = 30.0\n";

    /// μ(I) replaces the friction angle by μ_s = tan φ and the rule's constants.
    #[test]
    fn mu_i_takes_the_scene_friction_as_mu_s() {
        let t = Model::MuI.apply(SCENE, "s.toml").unwrap();
        let doc: toml_edit::DocumentMut = t.parse().unwrap();
        let m = &doc["materials"][0];
        assert!(m.get("friction_angle").is_none(), "{t}");
        let mu = &m["mu_i"];
        let f = |k: &str| mu[k].as_float().unwrap();
        assert!((f("mu_s") - 30f64.to_radians().tan()).abs() < 1e-15, "{t}");
        assert!((f("mu_2") - f("mu_s") - 0.26).abs() < 1e-15, "{t}");
        assert_eq!((f("i_0"), f("grain_diameter")), (0.279, 1e-3));
        assert!((f("grain_density") - 2500.0).abs() < 1e-9, "{t}");
    }

    /// A cone sets `yield_surface` on the material.
    #[test]
    fn a_cone_sets_the_yield_surface() {
        let t = Model::Cone("extension_cone")
            .apply(SCENE, "s.toml")
            .unwrap();
        assert!(t.contains("yield_surface = \"extension_cone\""), "{t}");
    }
}
