//! Derived constants of the Drucker–Prager soil (Eqs. 4–8, 22 of seed 000).

use super::pores::Pores;
use crate::math::Real;
use crate::scene::MaterialSpec;

/// One fine-grain material with its derived constants.
#[derive(Clone, Debug, serde::Serialize, serde::Deserialize)]
pub struct FineMaterial {
    pub name: String,
    /// ρ0 (kg/m³).
    pub rho0: Real,
    /// Shear modulus G = E / (2(1+ν)).
    pub shear: Real,
    /// Bulk modulus K = E / (3(1−2ν)).
    pub bulk: Real,
    /// Sound speed c0 = √(E / (3(1−2ν)ρ0)), Eq. (22).
    pub c0: Real,
    /// α_φ = tan φ / √(9 + 12 tan²φ), Eq. (6).
    pub alpha_phi: Real,
    /// k_c = 3c / √(9 + 12 tan²φ), Eq. (6).
    pub k_c: Real,
    /// α_ψ = tan ψ / √(9 + 12 tan²ψ), Eq. (6).
    pub alpha_psi: Real,
    /// Jaky's K0 = 1 − sin φ (Eq. 26).
    pub k0: Real,
    /// Friction angle φ (rad).
    pub phi: Real,
    /// Cohesion c (Pa).
    pub cohesion: Real,
    /// Porosity and permeability (None: water passes the soil freely).
    #[serde(default)]
    pub pores: Option<Pores>,
}

impl FineMaterial {
    /// The density whose weight the skeleton carries: ρ' = ρ_d − (1 − n) ρ_w for a
    /// saturated soil under water of density `rho_w`, else ρ0.
    pub fn skeleton_density(&self, rho_w: Option<Real>) -> Real {
        match (self.pores, rho_w) {
            (Some(p), Some(rw)) if p.saturated => p.submerged_density(self.rho0, rw),
            _ => self.rho0,
        }
    }
}

fn dp_alpha(angle_rad: Real) -> Real {
    let t = angle_rad.tan();
    t / (9.0 + 12.0 * t * t).sqrt()
}

impl FineMaterial {
    pub fn from_spec(m: &MaterialSpec) -> Self {
        let e = m.youngs_modulus;
        let nu = m.poisson_ratio;
        let phi = m.friction_angle.to_radians();
        let psi = m.dilation_angle.to_radians();
        let t = phi.tan();
        FineMaterial {
            name: m.name.clone(),
            rho0: m.density,
            shear: e / (2.0 * (1.0 + nu)),
            bulk: e / (3.0 * (1.0 - 2.0 * nu)),
            c0: (e / (3.0 * (1.0 - 2.0 * nu) * m.density)).sqrt(),
            alpha_phi: dp_alpha(phi),
            k_c: 3.0 * m.cohesion / (9.0 + 12.0 * t * t).sqrt(),
            alpha_psi: dp_alpha(psi),
            k0: 1.0 - phi.sin(),
            phi,
            cohesion: m.cohesion,
            pores: Pores::of(m),
        }
    }
}

/// Whether all fine materials share one impedance and sound speed, so that every
/// pair takes the reciprocals of its particle i (the common single-soil scene).
pub fn uniform_acoustics(mats: &[FineMaterial]) -> bool {
    mats.windows(2)
        .all(|w| w[0].rho0 * w[0].c0 == w[1].rho0 * w[1].c0 && w[0].c0 == w[1].c0)
}
