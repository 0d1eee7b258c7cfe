//! The water around a body filled to the body's true surface (issue 42).
//!
//! A lattice cut by a curved surface leaves its outermost points anywhere from half a
//! spacing to a spacing and a half off the surface, a half spacing further out on
//! average than the body's particles need (they lie half a spacing inside it,
//! [`coarse::relax`](crate::coarse::relax)). The water's density follows from its
//! continuity equation, not from the number of its neighbours, so that gap stays: the
//! body displaced more than its own volume, and a neutral disc (R/dp = 10) felt 2–5 %
//! more than its weight and rose at 17 mm/s.
//!
//! Here the water keeps every lattice point outside a body (so its count displaced is
//! the body's volume over dp^d, to the lattice's error), and the points within a band
//! around each body are relaxed by [`packing`](crate::numerics::packing)'s sweeps until evenly
//! spaced, the first layer half a spacing off the surface. The band is the kernel
//! support plus a spacing; the water beyond it stays on its lattice and holds the band
//! in. Mirror images across every solid's surface and the containers' faces stand in
//! for the solids' particles. (Packing against the bodies' own particles instead
//! changed the neutral disc's rise by under 3 %.) A
//! point whose neighbourhood is cut by the water's own edge (its kernel sum, images
//! included, under three quarters of a full lattice's) is a free surface or a region's
//! edge: it stays where it is, so that the band does not spread out of the water. A
//! point that cannot keep 0.3 dp off every solid (a wedge narrower than a spacing, as
//! under a body resting on the floor) stops where it is and is dropped: the water in a contact's gap is
//! [`water_buoyancy`](crate::interactions::water_buoyancy)'s.

use crate::geometry::start_solids::Solids;
use crate::numerics::math::{Real, Vect};
use crate::numerics::packing::{Packing, SWEEPS};

/// Move the water points `pts` near the bodies among `solids` onto the bodies' true
/// surfaces (see the module's text), lattice spacing `dp`; whether each point is kept.
pub fn conform<const D: usize>(pts: &mut [Vect<D>], solids: &Solids<D>, dp: Real) -> Vec<bool> {
    let mut kept = vec![true; pts.len()];
    if !solids.has_bodies() {
        return kept;
    }
    let packing = Packing::new(dp, D);
    let cut = packing.cutoff();
    let band = cut + dp;
    let eps = 1e-3 * dp;
    // the band (moving), and the water that holds it in (fixed)
    let (mut moving, mut fixed): (Vec<usize>, Vec<usize>) = (Vec::new(), Vec::new());
    for (i, p) in pts.iter().enumerate() {
        let s = solids.body_distance(p);
        if s < band {
            moving.push(i);
        } else if s < band + cut {
            fixed.push(i);
        }
    }
    if moving.is_empty() {
        return kept;
    }
    let images = |x: &[Vect<D>]| -> Vec<Vect<D>> {
        x.iter()
            .flat_map(|p| {
                solids
                    .near(p, cut, eps)
                    .map(|(s, n)| p - n * (2.0 * s))
                    .collect::<Vec<_>>()
            })
            .collect()
    };
    // points at the water's own edge stay
    let band_pts: Vec<Vect<D>> = moving.iter().map(|&i| pts[i]).collect();
    let mut around: Vec<Vect<D>> = fixed.iter().map(|&i| pts[i]).collect();
    let all: Vec<Vect<D>> = band_pts.iter().chain(&around).copied().collect();
    around.extend(images(&all));
    let support = packing.support(&band_pts, &around);
    let (mut free, mut edge) = (Vec::new(), Vec::new());
    for (&i, &s) in moving.iter().zip(&support) {
        if s >= 0.75 {
            free.push(i);
        } else {
            edge.push(i);
        }
    }
    fixed.extend(edge);
    let mut x: Vec<Vect<D>> = free.iter().map(|&i| pts[i]).collect();
    let mut held: Vec<Vect<D>> = fixed.iter().map(|&i| pts[i]).collect();
    held.extend(images(&held));
    let n_held = held.len();
    // a point in a wedge narrower than 0.8 dp cannot keep off both surfaces: it stops
    // where it was, and is dropped
    let mut stuck = vec![false; x.len()];
    for sweep in 0..SWEEPS {
        held.truncate(n_held);
        held.extend(images(&x));
        let force = packing.forces(&x, &held);
        for ((p, f), stuck) in x.iter_mut().zip(&force).zip(stuck.iter_mut()) {
            if *stuck {
                continue;
            }
            let was = *p;
            *p += packing.step((sweep, SWEEPS), f);
            // never closer than 0.4 dp to a surface
            let push: Vec<(Real, Vect<D>)> = solids.near(p, 0.4 * dp, eps).collect();
            for (s, n) in push {
                *p += n * (0.4 * dp - s);
            }
            if solids.near(p, 0.3 * dp, eps).next().is_some() {
                *p = was;
                *stuck = true;
            }
        }
    }
    for ((&i, p), &stuck) in free.iter().zip(&x).zip(&stuck) {
        pts[i] = *p;
        kept[i] = !stuck;
    }
    kept
}
