//! Element tests: one material point of a fine material driven through a homogeneous
//! strain path by the solver's own constitutive step
//! ([`constitutive_step`](super::plasticity::constitutive_step)): drained triaxial
//! compression under a constant confining stress, and simple shear. Stress is positive
//! in tension, as everywhere in the solver; the paths report pressures and deviators
//! positive in compression, as a laboratory does.

use super::material::FineMaterial;
use super::plasticity::{constitutive_step, StressUpdate};
use crate::math::{Real, Sym};
use nalgebra::Matrix3;

/// A material point: its stress and accumulated plastic strain ε_p.
#[derive(Clone, Debug)]
pub struct MaterialPoint<'a> {
    pub material: &'a FineMaterial,
    pub stress: Sym,
    pub plastic_strain: Real,
}

impl<'a> MaterialPoint<'a> {
    /// A point of `material` at `stress` (Pa, tension positive), with no plastic strain.
    pub fn new(material: &'a FineMaterial, stress: Sym) -> Self {
        MaterialPoint {
            material,
            stress,
            plastic_strain: 0.0,
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
        )
    }

    /// Take the update over `dt` under the velocity gradient `l`.
    pub fn step(&mut self, l: &Matrix3<Real>, dt: Real) {
        let u = self.trial(l, dt);
        self.stress = u.stress;
        self.plastic_strain += u.plastic_strain;
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
