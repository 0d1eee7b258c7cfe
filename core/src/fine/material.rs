//! Derived constants of the Drucker–Prager soil (Eqs. 4–8, 22 of seed 000), on the cone
//! of its `yield_surface`, with friction hardening (seed 004 Eq. 43) or μ(I).

use super::dilatancy::Dilatancy;
use super::hardening::Hardening;
use super::mu_i::MuI;
use super::pores::Pores;
use super::yield_surface::{fit, Yield};
use crate::numerics::math::{Real, Sym};
use crate::scene::{MaterialSpec, YieldSurface};
use nalgebra::Matrix3;

/// One fine-grain material with its derived constants.
#[derive(Clone, Debug, PartialEq, serde::Serialize, serde::Deserialize)]
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
    /// α_φ of φ on the cone `surface` (Eq. (6) for `plane_strain`; at ε_p = 0 with
    /// hardening, at I = 0 with μ(I)).
    pub alpha_phi: Real,
    /// k_c of c on the cone `surface` (Eq. (6) for `plane_strain`).
    pub k_c: Real,
    /// α_ψ of ψ on the cone `surface`.
    pub alpha_psi: Real,
    /// Jaky's K0 = 1 − sin φ (Eq. 26).
    pub k0: Real,
    /// Friction angle φ (rad): φ_e with hardening, atan μ_s with μ(I).
    pub phi: Real,
    /// Cohesion c (Pa).
    pub cohesion: Real,
    /// Porosity and permeability (None: water passes the soil freely).
    #[serde(default)]
    pub pores: Option<Pores>,
    /// The Drucker–Prager cone φ and c are fitted on.
    #[serde(default)]
    pub surface: YieldSurface,
    /// Friction hardening and softening (seed 004 Eq. 43).
    #[serde(default)]
    pub hardening: Option<Hardening>,
    /// The μ(I) rheology, on the `shear` cone.
    #[serde(default)]
    pub mu_i: Option<MuI>,
    /// State-dependent dilatancy (a soil with pores; the fluid's viscosity is set at
    /// the world's build, [`FineMaterial::immersed`]).
    #[serde(default)]
    pub dilatancy: Option<Dilatancy>,
}

impl FineMaterial {
    /// The yield constants of a particle with accumulated plastic strain `eps_p`,
    /// velocity gradient `l`, stress `sigma` (Pa, tension positive) and density `rho`
    /// for this step: the material's own, φ(ε_p) of seed 004 Eq. (43) refitted on its
    /// cone, or α_φ = μ(I)/3 from the deviatoric strain rate and the pressure at the
    /// start of the step (`mu_i`); with `dilatancy`, tan ψ/3 joins α_φ and sets α_ψ
    /// ([`Dilatancy`]).
    #[inline(always)]
    pub fn yield_at(&self, eps_p: Real, l: &Matrix3<Real>, sigma: &Sym, rho: Real) -> Yield {
        if let Some(d) = &self.dilatancy {
            return self.dilatant_yield(d, l, sigma, rho);
        }
        match (&self.hardening, &self.mu_i) {
            (None, None) => Yield {
                alpha_phi: self.alpha_phi,
                k_c: self.k_c,
                alpha_psi: self.alpha_psi,
            },
            (Some(h), _) => {
                let (alpha_phi, k_c) = fit(self.surface, h.angle(eps_p), self.cohesion);
                Yield {
                    alpha_phi,
                    k_c,
                    alpha_psi: self.alpha_psi,
                }
            }
            (None, Some(m)) => {
                let e = Sym::from_matrix_sym(l).dev();
                let rate = (2.0 * e.ddot(&e)).sqrt();
                Yield {
                    alpha_phi: m.mu(rate, -sigma.trace() / 3.0) / 3.0,
                    k_c: self.k_c,
                    alpha_psi: self.alpha_psi,
                }
            }
        }
    }

    /// [`FineMaterial::yield_at`] with dilatancy: I_m from the deviatoric strain rate
    /// and the effective pressure at the start of the step, φ from the density;
    /// α_φ = μ(I)/3 + tan ψ/3 (the material's own α_φ without `mu_i`), not below 0,
    /// and α_ψ = tan ψ/3.
    #[inline]
    fn dilatant_yield(&self, d: &Dilatancy, l: &Matrix3<Real>, sigma: &Sym, rho: Real) -> Yield {
        let e = Sym::from_matrix_sym(l).dev();
        let rate = (2.0 * e.ddot(&e)).sqrt();
        let i_m = d.number(rate, -sigma.trace() / 3.0);
        let base = match &self.mu_i {
            Some(m) => m.mu_of_i(Dilatancy::inertial_equivalent(i_m)) / 3.0,
            None => self.alpha_phi,
        };
        let tan_psi = d.tan_psi(d.fraction(rho, self.rho0), i_m);
        Yield {
            alpha_phi: (base + tan_psi / 3.0).max(0.0),
            k_c: self.k_c,
            alpha_psi: tan_psi / 3.0,
        }
    }

    /// The material immersed in a fluid of viscosity `eta_f` (Pa·s): its dilatancy's
    /// viscous number takes it.
    pub fn immersed(mut self, eta_f: Real) -> Self {
        if let Some(d) = self.dilatancy.as_mut() {
            d.eta_f = eta_f;
        }
        self
    }
}

impl FineMaterial {
    /// (α_φ, k_c) of the strongest cone the material reaches: its own, the largest of
    /// φ_e, φ_p and φ_r with hardening, μ_2 with μ(I). The dummy wall particles scale
    /// their stress on it ([`WallStrength`](crate::interactions::fine_wall::WallStrength)).
    /// On the static cone (μ_s) a particle flowing at μ(I) > μ_s passed the wall only
    /// μ_s/μ(I) of its shear, and a layer on a slope tan θ between μ_s and μ_2 slid on
    /// its bed instead of shearing.
    pub fn strongest_cone(&self) -> (Real, Real) {
        // with dilatancy: and the quasi-static dilatancy of the initial packing
        let dilated = |(a, k): (Real, Real)| match &self.dilatancy {
            Some(d) => (a + (d.k * (d.phi_0 - d.phi_c)).max(0.0) / 3.0, k),
            None => (a, k),
        };
        dilated(match (&self.hardening, &self.mu_i) {
            (None, None) => (self.alpha_phi, self.k_c),
            (Some(h), _) => {
                let phi = h.initial.max(h.peak).max(h.residual);
                fit(self.surface, phi, self.cohesion)
            }
            (None, Some(m)) => (m.mu_2 / 3.0, self.k_c),
        })
    }
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
    ///
    /// A dilatant soil ([`Dilatancy`]) dilates below ρ0 by design: its floor is the
    /// density of the loosest packing its law drives it to in a dense flow,
    /// φ_eq(I_m = 1) = φ_c / (1 + b), ρ0 φ_eq / φ0 (the end of the dense regime; a
    /// looser particle contracts as it shears, so the law itself holds the density
    /// above).
    pub fn density_floor(&self) -> Real {
        if let Some(d) = &self.dilatancy {
            return self.rho0 * (d.phi_eq(1.0) / d.phi_0).min(1.0);
        }
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

impl FineMaterial {
    pub fn from_spec(m: &MaterialSpec) -> Self {
        let e = m.youngs_modulus;
        let nu = m.poisson_ratio;
        let phi = m.static_friction_angle().to_radians();
        let psi = m.dilation_angle.to_radians();
        let surface = m.surface();
        let (alpha_phi, k_c) = fit(surface, phi, m.cohesion);
        FineMaterial {
            name: m.name.clone(),
            rho0: m.density,
            shear: e / (2.0 * (1.0 + nu)),
            bulk: e / (3.0 * (1.0 - 2.0 * nu)),
            c0: (e / (3.0 * (1.0 - 2.0 * nu) * m.density)).sqrt(),
            alpha_phi,
            k_c,
            alpha_psi: fit(surface, psi, 0.0).0,
            k0: 1.0 - phi.sin(),
            phi,
            cohesion: m.cohesion,
            pores: Pores::of(m),
            surface,
            hardening: m
                .hardening
                .as_ref()
                .map(|h| Hardening::from_spec(h, m.static_friction_angle())),
            mu_i: m.mu_i.as_ref().map(MuI::from_spec),
            dilatancy: m.dilatancy.as_ref().map(|d| Dilatancy {
                k: d.k,
                phi_c: d.phi_c,
                b: d.b,
                phi_0: 1.0 - m.porosity.unwrap_or(0.0),
                eta_f: 0.0,
                grains: m.mu_i.as_ref().map(|g| (g.grain_diameter, g.grain_density)),
            }),
        }
    }
}

/// Whether all fine materials share one impedance and sound speed, so that every
/// pair takes the reciprocals of its particle i (the common single-soil scene).
pub fn uniform_acoustics(mats: &[FineMaterial]) -> bool {
    mats.windows(2)
        .all(|w| w[0].rho0 * w[0].c0 == w[1].rho0 * w[1].c0 && w[0].c0 == w[1].c0)
}
