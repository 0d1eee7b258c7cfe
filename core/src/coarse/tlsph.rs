//! Total-Lagrangian SPH for elastic coarse grains, Eqs. (36)–(47).
//!
//! Neighbours, kernel gradients ∇⁰W_ij V⁰_j and the correction matrices 𝔹⁰ (Eq. 44)
//! are taken once in the reference configuration. h = 1.15 dp, cut-off 2h = 2.3 dp.
//! Tensors are 3×3 in both dimensions (plane strain: F_zz = 1).

use super::body::Body;
use super::material::SolidMaterial;
use super::particles::CoarseParticles;
use crate::numerics::kernel::WendlandC2;
use crate::numerics::math::{Real, Vect};
use nalgebra::{Matrix3, Vector3};
use rayon::prelude::*;

/// Particles per parallel work item.
const GRAIN: usize = 64;

/// Reference-configuration neighbour data of all elastic particles.
#[derive(Clone, Debug, Default, serde::Serialize, serde::Deserialize)]
pub struct Tlsph<const D: usize> {
    /// `nbr[off[k]..off[k+1]]`: neighbours (indices into `elastic`) of the k-th elastic
    /// particle, all in the same body; fixed.
    pub off: Vec<u32>,
    pub nbr: Vec<u32>,
    /// ∇⁰_i W_ij V⁰_j for each entry of `nbr` (3D layout).
    pub grad: Vec<Vector3<Real>>,
    /// Particles of elastic bodies.
    pub elastic: Vec<u32>,
    /// Deformation gradient 𝔽 (Eq. 36) of each elastic particle.
    pub def: Vec<Matrix3<Real>>,
    /// d𝔽/dt of Eq. (45).
    pub ddef: Vec<Matrix3<Real>>,
    /// Correction matrix 𝔹⁰ of Eq. (44).
    pub b0: Vec<Matrix3<Real>>,
    /// P_i 𝔹⁰_iᵀ of the current sub-step (first Piola–Kirchhoff times correction).
    pk1b: Vec<Matrix3<Real>>,
    /// Internal acceleration of the current sub-step.
    pub acc: Vec<Vect<D>>,
    pub kernel: Option<WendlandC2>,
}

fn m3<const D: usize>(v: &Vect<D>) -> Vector3<Real> {
    let mut o = Vector3::zeros();
    for k in 0..D {
        o[k] = v[k];
    }
    o
}

impl<const D: usize> Tlsph<D> {
    /// Whether this restored state holds the reference data of `template` (the same
    /// bodies as the scene builds them) bit for bit, and one deformation gradient, its
    /// rate and an acceleration per elastic particle (or none yet).
    pub fn restored_fits(&self, template: &Self) -> bool {
        let per_particle = |l: usize| l == self.elastic.len() || l == 0;
        self.off == template.off
            && self.nbr == template.nbr
            && self.elastic == template.elastic
            && self.grad == template.grad
            && self.b0 == template.b0
            && self.kernel == template.kernel
            && self.def.len() == self.elastic.len()
            && per_particle(self.ddef.len())
            && per_particle(self.pk1b.len())
            && per_particle(self.acc.len())
    }

    /// Set up from the reference configuration.
    pub fn new(p: &CoarseParticles<D>, bodies: &[Body<D>], dp: Real) -> Self {
        let kernel = WendlandC2::new(1.15 * dp, D);
        let cut = kernel.cutoff;
        let vol = dp.powi(D as i32);
        let mut t = Tlsph::<D> {
            kernel: Some(kernel),
            ..Default::default()
        };
        t.off.push(0);
        for b in bodies.iter().filter(|b| !b.is_rigid()) {
            // hash the body's reference positions into cells of size 2h
            let (lo, _) = bounds(&p.local[b.start..b.end]);
            let key = |x: &Vect<D>| -> [i64; 3] {
                let mut k = [0i64; 3];
                for a in 0..D {
                    k[a] = ((x[a] - lo[a]) / cut).floor() as i64;
                }
                k
            };
            let mut cells: std::collections::BTreeMap<[i64; 3], Vec<u32>> = Default::default();
            for i in b.start..b.end {
                cells.entry(key(&p.local[i])).or_default().push(i as u32);
            }
            for i in b.start..b.end {
                t.elastic.push(i as u32);
                let xi = p.local[i];
                let c = key(&xi);
                let mut found: Vec<u32> = Vec::new();
                let rz = if D == 3 { -1..=1 } else { 0..=0 };
                for dz in rz {
                    for dy in -1..=1 {
                        for dx in -1..=1 {
                            let k = [c[0] + dx, c[1] + dy, c[2] + dz];
                            if let Some(list) = cells.get(&k) {
                                for &j in list {
                                    let r = (xi - p.local[j as usize]).norm();
                                    if j as usize != i && r < cut {
                                        found.push(j);
                                    }
                                }
                            }
                        }
                    }
                }
                found.sort_unstable();
                let mut bsum = Matrix3::<Real>::zeros();
                for &j in &found {
                    let rij = xi - p.local[j as usize];
                    let r = rij.norm();
                    let g = m3(&rij) * (kernel.dw(r) / r * vol);
                    t.nbr.push(j);
                    t.grad.push(g);
                    // Eq. (44): Σ (r⁰_j − r⁰_i) ⊗ ∇⁰W V⁰
                    bsum -= m3(&rij) * g.transpose();
                }
                if D == 2 {
                    bsum[(2, 2)] = 1.0;
                }
                t.b0.push(bsum.try_inverse().unwrap_or_else(Matrix3::identity));
                t.off.push(t.nbr.len() as u32);
            }
        }
        // neighbour entries as indices into `elastic`
        let mut local = vec![u32::MAX; p.len()];
        for (k, &i) in t.elastic.iter().enumerate() {
            local[i as usize] = k as u32;
        }
        for j in &mut t.nbr {
            *j = local[*j as usize];
        }
        t.pk1b = vec![Matrix3::zeros(); t.elastic.len()];
        t.def = vec![Matrix3::identity(); t.elastic.len()];
        t.ddef = vec![Matrix3::zeros(); t.elastic.len()];
        t.acc = vec![Vect::<D>::zeros(); t.elastic.len()];
        t
    }

    pub fn is_empty(&self) -> bool {
        self.elastic.is_empty()
    }

    /// P 𝔹⁰ᵀ for every elastic particle: Neo-Hookean 𝕊 (Eq. 40) plus the Kelvin–Voigt
    /// damper of Eq. (47), Π = ρ c0 h / 2; ℙ = 𝔽 𝕊.
    pub fn stress(&mut self, p: &CoarseParticles<D>, bodies: &[Body<D>], solids: &[SolidMaterial]) {
        let h = self.kernel.map(|k| k.h).unwrap_or(0.0);
        let (elastic, def, ddef, b0) = (&self.elastic, &self.def, &self.ddef, &self.b0);
        self.pk1b
            .par_iter_mut()
            .with_min_len(GRAIN)
            .enumerate()
            .for_each(|(k, out)| {
                let i = elastic[k] as usize;
                let m = &solids[bodies[p.body[i] as usize].material];
                *out = first_piola(&def[k], &ddef[k], m, h) * b0[k].transpose();
            });
    }

    /// Internal acceleration of Eq. (43): (1/ρ⁰) Σ_j (P_i 𝔹_iᵀ + P_j 𝔹_jᵀ) ∇⁰W_ij V⁰_j.
    pub fn acceleration(
        &mut self,
        p: &CoarseParticles<D>,
        bodies: &[Body<D>],
        solids: &[SolidMaterial],
    ) {
        let (off, nbr, grad, elastic, pk1b) =
            (&self.off, &self.nbr, &self.grad, &self.elastic, &self.pk1b);
        self.acc
            .par_iter_mut()
            .with_min_len(GRAIN)
            .enumerate()
            .for_each(|(k, a)| {
                let i = elastic[k] as usize;
                let rho0 = solids[bodies[p.body[i] as usize].material].rho0;
                let mut s = Vector3::zeros();
                for e in off[k] as usize..off[k + 1] as usize {
                    s += (pk1b[k] + pk1b[nbr[e] as usize]) * grad[e];
                }
                let mut o = Vect::<D>::zeros();
                for d in 0..D {
                    o[d] = s[d] / rho0;
                }
                *a = o;
            });
    }

    /// Rate of the deformation gradient, Eq. (45): Σ_j (v_j − v_i) ⊗ ∇⁰W_ij V⁰_j 𝔹⁰_i.
    pub fn deformation_rate(&mut self, p: &CoarseParticles<D>) {
        let (off, nbr, grad, elastic, b0) =
            (&self.off, &self.nbr, &self.grad, &self.elastic, &self.b0);
        let vel = &p.vel;
        self.ddef
            .par_iter_mut()
            .with_min_len(GRAIN)
            .enumerate()
            .for_each(|(k, out)| {
                let vi = m3(&vel[elastic[k] as usize]);
                let mut l = Matrix3::zeros();
                for e in off[k] as usize..off[k + 1] as usize {
                    let vj = m3(&vel[elastic[nbr[e] as usize] as usize]);
                    l += (vj - vi) * grad[e].transpose();
                }
                *out = l * b0[k];
            });
    }

    /// Half-step update of 𝔽 (Eqs. 57, 59): 𝔽 += Δ d𝔽/dt.
    pub fn advance_deformation(&mut self, dt: Real) {
        self.def
            .par_iter_mut()
            .zip(self.ddef.par_iter())
            .with_min_len(GRAIN)
            .for_each(|(f, df)| *f += df * dt);
    }

    /// Current outward normals of elastic surface particles: n = 𝔽⁻ᵀ n⁰, normalised.
    pub fn update_normals(&self, p: &mut CoarseParticles<D>) {
        for (k, &i) in self.elastic.iter().enumerate() {
            let i = i as usize;
            let n0 = m3(&p.local_normal[i]);
            if n0.norm_squared() == 0.0 {
                continue;
            }
            let n = self.def[k]
                .try_inverse()
                .map(|fi| fi.transpose() * n0)
                .unwrap_or(n0);
            let l = n.norm();
            for d in 0..D {
                p.normal[i][d] = if l > 0.0 { n[d] / l } else { 0.0 };
            }
        }
    }

    /// Elastic strain energy Σ V⁰ 𝕎 (Eq. 39, with tr 𝔼 = (tr ℂ − 3)/2 ... in the
    /// compressible Neo-Hookean form μ/2 (tr ℂ − 3) − μ ln J + λ/2 (ln J)²).
    pub fn strain_energy(
        &self,
        p: &CoarseParticles<D>,
        bodies: &[Body<D>],
        solids: &[SolidMaterial],
        vol: Real,
    ) -> Real {
        let mut e = 0.0;
        for (k, &i) in self.elastic.iter().enumerate() {
            let m = &solids[bodies[p.body[i as usize] as usize].material];
            let f = self.def[k];
            let c = f.transpose() * f;
            let j = f.determinant();
            let lnj = j.ln();
            e += vol
                * (0.5 * m.shear * (c.trace() - 3.0) - m.shear * lnj + 0.5 * m.lambda * lnj * lnj);
        }
        e
    }
}

/// ℙ = 𝔽 (𝕊_S + 𝕊_D): Eq. (40) and Eq. (47).
pub fn first_piola(
    f: &Matrix3<Real>,
    df: &Matrix3<Real>,
    m: &SolidMaterial,
    h: Real,
) -> Matrix3<Real> {
    let c = f.transpose() * f;
    let j = f.determinant();
    let cinv = c.try_inverse().unwrap_or_else(Matrix3::identity);
    let lnj = if j > 0.0 { j.ln() } else { Real::NEG_INFINITY };
    let s_s = (Matrix3::identity() - cinv) * m.shear + cinv * (m.lambda * lnj);
    let pi = 0.5 * m.rho0 * m.c0 * h;
    let s_d = (df.transpose() * f + f.transpose() * df) * (0.5 * pi);
    f * (s_s + s_d)
}

fn bounds<const D: usize>(x: &[Vect<D>]) -> (Vect<D>, Vect<D>) {
    let mut lo = Vect::<D>::repeat(Real::INFINITY);
    let mut hi = Vect::<D>::repeat(Real::NEG_INFINITY);
    for p in x {
        lo = lo.inf(p);
        hi = hi.sup(p);
    }
    (lo, hi)
}
