//! Checks on the `[[materials]]` entries' soil-model keys (`yield_surface`, `hardening`,
//! `mu_i`, `dilatancy`), before the rest of the grains (`scene::validate`): a μ(I) block's μ_s sets
//! the friction angle the dilation angle is checked against.

use super::soil_model::{DilatancySpec, HardeningSpec, MuISpec, YieldSurface, PHI_MAX};
use super::validate::{fail, positive, Check};
use super::{MaterialSpec, Scene};

/// The soil-model keys of every `[[materials]]` entry.
pub(super) fn validate_soil_models(s: &Scene) -> Check {
    for (i, m) in s.materials.iter().enumerate() {
        check_soil_model(&format!("materials[{i}]"), m)?;
    }
    Ok(())
}

/// The soil-model keys of material `m` at key path `p` (`materials[i]`).
fn check_soil_model(p: &str, m: &MaterialSpec) -> Check {
    if let Some(mu) = &m.mu_i {
        if m.friction_angle.is_some() {
            return fail(
                format!("{p}.friction_angle"),
                "leave it out with [materials.mu_i]: μ_s is the static friction (φ = atan μ_s)",
            );
        }
        if m.hardening.is_some() {
            return fail(
                format!("{p}.hardening"),
                "give either [materials.hardening] or [materials.mu_i], not both",
            );
        }
        if let Some(y) = m.yield_surface {
            if y != YieldSurface::Shear {
                return fail(
                    format!("{p}.yield_surface"),
                    format!(
                        "μ(I) is a ratio √J2/p (Jop et al. 2006): it acts on the `shear` \
                         cone; found `{}`",
                        y.name()
                    ),
                );
            }
        }
        check_mu_i(&format!("{p}.mu_i"), mu)?;
    }
    if let Some(h) = &m.hardening {
        check_hardening(&format!("{p}.hardening"), h, m.dilation_angle)?;
    }
    if let Some(d) = &m.dilatancy {
        check_dilatancy(p, m, d)?;
    }
    Ok(())
}

/// A dilatancy block needs the soil's pores (its solid fraction 1 − n), no fixed
/// dilation angle and no hardening; K ≥ 0, φ_c and 1 − n in (0, φ_max), b ≥ 0.
fn check_dilatancy(p: &str, m: &MaterialSpec, d: &DilatancySpec) -> Check {
    let Some(n) = m.porosity else {
        return fail(
            format!("{p}.dilatancy"),
            "needs the soil's pores: give `porosity` (the solid fraction φ = 1 − n follows \
             the particle's density), with `permeability` or `grain_size` for the water",
        );
    };
    if m.dilation_angle != 0.0 {
        return fail(
            format!("{p}.dilation_angle"),
            "leave it out with [materials.dilatancy]: ψ follows from tan ψ = K (φ − φ_eq)",
        );
    }
    if m.hardening.is_some() {
        return fail(
            format!("{p}.hardening"),
            "give either [materials.hardening] or [materials.dilatancy], not both",
        );
    }
    let q = format!("{p}.dilatancy");
    if !(d.k >= 0.0 && d.k.is_finite()) {
        return fail(
            format!("{q}.k"),
            format!("must be ≥ 0 (K of tan ψ = K (φ − φ_eq)), found {:?}", d.k),
        );
    }
    if !(d.phi_c > 0.0 && d.phi_c < PHI_MAX) {
        return fail(
            format!("{q}.phi_c"),
            format!(
                "the critical solid fraction must lie in (0, {PHI_MAX:.4}) (the densest \
                 packing of spheres), found {:?}",
                d.phi_c
            ),
        );
    }
    if 1.0 - n >= PHI_MAX {
        return fail(
            format!("{p}.porosity"),
            format!(
                "with [materials.dilatancy] the solid fraction 1 − n must lie below \
                 {PHI_MAX:.4} (the densest packing of spheres): n = {n:?} gives {:?}",
                1.0 - n
            ),
        );
    }
    if !(d.b >= 0.0 && d.b.is_finite()) {
        return fail(
            format!("{q}.b"),
            format!(
                "must be ≥ 0 (b of φ_eq = φ_c / (1 + b √I)), found {:?}",
                d.b
            ),
        );
    }
    Ok(())
}

fn check_mu_i(p: &str, mu: &MuISpec) -> Check {
    positive(&format!("{p}.mu_s"), mu.mu_s)?;
    if !(mu.mu_2 >= mu.mu_s && mu.mu_2.is_finite()) {
        return fail(
            format!("{p}.mu_2"),
            format!(
                "must be at least mu_s = {:?} (μ grows from μ_s to μ_2 with I), found {:?}",
                mu.mu_s, mu.mu_2
            ),
        );
    }
    positive(&format!("{p}.i_0"), mu.i_0)?;
    positive(&format!("{p}.grain_diameter"), mu.grain_diameter)?;
    positive(&format!("{p}.grain_density"), mu.grain_density)
}

fn check_hardening(p: &str, h: &HardeningSpec, dilation: f64) -> Check {
    positive(&format!("{p}.peak_strain"), h.peak_strain)?;
    for (key, v) in [
        ("peak_angle", h.peak_angle),
        ("residual_angle", h.residual_angle),
    ] {
        if !(v > 0.0 && v < 90.0) {
            return fail(
                format!("{p}.{key}"),
                format!("must lie in (0, 90) degrees, found {v:?}"),
            );
        }
    }
    if !(h.softening >= 0.0 && h.softening.is_finite()) {
        return fail(
            format!("{p}.softening"),
            format!(
                "must be ≥ 0 (the rate H of the softening branch), found {:?}",
                h.softening
            ),
        );
    }
    // the hardening branch, sampled on (0, ε_p^peak], must stay an angle in (0, 90°)
    let [a, b, c, d] = h.cubic;
    let worst = (1..=64)
        .map(|k| {
            let e = h.peak_strain * k as f64 / 64.0;
            ((a * e + b) * e + c) * e + d
        })
        .find(|phi| !(*phi > 0.0 && *phi < std::f64::consts::FRAC_PI_2));
    if let Some(phi) = worst {
        return fail(
            format!("{p}.cubic"),
            format!(
                "the hardening branch a ε³ + b ε² + c ε + d (radians) must stay in (0, π/2) \
                 for 0 < ε ≤ peak_strain; it reaches {phi:?} rad"
            ),
        );
    }
    if dilation > h.residual_angle {
        return fail(
            format!("{p}.residual_angle"),
            format!(
                "must be at least the dilation angle {dilation:?}° (ψ ≤ φ at every strain), \
                 found {:?}",
                h.residual_angle
            ),
        );
    }
    Ok(())
}
