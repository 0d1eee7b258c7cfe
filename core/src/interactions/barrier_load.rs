//! Barrier loads: the reaction of every fine–wall pair on a barrier's wall particle,
//! summed per chunk into the load slot of its barrier panel (seed 000 Eq. (50) read
//! for walls: the wall receives −m_i a_iw).

use crate::geometry::walls::Walls;
use crate::numerics::load::Load;
use crate::numerics::math::{to3, Real, Vect};

/// Add the reaction −m_i a of one fine–wall pair on wall particle `w` to the slot of
/// its barrier panel in `slots` (nothing when `w` belongs to no barrier); the moment is
/// taken about the barrier's reference point.
#[inline(always)]
pub fn add_reaction<const D: usize>(
    walls: &Walls<D>,
    w: usize,
    a: &Vect<D>,
    mass: Real,
    slots: &mut [Load],
) {
    if let Some(b) = walls.objects[walls.object[w] as usize].barrier {
        let f = to3(a) * (-mass);
        let arm = to3(&(walls.pos[w] - walls.barriers[b].reference));
        let s = walls.load_slot(b, w);
        slots[s].force += f;
        slots[s].moment += arm.cross(&f);
    }
}
