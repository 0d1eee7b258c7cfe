//! The seepage drag implicit on both sides (issue 44, item 3), pair by pair and
//! exactly momentum-conserving.
//!
//! Over a step the pair (water i, soil j) exchanges the impulse J_ij = Δt c_ij
//! (u_i − v_j), with c_ij = V_i V_j (μ/k_j) W_ij / s_i the pair's drag coefficient of
//! seed 001 Eqs. (8), (10) ([`Seepage`]). The water's sub-steps take it implicitly
//! with the soil frozen at its start-of-step velocity v_j^n; the soil's reaction J⁰_ij
//! = Δt c_ij (ū_i − v_j^n), ū_i the water's mean over its sub-steps, then makes the
//! soil's step explicit in its own velocity, stable only for Δt < 2 ρ_d k / μ. Here
//! the step is closed by the backward Euler of the two families together:
//!
//! - m_i u_i' = m_i u_i* + Δt Σ_j c_ij (v_j' − u_i'),
//! - m_j v_j' = m_j v_j* + Δt Σ_i c_ij (u_i' − v_j'),
//!
//! u*, v* the velocities after every other force. Written in the increments over the
//! sub-steps' result, δu_i = u_i' − u_i^W and δv_j = v_j' − v_j^n, the water's equation
//! gives δu_i = Δt Σ_j c_ij δv_j / (m_i + Δt a_i), a_i = Σ_j c_ij, and the soil's
//! becomes the symmetric positive definite system (the Schur complement of the
//! coupled one)
//!
//!   K δv = R,  K = M + Δt A − Δt² Cᵀ (M_w + Δt a)⁻¹ C,  R_j = m_j (v_j^e − v_j^n),
//!
//! with A_j = Σ_i c_ij and v^e the soil's explicit velocity (the sub-steps' reaction
//! J⁰ included): the explicit step is K ≈ M. Each row sums to m_j + Δt Σ_i c_ij m_i
//! / (m_i + Δt a_i): where the drag locks the families together, a soil particle moves
//! with the water in its pores. K is solved by the conjugate gradient with the
//! Jacobi preconditioner ([`sparse_cg`](crate::numerics::sparse_cg)'s algorithm, over the D
//! components at once), its sums in a fixed order (the same result at any thread
//! count). The step is then closed with the pairs' impulses from the solution: the
//! soil receives Σ_i (J_ij − J⁰_ij) and the water the opposite, so that momentum is
//! conserved to round-off however far the iterations went.
//!
//! [`Seepage`]: super::soil_water::Seepage

use super::soil_water::SoilPoint;
use crate::numerics::math::{Real, Vect};
use crate::numerics::neighbors::CHUNK;
use rayon::prelude::*;

/// The relative residual ‖K δv − R‖ / ‖R‖ (per component) the solve stops at.
pub const TOLERANCE: Real = 1e-10;
/// The solve's iteration cap; the step stays momentum-conserving past it.
pub const MAX_ITERATIONS: usize = 500;

/// Rows of pair coefficients: for each particle of one family, the other's particles
/// and c_ij.
#[derive(Clone, Debug, Default)]
struct Rows {
    start: Vec<usize>,
    idx: Vec<u32>,
    c: Vec<Real>,
    /// Σ of each row's c.
    sum: Vec<Real>,
}

impl Rows {
    /// The rows from per-chunk buffers (each chunk's rows in order: their lengths, then
    /// their entries), concatenated in chunk order.
    fn concat(&mut self, chunks: &[ChunkRows]) {
        self.start.clear();
        self.idx.clear();
        self.c.clear();
        self.sum.clear();
        self.start.push(0);
        for ch in chunks {
            let mut at = 0;
            for &len in &ch.len {
                let r = at..at + len as usize;
                self.idx.extend_from_slice(&ch.idx[r.clone()]);
                self.c.extend_from_slice(&ch.c[r.clone()]);
                self.sum.push(ch.c[r].iter().sum());
                self.start.push(self.idx.len());
                at += len as usize;
            }
        }
    }

    /// The transpose of `rows` over `n` columns: for each column the rows that hold
    /// it, in row order.
    fn transpose(&mut self, rows: &Rows, n: usize) {
        self.start.clear();
        self.start.resize(n + 1, 0);
        for &i in &rows.idx {
            self.start[i as usize + 1] += 1;
        }
        for k in 0..n {
            self.start[k + 1] += self.start[k];
        }
        let nnz = rows.idx.len();
        self.idx.clear();
        self.idx.resize(nnz, 0);
        self.c.clear();
        self.c.resize(nnz, 0.0);
        self.sum.clear();
        self.sum.resize(n, 0.0);
        let mut next = self.start[..n].to_vec();
        for j in 0..rows.len() {
            for (i, c) in rows.row(j) {
                let at = next[i];
                self.idx[at] = j as u32;
                self.c[at] = c;
                self.sum[i] += c;
                next[i] += 1;
            }
        }
    }

    #[inline(always)]
    fn row(&self, j: usize) -> impl Iterator<Item = (usize, Real)> + '_ {
        let r = self.start[j]..self.start[j + 1];
        self.idx[r.clone()]
            .iter()
            .zip(&self.c[r])
            .map(|(&i, &c)| (i as usize, c))
    }

    fn len(&self) -> usize {
        self.sum.len()
    }
}

/// One chunk of soil rows while they are built (by the soil's force pass,
/// [`soil_force`](super::soil_water::soil_force)): each row's length, then the pairs.
/// Its buffers are kept between steps.
#[derive(Clone, Debug, Default)]
pub struct ChunkRows {
    len: Vec<u32>,
    idx: Vec<u32>,
    c: Vec<Real>,
}

impl ChunkRows {
    /// Empty, for a new step.
    pub fn clear(&mut self) {
        self.len.clear();
        self.idx.clear();
        self.c.clear();
    }

    /// The rows in order, each as its water indices and values.
    pub fn rows(&self) -> impl Iterator<Item = (&[u32], &[Real])> + '_ {
        let mut at = 0;
        self.len.iter().map(move |&len| {
            let r = at..at + len as usize;
            at += len as usize;
            (&self.idx[r.clone()], &self.c[r])
        })
    }

    /// Add one row whose pairs `fill` pushes onto the row's buffers (water indices,
    /// values) itself, so that its sink is a closure the compiler can inline.
    #[inline]
    pub fn row<R>(&mut self, fill: impl FnOnce(&mut Vec<u32>, &mut Vec<Real>) -> R) -> R {
        let before = self.idx.len();
        let r = fill(&mut self.idx, &mut self.c);
        self.len.push((self.idx.len() - before) as u32);
        r
    }
}

/// What a solve did: iterations and the relative residual reached (largest over the
/// components).
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct SolveStats {
    pub iterations: usize,
    pub residual: Real,
}

/// The soil and water of a step as the solve sees them.
pub struct Families<'a, const D: usize> {
    /// The soil frozen at the step's middle (velocity v^n).
    pub soil: &'a [SoilPoint<D>],
    pub soil_mass: &'a [Real],
    pub water_mass: &'a [Real],
}

/// The implicit drag's pair rows and scratch (rebuilt every step).
#[derive(Clone, Debug, Default)]
pub struct ImplicitDrag<const D: usize> {
    chunks: Vec<ChunkRows>,
    soil: Rows,
    water: Rows,
    /// m_i + Δt a_i per water particle.
    water_diag: Vec<Real>,
    /// m_j + Δt A_j per soil particle.
    soil_diag: Vec<Real>,
    /// The Jacobi preconditioner: 1 / K_jj.
    inv: Vec<Real>,
    /// The solution δv, the residual, the preconditioned residual, the direction, K p.
    x: Vec<Vect<D>>,
    r: Vec<Vect<D>>,
    z: Vec<Vect<D>>,
    p: Vec<Vect<D>>,
    q: Vec<Vect<D>>,
    /// Scratch over the water: (M_w + Δt a)⁻¹ Δt C p, and the same for the solution
    /// (the water's increment δu), summed along with it.
    t: Vec<Vect<D>>,
    tx: Vec<Vect<D>>,
}

/// Σ a_k ∘ b_k per component, summed in chunks of fixed size and then in order: the
/// same at any thread count.
fn dot<const D: usize>(a: &[Vect<D>], b: &[Vect<D>]) -> Vect<D> {
    let parts: Vec<Vect<D>> = a
        .par_chunks(CHUNK)
        .zip(b.par_chunks(CHUNK))
        .map(|(a, b)| {
            a.iter()
                .zip(b)
                .fold(Vect::<D>::zeros(), |s, (x, y)| s + x.component_mul(y))
        })
        .collect();
    parts.iter().fold(Vect::<D>::zeros(), |s, p| s + p)
}

impl<const D: usize> ImplicitDrag<D> {
    /// Chunk `CHUNK` soil rows' buffers for the force pass to fill, for `n` soil
    /// particles.
    pub fn chunks(&mut self, n: usize) -> &mut [ChunkRows] {
        self.chunks
            .resize_with(n.div_ceil(CHUNK), ChunkRows::default);
        &mut self.chunks
    }

    /// The pair rows of a step from the chunks the force pass filled: the soil's in
    /// order, the water's their transpose; and the diagonals.
    fn build(&mut self, f: &Families<'_, D>, dt: Real) {
        self.soil.concat(&self.chunks);
        self.water.transpose(&self.soil, f.water_mass.len());
        self.water_diag.clear();
        self.water_diag.extend(
            f.water_mass
                .iter()
                .zip(&self.water.sum)
                .map(|(m, a)| m + dt * a),
        );
        self.soil_diag.clear();
        self.soil_diag.extend(
            f.soil_mass
                .iter()
                .zip(&self.soil.sum)
                .map(|(m, a)| m + dt * a),
        );
        let (wd, dt2) = (&self.water_diag, dt * dt);
        self.inv.clear();
        self.inv
            .par_extend((0..self.soil.len()).into_par_iter().map(|j| {
                let kjj = self.soil_diag[j]
                    - dt2 * self.soil.row(j).map(|(i, c)| c * c / wd[i]).sum::<Real>();
                1.0 / kjj
            }));
    }

    /// y = K x; `t` receives (M_w + Δt a)⁻¹ Δt C x, the water's increment for x.
    fn apply(&self, x: &[Vect<D>], y: &mut [Vect<D>], t: &mut [Vect<D>], dt: Real) {
        let (water, wd) = (&self.water, &self.water_diag);
        t.par_iter_mut().enumerate().for_each(|(i, ti)| {
            let s = water
                .row(i)
                .fold(Vect::<D>::zeros(), |s, (j, c)| s + x[j] * c);
            *ti = s * (dt / wd[i]);
        });
        let (soil, sd, t) = (&self.soil, &self.soil_diag, &*t);
        y.par_iter_mut().enumerate().for_each(|(j, yj)| {
            let s = soil
                .row(j)
                .fold(Vect::<D>::zeros(), |s, (i, c)| s + t[i] * c);
            *yj = x[j] * sd[j] - s * dt;
        });
    }

    /// Close a step of `dt`: the soil's velocities `soil_vel` (v^e on entry, the
    /// soil's explicit result) and the water's `water_vel` (u^W, the sub-steps'
    /// result) receive the increments of the coupled backward Euler (module docs).
    /// Returns what the solve did.
    pub fn close(
        &mut self,
        f: &Families<'_, D>,
        dt: Real,
        soil_vel: &mut [Vect<D>],
        water_vel: &mut [Vect<D>],
    ) -> SolveStats {
        self.build(f, dt);
        let (ns, nw) = (f.soil.len(), f.water_mass.len());
        let zero = Vect::<D>::zeros();
        for v in [
            &mut self.x,
            &mut self.r,
            &mut self.z,
            &mut self.p,
            &mut self.q,
        ] {
            v.clear();
            v.resize(ns, zero);
        }
        for v in [&mut self.t, &mut self.tx] {
            v.clear();
            v.resize(nw, zero);
        }
        // R_j = m_j (v^e − v^n), on the soil the water drags only
        let soil = &self.soil;
        self.r.par_iter_mut().enumerate().for_each(|(j, r)| {
            if soil.sum[j] > 0.0 {
                *r = (soil_vel[j] - f.soil[j].vel) * f.soil_mass[j];
            }
        });
        let stats = self.conjugate_gradient(dt);
        // the pairs' impulses from the solution and the water's increment for it
        let (soil, x, t) = (&self.soil, &self.x, &self.tx);
        soil_vel.par_iter_mut().enumerate().for_each(|(j, v)| {
            if soil.sum[j] > 0.0 {
                let s = soil.row(j).fold(zero, |s, (i, c)| s + t[i] * c);
                *v += (s - x[j] * soil.sum[j]) * (dt / f.soil_mass[j]);
            }
        });
        water_vel.par_iter_mut().zip(t).for_each(|(u, du)| *u += du);
        stats
    }

    /// Solve K x = r (r on entry the right-hand side; x from 0).
    fn conjugate_gradient(&mut self, dt: Real) -> SolveStats {
        let bnorm = dot(&self.r, &self.r).map(Real::sqrt);
        if bnorm.iter().all(|&b| b == 0.0) {
            return SolveStats::default();
        }
        let inv = &self.inv;
        let precondition = |r: &[Vect<D>], z: &mut [Vect<D>]| {
            z.par_iter_mut()
                .zip(r)
                .zip(inv)
                .for_each(|((z, r), m)| *z = r * *m);
        };
        precondition(&self.r, &mut self.z);
        self.p.clone_from(&self.z);
        let mut rz = dot(&self.r, &self.z);
        let mut stats = SolveStats::default();
        let mut t = std::mem::take(&mut self.t);
        let mut q = std::mem::take(&mut self.q);
        while stats.iterations < MAX_ITERATIONS {
            self.apply(&self.p, &mut q, &mut t, dt);
            let pq = dot(&self.p, &q);
            // per component; a converged (or empty) component stays put
            let alpha = Vect::<D>::from_fn(|a, _| if pq[a] > 0.0 { rz[a] / pq[a] } else { 0.0 });
            self.x
                .par_iter_mut()
                .zip(self.r.par_iter_mut())
                .zip(self.p.par_iter().zip(&q))
                .for_each(|((x, r), (p, q))| {
                    *x += p.component_mul(&alpha);
                    *r -= q.component_mul(&alpha);
                });
            self.tx
                .par_iter_mut()
                .zip(&t)
                .for_each(|(tx, t)| *tx += t.component_mul(&alpha));
            stats.iterations += 1;
            let rr = dot(&self.r, &self.r);
            stats.residual = (0..D)
                .filter(|&a| bnorm[a] > 0.0)
                .map(|a| rr[a].sqrt() / bnorm[a])
                .fold(0.0, Real::max);
            if stats.residual <= TOLERANCE {
                break;
            }
            precondition(&self.r, &mut self.z);
            let rz_new = dot(&self.r, &self.z);
            let beta = Vect::<D>::from_fn(|a, _| if rz[a] > 0.0 { rz_new[a] / rz[a] } else { 0.0 });
            rz = rz_new;
            self.p
                .par_iter_mut()
                .zip(&self.z)
                .for_each(|(p, z)| *p = z + p.component_mul(&beta));
        }
        self.t = t;
        self.q = q;
        stats
    }
}
