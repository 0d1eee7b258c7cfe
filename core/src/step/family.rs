//! The skeleton every SPH family's stepper shares (the fine grains and the water): its
//! three relations (inner, wall, coarse: [`relations`](super::relations)) with their
//! fused Verlet lists and rebuild rules, the step's largest speed and displacement, the
//! barrier loads of its pair passes, its particle order, and the one finalize-and-guard
//! loop of seed 000 Eq. (56). A family's stepper is a thin layer over it: its packed
//! sources, its sweeps' buffers, and what its guard checks beyond the common set.

use super::relations::{CoarseRelation, InnerRelation, Relation, RelationStats, WallRelation};
use crate::fine::material::DensityFloor;
use crate::fine::state::FineParticles;
use crate::geometry::walls::Walls;
use crate::interactions::fine_coarse::CoarseSource;
use crate::numerics::guard::{check, Blowup, ChunkFailure, Family};
use crate::numerics::load::Load;
use crate::numerics::math::{Real, Vect};
use crate::numerics::neighbors::{CellGrid, NeighborLists, CHUNK};
use crate::numerics::periodic::Wrap;
use crate::numerics::permute::PermuteScratch;
use crate::water::state::WaterParticles;
use rayon::prelude::*;

/// What the skeleton needs of a family's particle arrays.
pub trait FamilyParticles<const D: usize> {
    fn positions(&self) -> &[Vect<D>];
    fn positions_mut(&mut self) -> &mut [Vect<D>];
    /// Reorder every array by `order` (new index k holds old particle `order[k]`).
    fn reorder(&mut self, order: &[u32], scratch: &mut PermuteScratch);
}

impl<const D: usize> FamilyParticles<D> for FineParticles<D> {
    fn positions(&self) -> &[Vect<D>] {
        &self.pos
    }
    fn positions_mut(&mut self) -> &mut [Vect<D>] {
        &mut self.pos
    }
    fn reorder(&mut self, order: &[u32], scratch: &mut PermuteScratch) {
        self.permute(order, scratch);
    }
}

impl<const D: usize> FamilyParticles<D> for WaterParticles<D> {
    fn positions(&self) -> &[Vect<D>] {
        &self.pos
    }
    fn positions_mut(&mut self) -> &mut [Vect<D>] {
        &mut self.pos
    }
    fn reorder(&mut self, order: &[u32], scratch: &mut PermuteScratch) {
        self.permute(order, scratch);
    }
}

/// A family's particle arrays that Eq. (56) closes the step on.
pub struct Closing<'a, const D: usize> {
    pub pos: &'a mut [Vect<D>],
    pub rho: &'a mut [Real],
    pub vel: &'a [Vect<D>],
    pub drho: &'a [Real],
    /// The soil's least densities; None: no floor (water).
    pub floor: Option<DensityFloor<'a>>,
}

/// The relations, lists, loads and scratch of one SPH family (see the module docs).
#[derive(Clone, serde::Serialize, serde::Deserialize)]
pub struct FamilyLists<const D: usize> {
    /// The family's relation with itself (fine–fine or water–water).
    inner: InnerRelation<D>,
    /// Its relation with the walls (fine–wall or water–wall).
    walls: WallRelation<D>,
    /// Its relation with the coarse particles (fine–coarse or water–coarse).
    coarse: CoarseRelation<D>,
    /// The three relations' lists, fused per chunk.
    pub lists: NeighborLists,
    /// The family's load on each barrier during the last step.
    pub step_loads: Vec<Load>,
    /// The same per barrier panel (`Walls::load_slot`).
    pub slot_loads: Vec<Load>,
    /// Scratch: written in full by every step before it is read (not serialised).
    #[serde(skip)]
    chunk_loads: Vec<Load>,
    #[serde(skip)]
    permute: PermuteScratch,
    #[serde(skip)]
    order: Vec<u32>,
    #[serde(skip)]
    failures: Vec<(Real, Real, ChunkFailure)>,
    /// Per chunk: the family's reactions on coarse particles in the last pass.
    #[serde(skip)]
    reactions: Vec<Vec<(u32, Vect<D>)>>,
}

impl<const D: usize> FamilyLists<D> {
    /// Lists over cells of `grid` with radius `radius` (kernel cut-off plus `skin`);
    /// `walls` bins the walls the family sees. `barriers` and `slots` size the loads.
    pub fn new(
        grid: CellGrid<D>,
        walls: WallRelation<D>,
        (radius, skin): (Real, Real),
        (barriers, slots): (usize, usize),
    ) -> Self {
        FamilyLists {
            coarse: CoarseRelation::new(grid.clone()),
            inner: InnerRelation::new(grid, radius, skin),
            walls,
            lists: NeighborLists::default(),
            step_loads: vec![Load::default(); barriers],
            slot_loads: vec![Load::default(); slots],
            chunk_loads: Vec::new(),
            permute: PermuteScratch::default(),
            order: Vec::new(),
            failures: Vec::new(),
            reactions: Vec::new(),
        }
    }

    /// The cells the family was binned in at the last list build.
    pub fn grid(&self) -> &CellGrid<D> {
        &self.inner.grid
    }

    /// Largest speed at the end of the last step.
    pub fn vmax(&self) -> Real {
        self.inner.vmax()
    }

    /// The family's three relations (`names`: inner, wall, coarse) with their builds and
    /// pairs.
    pub fn relation_stats(&self, names: [Relation; 3]) -> [(Relation, RelationStats); 3] {
        let pairs = self.lists.pairs();
        std::array::from_fn(|k| {
            let stats = RelationStats {
                builds: self.lists.builds,
                pairs: pairs[k],
            };
            (names[k], stats)
        })
    }

    /// Whether these lists, restored from a state, fit the family of `n` particles and
    /// `walls` wall particles, and `template`, the same family's lists as the scene
    /// builds them: the same cell grids, radius and skin; wall bins of the wall
    /// particles; and lists (unless gone, to be rebuilt at the next step) of `n`
    /// particles marked at their build, whose coarse entries index the coarse
    /// particles of that build. Says which part does not.
    pub fn restored_fits(
        &self,
        template: &Self,
        n: usize,
        walls: usize,
    ) -> Result<(), &'static str> {
        let (i, t) = (&self.inner, &template.inner);
        if !i.grid.same_geometry(&t.grid)
            || !self.coarse.grid().same_geometry(template.coarse.grid())
            || !self.walls.grid.same_geometry(&template.walls.grid)
        {
            return Err("cell grids");
        }
        if i.radius.to_bits() != t.radius.to_bits() || i.skin.to_bits() != t.skin.to_bits() {
            return Err("list radius");
        }
        if !self.walls.grid.contents_fit(walls) {
            return Err("wall bins");
        }
        if self.lists.chunks.is_empty() {
            return Ok(());
        }
        let fits = i.marks.pos.len() == n && self.lists.fit(n, walls, self.coarse.built_count());
        if !fits {
            return Err("neighbour lists");
        }
        Ok(())
    }

    /// [`InnerRelation::motion_in_range`] of the family's relation with itself.
    pub fn motion_in_range(&self, max_speed: Real) -> bool {
        self.inner.motion_in_range(max_speed)
    }

    /// Forget the lists: the next step rebuilds them (particles came or went).
    pub fn invalidate(&mut self) {
        self.lists.chunks.clear();
    }

    /// Bytes of the lists, marks and grids.
    pub fn bytes(&self) -> usize {
        self.lists.bytes()
            + self.inner.bytes()
            + self.order.capacity() * 4
            + self.walls.grid.bytes()
            + self.coarse.bytes()
    }

    /// Whether the lists must be rebuilt before a step of `dt` of `n` particles: they
    /// are gone (never built, or particles came or went) while there are particles, or
    /// one of the three relations' rules says so (the motion of the particles, the
    /// walls or the coarse particles `csrc` since the build may have used up the skin).
    pub fn needs_rebuild(
        &self,
        n: usize,
        walls: &Walls<D>,
        csrc: &[CoarseSource<D>],
        dt: Real,
    ) -> bool {
        if n == 0 {
            return false;
        }
        if self.lists.chunks.is_empty() {
            return true;
        }
        let (moved, skin) = (self.inner.moved(dt), self.inner.skin);
        self.inner.expired(moved)
            || self.walls.expired(moved, walls, skin)
            || self.coarse.expired(moved, csrc, skin)
    }

    /// Wrap the particles back into the period (if `wrap` has one), re-sort them by
    /// cell and rebuild the lists with their wall and coarse neighbours; pairs are
    /// separated by their minimum image across the period.
    pub fn rebuild<P: FamilyParticles<D>>(
        &mut self,
        p: &mut P,
        walls: &Walls<D>,
        csrc: &[CoarseSource<D>],
        wrap: &Wrap,
    ) {
        if let Some(period) = wrap {
            p.positions_mut()
                .par_iter_mut()
                .for_each(|x| period.wrap_point(x));
        }
        self.inner.grid.bin(p.positions());
        self.order.clear();
        self.order.extend_from_slice(self.inner.grid.order());
        p.reorder(&self.order, &mut self.permute);
        self.inner.mark(p.positions());
        self.walls.refresh(walls);
        self.coarse.refresh(csrc);
        self.lists.build(
            p.positions(),
            &self.inner.grid,
            self.walls.binned(walls),
            self.coarse.binned(),
            self.inner.radius,
            wrap,
        );
        self.reactions
            .resize_with(self.lists.chunks.len(), Vec::new);
    }

    /// Size the per-chunk loads and reactions for a pass over the lists (a restored
    /// state has none yet); returns the load slots per chunk.
    pub fn prepare_pass(&mut self, walls: &Walls<D>) -> usize {
        let nbs = walls.load_slots().max(1);
        self.chunk_loads
            .resize(self.lists.chunks.len() * nbs, Load::default());
        self.reactions
            .resize_with(self.lists.chunks.len(), Vec::new);
        nbs
    }

    /// The lists a pass runs over, and the per-chunk loads and coarse reactions it
    /// writes.
    #[allow(clippy::type_complexity)]
    pub fn pass_outputs(&mut self) -> (&NeighborLists, &mut [Load], &mut [Vec<(u32, Vect<D>)>]) {
        (&self.lists, &mut self.chunk_loads, &mut self.reactions)
    }

    /// The coarse reactions of the last pass, per chunk.
    pub fn reactions(&self) -> &[Vec<(u32, Vect<D>)>] {
        &self.reactions
    }

    /// The pass's per-chunk loads summed into the family's panel and barrier loads.
    pub fn sum_loads(&mut self, walls: &Walls<D>) {
        let nbs = walls.load_slots().max(1);
        crate::geometry::panels::sum_slots(
            walls,
            &self.chunk_loads,
            nbs,
            &mut self.slot_loads,
            &mut self.step_loads,
        );
    }

    /// Seed 000 Eq. (56): x and ρ to the end of the step by `half`, ρ then held at its
    /// floor (if any); each chunk records its largest speed and displacement since the
    /// list build, and its first failing particle (`more(i)`: the family's own check of
    /// particle i, after the common ones, on the density before the floor).
    pub fn close_step(
        &mut self,
        c: Closing<'_, D>,
        half: Real,
        max_speed: Real,
        more: impl Fn(usize) -> Option<(&'static str, Real)> + Sync,
    ) {
        let marks = &self.inner.marks;
        let floor = c.floor;
        c.pos
            .par_chunks_mut(CHUNK)
            .zip(c.rho.par_chunks_mut(CHUNK))
            .zip(c.vel.par_chunks(CHUNK))
            .zip(c.drho.par_chunks(CHUNK))
            .enumerate()
            .map(|(c, (((x, r), v), d))| {
                let mut vmax2: Real = 0.0;
                let mut disp2: Real = 0.0;
                let mut fail: ChunkFailure = None;
                for k in 0..x.len() {
                    let i = c * CHUNK + k;
                    let (v2, d2) = marks.close_step(i, (&mut x[k], &mut r[k]), (&v[k], d[k]), half);
                    vmax2 = vmax2.max(v2);
                    disp2 = disp2.max(d2);
                    if fail.is_none() {
                        // |dρ/dt| Δt / ρ over the step
                        let change = (d[k] * 2.0 * half / r[k]).abs();
                        fail = check(i, (v2, &x[k]), (r[k], change), || more(i), max_speed);
                    }
                    if let Some(f) = &floor {
                        f.hold(i, &mut r[k]);
                    }
                }
                (vmax2, disp2, fail)
            })
            .collect_into_vec(&mut self.failures);
    }

    /// Stop on the first failing particle of the step (`ids`, `pos`: the family's
    /// arrays; `at`: step and time); otherwise keep the step's largest speed and
    /// displacement for Δt and the skin, and return the speed.
    pub fn guard(
        &mut self,
        family: Family,
        (ids, pos): (&[u32], &[Vect<D>]),
        at: (u64, Real),
        max_speed: Real,
    ) -> Result<Real, Blowup> {
        let (vmax2, disp2) = crate::numerics::guard::reduce(&self.failures).map_err(|f| {
            let x = pos[f.0].iter().copied().collect();
            Blowup::of_particle(at, family, ids[f.0], x, f, max_speed)
        })?;
        Ok(self.inner.end_step(vmax2, disp2))
    }
}
