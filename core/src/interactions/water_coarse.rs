//! Water on coarse grains (seed 001 §1.7's boundary role of the DEM object, here in
//! the form of the water's walls): a coarse particle near a water particle is a moving
//! dummy particle. It takes the water particle's pressure extrapolated along the
//! relative acceleration of water at rest and the body, ρ_i (g − a_c)·(x_c − x_i)
//! (Adami, Hu & Adams 2012; [`wall_pressure`]), the velocity mirrored along its
//! outward normal (Eq. 34 with the
//! body's velocity v̄ of Eq. 60), and no-slip bodies add the viscous term with the
//! mirrored velocity 2v̄ − v_i. The coarse particle receives exactly −m_i a_ic, so the
//! momentum the water gives a body over each step is what the body gives the water,
//! to round-off; buoyancy is the sum of these pressure forces over the body's surface.

use super::fine_coarse::CoarseSource;
use super::water_wall::{boundary_pair, wall_pressure};
use crate::numerics::math::{Real, Vect};
use crate::water::correction::{self, Corr};
use crate::water::momentum::{p_star, WaterParams};

/// The direction along which coarse particle `c` mirrors a water particle seen along
/// `e` (from the coarse particle to the water particle): its outward normal when the
/// water particle lies in front of it, `e` otherwise (at corners, and for interior
/// particles whose normal is zero).
#[inline(always)]
fn mirror<const D: usize>(c: &CoarseSource<D>, e: &Vect<D>) -> Vect<D> {
    if c.normal.dot(e) > 0.0 {
        c.normal
    } else {
        *e
    }
}

/// Coarse particle `c`'s term of Σ (before the factor 2/ρ_i) in dv_i/dt of water
/// particle i at `xi` moving with `vi`, at density `rho` and pressure `p`, with the
/// correction `b` (None outside the kernel).
#[allow(clippy::too_many_arguments)]
#[inline(always)]
pub fn momentum<const D: usize>(
    prm: &WaterParams<D>,
    c: &CoarseSource<D>,
    (xi, vi, rho, p): (&Vect<D>, &Vect<D>, Real, Real),
    b: &Corr<D>,
    no_slip: bool,
) -> Option<Vect<D>> {
    let (rij, r, dw) = boundary_pair(prm, xi, &c.pos)?;
    let e = rij * (1.0 / r);
    let n = mirror(c, &e);
    // U_L − U_R = 2 (U_L − u_c) along n
    let du = 2.0 * n.dot(&(c.vel - vi));
    // the body's own acceleration enters the extrapolation (Adami et al. 2012):
    // ρ_i (g − a_c)·(x_c − x_i)
    let pc = wall_pressure(p, rho * (prm.gravity - c.acc).dot(&(-rij)));
    let be = b * e;
    let mut t = be * (-p_star(prm, p, pc, du) * dw);
    if no_slip {
        // Morris' term with the corrected gradient, as between water particles
        t += (vi - c.vel) * (2.0 * prm.mu * dw / r * e.dot(&be));
    }
    Some(t * c.vol)
}

/// Coarse particle `c`'s term of Σ (before the factor ρ_i) in dρ_i/dt of water particle
/// i at `xi` moving with `vi`: the mirrored normal velocity, 2 ((v_i − v̄)·n) n·e ∂W/∂r V.
#[inline(always)]
pub fn continuity<const D: usize>(
    prm: &WaterParams<D>,
    c: &CoarseSource<D>,
    xi: &Vect<D>,
    vi: &Vect<D>,
) -> Real {
    let Some((rij, r, dw)) = boundary_pair(prm, xi, &c.pos) else {
        return 0.0;
    };
    let e = rij * (1.0 / r);
    let n = mirror(c, &e);
    2.0 * (vi - c.vel).dot(&n) * n.dot(&e) * dw * c.vol
}

/// Coarse particle `c`'s share of M_i ([`correction`]) for water particle i at `xi`.
#[inline(always)]
pub fn moment<const D: usize>(prm: &WaterParams<D>, c: &CoarseSource<D>, xi: &Vect<D>) -> Corr<D> {
    match boundary_pair(prm, xi, &c.pos) {
        Some((rij, r, dw)) => correction::share(&(rij / r), r, dw, c.vol),
        None => Corr::<D>::zeros(),
    }
}

/// The share of coarse particle `c`'s momentum term (before the factor 2/ρ_i) that the
/// body's hydrostatic field carries ([`water_buoyancy`](super::water_buoyancy)): the
/// pair of [`momentum`] with P* replaced by the field's mean ½ (p_b(x_i) + p_b(x_c)),
/// `p_c` = p_b(x_c), `rho_g` = ρ_w g_h, and without the viscous term.
#[inline(always)]
pub fn hydrostatic_share<const D: usize>(
    prm: &WaterParams<D>,
    c: &CoarseSource<D>,
    xi: &Vect<D>,
    b: &Corr<D>,
    (p_c, rho_g): (Real, &Vect<D>),
) -> Option<Vect<D>> {
    let (rij, r, dw) = boundary_pair(prm, xi, &c.pos)?;
    let mean = p_c + 0.5 * rho_g.dot(&rij);
    Some((b * rij) * (-mean * dw * c.vol / r))
}
