//! Barrier panels: a barrier split into a grid of panels whose loads are reported
//! separately (scene key `panels`). Each wall particle of a paneled barrier belongs to
//! one panel, chosen from its initial position; the barrier's load is the sum of its
//! panels' loads, in a fixed order.

use crate::geometry::walls::{Barrier, Walls};
use crate::numerics::load::Load;
use crate::numerics::math::{Real, Vect};

/// Axes a barrier's panels split, in order: all axes but the thinnest (the
/// barrier's thickness), ascending.
pub fn panel_axes<const D: usize>(lo: &Vect<D>, hi: &Vect<D>) -> Vec<usize> {
    let thin = (0..D)
        .min_by(|&a, &b| (hi[a] - lo[a]).total_cmp(&(hi[b] - lo[b])))
        .unwrap_or(0);
    (0..D).filter(|&a| a != thin).collect()
}

impl<const D: usize> Walls<D> {
    /// Split barrier `b` into `counts` panels along its [`panel_axes`] (one count per
    /// axis; D − 1 counts). Must be called once per barrier, in barrier order, after
    /// all wall particles exist.
    pub fn split_panels(&mut self, b: usize, counts: &[usize]) {
        if self.panel.len() != self.pos.len() {
            self.panel.resize(self.pos.len(), 0);
        }
        let object = self.barriers[b].object as u16;
        let mine: Vec<usize> = (0..self.pos.len())
            .filter(|&w| self.object[w] == object)
            .collect();
        let mut lo = Vect::<D>::repeat(Real::INFINITY);
        let mut hi = Vect::<D>::repeat(Real::NEG_INFINITY);
        for &w in &mine {
            lo = lo.inf(&self.pos[w]);
            hi = hi.sup(&self.pos[w]);
        }
        let bar = &mut self.barriers[b];
        bar.panels = counts.to_vec();
        bar.panel_axes = panel_axes(&lo, &hi);
        bar.panel_lo = lo;
        bar.panel_hi = hi;
        for &w in &mine {
            self.panel[w] = self.barriers[b].panel_of(&self.pos[w]) as u32;
        }
    }
}

impl<const D: usize> Barrier<D> {
    /// Panel holding point `x` (in the barrier's initial frame): the grid cell of its
    /// projection on the panel axes, clamped to the grid. 0 without panels.
    pub fn panel_of(&self, x: &Vect<D>) -> usize {
        let mut index = 0;
        for (&a, &n) in self.panel_axes.iter().zip(&self.panels) {
            let span = (self.panel_hi[a] - self.panel_lo[a]).max(Real::MIN_POSITIVE);
            let f = ((x[a] - self.panel_lo[a]) / span * n as Real).max(0.0);
            index = index * n + (f as usize).min(n - 1);
        }
        index
    }
}

/// Split every barrier with a `panels` key, then number the load slots in barrier
/// order.
pub fn split_scene_panels<const D: usize>(walls: &mut Walls<D>, scene: &crate::scene::Scene) {
    for spec in &scene.barriers {
        if let Some(counts) = &spec.panels {
            if let Some(b) = walls.barriers.iter().position(|x| x.name == spec.name) {
                walls.split_panels(b, counts);
            }
        }
    }
    let mut slot = 0;
    for b in 0..walls.barriers.len() {
        walls.barriers[b].slot0 = slot;
        slot += walls.panel_count(b);
    }
}

/// Sum per-chunk slot loads into per-slot loads, then each barrier's slots into its
/// load, in a fixed order (the result does not depend on the thread count).
pub fn sum_slots<const D: usize>(
    walls: &Walls<D>,
    chunk_loads: &[Load],
    slots_per_chunk: usize,
    slot_loads: &mut Vec<Load>,
    step_loads: &mut [Load],
) {
    let chunks = chunk_loads.len() / slots_per_chunk.max(1);
    slot_loads.resize(walls.load_slots(), Load::default());
    for (s, l) in slot_loads.iter_mut().enumerate() {
        *l = Load::default();
        for c in 0..chunks {
            l.add(&chunk_loads[c * slots_per_chunk + s]);
        }
    }
    for (b, l) in step_loads.iter_mut().enumerate() {
        let bar = &walls.barriers[b];
        *l = slot_loads[bar.slot0];
        for s in 1..walls.panel_count(b) {
            l.add(&slot_loads[bar.slot0 + s]);
        }
    }
}
