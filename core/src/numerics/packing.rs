//! Particle packing by relaxation: the sweeps that even out a lattice cut by a curved
//! surface, shared by the coarse-grain bodies ([`coarse::relax`]) and the water filled
//! around them ([`world::water_at_bodies`]).
//!
//! Each sweep pushes every moving particle away from its neighbours with the kernel
//! gradient, F_i = −Σ_j ∇W(r_ij) dp^d, over the moving particles, the fixed ones and
//! the mirror images that stand in for the material beyond a surface (the level-set
//! relaxation of seed 000 §5.2, its ref. [40]). Displacements are Jacobi updates (all
//! forces first, then all moves), so the result does not depend on the order of the
//! particles.
//!
//! [`coarse::relax`]: crate::coarse::relax
//! [`world::water_at_bodies`]: crate::world::water_at_bodies

use crate::numerics::kernel::WendlandC2;
use crate::numerics::math::{Real, Vect};
use std::collections::HashMap;

/// Sweeps of relaxation.
pub const SWEEPS: usize = 120;

/// The relaxation's kernel and step at spacing `dp`.
pub struct Packing {
    kernel: WendlandC2,
    h: Real,
    dp: Real,
    vol: Real,
}

impl Packing {
    /// A packing at spacing `dp` in `dim` dimensions: h = 1.15 dp.
    pub fn new(dp: Real, dim: usize) -> Self {
        let h = 1.15 * dp;
        Packing {
            kernel: WendlandC2::new(h, dim),
            h,
            dp,
            vol: dp.powi(dim as i32),
        }
    }

    /// The kernel's support radius.
    pub fn cutoff(&self) -> Real {
        self.kernel.cutoff
    }

    /// The force on each of `moving` from the other moving particles and from `others`
    /// (fixed particles and images).
    pub fn forces<const D: usize>(&self, moving: &[Vect<D>], others: &[Vect<D>]) -> Vec<Vect<D>> {
        let mut force = vec![Vect::<D>::zeros(); moving.len()];
        self.pairs(moving, others, |i, rij, r| {
            force[i] -= rij * (self.kernel.dw(r) / r * self.vol);
        });
        force
    }

    /// The kernel sum Σ_j W(r_ij) dp^d of each of `moving` over all particles, itself
    /// included: 1 in a full lattice, less where its neighbourhood is cut.
    pub fn support<const D: usize>(&self, moving: &[Vect<D>], others: &[Vect<D>]) -> Vec<Real> {
        let self_weight = self.kernel.w(0.0) * self.vol;
        let mut sum = vec![self_weight; moving.len()];
        self.pairs(moving, others, |i, _, r| {
            sum[i] += self.kernel.w(r) * self.vol
        });
        sum
    }

    /// Every pair (i, j) of a moving particle i and another particle j (moving or in
    /// `others`) closer than the kernel's support, found through cells of that size,
    /// with x_i − x_j and its length, in a fixed order.
    fn pairs<const D: usize>(
        &self,
        moving: &[Vect<D>],
        others: &[Vect<D>],
        mut pair: impl FnMut(usize, Vect<D>, Real),
    ) {
        let cut = self.kernel.cutoff;
        let n = moving.len();
        let cell = |x: &Vect<D>| -> [i64; 3] {
            let mut c = [0i64; 3];
            for k in 0..D {
                c[k] = (x[k] / cut).floor() as i64;
            }
            c
        };
        let mut grid: HashMap<[i64; 3], Vec<u32>> = HashMap::new();
        for (k, x) in moving.iter().chain(others.iter()).enumerate() {
            grid.entry(cell(x)).or_default().push(k as u32);
        }
        let at = |k: usize| -> &Vect<D> {
            if k < n {
                &moving[k]
            } else {
                &others[k - n]
            }
        };
        let range = |k: usize| if k < D { -1..=1 } else { 0..=0 };
        for (i, xi) in moving.iter().enumerate() {
            let c = cell(xi);
            for dx in range(0) {
                for dy in range(1) {
                    for dz in range(2) {
                        let Some(list) = grid.get(&[c[0] + dx, c[1] + dy, c[2] + dz]) else {
                            continue;
                        };
                        for &j in list {
                            let j = j as usize;
                            if j == i {
                                continue;
                            }
                            let rij = xi - at(j);
                            let r = rij.norm();
                            if r >= cut || r == 0.0 {
                                continue;
                            }
                            pair(i, rij, r);
                        }
                    }
                }
            }
        }
    }

    /// The move of a particle under force `f` in sweep `sweep` of `sweeps`: a fraction
    /// of h² F, shrinking over the sweeps, capped at dp/10.
    pub fn step<const D: usize>(&self, (sweep, sweeps): (usize, usize), f: &Vect<D>) -> Vect<D> {
        let relax = 0.1 * (1.0 - sweep as Real / sweeps as Real) + 0.02;
        let mut dx = f * (relax * self.h * self.h);
        let len = dx.norm();
        if len > 0.1 * self.dp {
            dx *= 0.1 * self.dp / len;
        }
        dx
    }
}
