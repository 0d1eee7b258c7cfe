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
/// `strength`·I (the contact is open). The flag says whether it opened.
#[inline(always)]
pub fn cut<const D: usize>(sstar: Sym, n: &Vect<D>, strength: Real) -> (Sym, bool) {
    if n.dot(&sstar.dot_vec(n)) > strength {
        (Sym::iso(strength), true)
    } else {
        (sstar, false)
    }
}

/// The closed wall pairs of one soil particle with one wall object: their summed
/// acceleration, and what each pair's open contact would give across the face.
///
/// The cut of [`cut`] tests each pair's normal traction n·σ*·n, but a pair acts along its
/// own direction e: a = k σ*·e (k = (2/ρ_i) ∂W/∂r V_w < 0). Summed over a particle's
/// pairs with a flat face, the shear of σ* cancels across the face (Σ k e ∥ n); where
/// the pairs are one-sided (near the edge of a receding barrier's face, or at its toe)
/// it need not, and a particle whose every contact is in compression was pulled after
/// the barrier (issue 74 grid: −3.3e-3 N/m at 1 m/s in 1 µs steps). So the closed pairs
/// of a particle with an object together pull no harder across its face than open
/// contacts would: open, each carries σ_t I and its part across the face is
/// σ_t k (e·n) ≥ −σ_t |k e·n| (none without cohesion). The limit acts on the sum, not
/// on each pair: one pair's pull balanced by its mirror (steady shear on a bed) is not
/// a pull of the particle, and limiting each pair raised the Bagnold layer's surface
/// speed (docs/method.md, §Walls).
#[derive(Clone, Copy, Debug)]
pub struct ClosedPairs<const D: usize> {
    /// Σ a over the closed pairs.
    pub sum: Vect<D>,
    /// Σ |k e·n|: the scale of the open contacts' pull, and each pair's share of a
    /// correction.
    pub weight: Real,
    pub count: u32,
}

impl<const D: usize> ClosedPairs<D> {
    pub fn zero() -> Self {
        ClosedPairs {
            sum: Vect::<D>::zeros(),
            weight: 0.0,
            count: 0,
        }
    }

    /// Add a closed pair's acceleration `a`; returns its weight |k e·n|.
    #[inline(always)]
    pub fn add(&mut self, a: &Vect<D>, n: &Vect<D>, e: &Vect<D>, k: Real) -> Real {
        let w = (k * e.dot(n)).abs();
        self.sum += a;
        self.weight += w;
        self.count += 1;
        w
    }

    /// How much the pairs' summed acceleration across the face of normal `n` (towards
    /// the soil) falls short of the open contacts' bound −σ_t Σ|k e·n| at tensile
    /// strength `strength` (0 when it does not; never for an unbounded strength).
    #[inline(always)]
    pub fn deficit(&self, n: &Vect<D>, strength: Real) -> Real {
        if self.count == 0 || !strength.is_finite() {
            return 0.0;
        }
        (-strength * self.weight - self.sum.dot(n)).max(0.0)
    }

    /// The share of the correction of a pair of weight `w`: w / Σ w, or an equal share
    /// where no pair has weight.
    #[inline(always)]
    pub fn share(&self, w: Real) -> Real {
        if self.weight > 0.0 {
            w / self.weight
        } else {
            1.0 / self.count as Real
        }
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
        assert_eq!(cut(s, &n, 0.0).0 .0, s.0);
        let mut t = Sym::iso(300.0);
        t.0[3] = 80.0;
        assert_eq!(cut(t, &n, 0.0).0 .0, [0.0; 6]);
        assert_eq!(cut(t, &n, 200.0).0 .0, Sym::iso(200.0).0);
        assert_eq!(cut(t, &n, 400.0).0 .0, t.0);
        assert!(cut(t, &n, 0.0).1 && !cut(s, &n, 0.0).1);
    }

    /// Two steep pairs on a face in compression (n·σ*·n = −P) whose shear pulls across
    /// the face on one side and pushes on the other: mirrored, nothing is short; alone,
    /// the pulling pair falls short of no pull by its pull without cohesion, and by
    /// its pull less σ_t |k e·n| with σ_t; a soil of unbounded strength is never short.
    #[test]
    fn closed_pairs_together_pull_no_harder_than_open_ones() {
        let n = Vector2::new(-1.0, 0.0);
        let k = -2.0;
        let (p, tau) = (100.0, -80.0);
        let mut s = Sym::iso(-p);
        s.0[3] = tau;
        assert!(!cut(s, &n, 0.0).1);
        let up = Vector2::new(-0.3, 0.91_f64.sqrt());
        let down = Vector2::new(-0.3, -(0.91_f64.sqrt()));
        let a_up = s.dot_vec(&up) * k;
        assert!(a_up.dot(&n) < 0.0, "the test pair must pull: {a_up}");
        let mut both = ClosedPairs::zero();
        both.add(&a_up, &n, &up, k);
        both.add(&(s.dot_vec(&down) * k), &n, &down, k);
        assert_eq!(both.deficit(&n, 0.0), 0.0);
        let mut one = ClosedPairs::zero();
        let w = one.add(&a_up, &n, &up, k);
        assert!((w - 0.6).abs() < 1e-15 && one.share(w) == 1.0);
        assert_eq!(one.deficit(&n, 0.0), -a_up.dot(&n));
        let st = 30.0;
        assert!((one.deficit(&n, st) - (-a_up.dot(&n) - st * 0.6)).abs() < 1e-12);
        assert_eq!(one.deficit(&n, Real::INFINITY), 0.0);
    }
}
