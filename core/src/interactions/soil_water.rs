//! Soil and water: the seepage force and the pore-pressure force of seed 001
//! Eqs. (8)–(10), between the fine grains (a soil with [`Pores`]) and the water.
//!
//! The pore water is a continuum over the whole volume (seed 001): its particles carry
//! the water's mass ρ_w V and the superficial (Darcy) velocity, so a soil at rest
//! passes the discharge q = u_w = (k/μ)(ρ_w g − ∇p) (Darcy). Porosity does not enter
//! the water's continuity; it enters the soil's mass, ρ_d = (1 − n) ρ_grain, and the
//! buoyancy of its grains, (1 − n) ∇p (docs/method.md §Saturated soil).
//!
//! - Seepage, Eqs. (8) and (10): the pair (soil j, water i) exchanges the force
//!   V_i V_j (μ/k_j)(u_i − u_j) W_ij, equal and opposite. Over the water's sub-steps
//!   of a step the soil's positions and velocities are frozen, so the water's drag
//!   is linear in its own velocity, −(a_i u_i − b_i)/ρ_i with a_i = Σ_j V_j (μ/k_j)
//!   W_ij and b_i = Σ_j V_j (μ/k_j) W_ij u_j ([`Seepage`]); it is taken implicitly
//!   (backward Euler, stable for any k). The soil receives the exact opposite of
//!   the water's impulse, from the sub-steps' mean of V_i and V_i u_i
//!   ([`WaterDrag`]).
//! - Pore pressure, Eq. (9)'s second term, splits into its hydrostatic part and
//!   the excess over it. On the grains the hydrostatic part is their buoyancy,
//!   −(1 − n) ρ_w g per unit volume, taken as far as water surrounds the particle
//!   (Σ V_i W_ij against its sum in full, [`full_sum`], at most 1). The excess part the seepage
//!   force already carries: the water's own balance makes f = −∇p_e at steady
//!   seepage, so the grains receive ρ_w g i under a gradient i (Terzaghi). Adding the
//!   whole −(1 − n)∇p to f, as Eq. (9) reads, counts the excess twice ((2 − n) ρ_w g
//!   i; measured in docs/method.md §Saturated soil), and its mixture-theory reading,
//!   n f − (1 − n)∇p, loses lift where the soil's edge smooths ∇p but not f (the
//!   column's lift 4 % low). The buoyancy has no reaction on the water: the pore
//!   water, over the whole volume, weighs (1 − n) ρ_w g more per unit volume than
//!   the real one, which balances it. The pore pressure at each soil particle is
//!   interpolated from the water, exact for a linear field even where the water's
//!   support is cut (walls, free surface), for the outputs.
//!
//! The soil's Drucker–Prager model then works on effective stress: its stress is σ'
//! and the pore pressure enters its momentum only through these forces.
//!
//! [`Pores`]: crate::fine::pores::Pores

use crate::fine::material::FineMaterial;
use crate::numerics::kernel::WendlandC2;
use crate::numerics::math::{Real, Vect};
use crate::numerics::neighbors::CellGrid;
use nalgebra::SMatrix;

/// A soil particle as the water sees it over a step: at the middle of the step.
#[derive(Clone, Copy, Debug)]
pub struct SoilPoint<const D: usize> {
    pub pos: Vect<D>,
    /// Velocity at the start of the step.
    pub vel: Vect<D>,
    pub vol: Real,
    /// μ/k (Pa·s/m²); 0 for a soil the water passes freely.
    pub drag: Real,
    /// 1 − n, the grains' share of the volume (0 without pores).
    pub solid: Real,
}

/// A D × D matrix of the velocity gradients.
pub type Mat<const D: usize> = SMatrix<Real, D, D>;

/// Σ V W over the lattice of spacing `dp`: its least value at any point of the unit
/// cell (sampled at quarter spacings), and its value at a lattice point. The least is
/// the kernel sum a water particle inside a soil meets at least (1 for a continuum;
/// 0.99–1.03 for the Wendland C2 kernel at h = 1.3 dp in 2D as the point moves off
/// the lattice); the value at a lattice point is what a particle of a family meets
/// of its own family in full support.
pub fn lattice_sum<const D: usize>(k: &WendlandC2, dp: Real) -> (Real, Real) {
    let n = (k.cutoff / dp).ceil() as i64 + 1;
    let vol = dp.powi(D as i32);
    let sum_at = |off: [Real; 3]| {
        let mut sum = 0.0;
        let mut cell = [0i64; 3];
        let count = (2 * n + 1).pow(D as u32);
        for c in 0..count {
            let mut rest = c;
            for a in cell.iter_mut().take(D) {
                *a = rest % (2 * n + 1) - n;
                rest /= 2 * n + 1;
            }
            let r2: Real = (0..D)
                .map(|a| ((cell[a] as Real + off[a]) * dp).powi(2))
                .sum();
            if r2 < k.cutoff * k.cutoff {
                sum += k.w(r2.sqrt()) * vol;
            }
        }
        sum
    };
    let mut least = Real::INFINITY;
    for c in 0..4usize.pow(D as u32) {
        let mut off = [0.0; 3];
        let mut rest = c;
        for o in off.iter_mut().take(D) {
            *o = (rest % 4) as Real * 0.25;
            rest /= 4;
        }
        least = least.min(sum_at(off));
    }
    (least, sum_at([0.0; 3]))
}

/// Σ V W at `x` over the particles at `pos` (volumes `vol`) binned in `grid`: the
/// kernel sum of a family at a point, the point's own particle included.
pub fn kernel_sum<const D: usize>(
    x: &Vect<D>,
    pos: &[Vect<D>],
    vol: impl Fn(usize) -> Real,
    grid: &CellGrid<D>,
    k: &WendlandC2,
) -> Real {
    let cut2 = k.cutoff * k.cutoff;
    let mut s = 0.0;
    grid.for_each_near(x, |j| {
        let j = j as usize;
        let r2 = (x - pos[j]).norm_squared();
        if r2 < cut2 {
            s += k.w(r2.sqrt()) * vol(j);
        }
    });
    s
}

/// The soil's kernel sum in full at a particle whose own family gives `own` there:
/// the least lattice sum scaled by the particle's own support, `own` over its lattice
/// value (1 inside, less at a free surface or a wall, where both families are cut
/// alike), not below a tenth of the least.
#[inline(always)]
pub fn full_sum((least, at_point): (Real, Real), own: Real) -> Real {
    (least * (own / at_point).min(1.0)).max(0.1 * least)
}

impl<const D: usize> SoilPoint<D> {
    /// Soil particle of material `m` at density `rho` under water of viscosity `mu`:
    /// its porosity follows its density and its permeability Kozeny–Carman
    /// ([`Pores::porosity_at`], [`Pores::permeability_at`]; issue 44 item 1).
    ///
    /// [`Pores::porosity_at`]: crate::fine::pores::Pores::porosity_at
    /// [`Pores::permeability_at`]: crate::fine::pores::Pores::permeability_at
    pub fn of(
        m: &FineMaterial,
        mu: Real,
        (pos, vel): (Vect<D>, Vect<D>),
        vol: Real,
        rho: Real,
    ) -> Self {
        let (drag, solid) = m.pores.map_or((0.0, 0.0), |p| {
            let n = p.porosity_at(rho, m.rho0);
            (mu / p.permeability_at(n), 1.0 - n)
        });
        SoilPoint {
            pos,
            vel,
            vol,
            drag,
            solid,
        }
    }
}

/// The water's drag coefficients of a step, seed 001 Eqs. (8), (10): a_i = Σ_j V_j
/// (μ/k_j) W_ij / s_i (Pa·s/m²) and b_i = Σ_j V_j (μ/k_j) W_ij u_j / s_i, with s_i
/// the larger of Σ_j V_j W_ij and the soil's sum in full there ([`full_sum`]: the
/// least lattice sum, cut where the water's own support is cut). Inside a soil, at
/// its free surface and at walls alike this is the Shepard mean, so the water meets
/// μ/k exactly wherever it sits on the soil's lattice (the plain sum swings by 4 %
/// with the offset); where the water leaves the soil the drag tapers with the soil's
/// presence.
///
/// Each pair compares u_i with the soil's velocity at the pair's midpoint,
/// v_j + ½ (Ḡ_i + L_j)(x_i − x_j), L_j the soil particle's velocity gradient and Ḡ_i
/// the Shepard mean of the soil's gradients around i (issue 44): the plain v_j made
/// the drag compare u_i with the kernel mean of the soil's velocity, which differs
/// from the soil's velocity at x_i by about 0.07 R² ∇²v inside a soil and by the
/// kernel's first moment times ∇v at its edges, a viscosity of about (μ/k) 0.07 R² on
/// a soil locked to its water (docs/method.md §Pore-pressure feedback). The midpoint
/// velocity is exact for a linear field and cancels the curvature to second order;
/// the pair's force stays equal and opposite.
#[derive(Clone, Copy, Debug)]
pub struct Seepage<const D: usize> {
    pub a: Real,
    pub b: Vect<D>,
    /// 1/s_i, by which the soil's reaction is weighted too.
    pub inv: Real,
    /// Ḡ_i, the Shepard mean of the soil's velocity gradients around i.
    pub grad: Mat<D>,
}

impl<const D: usize> Seepage<D> {
    /// The coefficients of a water particle at `x` from the soil particles `near`
    /// (indices into `soil`), not yet normalised, and the soil's sum Σ_j V_j W_ij there
    /// (over soils with pores). With the soil's velocity gradients `grads` (L_j of
    /// each soil particle; empty: none), each pair against the soil's velocity at its
    /// midpoint (else v_j, and Ḡ_i stays zero). The gradients are kept apart from the
    /// points so that the plain drag's pair loop reads no more than it needs.
    pub fn raw(
        x: &Vect<D>,
        soil: &[SoilPoint<D>],
        near: &[u32],
        k: &WendlandC2,
        grads: &[Mat<D>],
    ) -> (Self, Real) {
        let midpoint = !grads.is_empty();
        let cut2 = k.cutoff * k.cutoff;
        let mut s = Seepage {
            a: 0.0,
            b: Vect::<D>::zeros(),
            inv: 1.0,
            grad: Mat::<D>::zeros(),
        };
        let mut sum = 0.0;
        // Σ c r_ij, for the ½ Ḡ_i r_ij of each pair once Ḡ_i is known
        let mut moment = Vect::<D>::zeros();
        for &j in near {
            let q = &soil[j as usize];
            if q.drag == 0.0 {
                continue;
            }
            let rij = x - q.pos;
            let r2 = rij.norm_squared();
            if r2 < cut2 {
                let vw = q.vol * k.w(r2.sqrt());
                let c = q.drag * vw;
                sum += vw;
                s.a += c;
                if midpoint {
                    let l = &grads[j as usize];
                    s.b += (q.vel + l * rij * 0.5) * c;
                    s.grad += l * vw;
                    moment += rij * c;
                } else {
                    s.b += q.vel * c;
                }
            }
        }
        if midpoint && sum > 0.0 {
            s.grad /= sum;
            s.b += s.grad * moment * 0.5;
        }
        (s, sum)
    }

    /// The coefficients divided by s = max(`sum`, `full`), `full` the kernel sum a
    /// soil would give there ([`full_sum`]).
    pub fn normalised(self, sum: Real, full: Real) -> Self {
        let inv = 1.0 / sum.max(full);
        Seepage {
            a: self.a * inv,
            b: self.b * inv,
            inv,
            grad: self.grad,
        }
    }

    /// The velocity after the drag over `dt` of a water particle of density `rho`
    /// whose other forces gave `u`: backward Euler of du/dt = −(a u − b)/ρ.
    #[inline(always)]
    pub fn drag(&self, u: Vect<D>, rho: Real, dt: Real) -> Vect<D> {
        if self.a == 0.0 {
            return u;
        }
        let f = dt / rho;
        (u + self.b * f) / (1.0 + self.a * f)
    }
}

/// One water particle's share of the drag over a step: the means over its sub-steps
/// of V_i and V_i u_i (u_i after the drag), from which the soil's reaction follows.
#[derive(Clone, Copy, Debug)]
pub struct WaterDrag<const D: usize> {
    pub vol: Real,
    pub vol_vel: Vect<D>,
}

impl<const D: usize> Default for WaterDrag<D> {
    fn default() -> Self {
        WaterDrag {
            vol: 0.0,
            vol_vel: Vect::<D>::zeros(),
        }
    }
}

impl<const D: usize> WaterDrag<D> {
    /// Add a sub-step of weight `share` (1/k) with volume `vol` and velocity `u`
    /// (both weighted by the particle's [`Seepage::inv`]).
    #[inline(always)]
    pub fn add(&mut self, vol: Real, u: &Vect<D>, share: Real) {
        self.vol += vol * share;
        self.vol_vel += u * (vol * share);
    }
}

/// The water around a soil particle, for its forces at the end of the water's
/// sub-steps.
pub struct WaterAround<'a, const D: usize> {
    /// Positions at which the seepage was frozen (see [`Seepage`]).
    pub frozen: &'a [Vect<D>],
    /// Each particle's share of the drag over the step.
    pub drag: &'a [WaterDrag<D>],
    /// Volumes now.
    pub vol: &'a [Real],
    /// Each particle's Ḡ ([`Seepage::grad`]); empty without the midpoint drag.
    pub grad: &'a [Mat<D>],
    /// −ρ_w g: the buoyancy of water per unit volume (N/m³, upward).
    pub buoyancy: Vect<D>,
}

/// The water's force on soil particle `q` over the step (seepage and buoyancy, N),
/// from the water particles `near`; `l` is the particle's velocity gradient, with
/// which the pairs' midpoint velocities were taken (zero without the midpoint
/// drag). `full` is the kernel sum the water would give there in full
/// ([`full_sum`] of the soil's own sum). Each pair that exchanges drag
/// is handed to `pair` with its coefficient c_ij = V_j (μ/k_j) W_ij ⟨V_i/s_i⟩ (N·s/m),
/// for the implicit close of the step ([`seepage_implicit`](super::seepage_implicit)),
/// and each water particle within the kernel to `wet` with its V_i W_ij, for
/// [`pore_water_inertia`] at the end of the step.
pub fn soil_force<const D: usize>(
    (q, l): (&SoilPoint<D>, &Mat<D>),
    w: &WaterAround<'_, D>,
    near: &[u32],
    k: &WendlandC2,
    full: Real,
    (mut pair, mut wet): (impl FnMut(u32, Real), impl FnMut(u32, Real)),
) -> Vect<D> {
    let cut2 = k.cutoff * k.cutoff;
    let mut seep = Vect::<D>::zeros();
    let mut s0 = 0.0;
    let midpoint = !w.grad.is_empty();
    for &i in near {
        let iu = i as usize;
        let r2 = (q.pos - w.frozen[iu]).norm_squared();
        if r2 < cut2 {
            let wk = k.w(r2.sqrt());
            let vw = wk * w.vol[iu];
            s0 += vw;
            wet(i, vw);
            if q.drag > 0.0 {
                let d = &w.drag[iu];
                // the soil's velocity at the pair's midpoint, as the water took it
                let mid = if midpoint {
                    q.vel + (w.grad[iu] + l) * (w.frozen[iu] - q.pos) * 0.5
                } else {
                    q.vel
                };
                seep += (d.vol_vel - mid * d.vol) * (q.drag * wk);
                if d.vol > 0.0 {
                    pair(i, q.drag * wk * q.vol * d.vol);
                }
            }
        }
    }
    // the grains' buoyancy, as far as the water surrounds them
    let wet = (s0 / full).min(1.0);
    (seep + w.buoyancy * (q.solid * wet)) * q.vol
}

/// The impulse (N·s) the water's velocity change over a step, `du`, hands soil
/// particle `q` through the inertial part of its pore pressure: Eq. (9)'s pressure
/// term −(1 − n)∇p with the water's momentum ∇p = ρ_w (g − a_w) − f gives the grains
/// their buoyancy −(1 − n) ρ_w g, the seepage force f, and (1 − n) ρ_w a_w, taken here
/// as (1 − n) ρ_w V ⟨Δu⟩ with ⟨Δu⟩ the water's Shepard mean around the particle, as
/// far as the water surrounds it (`full`, as the buoyancy). The pore water over the
/// whole volume carries (1 − n) ρ_w per unit volume more mass than the real one; this
/// term hands that surplus's inertia to the grains, so that a soil moving with its
/// water carries the mixture's momentum (ρ_d + n ρ_w) V v (issue 44 item 1), and a
/// saturated soil falls freely at g. It has no reaction on the water: the surplus it
/// removes is not the real water's. `wet` holds the water particles within the
/// particle's kernel with their V_i W_ij, as [`soil_force`] handed them over.
pub fn pore_water_inertia<const D: usize>(
    q: &SoilPoint<D>,
    du: &[Vect<D>],
    (idx, wet): (&[u32], &[Real]),
    (full, rho_w): (Real, Real),
) -> Vect<D> {
    if q.solid == 0.0 {
        return Vect::<D>::zeros();
    }
    let (mut s0, mut m) = (0.0, Vect::<D>::zeros());
    for (&i, &vw) in idx.iter().zip(wet) {
        s0 += vw;
        m += du[i as usize] * vw;
    }
    if s0 == 0.0 {
        return Vect::<D>::zeros();
    }
    m * (q.solid * rho_w * q.vol / s0.max(full))
}

/// The pore pressure at `x` from the water particles `near` (positions `pos`,
/// volumes `vol`, pressures `p`), exact for a linear field even where the water's
/// support is cut (walls, free surface); Shepard's where the water is too sparse for
/// that; None without water within the kernel.
pub fn pore_pressure<const D: usize>(
    x: &Vect<D>,
    (pos, vol, p): (&[Vect<D>], &[Real], &[Real]),
    near: &[u32],
    k: &WendlandC2,
) -> Option<Real> {
    let cut2 = k.cutoff * k.cutoff;
    // Σ V W, Σ V p W, Σ V W (x_i − x_j), Σ V ∇W, Σ V p ∇W, Σ V ∇W ⊗ (x_i − x_j)
    let (mut s0, mut s1) = (0.0, 0.0);
    let mut t = Vect::<D>::zeros();
    let (mut g0, mut g1) = (Vect::<D>::zeros(), Vect::<D>::zeros());
    let mut m = SMatrix::<Real, D, D>::zeros();
    for &i in near {
        let i = i as usize;
        let rij = x - pos[i];
        let r2 = rij.norm_squared();
        if r2 < cut2 {
            let r = r2.sqrt();
            let (v, pi) = (vol[i], p[i]);
            let wv = k.w(r) * v;
            s0 += wv;
            s1 += wv * pi;
            t -= rij * wv;
            if r > 0.0 {
                // ∇_j W_ji = W'(r) (x_j − x_i)/r
                let grad = rij * (k.dw(r) / r * v);
                g0 += grad;
                g1 += grad * pi;
                m -= grad * rij.transpose();
            }
        }
    }
    if s0 == 0.0 {
        return None;
    }
    // p_i = p + ∇p·(x_i − x_j):  Σ V W p_i = p S0 + t·∇p  and  Σ V ∇W p_i = p g0 + M ∇p,
    // solved by eliminating ∇p = M⁻¹ (g1 − p g0), where S0 > 0.3
    let exact = (s0 > 0.3)
        .then(|| m.try_inverse())
        .flatten()
        .and_then(|inv| {
            let (a0, a1) = (inv * g0, inv * g1);
            let den = s0 - t.dot(&a0);
            (den.abs() > 0.1 * s0).then(|| (s1 - t.dot(&a1)) / den)
        });
    Some(exact.unwrap_or(s1 / s0))
}

#[cfg(test)]
mod tests {
    use super::*;
    use nalgebra::Vector2;

    fn lattice(dp: Real, n: i32, lo_y: i32) -> Vec<Vect<2>> {
        let mut x = Vec::new();
        for i in -n..=n {
            for j in lo_y..=n {
                x.push(Vector2::new(i as Real * dp, j as Real * dp));
            }
        }
        x
    }

    /// The pore pressure interpolated at a soil particle is exact for a linear field, in
    /// full support and where the water is cut off by a floor below the particle; the
    /// buoyancy is (1 − n) ρ_w g V in full water.
    #[test]
    fn pore_pressure_is_exact_for_a_linear_field() {
        let dp = 0.01;
        let k = WendlandC2::new(1.3 * dp, 2);
        let grad = Vector2::new(300.0, -9810.0);
        for lo in [-6, 0] {
            let pos = lattice(dp, 6, lo);
            let n = pos.len();
            let p: Vec<Real> = pos.iter().map(|x| 5000.0 + grad.dot(x)).collect();
            let vol = vec![dp * dp; n];
            let drag = vec![WaterDrag::default(); n];
            let grads = vec![Mat::<2>::zeros(); n];
            let w = WaterAround {
                frozen: &pos,
                drag: &drag,
                vol: &vol,
                grad: &grads,
                buoyancy: Vector2::new(0.0, 9810.0),
            };
            let q = SoilPoint {
                pos: Vector2::new(0.001, 0.0),
                vel: Vector2::zeros(),
                vol: dp * dp,
                drag: 0.0,
                solid: 0.6,
            };
            let near: Vec<u32> = (0..n as u32).collect();
            let f = soil_force(
                (&q, &Mat::<2>::zeros()),
                &w,
                &near,
                &k,
                lattice_sum::<2>(&k, dp).0,
                (|_, _| {}, |_, _| {}),
            );
            let ph = pore_pressure(&q.pos, (&pos, &vol, &p), &near, &k).unwrap();
            // no seepage: the grains' buoyancy, in full where the water surrounds them,
            // in part on the floor
            let full = 9810.0 * 0.6 * dp * dp;
            if lo < 0 {
                assert!((f - Vector2::new(0.0, full)).norm() < 5e-3 * full, "{f}");
            } else {
                assert!(f[0] == 0.0 && f[1] > 0.5 * full && f[1] < full, "{f}");
            }
            let p_exact = 5000.0 + grad.dot(&q.pos);
            assert!(
                (ph - p_exact).abs() < 1e-9 * p_exact,
                "{lo}: {ph} {p_exact}"
            );
        }
    }

    /// The soil's reaction is the exact opposite of the water's implicit drag impulse.
    #[test]
    fn drag_is_equal_and_opposite() {
        let dp = 0.01;
        let k = WendlandC2::new(1.3 * dp, 2);
        let water = lattice(dp, 3, -3);
        let soil: Vec<SoilPoint<2>> = lattice(dp, 3, -3)
            .iter()
            .enumerate()
            .map(|(j, x)| SoilPoint {
                pos: x + Vector2::new(0.3 * dp, 0.2 * dp),
                vel: Vector2::new(0.01 * j as Real, -0.02),
                vol: dp * dp,
                drag: 1e5,
                solid: 0.6,
            })
            .collect();
        let l = Mat::<2>::new(3.0, -1.0, 0.5, 2.0);
        let soil_grads = vec![l; soil.len()];
        let (rho, dt, vol) = (1000.0, 1e-3, dp * dp);
        let mut impulse = Vector2::<Real>::zeros();
        let mut drag = vec![WaterDrag::default(); water.len()];
        let mut grads = vec![Mat::<2>::zeros(); water.len()];
        // three sub-steps, each water particle starting from its own velocity
        for s in 0..3 {
            for (i, x) in water.iter().enumerate() {
                let near: Vec<u32> = (0..soil.len() as u32).collect();
                let (c, sum) = Seepage::raw(x, &soil, &near, &k, &soil_grads);
                let c = c.normalised(sum, lattice_sum::<2>(&k, dp).0);
                grads[i] = c.grad;
                let u0 = Vector2::new(0.1 * s as Real, 0.05 * i as Real);
                let u = c.drag(u0, rho, dt);
                impulse += (u - u0) * (rho * vol);
                drag[i].add(vol * c.inv, &u, 1.0 / 3.0);
            }
        }
        let vols = vec![vol; water.len()];
        let w = WaterAround {
            frozen: &water,
            drag: &drag,
            vol: &vols,
            grad: &grads,
            buoyancy: Vector2::zeros(),
        };
        let mut reaction = Vector2::<Real>::zeros();
        for q in &soil {
            let q = SoilPoint { solid: 0.0, ..*q };
            let near: Vec<u32> = (0..water.len() as u32).collect();
            reaction +=
                soil_force((&q, &l), &w, &near, &k, 1.0, (|_, _| {}, |_, _| {})) * (3.0 * dt);
        }
        assert!(impulse.norm() > 1e-6);
        assert!(
            (impulse + reaction).norm() < 1e-12 * impulse.norm().max(1.0),
            "{impulse} {reaction}"
        );
    }

    /// A soil and its water moving together in a linear velocity field (a simple
    /// shear, the soil's gradient L) exchange no drag, at the soil's free surface as
    /// inside it: each pair compares the water with the soil's velocity at the pair's
    /// midpoint. Before (the plain v_j) the water met the kernel mean of the soil's
    /// velocity, off by the kernel's first moment times L at the edges: measured here
    /// without the gradient, the worst surface particle feels 22 % of the drag a
    /// relative velocity of L dp would give.
    #[test]
    fn a_locked_linear_field_exchanges_no_drag() {
        let dp = 0.01;
        let k = WendlandC2::new(1.3 * dp, 2);
        let l = Mat::<2>::new(0.0, 2.0, 0.0, 0.0);
        let field = |x: &Vect<2>| l * x + Vector2::new(0.1, 0.0);
        let pts = lattice(dp, 4, 0);
        let (mu_k, vol) = (1e5, dp * dp);
        let near: Vec<u32> = (0..pts.len() as u32).collect();
        for with_gradient in [true, false] {
            let g = if with_gradient { l } else { Mat::<2>::zeros() };
            let soil: Vec<SoilPoint<2>> = pts
                .iter()
                .map(|x| SoilPoint {
                    pos: *x,
                    vel: field(x),
                    vol,
                    drag: mu_k,
                    solid: 0.6,
                })
                .collect();
            let soil_grads = vec![g; soil.len()];
            let mut drag = vec![WaterDrag::default(); pts.len()];
            let mut grads = vec![Mat::<2>::zeros(); pts.len()];
            for (i, x) in pts.iter().enumerate() {
                let (c, sum) = Seepage::raw(x, &soil, &near, &k, &soil_grads);
                let c = c.normalised(sum, lattice_sum::<2>(&k, dp).0);
                grads[i] = c.grad;
                drag[i].add(vol * c.inv, &field(x), 1.0);
            }
            let vols = vec![vol; pts.len()];
            let w = WaterAround {
                frozen: &pts,
                drag: &drag,
                vol: &vols,
                grad: &grads,
                buoyancy: Vector2::zeros(),
            };
            // the drag of a relative velocity L dp on a particle in full support
            let unit = mu_k * vol * (l * Vector2::new(0.0, dp)).norm();
            let worst = soil
                .iter()
                .map(|q| {
                    let q = SoilPoint { solid: 0.0, ..*q };
                    soil_force((&q, &g), &w, &near, &k, 1.0, (|_, _| {}, |_, _| {})).norm() / unit
                })
                .fold(0.0, Real::max);
            eprintln!("gradient {with_gradient}: worst drag {worst:.3e} of L dp's");
            if with_gradient {
                assert!(
                    worst < 1e-9,
                    "the drag of a locked shear: {worst:e} of L dp's"
                );
            } else {
                assert!(
                    worst > 0.05,
                    "without the gradient the edges feel {worst:e}"
                );
            }
        }
    }
}
