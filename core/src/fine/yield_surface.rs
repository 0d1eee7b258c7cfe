//! The Drucker–Prager cone f = √J2 + α_φ I1 − k_c fitted to Mohr–Coulomb's φ and c
//! (stress positive in tension, I1 = −3p), and the per-particle yield constants the
//! stress update takes.

use crate::numerics::math::Real;
use crate::scene::YieldSurface;

/// The constants of one particle's yield surface and plastic potential for one step:
/// f = √J2 + α_φ I1 − k_c, g = √J2 + α_ψ I1 (seed 000 Eqs. 4–5).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Yield {
    pub alpha_phi: Real,
    pub k_c: Real,
    pub alpha_psi: Real,
}

/// (α, k) of the cone `surface` for the angle `angle` (rad) and cohesion `c` (Pa):
/// - `plane_strain`, seed 000 Eq. (6): α = tan φ/√(9 + 12 tan²φ), k = 3c/√(9 + 12 tan²φ);
/// - `compression_cone` (through Mohr–Coulomb's compression meridian, seed 004's
///   "outer circle"): α = 2 sin φ/(√3 (3 − sin φ)), k = 6c cos φ/(√3 (3 − sin φ));
/// - `extension_cone`: α = 2 sin φ/(√3 (3 + sin φ)), k = 6c cos φ/(√3 (3 + sin φ));
/// - `shear`, √J2 = c + tan φ · p: α = tan φ/3, k = c.
///
/// The same fit with ψ in place of φ gives the plastic potential's α_ψ.
pub fn fit(surface: YieldSurface, angle: Real, c: Real) -> (Real, Real) {
    match surface {
        YieldSurface::PlaneStrain => {
            let t = angle.tan();
            let r = (9.0 + 12.0 * t * t).sqrt();
            (t / r, 3.0 * c / r)
        }
        YieldSurface::CompressionCone => {
            let s = angle.sin();
            let r = 3.0_f64.sqrt() * (3.0 - s);
            (2.0 * s / r, 6.0 * c * angle.cos() / r)
        }
        YieldSurface::ExtensionCone => {
            let s = angle.sin();
            let r = 3.0_f64.sqrt() * (3.0 + s);
            (2.0 * s / r, 6.0 * c * angle.cos() / r)
        }
        YieldSurface::Shear => (angle.tan() / 3.0, c),
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Each fit meets Mohr–Coulomb where it is built to: the compression cone in
    /// triaxial compression (σ1/σ3 = (1 + sin φ)/(1 − sin φ)), the extension cone in
    /// triaxial extension, and the plane-strain fit's α at c = 0 against the closed form
    /// from seed 000 Eq. (6).
    #[test]
    fn cones_meet_mohr_coulomb_on_their_meridians() {
        let phi: Real = 28.6_f64.to_radians();
        let s = phi.sin();
        let n = (1.0 + s) / (1.0 - s);
        // compression: σ_a = −n σ3, σ_r = −σ3 (tension positive)
        let (a, _) = fit(YieldSurface::CompressionCone, phi, 0.0);
        let (sa, sr) = (-n, -1.0);
        let q: Real = sr - sa;
        let f = q / 3.0_f64.sqrt() + a * (sa + 2.0 * sr);
        assert!(f.abs() < 1e-12, "compression meridian: f = {f}");
        // extension: σ_a = −σ3, σ_r = −n σ3 (two major principal stresses)
        let (a, _) = fit(YieldSurface::ExtensionCone, phi, 0.0);
        let (sa, sr) = (-1.0, -n);
        let q: Real = sa - sr;
        let f = q / 3.0_f64.sqrt() + a * (sa + 2.0 * sr);
        assert!(f.abs() < 1e-12, "extension meridian: f = {f}");
        let t = phi.tan();
        let (a, k) = fit(YieldSurface::PlaneStrain, phi, 1.0);
        assert!((a - t / (9.0 + 12.0 * t * t).sqrt()).abs() < 1e-15);
        assert!((k - 3.0 / (9.0 + 12.0 * t * t).sqrt()).abs() < 1e-15);
        assert_eq!(fit(YieldSurface::Shear, phi, 7.0), (t / 3.0, 7.0));
    }
}
