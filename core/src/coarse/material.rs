//! Derived constants of a coarse-grain solid (Neo-Hookean, Eqs. 39–40).

use crate::numerics::math::Real;
use crate::scene::SolidSpec;

/// One solid material.
#[derive(Clone, Debug, PartialEq, serde::Serialize, serde::Deserialize)]
pub struct SolidMaterial {
    pub name: String,
    /// ρ0 (kg/m³).
    pub rho0: Real,
    /// Young's modulus E (Pa).
    pub youngs: Real,
    /// Poisson's ratio ν.
    pub poisson: Real,
    /// Lamé λ = Eν / ((1+ν)(1−2ν)).
    pub lambda: Real,
    /// Shear modulus μ = G = E / (2(1+ν)).
    pub shear: Real,
    /// Bulk modulus K = λ + 2μ/3.
    pub bulk: Real,
    /// Sound speed c0 = √(K/ρ0), as for the fine grains (Eq. 22).
    pub c0: Real,
}

impl SolidMaterial {
    pub fn from_spec(m: &SolidSpec) -> Self {
        let (e, nu) = (m.youngs_modulus, m.poisson_ratio);
        let lambda = e * nu / ((1.0 + nu) * (1.0 - 2.0 * nu));
        let shear = e / (2.0 * (1.0 + nu));
        let bulk = lambda + 2.0 * shear / 3.0;
        SolidMaterial {
            name: m.name.clone(),
            rho0: m.density,
            youngs: e,
            poisson: nu,
            lambda,
            shear,
            bulk,
            c0: (bulk / m.density).sqrt(),
        }
    }

    /// Plane-strain contact modulus E/(1−ν²) of this solid.
    pub fn contact_modulus(&self) -> Real {
        self.youngs / (1.0 - self.poisson * self.poisson)
    }
}
