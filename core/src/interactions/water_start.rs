//! The water's start as an incompressible fluid at rest: the pressure it takes the
//! instant it is released (issue 42).
//!
//! A weakly compressible column filled at its hydrostatic pressure and released at
//! t = 0 (a dam break) is not in the state an incompressible fluid would be in: where a
//! gate vanished, the pressure of real water drops at once to the solution of
//!
//!   ∇²p = ρ ∇·g = 0,   p = 0 on the free surface,   ∂p/∂n = ρ g·n on walls and bodies
//!
//! (the pressure of the first instant of a flow from rest, Stansby, Chegini & Barnes
//! 1998, whose initial acceleration g − ∇p/ρ is divergence-free). Started hydrostatic,
//! the weakly compressible water reaches that state by an acoustic wave instead: in
//! `dam_break_2d` the whole column rang between −700 Pa and hydrostatic for 70 ms,
//! and its walls read pulls of up to 44 N/m. A tank at rest is its own solution: its
//! start stays hydrostatic to O(ρ g dp).
//!
//! At rest the weakly compressible water balances ∇p = ρ g, so the operator is
//! ∇·(∇p/ρ) (zero for the hydrostatic start of either equation of state), in
//! Brookshaw's (1985) SPH form with 1/ρ at the pair's midpoint,
//!
//!   ∇·(∇p/ρ)_i ≈ −Σ_j a_ij (p_i − p_j),   a_ij = 2 (V_i + V_j) |∂W/∂r| / (r (ρ_i + ρ_j)),
//!
//! symmetric, so the system is solved by conjugate gradients. It does not reproduce a
//! linear field where a neighbourhood is lopsided (the staircase gap around a body),
//! so the unknown is the departure q = p − p_h from the hydrostatic start p_h, whose
//! Laplacian is zero and which meets the walls' condition exactly: a wall or body
//! particle takes the water's hydrostatic extrapolation
//! ([`water_wall`](super::water_wall)), so q_b = q_i and its term vanishes (Neumann).
//! A particle whose kernel support falls short of the fullest in the water by more
//! than a quarter, and beyond which no particle lies (Marrone et al. 2010's scan),
//! lies at the free surface: its missing neighbours hold the q that
//! makes p zero half a spacing out, along the direction its support is missing in
//! (Dirichlet), a term (K − S_i)(q_i − q_s), S_i its support. A column fill's
//! hydrostatic start under a surface η(x) is not harmonic (∇²p_h = −ρ g η''): where a
//! particle's support is full its SPH Laplacian of p_h is the source. A tank at rest
//! is its own solution, q = 0.

use super::fine_coarse::CoarseSource;
use super::water_wall::boundary_pair;
use crate::geometry::walls::Walls;
use crate::numerics::math::{Real, Vect};
use crate::numerics::neighbors::{NeighborLists, CHUNK};
use crate::numerics::pairs::clusters::ClusterPairs;
use crate::numerics::periodic::Separation;
use crate::numerics::sparse_cg::{conjugate_gradient, Symmetric};
use crate::water::momentum::WaterParams;
use crate::water::state::WaterParticles;

/// A particle is at the free surface when its support falls short of the fullest by
/// more than this share. Measured at h = 1.3 dp (2D): the top layer of a flat surface
/// lacks 0.32 of it, the next under 0.1. A water particle in the staircase gap
/// around a disc lacks up to 0.21 at R/dp = 10 and 0.31 at R/dp = 40, which is no
/// free surface: the scan ([`free_surface`]) tells them apart.
const SURFACE_DEFICIT: Real = 0.25;

/// A support within this share of the fullest is full: there the SPH Laplacian of the
/// hydrostatic start is trusted as its source.
const FULL: Real = 0.01;

/// The solved start: each particle's pressure, and the conjugate gradient's
/// iterations and relative residual.
#[derive(Debug)]
pub struct Start {
    pub pressure: Vec<Real>,
    pub iterations: usize,
    pub residual: Real,
}

/// Runs over the water–water, water–wall and water–coarse relations.
///
/// The incompressible start pressure of the water `w` (particle volumes `vol`,
/// spacing `dp`) from its hydrostatic start pressure `p0`, or None
/// where it has no free surface (a closed box fixes the pressure only up to a
/// constant: the hydrostatic start stays).
pub fn incompressible_start<const D: usize>(
    w: &WaterParticles<D>,
    (vol, p0): (impl Fn(usize) -> Real, &[Real]),
    (walls, csrc): (&Walls<D>, &[CoarseSource<D>]),
    lists: &NeighborLists,
    prm: &WaterParams<D>,
    dp: Real,
) -> Option<Start> {
    let n = w.len();
    let Couplings {
        edges,
        mut support,
        mut diag,
        mut away,
        mut source,
    } = couplings(w, (&vol, p0), &lists.clusters, prm);
    // walls and bodies: their share of the support (their terms vanish for q)
    let boundaries = |i: usize, f: &mut dyn FnMut(&Vect<D>, Real)| {
        let (cl, k) = (&lists.chunks[i / CHUNK], i % CHUNK);
        for &b in cl.wall(k) {
            f(&walls.pos[b as usize], walls.volume);
        }
        for &c in cl.coarse(k) {
            let c = &csrc[c as usize];
            f(&c.pos, c.vol);
        }
    };
    for i in 0..n {
        let xi = w.pos[i];
        boundaries(i, &mut |xb, vb| {
            if let Some((rij, r, dw)) = boundary_pair(prm, &xi, xb) {
                let a = 2.0 * vb * -dw / r;
                support[i] += a;
                away[i] += rij * a;
                // (p_i − p_b)/ρ_i with the walls' extrapolation p_b
                source[i] += a * prm.hydrostatic.dot(&rij);
            }
        });
    }
    let full = support.iter().copied().fold(0.0, Real::max);
    let out: Vec<Vect<D>> = away
        .iter()
        .map(|a| a.try_normalize(0.0).unwrap_or_else(Vect::<D>::zeros))
        .collect();
    let surface = free_surface(w, &support, &out, (&edges, &boundaries), prm);
    // the free surface: the missing support at q_s = −p_h(x_i + ½dp n_i), where the
    // pressure is zero
    let mut rhs = vec![0.0; n];
    for i in 0..n {
        let missing = full - support[i];
        if missing < FULL * full {
            rhs[i] = -source[i];
        }
        if surface[i] {
            let at_surface = p0[i] + w.rho[i] * prm.hydrostatic.dot(&(out[i] * (0.5 * dp)));
            diag[i] += missing / w.rho[i];
            rhs[i] = -missing / w.rho[i] * at_surface;
        }
    }
    if !surface.iter().any(|&s| s) {
        return None;
    }
    let a = Symmetric { diag, edges };
    let (q, iterations, residual) = conjugate_gradient(&a, &rhs, 1e-10, 20 * n + 100);
    Some(Start {
        pressure: q.iter().zip(p0).map(|(q, p)| p + q).collect(),
        iterations,
        residual,
    })
}

/// The water–water couplings a_ij of the start's Poisson problem, each pair once,
/// from the half lists held in the cluster lists `cp`; each particle's support Σ a,
/// the diagonal, the pull Σ a (x_i − x_j) of its neighbours (away from which its
/// support is missing) and the source −∇²p_h of the hydrostatic start `p0`.
struct Couplings<const D: usize> {
    edges: Vec<(u32, u32, Real)>,
    support: Vec<Real>,
    diag: Vec<Real>,
    away: Vec<Vect<D>>,
    source: Vec<Real>,
}

fn couplings<const D: usize>(
    w: &WaterParticles<D>,
    (vol, p0): (&impl Fn(usize) -> Real, &[Real]),
    cp: &ClusterPairs,
    prm: &WaterParams<D>,
) -> Couplings<D> {
    let n = w.len();
    let kernel = &prm.kernel;
    let cut2 = kernel.cutoff * kernel.cutoff;
    // the water–water couplings a_ij, each pair once; each particle's support Σ a and
    // the pull Σ a (x_i − x_j) of its neighbours, away from which its support is missing
    let mut edges: Vec<(u32, u32, Real)> = Vec::new();
    let mut support = vec![0.0; n];
    let mut diag = vec![0.0; n];
    let mut away = vec![Vect::<D>::zeros(); n];
    // −∇²p_h: zero for one region's hydrostatic start, ρ g η'' under a column
    // fill's surface η
    let mut source = vec![0.0; n];
    for i in 0..n {
        // i's half list: the entries j > i of its cluster's list, in ascending order
        for &j in cp.of(cp.of[i] as usize) {
            let j = j as usize;
            if j <= i {
                continue;
            }
            let rij = prm.wrap.of(w.pos[i] - w.pos[j]);
            let r2 = rij.norm_squared();
            if r2 >= cut2 || r2 == 0.0 {
                continue;
            }
            let r = r2.sqrt();
            let a = (vol(i) + vol(j)) * -kernel.dw(r) / r;
            support[i] += a;
            support[j] += a;
            away[i] += rij * a;
            away[j] -= rij * a;
            // ∇·(∇p/ρ): 1/ρ at the pair's midpoint
            let a = a * 2.0 / (w.rho[i] + w.rho[j]);
            edges.push((i as u32, j as u32, a));
            diag[i] += a;
            diag[j] += a;
            source[i] += a * (p0[i] - p0[j]);
            source[j] += a * (p0[j] - p0[i]);
        }
    }
    Couplings {
        edges,
        support,
        diag,
        away,
        source,
    }
}

/// Which particles lie at the free surface: their support (`support`, with the fullest
/// K) falls short by more than [`SURFACE_DEFICIT`], and the scan disc of Marrone et
/// al. (2010), radius h about T = x_i + h n_i with n_i (`out`) the direction the
/// support is missing in, holds no neighbour, water (the pairs `edges`) or wall and
/// body particle (`boundaries`). A gap between the water and a body's staircase
/// surface lacks as much support as a free surface, but the body's particles fill
/// its scan disc.
#[allow(clippy::type_complexity)]
fn free_surface<const D: usize>(
    w: &WaterParticles<D>,
    support: &[Real],
    out: &[Vect<D>],
    (edges, boundaries): (
        &[(u32, u32, Real)],
        &dyn Fn(usize, &mut dyn FnMut(&Vect<D>, Real)),
    ),
    prm: &WaterParams<D>,
) -> Vec<bool> {
    let full = support.iter().copied().fold(0.0, Real::max);
    let h = prm.kernel.h;
    let mut surface: Vec<bool> = support
        .iter()
        .map(|s| full - s > SURFACE_DEFICIT * full)
        .collect();
    let scan = |i: usize, x: &Vect<D>| prm.wrap.of(x - w.pos[i] - out[i] * h).norm() < h;
    for &(i, j, _) in edges {
        let (i, j) = (i as usize, j as usize);
        if surface[i] && scan(i, &w.pos[j]) {
            surface[i] = false;
        }
        if surface[j] && scan(j, &w.pos[i]) {
            surface[j] = false;
        }
    }
    for (i, s) in surface.iter_mut().enumerate() {
        if *s {
            boundaries(i, &mut |xb, _| {
                if scan(i, xb) {
                    *s = false;
                }
            });
        }
    }
    surface
}
