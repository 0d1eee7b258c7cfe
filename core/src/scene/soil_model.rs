//! The soil-model keys of a `[[materials]]` entry: which Drucker–Prager cone a friction
//! angle means (`yield_surface`), friction hardening and softening (`hardening`, seed 004
//! Eq. 43), the μ(I) rheology (`mu_i`, Jop, Forterre & Pouliquen 2006) and the
//! dilatancy of a soil in a fluid (`dilatancy`, Pailha & Pouliquen 2009). The formulas
//! are in `fine::yield_surface`, `fine::hardening`, `fine::mu_i` and `fine::dilatancy`,
//! and in docs/method.md §Soil models and §Pore-pressure feedback.

use serde::Deserialize;

/// `yield_surface`: the Drucker–Prager cone √J2 + α I1 = k fitted to Mohr–Coulomb's φ
/// and c (stress positive in tension, I1 = −3p).
#[derive(Debug, Clone, Copy, Deserialize, PartialEq, Eq, Default, serde::Serialize)]
#[serde(rename_all = "snake_case")]
pub enum YieldSurface {
    /// Seed 000 Eq. (6): α = tan φ/√(9 + 12 tan²φ), k = 3c/√(9 + 12 tan²φ); matches
    /// Mohr–Coulomb in plane strain (the default).
    #[default]
    PlaneStrain,
    /// The cone through Mohr–Coulomb's compression meridian (seed 004, "outer circle"):
    /// α = 2 sin φ/(√3 (3 − sin φ)), k = 6c cos φ/(√3 (3 − sin φ)); exact in triaxial
    /// compression.
    CompressionCone,
    /// The cone through the extension meridian: α = 2 sin φ/(√3 (3 + sin φ)),
    /// k = 6c cos φ/(√3 (3 + sin φ)); exact in triaxial extension.
    ExtensionCone,
    /// √J2 = c + tan φ · p: the friction angle is the ratio of the shear stress
    /// √J2 to the pressure (simple shear's τ/p, μ of the μ(I) rheology).
    Shear,
}

impl YieldSurface {
    /// The key's value in a scene file.
    pub fn name(self) -> &'static str {
        match self {
            YieldSurface::PlaneStrain => "plane_strain",
            YieldSurface::CompressionCone => "compression_cone",
            YieldSurface::ExtensionCone => "extension_cone",
            YieldSurface::Shear => "shear",
        }
    }
}

/// `[materials.hardening]`: the friction angle as a function of the accumulated
/// equivalent plastic strain ε_p (seed 004 Eq. 43). The material's `friction_angle` is
/// φ_e, the angle at ε_p = 0.
#[derive(Debug, Clone, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct HardeningSpec {
    /// ε_p at the peak, ε_p^peak (> 0).
    pub peak_strain: f64,
    /// [a, b, c, d] of the hardening branch φ = a ε_p³ + b ε_p² + c ε_p + d, φ in
    /// radians, for 0 < ε_p ≤ ε_p^peak.
    pub cubic: [f64; 4],
    /// Peak angle φ_p (degrees), where the softening branch starts.
    pub peak_angle: f64,
    /// Residual angle φ_r (degrees), reached at large strain.
    pub residual_angle: f64,
    /// Softening rate H of φ = φ_r + (φ_p − φ_r) exp(−H (ε_p − ε_p^peak)) (≥ 0).
    pub softening: f64,
}

/// `[materials.mu_i]`: the rate-dependent friction μ(I) = μ_s + (μ_2 − μ_s)/(1 + I_0/I),
/// I = γ̇ d/√(p/ρ_s) (Jop, Forterre & Pouliquen 2006), on the `shear` cone √J2 = μ p.
#[derive(Debug, Clone, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct MuISpec {
    /// Static friction μ_s (> 0).
    pub mu_s: f64,
    /// Limiting friction μ_2 at large I (≥ μ_s).
    pub mu_2: f64,
    /// I_0 (> 0).
    pub i_0: f64,
    /// Grain diameter d (m, > 0).
    pub grain_diameter: f64,
    /// Grain density ρ_s (kg/m³, > 0): the solid's, not the bulk density.
    pub grain_density: f64,
}

/// The densest packing of equal spheres, π/(3√2) (Kepler, Hales 2005): no solid
/// fraction or critical fraction of `[materials.dilatancy]` lies above it.
pub const PHI_MAX: f64 = 0.740_480_489_693_061;

/// `[materials.dilatancy]`: tan ψ = K (φ − φ_eq), φ_eq = φ_c / (1 + b √I_m) (Pailha &
/// Pouliquen 2009; Boyer et al. 2011), φ the solid fraction 1 − n, following the
/// particle's density; the friction is μ + tan ψ (`fine::dilatancy`). Needs the soil's
/// `porosity`.
#[derive(Debug, Clone, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct DilatancySpec {
    /// K (≥ 0).
    pub k: f64,
    /// The critical solid fraction φ_c, in (0, 0.7405).
    pub phi_c: f64,
    /// b of φ_eq (≥ 0). Default 1 (Boyer et al. 2011).
    #[serde(default = "one")]
    pub b: f64,
}

fn one() -> f64 {
    1.0
}
