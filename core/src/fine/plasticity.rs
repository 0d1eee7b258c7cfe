//! Elastic–perfectly-plastic Drucker–Prager update with the Jaumann rate (Eqs. 4–12).
//!
//! Stress is positive in tension. The elastic rate is written with the deviatoric strain
//! rate, 2G ė + K tr(ε̇) I (Eq. 7 prints 2G ε̇, which double-counts the volumetric part),
//! and the plastic flow direction uses the plastic potential g of Eq. (5), i.e. α_ψ, as
//! required by the non-associated rule whose multiplier Eq. (8) has the denominator
//! 9α_φKα_ψ + G.

use super::material::FineMaterial;
use super::yield_surface::Yield;
use crate::numerics::math::{Real, Sym};
use nalgebra::Matrix3;

/// Result of one constitutive update.
#[derive(Clone, Copy, Debug)]
pub struct StressUpdate {
    pub stress: Sym,
    /// Increment of accumulated deviatoric plastic strain, √(2/3 Δe_p:Δe_p).
    pub plastic_strain: Real,
}

/// One particle's constitutive step: its yield constants for the step
/// ([`FineMaterial::yield_at`]: fixed, hardened by its accumulated plastic strain
/// `eps_p`, μ(I), or dilatant at its density `rho`) and [`update_stress`]. The solver and the element tests
/// ([`element`](super::element)) both step the stress through here.
#[inline(always)]
pub fn constitutive_step(
    m: &FineMaterial,
    l: &Matrix3<Real>,
    sigma: &Sym,
    eps_p: Real,
    diffusion: &Sym,
    dt: Real,
    rho: Real,
) -> StressUpdate {
    let y = m.yield_at(eps_p, l, sigma, rho);
    update_stress(m, &y, l, sigma, diffusion, dt)
}

/// Integrate the stress over `dt` given the velocity gradient `l` (L_ab = ∂v_a/∂x_b,
/// zero out-of-plane rows/columns in 2D) and the stress-diffusion rate `diffusion`
/// (Eq. 25), then apply the return mapping (Eqs. 11–12).
#[inline]
pub fn update_stress(
    m: &FineMaterial,
    y: &Yield,
    l: &Matrix3<Real>,
    sigma: &Sym,
    diffusion: &Sym,
    dt: Real,
) -> StressUpdate {
    let strain_rate = Sym::from_matrix_sym(l);
    let tr = strain_rate.trace();
    // Elastic rate, Eq. (7) without the plastic term, with the Jaumann and diffusion
    // terms.
    let mut elastic = strain_rate.dev().scale(2.0 * m.shear);
    let kt = m.bulk * tr;
    elastic.0[0] += kt;
    elastic.0[1] += kt;
    elastic.0[2] += kt;
    let unreturned = elastic.add(&jaumann(sigma, l)).add(diffusion);
    let mut rate = unreturned;
    let mut corrected = false;

    // Plastic corrector on the yield surface, Eqs. (7)–(8).
    let i1 = sigma.trace();
    let s = sigma.dev();
    let j2 = 0.5 * s.ddot(&s);
    if j2 > 0.0 {
        let sj = j2.sqrt();
        let f = sj + y.alpha_phi * i1 - y.k_c;
        if f >= -1e-12 * (y.k_c + y.alpha_phi * i1.abs() + sj) {
            let num = 3.0 * y.alpha_phi * m.bulk * tr + (m.shear / sj) * s.ddot(&strain_rate);
            let gamma = num / (9.0 * y.alpha_phi * m.bulk * y.alpha_psi + m.shear);
            if gamma > 0.0 {
                let mut g = s.scale(gamma * m.shear / sj);
                let v = gamma * 3.0 * m.bulk * y.alpha_psi;
                g.0[0] += v;
                g.0[1] += v;
                g.0[2] += v;
                rate = rate.sub(&g);
                corrected = true;
            }
        }
    }

    let mut trial = *sigma;
    trial.axpy(dt, &rate);
    let stress = return_map(y, trial);
    if !corrected && stress == trial {
        // elastic: the trial state is the elastic one
        return StressUpdate {
            stress,
            plastic_strain: 0.0,
        };
    }
    let mut elastic_trial = *sigma;
    elastic_trial.axpy(dt, &unreturned);
    let de = elastic_trial.dev().sub(&stress.dev()).scale(0.5 / m.shear);
    StressUpdate {
        stress,
        plastic_strain: (2.0 / 3.0 * de.ddot(&de)).sqrt(),
    }
}

/// The Jaumann terms σ Ωᵀ + Ω σ of Eq. (9) with the spin Ω = ½ (L − Lᵀ) of Eq. (10):
/// for symmetric σ and antisymmetric Ω this is Ω σ − σ Ω = Ω σ + (Ω σ)ᵀ, written out
/// for the six components (a third of the operations of the matrix products).
#[inline(always)]
pub fn jaumann(sigma: &Sym, l: &Matrix3<Real>) -> Sym {
    let [a, b, c, d, e, f] = sigma.0; // xx, yy, zz, xy, xz, yz
    let p = 0.5 * (l[(0, 1)] - l[(1, 0)]);
    let q = 0.5 * (l[(0, 2)] - l[(2, 0)]);
    let r = 0.5 * (l[(1, 2)] - l[(2, 1)]);
    Sym([
        2.0 * (p * d + q * e),
        2.0 * (r * f - p * d),
        -2.0 * (q * e + r * f),
        p * (b - a) + q * f + r * e,
        q * (c - a) + p * f - r * d,
        r * (c - b) - p * e - q * d,
    ])
}

/// Return mapping to the Drucker–Prager cone: tension cut-off at the apex, Eq. (11),
/// then radial scaling of the deviator, Eq. (12).
#[inline]
pub fn return_map(y: &Yield, mut sigma: Sym) -> Sym {
    let mut i1 = sigma.trace();
    if y.alpha_phi > 0.0 && -y.alpha_phi * i1 + y.k_c < 0.0 {
        let shift = (i1 - y.k_c / y.alpha_phi) / 3.0;
        sigma.0[0] -= shift;
        sigma.0[1] -= shift;
        sigma.0[2] -= shift;
        i1 = sigma.trace();
    }
    let s = sigma.dev();
    let sj = (0.5 * s.ddot(&s)).sqrt();
    let cap = (-y.alpha_phi * i1 + y.k_c).max(0.0);
    if cap < sj {
        let r = cap / sj;
        let mut out = s.scale(r);
        let p = i1 / 3.0;
        out.0[0] += p;
        out.0[1] += p;
        out.0[2] += p;
        return out;
    }
    sigma
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::scene::MaterialSpec;

    fn sand(phi: f64, c: f64) -> FineMaterial {
        FineMaterial::from_spec(&MaterialSpec {
            name: "s".into(),
            density: 2000.0,
            youngs_modulus: 5e6,
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

    /// The material's own yield constants (no hardening, no μ(I)).
    fn fixed(m: &FineMaterial) -> Yield {
        m.yield_at(0.0, &Matrix3::zeros(), &Sym::ZERO, m.rho0)
    }

    /// The written-out Jaumann terms equal σ Ωᵀ + Ω σ by matrix products.
    #[test]
    fn jaumann_terms_match_the_matrix_products() {
        let sigma = Sym([-3.0e3, -1.2e3, -2.1e3, 450.0, -320.0, 180.0]);
        let l = Matrix3::new(0.3, -1.7, 0.4, 2.2, -0.5, 0.9, -0.6, 1.3, 0.1);
        let w = (l - l.transpose()) * 0.5;
        let s = sigma.to_matrix();
        let want = Sym::from_matrix_sym(&(s * w.transpose() + w * s));
        let got = jaumann(&sigma, &l);
        for k in 0..6 {
            assert!(
                (got.0[k] - want.0[k]).abs() < 1e-12 * 1e4,
                "component {k}: {} against {}",
                got.0[k],
                want.0[k]
            );
        }
        // 2D: σ̇_xx = 2 σ_xy ω, σ̇_xy = ω (σ_yy − σ_xx) with ω = ½ (∂u/∂y − ∂v/∂x)
        let mut l2 = Matrix3::zeros();
        (l2[(0, 1)], l2[(1, 0)]) = (0.8, -0.2);
        let s2 = Sym([-3.0e3, -1.2e3, -2.1e3, 450.0, 0.0, 0.0]);
        let j = jaumann(&s2, &l2);
        assert!((j.0[0] - 2.0 * 450.0 * 0.5).abs() < 1e-9);
        assert!((j.0[3] - 0.5 * (-1.2e3 + 3.0e3)).abs() < 1e-9);
        assert_eq!((j.0[2], j.0[4], j.0[5]), (0.0, 0.0, 0.0));
    }

    /// Uniaxial compression in the elastic range: σ_xx = (K + 4G/3) ε, σ_yy = (K − 2G/3) ε.
    #[test]
    fn elastic_uniaxial_strain() {
        let m = sand(30.0, 0.0);
        let mut l = Matrix3::zeros();
        l[(0, 0)] = -1e-3; // compression rate
        let p0 = Sym::iso(-1e4); // confinement keeps it elastic
        let u = constitutive_step(&m, &l, &p0, 0.0, &Sym::ZERO, 1.0e-3, m.rho0);
        let eps = -1e-6;
        assert!((u.stress.0[0] - (-1e4 + (m.bulk + 4.0 * m.shear / 3.0) * eps)).abs() < 1e-9);
        assert!((u.stress.0[1] - (-1e4 + (m.bulk - 2.0 * m.shear / 3.0) * eps)).abs() < 1e-9);
        assert_eq!(u.plastic_strain, 0.0);
    }

    /// After return mapping the state lies on the cone √J2 = −α_φ I1 + k_c.
    #[test]
    fn return_map_lands_on_yield_surface() {
        for (phi, c) in [(30.0, 0.0), (21.9, 0.0), (15.0, 8400.0)] {
            let m = sand(phi, c);
            let s = Sym([-1e4, -3e4, -2e4, 2e4, 1e3, -5e3]);
            let r = return_map(&fixed(&m), s);
            let f = r.j2().sqrt() + m.alpha_phi * r.trace() - m.k_c;
            assert!(f.abs() < 1e-8 * 3e4, "phi {phi}: f = {f}");
            assert!((r.trace() - s.trace()).abs() < 1e-8, "pressure kept");
        }
        // tension beyond the apex returns to the apex
        let m = sand(30.0, 0.0);
        let r = return_map(&fixed(&m), Sym([1e3, 2e3, 5e2, 1e2, 0.0, 0.0]));
        assert!(r.0.iter().all(|x| x.abs() < 1e-9), "{r:?}");
    }

    /// Simple shear of a confined sample saturates at the Drucker–Prager strength
    /// √J2 = α_φ·3p for c = 0; a wrong friction angle fails the check.
    #[test]
    fn simple_shear_strength() {
        let m = sand(30.0, 0.0);
        let mut s = Sym::iso(-1e5);
        let mut l = Matrix3::zeros();
        l[(0, 1)] = 1.0;
        let mut acc = 0.0;
        // elastic until γ = τ_y / G ≈ 0.025; shear to γ = 0.06
        for _ in 0..6000 {
            let u = constitutive_step(&m, &l, &s, 0.0, &Sym::ZERO, 1e-5, m.rho0);
            s = u.stress;
            acc += u.plastic_strain;
        }
        let strength = m.alpha_phi * 3.0e5;
        assert!(
            (s.j2().sqrt() / strength - 1.0).abs() < 1e-3,
            "{} vs {strength}",
            s.j2().sqrt()
        );
        assert!(acc > 0.005, "plastic strain accumulates: {acc}");
        let wrong = sand(25.0, 0.0).alpha_phi * 3.0e5;
        assert!((s.j2().sqrt() / wrong - 1.0).abs() > 0.1);
    }

    /// Lateral earth pressure of a plane-strain element under a fixed vertical stress:
    /// stretched sideways (a barrier moving away) it reaches the active limit, squeezed
    /// (a barrier pushed in) the passive limit. The plane-strain Drucker–Prager fit of
    /// Eq. (6) is built to reproduce Mohr–Coulomb in plane strain, so the limits land
    /// near Rankine's K_a = (1 − sin φ)/(1 + sin φ) and K_p = 1/K_a (φ = 30°: 1/3 and 3);
    /// with ψ = 0 instead of the associated ψ = φ they differ by about 5 %.
    fn lateral_limit(m: &FineMaterial, rate: Real) -> Real {
        let sv = -1.0e3;
        let nu = 0.3;
        let k_start = 0.43; // ν/(1 − ν), an elastic oedometric state
        let mut s = Sym([k_start * sv, sv, nu * (1.0 + k_start) * sv, 0.0, 0.0, 0.0]);
        let dt = 1.0;
        for _ in 0..3000 {
            // the vertical strain rate that keeps σ_yy = σ_v (σ_yy is affine in it)
            let probe = |eyy: Real| {
                let mut l = Matrix3::zeros();
                l[(0, 0)] = rate;
                l[(1, 1)] = eyy;
                constitutive_step(m, &l, &s, 0.0, &Sym::ZERO, dt, m.rho0)
            };
            let (f0, f1) = (probe(0.0).stress.0[1] - sv, probe(1e-6).stress.0[1] - sv);
            let eyy = -f0 * 1e-6 / (f1 - f0);
            s = probe(eyy).stress;
        }
        s.0[0] / s.0[1]
    }

    #[test]
    fn active_and_passive_earth_pressure() {
        let rankine = |phi: Real| {
            let sn = phi.to_radians().sin();
            (1.0 - sn) / (1.0 + sn)
        };
        let m = sand(30.0, 0.0);
        let ka = lateral_limit(&m, 1e-6);
        let kp = lateral_limit(&m, -1e-6);
        let (ka_ref, kp_ref) = (rankine(30.0), 1.0 / rankine(30.0));
        assert!(
            (ka / ka_ref - 1.0).abs() < 0.06,
            "K_a = {ka} vs Rankine {ka_ref}"
        );
        assert!(
            (kp / kp_ref - 1.0).abs() < 0.06,
            "K_p = {kp} vs Rankine {kp_ref}"
        );
        // the check sees a wrong friction angle
        assert!((lateral_limit(&sand(25.0, 0.0), 1e-6) / ka_ref - 1.0).abs() > 0.15);
    }
}
