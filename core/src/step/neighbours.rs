//! The neighbour stage: Verlet lists of fine particles with their fine, wall and
//! coarse neighbours, rebuilt (particles re-sorted by cell) once the motion since the
//! last build may have used up the skin.

use super::Stepper;
use crate::fine::source::pack;
use crate::math::Real;
use crate::world::World;

impl<const D: usize> Stepper<D> {
    /// Rebuild the lists if the skin may be used up over a step of `dt`; true if it
    /// did.
    pub(super) fn refresh_lists(&mut self, world: &mut World<D>, dt: Real) -> bool {
        if !self.needs_rebuild(world, dt) {
            return false;
        }
        self.rebuild(world);
        pack(&world.fine, &world.materials, &mut self.src);
        true
    }

    fn needs_rebuild(&self, world: &World<D>, dt: Real) -> bool {
        if self.lists.chunks.is_empty() && !world.fine.is_empty() {
            return true;
        }
        if world.fine.is_empty() {
            return false;
        }
        let fine = self.max_disp + 0.5 * dt * self.vmax;
        let wall = self.walls.moved_since_build(&world.walls);
        // infinite when the coarse particles' count changed
        let coarse = self.coarse_bins.moved_since_build(&self.csrc);
        2.0 * fine > self.params.skin
            || fine + wall > self.params.skin
            || fine + coarse > self.params.skin
    }

    /// Re-sort particles by cell and rebuild the Verlet lists.
    fn rebuild(&mut self, world: &mut World<D>) {
        self.fine_grid.bin(&world.fine.pos);
        self.order.clear();
        self.order.extend_from_slice(self.fine_grid.order());
        world.fine.permute(&self.order, &mut self.permute);
        self.fine_grid.bin(&world.fine.pos);
        self.at_build.mark(&world.fine.pos);
        self.walls.refresh(&world.walls);
        self.coarse_bins.refresh(&self.csrc);
        let radius = self.kernel.cutoff + self.params.skin;
        self.lists.build(
            &world.fine.pos,
            &self.fine_grid,
            self.walls.binned(&world.walls),
            self.coarse_bins.binned(),
            radius,
            &crate::periodic::Open,
        );
        self.reactions
            .resize_with(self.lists.chunks.len(), Vec::new);
        self.max_disp = 0.0;
    }
}
