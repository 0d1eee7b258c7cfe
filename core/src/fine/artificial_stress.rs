//! Artificial stress against the tensile instability (seed 000 §2.3), used only for
//! cohesive materials (c > 0).
//!
//! 2D: Gray et al. (2001), Eqs. (28)–(31). The momentum equation of seed 000 is in
//! volume form (2/ρ_i Σ σ*·∇W V_j), so R carries stress units: R' = −ε σ' for tensile
//! principal stresses σ' > 0 (Eq. 30 is written for the σ/ρ² form).
//! 3D: the artificial-pressure equivalent, R = −ε max(I1/3, 0) I.

use crate::numerics::math::{Real, Sym};

/// Artificial stress R_i of one particle.
#[inline]
pub fn gray2001_artificial_stress<const D: usize>(sigma: &Sym, epsilon: Real) -> Sym {
    if D == 2 {
        let (sxx, syy, sxy) = (sigma.0[0], sigma.0[1], sigma.0[3]);
        // Eq. (29): tan 2θ = 2σxy / (σxx − σyy)
        let theta = 0.5 * (2.0 * sxy).atan2(sxx - syy);
        let (s, c) = theta.sin_cos();
        // Eq. (31)
        let pxx = c * c * sxx + 2.0 * s * c * sxy + s * s * syy;
        let pyy = s * s * sxx - 2.0 * s * c * sxy + c * c * syy;
        // Eq. (30)
        let rxx = if pxx > 0.0 { -epsilon * pxx } else { 0.0 };
        let ryy = if pyy > 0.0 { -epsilon * pyy } else { 0.0 };
        // Eq. (28)
        Sym([
            c * c * rxx + s * s * ryy,
            s * s * rxx + c * c * ryy,
            0.0,
            s * c * (rxx - ryy),
            0.0,
            0.0,
        ])
    } else {
        let p = sigma.trace() / 3.0;
        if p > 0.0 {
            Sym::iso(-epsilon * p)
        } else {
            Sym::ZERO
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn rotated_uniaxial_tension() {
        // principal tension 2 along 30°, compression −1 across
        let th: f64 = 30f64.to_radians();
        let (s, c) = th.sin_cos();
        let (a, b) = (2.0, -1.0);
        let sig = Sym([
            c * c * a + s * s * b,
            s * s * a + c * c * b,
            0.0,
            s * c * (a - b),
            0.0,
            0.0,
        ]);
        let r = gray2001_artificial_stress::<2>(&sig, 0.5);
        // expected −0.5·2 along the tension direction only
        let e = Sym([-(c * c), -(s * s), 0.0, -(s * c), 0.0, 0.0]);
        for k in 0..6 {
            assert!((r.0[k] - e.0[k]).abs() < 1e-12, "{r:?} vs {e:?}");
        }
        assert_eq!(
            gray2001_artificial_stress::<2>(&Sym::iso(-3.0), 0.5),
            Sym::ZERO
        );
    }
}
