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

impl FineMaterial {
    /// The least density the soil can take: its elastic density ρ0 (1 + P/K) at the
    /// apex of the Drucker–Prager cone, P = −k_c/(3α_φ), where the tension cut-off of
    /// seed 000 Eq. (11) holds the stress. ρ0 for a cohesionless soil, which carries no
    /// tension and, with ψ = 0, cannot dilate; 0 without friction (no apex).
    pub fn density_floor(&self) -> Real {
        if self.alpha_phi <= 0.0 {
            return 0.0;
        }
        let p_apex = -self.k_c / (3.0 * self.alpha_phi);
        (self.rho0 * (1.0 + p_apex / self.bulk)).max(0.0)
    }
}

/// Per particle its material index, per material its least density
/// ([`FineMaterial::density_floor`]).
#[derive(Clone, Copy)]
pub struct DensityFloor<'a> {
    pub material: &'a [u16],
    pub floor: &'a [Real],
}

impl DensityFloor<'_> {
    /// Particle i's density raised to its material's floor. Only a positive density is
    /// raised: a negative or NaN one is left for the stability guard to report.
    #[inline(always)]
    pub fn hold(&self, i: usize, rho: &mut Real) {
        let f = self.floor[self.material[i] as usize];
        if *rho > 0.0 && *rho < f {
            *rho = f;
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
