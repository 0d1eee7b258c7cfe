//! Wendland C2 kernel, Eq. (61) of seed 000.
//!
//! W(q, h) = α_d (1 − q/2)⁴ (2q + 1) for 0 ≤ q ≤ 2, with q = r/h and
//! α_d = 3/(4h), 7/(4πh²), 21/(16πh³) in 1, 2, 3 dimensions. Cut-off radius 2h.

use crate::numerics::math::Real;
use std::f64::consts::PI;

/// The Wendland C2 kernel for a fixed smoothing length.
#[derive(Clone, Copy, Debug, PartialEq, serde::Serialize, serde::Deserialize)]
pub struct WendlandC2 {
    pub h: Real,
    inv_h: Real,
    alpha: Real,
    /// −5 α_d / h, the constant factor of ∂W/∂r.
    dw_coef: Real,
    /// Cut-off radius 2h.
    pub cutoff: Real,
}

impl WendlandC2 {
    pub fn new(h: Real, dim: usize) -> Self {
        let alpha = match dim {
            1 => 3.0 / (4.0 * h),
            2 => 7.0 / (4.0 * PI * h * h),
            _ => 21.0 / (16.0 * PI * h * h * h),
        };
        WendlandC2 {
            h,
            inv_h: 1.0 / h,
            alpha,
            dw_coef: -5.0 * alpha * (1.0 / h),
            cutoff: 2.0 * h,
        }
    }

    /// W(r).
    #[inline(always)]
    pub fn w(&self, r: Real) -> Real {
        let q = r * self.inv_h;
        if q >= 2.0 {
            return 0.0;
        }
        let t = 1.0 - 0.5 * q;
        let t2 = t * t;
        self.alpha * t2 * t2 * (2.0 * q + 1.0)
    }

    /// ∂W/∂r (≤ 0). d/dq[(1−q/2)⁴(2q+1)] = −5q(1−q/2)³.
    #[inline(always)]
    pub fn dw(&self, r: Real) -> Real {
        let q = r * self.inv_h;
        if q >= 2.0 {
            return 0.0;
        }
        let t = 1.0 - 0.5 * q;
        self.dw_coef * q * t * t * t
    }

    /// 1/h and the constant factor c of ∂W/∂r = c q (1 − q/2)³, q = r/h, for passes
    /// that take [`dw_within`](Self::dw_within) on lanes.
    pub fn dw_factors(&self) -> (Real, Real) {
        (self.inv_h, self.dw_coef)
    }

    /// ∂W/∂r for r already known to lie within the cut-off (the sweeps test r² first).
    #[inline(always)]
    pub fn dw_within(&self, r: Real) -> Real {
        let q = r * self.inv_h;
        let t = 1.0 - 0.5 * q;
        self.dw_coef * q * t * t * t
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Zeroth moment: Σ W V = 1 on a lattice (partition of unity), and the gradient
    /// moment −Σ r_ij ⊗ ∇W V = I, the identity behind Eq. (24).
    #[test]
    fn lattice_moments_2d_and_3d() {
        for dim in [2usize, 3] {
            let dp = 0.01;
            let k = WendlandC2::new(1.3 * dp, dim);
            let n = 4i32;
            let (mut s0, mut sxx, mut sxy) = (0.0, 0.0, 0.0);
            let zr = if dim == 3 { -n..=n } else { 0..=0 };
            for i in -n..=n {
                for j in -n..=n {
                    for l in zr.clone() {
                        let (x, y, z) = (i as f64 * dp, j as f64 * dp, l as f64 * dp);
                        let r = (x * x + y * y + z * z).sqrt();
                        let vol = dp.powi(dim as i32);
                        s0 += k.w(r) * vol;
                        if r > 0.0 {
                            // r_ij = x_i − x_j with x_i = 0 → r_ij = −x; ∇_i W = dW e_ij.
                            let f = k.dw(r) / r * vol;
                            sxx += -(-x) * (-x) * f;
                            sxy += -(-x) * (-y) * f;
                        }
                    }
                }
            }
            // The lattice sum is a quadrature of ∫W dV = 1 (tested exactly below); at
            // h = 1.3 dp its error is about 1 %.
            assert!((s0 - 1.0).abs() < 0.02, "dim {dim}: ΣWV = {s0}");
            // Same quadrature error for the first moment (2.6 % in 2D at h = 1.3 dp); a
            // sign error in ∇W or a wrong α_d would be off by 100 % or a dimension factor.
            assert!((sxx - 1.0).abs() < 0.03, "dim {dim}: −Σ x∂W V = {sxx}");
            assert!(sxy.abs() < 1e-12);
        }
    }

    /// Continuous normalisation ∫W dV = 1 by radial quadrature.
    #[test]
    fn normalisation_integral() {
        for dim in [1usize, 2, 3] {
            let k = WendlandC2::new(0.7, dim);
            let n = 20000;
            let dr = k.cutoff / n as f64;
            let mut s = 0.0;
            for i in 0..n {
                let r = (i as f64 + 0.5) * dr;
                let shell = match dim {
                    1 => 2.0,
                    2 => 2.0 * PI * r,
                    _ => 4.0 * PI * r * r,
                };
                s += k.w(r) * shell * dr;
            }
            assert!((s - 1.0).abs() < 1e-6, "dim {dim}: {s}");
        }
    }

    #[test]
    fn derivative_matches_finite_difference() {
        let k = WendlandC2::new(0.013, 3);
        for i in 1..50 {
            let r = i as f64 * 0.0005;
            let e = 1e-8;
            let fd = (k.w(r + e) - k.w(r - e)) / (2.0 * e);
            assert!((fd - k.dw(r)).abs() <= 1e-5 * k.dw(0.013).abs().max(1.0));
        }
    }
}
