//! The sampling that the start checks share ([`body_overlaps`](super::body_overlaps),
//! [`placement`](super::placement)): the first point of a regular grid over a box where
//! a test holds.

use crate::numerics::math::{Real, Vect};

/// Sample points per axis (2D, 3D).
pub const PER_AXIS: [usize; 2] = [64, 20];

/// The first point, in a fixed order, of the [`PER_AXIS`] grid of cell centres over
/// the box [`lo`, `hi`] at which `hit` holds.
pub fn first<const D: usize>(
    (lo, hi): (Vect<D>, Vect<D>),
    hit: impl Fn(&Vect<D>) -> bool,
) -> Option<Vect<D>> {
    let m = PER_AXIS[D - 2];
    let step = (hi - lo) / m as Real;
    (0..m.pow(D as u32)).find_map(|n| {
        let mut p = lo;
        let mut rest = n;
        for k in 0..D {
            p[k] += ((rest % m) as Real + 0.5) * step[k];
            rest /= m;
        }
        hit(&p).then_some(p)
    })
}
