//! The fine-grain–wall interface as a contact that opens.
//!
//! The one-sided Riemann problem of seed 000 Eqs. (32)–(35) treats the wall as glued
//! to the soil: when the wall recedes, Eq. (34) mirrors the velocity, the jump
//! U_L − U_R = 2(U_L − u_w) is negative, and the dissipation term of Eq. (20) lowers
//! P* by ½ β ρc |U_L − U_R| (β of Eq. 23 reaches 1 at |U_L − U_R| = c/η). A barrier
//! pulled at 0.1 m/s from a 0.1 m layer lowers P* by ~1.6 kPa, several times the
//! layer's pressure, and the wall pulls the soil after it.
//!
//! A soil carries no tension beyond its strength, and the strongest tension a
//! Drucker–Prager soil (Eqs. 4–6) can hold is the apex of its cone, the isotropic stress
//! σ_t I with σ_t = k_c/(3α_φ) = c cot φ (0 for c = 0; √J2 = 0 there, so it carries
//! no shear either). So the interface stress σ* of one wall pair is cut at the apex:
//! when its normal traction n·σ*·n on the wall plane (n of Eq. 33) exceeds σ_t, the
//! contact is open and the pair carries σ_t I. A cohesionless soil that separates
//! from a wall receives nothing from it, and the wall nothing from the soil; a cohesive
//! soil is held back by at most σ_t per unit area.

use crate::fine::material::FineMaterial;
use crate::numerics::math::{Real, Sym, Vect};

/// Tensile strength of the interface: the apex stress k_c/(3α_φ) of the
/// Drucker–Prager cone (Eqs. 4, 6); 0 without cohesion, unbounded for a cohesive soil
/// without friction (α_φ = 0, whose cone has no apex).
pub fn tensile_strength(m: &FineMaterial) -> Real {
    if m.k_c <= 0.0 {
        0.0
    } else if m.alpha_phi > 0.0 {
        m.k_c / (3.0 * m.alpha_phi)
    } else {
        Real::INFINITY
    }
}

/// The interface stress of one wall pair: `sstar` while its normal traction n·σ*·n on
/// the wall plane of normal `n` stays at or below `strength`, else the apex stress
/// `strength`·I (the contact is open).
#[inline(always)]
pub fn cut<const D: usize>(sstar: Sym, n: &Vect<D>, strength: Real) -> Sym {
    if n.dot(&sstar.dot_vec(n)) > strength {
        Sym::iso(strength)
    } else {
        sstar
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use nalgebra::Vector2;

    fn soil(phi: Real, c: Real) -> FineMaterial {
        FineMaterial::from_spec(&crate::scene::MaterialSpec {
            name: "soil".into(),
            density: 2000.0,
            youngs_modulus: 1e7,
            poisson_ratio: 0.3,
            friction_angle: Some(phi),
            yield_surface: None,
            hardening: None,
            mu_i: None,
            dilatancy: None,
            cohesion: c,
            dilation_angle: 0.0,
            porosity: None,
            permeability: None,
            grain_size: None,
            saturated: false,
        })
    }

    /// The apex of the cone of Eq. (4) lies at c cot φ: f(3σ_t, 0) = 0.
    #[test]
    fn strength_is_the_apex() {
        assert_eq!(tensile_strength(&soil(30.0, 0.0)), 0.0);
        let m = soil(30.0, 1000.0);
        let st = tensile_strength(&m);
        assert!((m.alpha_phi * 3.0 * st - m.k_c).abs() <= 1e-12 * m.k_c);
        let cot = 1.0 / 30f64.to_radians().tan();
        assert!((st - 1000.0 * cot).abs() <= 1e-9 * st, "{st}");
        assert_eq!(tensile_strength(&soil(0.0, 1000.0)), Real::INFINITY);
    }

    /// A compressed contact keeps its stress; one in tension beyond the strength
    /// carries the apex stress, and nothing at all without cohesion.
    #[test]
    fn opens_beyond_the_strength() {
        let n = Vector2::new(-1.0, 0.0);
        let mut s = Sym::iso(-500.0);
        s.0[3] = 80.0;
        assert_eq!(cut(s, &n, 0.0).0, s.0);
        let mut t = Sym::iso(300.0);
        t.0[3] = 80.0;
        assert_eq!(cut(t, &n, 0.0).0, [0.0; 6]);
        assert_eq!(cut(t, &n, 200.0).0, Sym::iso(200.0).0);
        assert_eq!(cut(t, &n, 400.0).0, t.0);
    }
}
