//! Element tests: one material point of a fine material driven through a homogeneous
//! strain path by the solver's own constitutive step
//! ([`constitutive_step`](super::plasticity::constitutive_step)): drained triaxial
//! compression under a constant confining stress, simple shear, and undrained simple
//! shear of a dilatant soil (its volume held, so that its effective pressure carries
//! the dilatancy, issue 44 item 7). Stress is positive in tension, as everywhere in the
//! solver; the paths report pressures and deviators positive in compression, as a
//! laboratory does.

use super::material::FineMaterial;
use super::plasticity::{constitutive_step, StressUpdate};
use crate::numerics::math::{Real, Sym};
use nalgebra::Matrix3;

/// A material point: its stress, accumulated plastic strain ε_p and density.
#[derive(Clone, Debug)]
pub struct MaterialPoint<'a> {
    pub material: &'a FineMaterial,
    pub stress: Sym,
    pub plastic_strain: Real,
    /// ρ (kg/m³), following the volumetric strain: a dilatant soil's solid fraction.
    pub density: Real,
}

impl<'a> MaterialPoint<'a> {
    /// A point of `material` at `stress` (Pa, tension positive) and the material's
    /// density, with no plastic strain.
    pub fn new(material: &'a FineMaterial, stress: Sym) -> Self {
        MaterialPoint {
            material,
            stress,
            plastic_strain: 0.0,
            density: material.rho0,
        }
    }

    /// The update over `dt` under the velocity gradient `l`, without taking it.
    pub fn trial(&self, l: &Matrix3<Real>, dt: Real) -> StressUpdate {
        constitutive_step(
            self.material,
            l,
            &self.stress,
            self.plastic_strain,
            &Sym::ZERO,
            dt,
            self.density,
        )
    }

    /// Take the update over `dt` under the velocity gradient `l`; the density follows
    /// the volumetric strain, ρ ← ρ exp(−tr L Δt).
    pub fn step(&mut self, l: &Matrix3<Real>, dt: Real) {
        let u = self.trial(l, dt);
        self.stress = u.stress;
        self.plastic_strain += u.plastic_strain;
        self.density *= (-l.trace() * dt).exp();
    }

    /// Pressure p = −I1/3 (positive in compression).
    pub fn pressure(&self) -> Real {
        -self.stress.trace() / 3.0
    }

    /// √J2 of the stress.
    pub fn shear_stress(&self) -> Real {
        self.stress.j2().sqrt()
    }
}

/// One state of a triaxial path.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct TriaxialState {
    /// Axial strain (positive in compression).
    pub axial_strain: Real,
    /// Volumetric strain (positive in compression).
    pub volumetric_strain: Real,
    /// Deviator q = σ_a − σ_r (compression positive).
    pub q: Real,
    /// Mean stress p (compression positive).
    pub p: Real,
    /// Accumulated equivalent plastic strain ε_p.
    pub plastic_strain: Real,
}

/// Drained triaxial compression: the point starts isotropic at `confining` (σ3, Pa,
/// compression positive), is shortened along x to the axial strain `axial_strain` in
/// `steps` equal increments, and its two lateral strain rates are solved each increment
/// so that the lateral stresses stay at σ3 (to 1e-12 relative). Returns the start and
/// every increment's state.
///
/// # Panics
/// If `confining` or `axial_strain` is not positive, or `steps` is zero.
pub fn triaxial_compression(
    material: &FineMaterial,
    confining: Real,
    axial_strain: Real,
    steps: usize,
) -> Vec<TriaxialState> {
    assert!(confining > 0.0 && axial_strain > 0.0 && steps > 0);
    let mut pt = MaterialPoint::new(material, Sym::iso(-confining));
    let de = axial_strain / steps as Real;
    let l_of = |lateral: Real| {
        let mut l = Matrix3::zeros();
        l[(0, 0)] = -de;
        l[(1, 1)] = lateral;
        l[(2, 2)] = lateral;
        l
    };
    // residual of the lateral stress (σ_yy = σ_zz by symmetry) after the increment
    let lateral_error =
        |pt: &MaterialPoint, lateral: Real| pt.trial(&l_of(lateral), 1.0).stress.0[1] + confining;
    let state = |pt: &MaterialPoint, ea: Real, ev: Real| TriaxialState {
        axial_strain: ea,
        volumetric_strain: ev,
        q: pt.stress.0[1] - pt.stress.0[0],
        p: pt.pressure(),
        plastic_strain: pt.plastic_strain,
    };
    let mut out = vec![state(&pt, 0.0, 0.0)];
    // elastically the lateral rate is ν de (Poisson): the first guess
    let mut guess = 0.25 * de;
    let (mut ea, mut ev) = (0.0, 0.0);
    for _ in 0..steps {
        // secant iterations on the lateral rate (the update is piecewise smooth in it)
        let (mut x0, mut x1) = (guess, guess * 1.01 + 1e-3 * de);
        let (mut f0, mut f1) = (lateral_error(&pt, x0), lateral_error(&pt, x1));
        for _ in 0..100 {
            if f1.abs() <= 1e-12 * confining || f1 == f0 {
                break;
            }
            let x2 = x1 - f1 * (x1 - x0) / (f1 - f0);
            (x0, f0) = (x1, f1);
            x1 = x2;
            f1 = lateral_error(&pt, x1);
        }
        pt.step(&l_of(x1), 1.0);
        guess = x1;
        ea += de;
        ev += de - 2.0 * x1;
        out.push(state(&pt, ea, ev));
    }
    out
}

/// One state of a simple-shear path.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct ShearState {
    /// Engineering shear strain γ.
    pub gamma: Real,
    /// √J2 of the stress.
    pub shear_stress: Real,
    /// Mean stress p (compression positive).
    pub p: Real,
    /// Accumulated equivalent plastic strain ε_p.
    pub plastic_strain: Real,
}

/// Simple shear v_x = γ̇ y of a point starting isotropic at `pressure` (Pa, compression
/// positive), to the engineering shear strain `gamma` in `steps` equal increments of
/// duration `dt` each (the strain rate γ/(steps dt) matters only to μ(I)). Returns the
/// start and every increment's state.
///
/// # Panics
/// If `pressure`, `gamma` or `dt` is not positive, or `steps` is zero.
pub fn simple_shear(
    material: &FineMaterial,
    pressure: Real,
    gamma: Real,
    steps: usize,
    dt: Real,
) -> Vec<ShearState> {
    assert!(pressure > 0.0 && gamma > 0.0 && dt > 0.0 && steps > 0);
    let mut pt = MaterialPoint::new(material, Sym::iso(-pressure));
    let dg = gamma / steps as Real;
    let mut l = Matrix3::zeros();
    l[(0, 1)] = dg / dt;
    let state = |pt: &MaterialPoint, g: Real| ShearState {
        gamma: g,
        shear_stress: pt.shear_stress(),
        p: pt.pressure(),
        plastic_strain: pt.plastic_strain,
    };
    let mut out = vec![state(&pt, 0.0)];
    for k in 1..=steps {
        pt.step(&l, dt);
        out.push(state(&pt, dg * k as Real));
    }
    out
}

/// One state of an undrained simple-shear path.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct UndrainedState {
    /// Engineering shear strain γ.
    pub gamma: Real,
    /// Effective mean stress p' (compression positive).
    pub p: Real,
    /// Excess pore pressure, the total mean stress p0 held: u_e = p0 − p'.
    pub excess_pore_pressure: Real,
    /// √J2 of the effective stress.
    pub shear_stress: Real,
}

/// Undrained simple shear v_x = γ̇ y at constant volume (grains and water taken
/// incompressible: the skeleton's volume is held, as in a sealed sample): the point
/// starts at the effective pressure `pressure` (Pa) and the density `density`, on its
/// yield surface (σ_xy = k_c + 3 α_φ p), and is sheared to `gamma` in `steps` equal
/// increments of `dt` each. Its dilatancy then moves p' (issue 44 item 7); the total
/// mean stress is held at the start's, so the pore water takes u_e = p0 − p'.
///
/// # Panics
/// If `pressure`, `density`, `gamma` or `dt` is not positive, or `steps` is zero.
pub fn undrained_simple_shear(
    material: &FineMaterial,
    (pressure, density): (Real, Real),
    gamma: Real,
    steps: usize,
    dt: Real,
) -> Vec<UndrainedState> {
    assert!(pressure > 0.0 && density > 0.0 && gamma > 0.0 && dt > 0.0 && steps > 0);
    let dg = gamma / steps as Real;
    let mut l = Matrix3::zeros();
    l[(0, 1)] = dg / dt;
    let iso = Sym::iso(-pressure);
    let y = material.yield_at(0.0, &l, &iso, density);
    let mut start = iso;
    start.0[3] = y.k_c + 3.0 * y.alpha_phi * pressure;
    let mut pt = MaterialPoint {
        density,
        ..MaterialPoint::new(material, start)
    };
    let state = |pt: &MaterialPoint, g: Real| UndrainedState {
        gamma: g,
        p: pt.pressure(),
        excess_pore_pressure: pressure - pt.pressure(),
        shear_stress: pt.shear_stress(),
    };
    let mut out = vec![state(&pt, 0.0)];
    for k in 1..=steps {
        pt.step(&l, dt);
        out.push(state(&pt, dg * k as Real));
    }
    out
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::scene::{DilatancySpec, MaterialSpec, YieldSurface};

    /// A dilatant soil on the shear cone, μ_s = 0.4, dry (η_f = 0: I_m = 0 at any
    /// rate, φ_eq = φ_c), with porosity `n` and dilatancy constant `k`.
    fn dilatant(n: Real, k: Real) -> FineMaterial {
        FineMaterial::from_spec(&MaterialSpec {
            name: "beads".into(),
            density: 2500.0 * (1.0 - n),
            youngs_modulus: 1e8,
            poisson_ratio: 0.3,
            friction_angle: Some(0.4_f64.atan().to_degrees()),
            yield_surface: Some(YieldSurface::Shear),
            hardening: None,
            mu_i: None,
            dilatancy: Some(DilatancySpec {
                k,
                phi_c: 0.57,
                b: 1.0,
            }),
            cohesion: 0.0,
            dilation_angle: 0.0,
            porosity: Some(n),
            permeability: Some(1e-10),
            grain_size: None,
            saturated: true,
        })
    }

    /// Undrained simple shear of a dense (φ = 0.60) and a loose (0.55) point against the
    /// dilatancy law integrated at constant volume. φ stays at its start, so tan ψ = K
    /// (φ − φ_c) and μ = μ_s + tan ψ are constant, and on the yield surface the
    /// Drucker–Prager multiplier (seed 000 Eq. 8) gives dp'/dγ = K_b tan ψ G / (K_b μ
    /// tan ψ + G) (K_b, G the bulk and shear moduli): p' = p0 + γ dp'/dγ, to 1e-6 p0 over
    /// γ = 0.05 %. The dense point gains p' (to 5.4 p0; u_e < 0); the loose one
    /// liquefies, p' < 1e-3 p0 by the end (at γ = 0.014 %). The law's K = 4 passes; the same check against K = 4.4 fails.
    #[test]
    fn undrained_simple_shear_follows_the_dilatancy_law() {
        let (p0, gamma, k) = (1000.0, 5e-4, 4.0);
        for (k_model, must_pass) in [(k, true), (1.1 * k, false)] {
            for n in [0.40, 0.45] {
                let m = dilatant(n, k_model);
                let path = undrained_simple_shear(&m, (p0, m.rho0), gamma, 5000, 1e-3);
                let t = k * ((1.0 - n) - 0.57);
                let mu = 0.4 + t;
                let slope = m.bulk * t * m.shear / (m.bulk * mu * t + m.shear);
                let mut worst: Real = 0.0;
                for s in &path {
                    let want = p0 + s.gamma * slope;
                    if want > 1e-3 * p0 {
                        worst = worst.max((s.p - want).abs() / p0);
                    }
                }
                let last = path.last().unwrap();
                if must_pass {
                    if n < 0.42 {
                        assert!(last.p > p0 && last.excess_pore_pressure < 0.0, "{last:?}");
                    } else {
                        assert!(last.p < 1e-3 * p0, "the loose point keeps p' {}", last.p);
                    }
                }
                assert_eq!(
                    worst < 1e-6,
                    must_pass,
                    "K = {k_model}, n = {n}: largest |p' − p'_law| / p0 = {worst:.3e}"
                );
            }
        }
    }
}
