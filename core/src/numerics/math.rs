//! Dimension-generic aliases and the symmetric stress tensor.
//!
//! Physics code is written once for `const D: usize` (2 or 3). Stress is always a
//! symmetric 3×3 tensor: in 2D (plane strain) the out-of-plane normal stress σ_zz is
//! kept and the xz/yz shear components stay zero.

use nalgebra::{Matrix3, SVector, Vector3};

/// Floating-point type used throughout the solver.
pub type Real = f64;
/// A position, velocity or force in `D` dimensions.
pub type Vect<const D: usize> = SVector<Real, D>;

/// Embed a `D`-vector into 3D (z = 0 in 2D).
#[inline(always)]
pub fn to3<const D: usize>(v: &Vect<D>) -> Vector3<Real> {
    let mut o = Vector3::zeros();
    for k in 0..D {
        o[k] = v[k];
    }
    o
}

/// Project a 3D vector onto the first `D` components.
#[inline(always)]
pub fn from3<const D: usize>(v: &Vector3<Real>) -> Vect<D> {
    let mut o = Vect::<D>::zeros();
    for k in 0..D {
        o[k] = v[k];
    }
    o
}

/// The unit vector against gravity `g`, −g/|g|, along which "up", a region's top and a
/// depth are measured; zero without gravity.
#[inline]
pub fn up<const D: usize>(g: &Vect<D>) -> Vect<D> {
    let n = g.norm();
    if n > 0.0 {
        -g / n
    } else {
        Vect::<D>::zeros()
    }
}

/// The extent of the box [lo, hi] along `dir`: the least and the greatest projection of
/// its corners.
pub fn box_extent<const D: usize>(lo: &Vect<D>, hi: &Vect<D>, dir: &Vect<D>) -> (Real, Real) {
    let (mut a, mut b) = (Real::INFINITY, Real::NEG_INFINITY);
    for corner in 0..(1usize << D) {
        let mut c = Vect::<D>::zeros();
        for k in 0..D {
            c[k] = if corner & (1 << k) != 0 { hi[k] } else { lo[k] };
        }
        a = a.min(c.dot(dir));
        b = b.max(c.dot(dir));
    }
    (a, b)
}

/// The extent along `up` of particles of spacing `dp`, each the centre of a lattice
/// cell dp wide: the lowest projection less dp/2 and the highest plus dp/2.
pub fn extent<'a, const D: usize>(
    pts: impl IntoIterator<Item = &'a Vect<D>>,
    up: &Vect<D>,
    dp: Real,
) -> (Real, Real) {
    let (lo, hi) = pts
        .into_iter()
        .map(|p| p.dot(up))
        .fold((Real::INFINITY, Real::NEG_INFINITY), |(lo, hi), z| {
            (lo.min(z), hi.max(z))
        });
    (lo - 0.5 * dp, hi + 0.5 * dp)
}

/// m −= a ⊗ b (the accumulation of Eq. 24's velocity gradient), element by element.
#[inline(always)]
pub fn sub_outer<const D: usize>(m: &mut nalgebra::SMatrix<Real, D, D>, a: &Vect<D>, b: &Vect<D>) {
    for c in 0..D {
        for r in 0..D {
            m[(r, c)] -= a[r] * b[c];
        }
    }
}

/// Symmetric 3×3 tensor stored as (xx, yy, zz, xy, xz, yz).
#[derive(Clone, Copy, Debug, Default, PartialEq, serde::Serialize, serde::Deserialize)]
pub struct Sym(pub [Real; 6]);

impl Sym {
    pub const ZERO: Sym = Sym([0.0; 6]);

    #[inline(always)]
    pub fn iso(p: Real) -> Sym {
        Sym([p, p, p, 0.0, 0.0, 0.0])
    }
    #[inline(always)]
    pub fn trace(&self) -> Real {
        self.0[0] + self.0[1] + self.0[2]
    }
    /// Deviatoric part σ^s = σ − tr(σ)/3 I.
    #[inline(always)]
    pub fn dev(&self) -> Sym {
        let m = self.trace() / 3.0;
        let a = self.0;
        Sym([a[0] - m, a[1] - m, a[2] - m, a[3], a[4], a[5]])
    }
    /// Double contraction A : B.
    #[inline(always)]
    pub fn ddot(&self, o: &Sym) -> Real {
        let a = self.0;
        let b = o.0;
        a[0] * b[0] + a[1] * b[1] + a[2] * b[2] + 2.0 * (a[3] * b[3] + a[4] * b[4] + a[5] * b[5])
    }
    /// Second invariant of the deviator, J2 = ½ s:s.
    #[inline(always)]
    pub fn j2(&self) -> Real {
        let s = self.dev();
        0.5 * s.ddot(&s)
    }
    #[inline(always)]
    pub fn scale(&self, k: Real) -> Sym {
        let a = self.0;
        Sym([a[0] * k, a[1] * k, a[2] * k, a[3] * k, a[4] * k, a[5] * k])
    }
    #[inline(always)]
    pub fn add(&self, o: &Sym) -> Sym {
        let (a, b) = (self.0, o.0);
        Sym([
            a[0] + b[0],
            a[1] + b[1],
            a[2] + b[2],
            a[3] + b[3],
            a[4] + b[4],
            a[5] + b[5],
        ])
    }
    #[inline(always)]
    pub fn sub(&self, o: &Sym) -> Sym {
        let (a, b) = (self.0, o.0);
        Sym([
            a[0] - b[0],
            a[1] - b[1],
            a[2] - b[2],
            a[3] - b[3],
            a[4] - b[4],
            a[5] - b[5],
        ])
    }
    /// a·self + b (fused update used in hot loops).
    #[inline(always)]
    pub fn axpy(&mut self, k: Real, o: &Sym) {
        for c in 0..6 {
            self.0[c] += k * o.0[c];
        }
    }
    /// [`axpy`](Self::axpy) on the components a `D`-dimensional state can hold: in
    /// plane strain (D = 2) σ_xz = σ_yz = 0 throughout, so those two are skipped.
    #[inline(always)]
    pub fn axpy_in<const D: usize>(&mut self, k: Real, o: &Sym) {
        let m = if D == 2 { 4 } else { 6 };
        for c in 0..m {
            self.0[c] += k * o.0[c];
        }
    }
    /// Tensor–vector product σ·e for the first `D` components (2D: in-plane block).
    #[inline(always)]
    pub fn dot_vec<const D: usize>(&self, e: &Vect<D>) -> Vect<D> {
        let a = self.0;
        let mut o = Vect::<D>::zeros();
        if D == 2 {
            o[0] = a[0] * e[0] + a[3] * e[1];
            o[1] = a[3] * e[0] + a[1] * e[1];
        } else {
            o[0] = a[0] * e[0] + a[3] * e[1] + a[4] * e[2];
            o[1] = a[3] * e[0] + a[1] * e[1] + a[5] * e[2];
            o[2] = a[4] * e[0] + a[5] * e[1] + a[2] * e[2];
        }
        o
    }
    #[inline(always)]
    pub fn to_matrix(&self) -> Matrix3<Real> {
        let a = self.0;
        Matrix3::new(a[0], a[3], a[4], a[3], a[1], a[5], a[4], a[5], a[2])
    }
    /// Symmetric part of a general matrix.
    #[inline(always)]
    pub fn from_matrix_sym(m: &Matrix3<Real>) -> Sym {
        Sym([
            m[(0, 0)],
            m[(1, 1)],
            m[(2, 2)],
            0.5 * (m[(0, 1)] + m[(1, 0)]),
            0.5 * (m[(0, 2)] + m[(2, 0)]),
            0.5 * (m[(1, 2)] + m[(2, 1)]),
        ])
    }
    pub fn is_finite(&self) -> bool {
        self.0.iter().all(|v| v.is_finite())
    }
    /// Component (a, b) of the tensor.
    pub fn get(&self, a: usize, b: usize) -> Real {
        match (a.min(b), a.max(b)) {
            (0, 0) => self.0[0],
            (1, 1) => self.0[1],
            (2, 2) => self.0[2],
            (0, 1) => self.0[3],
            (0, 2) => self.0[4],
            _ => self.0[5],
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn j2_of_pure_shear() {
        let s = Sym([0.0, 0.0, 0.0, 3.0, 0.0, 0.0]);
        assert!((s.j2() - 9.0).abs() < 1e-12);
        let p = Sym::iso(-5.0);
        assert!(p.j2().abs() < 1e-12);
    }

    /// Up is −g/|g| for any gravity, and zero without one.
    #[test]
    fn up_opposes_gravity() {
        let g = Vect::<3>::new(3.0, 0.0, -4.0);
        assert_eq!(up(&g), Vect::<3>::new(-0.6, 0.0, 0.8));
        assert_eq!(up(&Vect::<2>::new(0.0, -9.81)), Vect::<2>::new(-0.0, 1.0));
        assert_eq!(up(&Vect::<2>::zeros()), Vect::<2>::zeros());
    }

    #[test]
    fn matrix_roundtrip() {
        let s = Sym([1.0, 2.0, 3.0, 4.0, 5.0, 6.0]);
        assert_eq!(Sym::from_matrix_sym(&s.to_matrix()), s);
        assert!((s.ddot(&s) - (s.to_matrix().component_mul(&s.to_matrix())).sum()).abs() < 1e-12);
    }
}
