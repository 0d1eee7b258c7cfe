//! Water on walls and barriers: the dummy wall particles of seed 000 Eqs. (32)–(35),
//! which are Zhang, Hu & Adams (2017) §3.3 for a fluid.
//!
//! Wall particle w takes the pressure of water particle i extrapolated hydrostatically
//! to the wall, P_w = P_i + ρ_i g·(x_w − x_i) ([`wall_pressure`]: not below zero
//! upwards), and the velocity
//! mirrored along the wall normal n of Eq. (33), U_R = 2u_w − U_L (Eq. 34); P* of the
//! one-sided Riemann problem carries the water's limiter, and is not below zero: free
//! water has no tensile strength, so a particle in tension leaves the wall rather than
//! pulling it (a wall never reads a pull; without it the right wall of
//! `lobovsky_dam_break.toml` is pulled after the impact). A saturated soil's pore water
//! keeps its suction (`WaterParams::push_only` is false there). No-slip walls add the Morris
//! viscous term with the mirrored velocity 2u_w − v_i (the wall velocity at the
//! surface); free-slip walls add none. In the continuity equation U* = u_w.
//!
//! granmix departs from Eq. (35) here: the seed raises the wall pressure towards
//! walls below the particle and leaves it at P_i towards walls above
//! (max(0, g·(x_w − x_i))). Along a side wall that gives the wall particles below a
//! water particle more pressure than those above, a net upward push that keeps the
//! first layer of a resting tank sliding up and down the wall (0.17 m/s in the 0.5 m
//! tank of `models/scenes/hydrostatic_tank.toml`). The unclipped extrapolation of
//! Adami, Hu & Adams (2012) balances it.

use super::fine_wall::normal;
use crate::geometry::walls::Walls;
use crate::numerics::math::{Real, Vect};
use crate::numerics::periodic::Separation;
use crate::water::correction::{self, Corr};
use crate::water::momentum::{p_star, WaterParams};

/// Water particle i against the walls of its list, for one step.
pub struct WaterAtWall<const D: usize> {
    pub pos: Vect<D>,
    pub vel: Vect<D>,
    pub rho: Real,
    /// P_i.
    pub p: Real,
    /// Wall normal of Eq. (33) at i.
    pub n: Vect<D>,
    /// No-slip: the viscous wall term is on.
    pub no_slip: bool,
    /// Kernel gradient correction B_i ([`correction`](crate::water::correction)).
    pub corr: Corr<D>,
    /// The acceleration the resting pressure gradient balances, ∇p = ρ a: the
    /// hydrostatic gravity, plus a soil's seepage drag on i where there is one.
    pub hyd: Vect<D>,
}

impl<const D: usize> WaterAtWall<D> {
    /// The state of particle i at the walls `wl` of its list.
    #[inline(always)]
    pub fn new(
        prm: &WaterParams<D>,
        walls: &Walls<D>,
        (pos, vel, rho, p): (Vect<D>, Vect<D>, Real, Real),
        wl: &[u32],
        no_slip: bool,
        corr: Corr<D>,
    ) -> Self {
        WaterAtWall {
            pos,
            vel,
            rho,
            p,
            n: normal(&prm.kernel, walls, &pos, wl, &prm.wrap),
            hyd: prm.hydrostatic,
            no_slip,
            corr,
        }
    }

    /// The wall particle's terms of Σ (before the factor 2/ρ_i) in dv_i/dt, Eqs.
    /// (32)–(35) and the no-slip viscous term (None outside the kernel).
    #[inline(always)]
    pub fn momentum(&self, prm: &WaterParams<D>, walls: &Walls<D>, w: usize) -> Option<Vect<D>> {
        let (rij, r, dw) = boundary_pair(prm, &self.pos, &walls.pos[w])?;
        let e = rij * (1.0 / r);
        let vw = walls.velocity(w);
        // Eq. (34): U_L − U_R = 2 (U_L − u_w) along n
        let du = 2.0 * self.n.dot(&(vw - self.vel));
        // Eq. (35) without its clip at zero: P_w = P_i + ρ_i g·(x_w − x_i), the
        // hydrostatic extrapolation of Adami et al. (2012), not below zero upwards
        let pw = wall_pressure(self.p, self.rho * self.hyd.dot(&(-rij)));
        // free water has no tensile strength: a wall pushes, never pulls (issue 42)
        let ps = p_star(prm, self.p, pw, du);
        let ps = if prm.push_only { ps.max(0.0) } else { ps };
        let be = self.corr * e;
        let mut t = be * (-ps * dw);
        if self.no_slip {
            // Morris' term with the corrected gradient, as between water particles
            t += (self.vel - vw) * (2.0 * prm.mu * dw / r * e.dot(&be));
        }
        Some(t * walls.volume)
    }
}

/// A water particle at `xi` and a boundary particle (wall or coarse) at `xj`: x_i − x_j
/// (its minimum image across a periodic seam), r and ∂W/∂r, or None outside the
/// kernel (and at r = 0).
#[inline(always)]
pub fn boundary_pair<const D: usize>(
    prm: &WaterParams<D>,
    xi: &Vect<D>,
    xj: &Vect<D>,
) -> Option<(Vect<D>, Real, Real)> {
    let kernel = &prm.kernel;
    let rij = prm.wrap.of(xi - xj);
    let r2 = rij.norm_squared();
    if r2 >= kernel.cutoff * kernel.cutoff || r2 == 0.0 {
        return None;
    }
    let r = r2.sqrt();
    Some((rij, r, kernel.dw(r)))
}

/// The pressure of a wall particle against a water particle at pressure `p`, with
/// `rise` = ρ_i g·(x_w − x_i) the hydrostatic change from the particle to the wall:
/// p + rise, but an upward extrapolation (rise < 0) stops at zero. A wall particle
/// above the free surface carries no water, and a negative pressure there would pull
/// the surface particles up the wall (they climb the side walls of a resting tank
/// within 0.4 s). A particle already in tension keeps its own pressure.
#[inline(always)]
pub fn wall_pressure(p: Real, rise: Real) -> Real {
    if rise >= 0.0 {
        p + rise
    } else {
        p + rise.max(-p.max(0.0))
    }
}

/// Wall particle `w`'s term of Σ (before the factor ρ_i) in dρ_i/dt of water particle
/// i at `xi` moving with `vi`: U* = u_w, 2 (v_i − u_w)·e ∂W/∂r V_w.
#[inline(always)]
pub fn continuity<const D: usize>(
    prm: &WaterParams<D>,
    walls: &Walls<D>,
    xi: &Vect<D>,
    vi: &Vect<D>,
    w: usize,
) -> Real {
    let Some((rij, r, dw)) = boundary_pair(prm, xi, &walls.pos[w]) else {
        return 0.0;
    };
    2.0 * (vi - walls.velocity(w)).dot(&rij) / r * dw * walls.volume
}

/// Wall particle `w`'s share of M_i ([`correction`](crate::water::correction)) for
/// water particle i at `xi` (zero outside the kernel).
#[inline(always)]
pub fn moment<const D: usize>(
    prm: &WaterParams<D>,
    walls: &Walls<D>,
    xi: &Vect<D>,
    w: usize,
) -> Corr<D> {
    match boundary_pair(prm, xi, &walls.pos[w]) {
        Some((rij, r, dw)) => correction::share(&(rij / r), r, dw, walls.volume),
        None => Corr::<D>::zeros(),
    }
}
