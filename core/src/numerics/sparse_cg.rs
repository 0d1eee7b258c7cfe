//! A symmetric sparse matrix held as its diagonal and its off-diagonal pairs, and the
//! Jacobi-preconditioned conjugate gradient that solves it (Saad, *Iterative Methods
//! for Sparse Linear Systems*, 2nd ed., Algorithm 9.1). Sequential, so that its result
//! is the same at any thread count.

use crate::numerics::math::Real;

/// A = diag(d) − Σ_(i,j,a) a (e_i e_jᵀ + e_j e_iᵀ): each off-diagonal pair once, with
/// its coupling a (the entry is −a).
#[derive(Debug, Clone, Default)]
pub struct Symmetric {
    pub diag: Vec<Real>,
    pub edges: Vec<(u32, u32, Real)>,
}

impl Symmetric {
    /// y = A x.
    pub fn apply(&self, x: &[Real], y: &mut [Real]) {
        for ((yi, d), xi) in y.iter_mut().zip(&self.diag).zip(x) {
            *yi = d * xi;
        }
        for &(i, j, a) in &self.edges {
            let (i, j) = (i as usize, j as usize);
            y[i] -= a * x[j];
            y[j] -= a * x[i];
        }
    }
}

fn dot(a: &[Real], b: &[Real]) -> Real {
    a.iter().zip(b).map(|(x, y)| x * y).sum()
}

/// Solve A x = b (A symmetric positive definite) from x = 0 until ‖r‖ ≤ `tol` ‖b‖ or
/// `max_iter` iterations: x, the iterations taken and ‖r‖/‖b‖.
pub fn conjugate_gradient(
    a: &Symmetric,
    b: &[Real],
    tol: Real,
    max_iter: usize,
) -> (Vec<Real>, usize, Real) {
    let n = b.len();
    let mut x = vec![0.0; n];
    let bnorm = dot(b, b).sqrt();
    if bnorm == 0.0 {
        return (x, 0, 0.0);
    }
    let inv: Vec<Real> = a
        .diag
        .iter()
        .map(|&d| if d > 0.0 { 1.0 / d } else { 1.0 })
        .collect();
    let mut r = b.to_vec();
    let mut z: Vec<Real> = r.iter().zip(&inv).map(|(r, m)| r * m).collect();
    let mut p = z.clone();
    let mut q = vec![0.0; n];
    let mut rz = dot(&r, &z);
    let mut it = 0;
    let mut res = 1.0;
    while it < max_iter {
        a.apply(&p, &mut q);
        let alpha = rz / dot(&p, &q);
        for k in 0..n {
            x[k] += alpha * p[k];
            r[k] -= alpha * q[k];
        }
        it += 1;
        res = dot(&r, &r).sqrt() / bnorm;
        if res <= tol {
            break;
        }
        for k in 0..n {
            z[k] = r[k] * inv[k];
        }
        let rz_new = dot(&r, &z);
        let beta = rz_new / rz;
        rz = rz_new;
        for k in 0..n {
            p[k] = z[k] + beta * p[k];
        }
    }
    (x, it, res)
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The 1D Poisson problem −u'' = 1 on (0, 1), u(0) = u(1) = 0, on n interior
    /// points: the second-order stencil is exact for the quadratic u = x(1 − x)/2.
    #[test]
    fn solves_the_discrete_poisson_problem_exactly() {
        let n = 99;
        let h = 1.0 / (n + 1) as Real;
        let a = Symmetric {
            diag: vec![2.0; n],
            edges: (0..n - 1).map(|i| (i as u32, i as u32 + 1, 1.0)).collect(),
        };
        let b = vec![h * h; n];
        let (x, it, res) = conjugate_gradient(&a, &b, 1e-12, 1000);
        assert!(res <= 1e-12 && it <= n, "{it} iterations, residual {res:e}");
        for (k, xk) in x.iter().enumerate() {
            let s = (k + 1) as Real * h;
            assert!((xk - 0.5 * s * (1.0 - s)).abs() < 1e-10, "x[{k}] = {xk}");
        }
    }
}
