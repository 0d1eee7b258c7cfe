//! State-dependent dilatancy of a soil in a fluid (issue 44, item 2): a soil denser
//! than its equilibrium packing dilates as it shears, a looser one contracts.
//!
//! - Dilatancy angle (Roux & Radjai 1998; Pailha & Pouliquen 2009, J. Fluid Mech. 633,
//!   Eq. 2.6): tan ψ = K (φ − φ_eq), φ the solid fraction of the particle, from its
//!   density: φ = (1 − n) ρ / ρ0.
//! - Equilibrium packing (Boyer, Guazzelli & Pouliquen 2011, PRL 107, 188301):
//!   φ_eq = φ_c / (1 + b √I_m).
//! - The dimensionless shear rate blends the viscous number I_v = η_f γ̇ / p' with the
//!   inertial number I = γ̇ d / √(p'/ρ_s) of μ(I) (Trulsson, Andreotti & Claudin 2012,
//!   PRL 109, 118305): I_m = I_v + α I², α = 0.635. Without a grain diameter (no
//!   `mu_i` block) I_m = I_v; dry (η_f = 0) I_m = α I², and the friction's own μ(I)
//!   reads I = √(I_m/α), so that a dry μ(I) soil keeps its law.
//! - Friction (Pailha & Pouliquen 2009 Eq. 2.5): μ = μ(I) + tan ψ, on the `shear`
//!   cone √J2 = μ p' (α_φ = μ/3); the plastic potential carries ψ (α_ψ = tan ψ/3), so
//!   that the plastic volumetric strain rate is tan ψ times the plastic shear rate.
//!
//! γ̇ = √(2 ė:ė), ė the deviatoric strain rate, as in [`mu_i`](super::mu_i). Where p'
//! ≤ 0 (a liquefied or stretched soil) I_m → ∞: φ_eq → 0 and the friction takes μ_2.

use crate::numerics::math::Real;

/// Trulsson et al.'s (2012) weight of I² against I_v in I_m = I_v + α I².
pub const TRULSSON_ALPHA: Real = 0.635;

/// A material's dilatancy constants, with the fluid it is immersed in.
#[derive(Clone, Copy, Debug, PartialEq, serde::Serialize, serde::Deserialize)]
pub struct Dilatancy {
    /// K of tan ψ = K (φ − φ_eq) (≥ 0).
    pub k: Real,
    /// φ_c, the critical solid fraction (φ_eq at I_m = 0).
    pub phi_c: Real,
    /// b of φ_eq = φ_c / (1 + b √I_m).
    pub b: Real,
    /// The solid fraction at the material's density ρ0: 1 − n.
    pub phi_0: Real,
    /// The fluid's dynamic viscosity η_f (Pa·s); 0 dry.
    pub eta_f: Real,
    /// Grain diameter d (m) and grain density ρ_s (kg/m³) of the inertial number; None
    /// without a μ(I) block (then I_m = I_v).
    pub grains: Option<(Real, Real)>,
}

impl Dilatancy {
    /// The solid fraction of a particle of density `rho` of a material of density `rho0`.
    #[inline(always)]
    pub fn fraction(&self, rho: Real, rho0: Real) -> Real {
        self.phi_0 * rho / rho0
    }

    /// I_m at shear rate `rate` (1/s) and effective pressure `p` (Pa, compression
    /// positive): infinite where p ≤ 0 and the soil shears, 0 at rest.
    #[inline]
    pub fn number(&self, rate: Real, p: Real) -> Real {
        if rate <= 0.0 {
            return 0.0;
        }
        if p <= 0.0 {
            return Real::INFINITY;
        }
        let iv = self.eta_f * rate / p;
        let inertial = self.grains.map_or(0.0, |(d, rho_s)| {
            let i = rate * d / (p / rho_s).sqrt();
            TRULSSON_ALPHA * i * i
        });
        iv + inertial
    }

    /// φ_eq(I_m).
    #[inline]
    pub fn phi_eq(&self, i_m: Real) -> Real {
        if i_m.is_infinite() {
            return 0.0;
        }
        self.phi_c / (1.0 + self.b * i_m.sqrt())
    }

    /// tan ψ = K (φ − φ_eq(I_m)) of a particle at solid fraction `phi`.
    #[inline]
    pub fn tan_psi(&self, phi: Real, i_m: Real) -> Real {
        self.k * (phi - self.phi_eq(i_m))
    }

    /// The inertial number μ(I) reads at I_m: √(I_m/α) (infinite stays infinite).
    #[inline]
    pub fn inertial_equivalent(i_m: Real) -> Real {
        (i_m / TRULSSON_ALPHA).sqrt()
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn beads() -> Dilatancy {
        Dilatancy {
            k: 40.0,
            phi_c: 0.57,
            b: 1.0,
            phi_0: 0.6,
            eta_f: 0.012,
            grains: Some((225e-6, 2500.0)),
        }
    }

    /// tan ψ = K (φ − φ_c / (1 + b √(I_v + α I²))) by hand, for Rondon's beads: dense
    /// (φ = 0.60) dilates, loose (0.55) contracts at rest; shearing lowers φ_eq; p' ≤ 0
    /// sends φ_eq to 0.
    #[test]
    fn dilatancy_follows_the_law() {
        let d = beads();
        let (rate, p): (Real, Real) = (2.0, 150.0);
        let iv = 0.012 * rate / p;
        let i = rate * 225e-6 / (p / 2500.0).sqrt();
        let im = iv + 0.635 * i * i;
        assert!((d.number(rate, p) - im).abs() < 1e-15);
        let eq = 0.57 / (1.0 + im.sqrt());
        for phi in [0.60, 0.55] {
            assert!((d.tan_psi(phi, im) - 40.0 * (phi - eq)).abs() < 1e-12);
        }
        assert!(d.tan_psi(0.60, 0.0) > 0.0 && d.tan_psi(0.55, 0.0) < 0.0);
        assert_eq!(d.number(0.0, p), 0.0);
        assert_eq!(d.number(rate, 0.0), Real::INFINITY);
        assert_eq!(d.phi_eq(Real::INFINITY), 0.0);
        assert!((d.fraction(1500.0, 1500.0) - 0.6).abs() < 1e-15);
        assert!((d.fraction(1525.0, 1500.0) - 0.61).abs() < 1e-12);
    }
}
