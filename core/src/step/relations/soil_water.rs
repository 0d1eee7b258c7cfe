//! The soil–water relation (seed 001 Eqs. 8–10): for each water particle the soil
//! particles within the kernel cut-off plus 1.5 skins, and the transpose. Its rebuild
//! rule: the lists hold until either family rebuilds its own lists or its particle
//! count changes, since each family moves at most a skin from its place at the
//! other's build, and half a skin after its own.

use crate::cross_lists::CrossLists;
use crate::math::{Real, Vect};
use crate::neighbors::CellGrid;

/// The families' list builds and particle counts a build of the relation was made at:
/// `[fine builds, water builds, fine count, water count]`.
pub type BuiltAt = [usize; 4];

/// The water–soil pairs (see the module docs).
/// A restored state keeps only the radius: its first step builds the lists.
#[derive(Clone, Default, serde::Serialize, serde::Deserialize)]
pub struct SoilWaterRelation<const D: usize> {
    #[serde(skip)]
    lists: CrossLists,
    /// Cells of the soil for the lists' build, `radius` wide.
    #[serde(skip)]
    grid: Option<CellGrid<D>>,
    radius: Real,
    #[serde(skip)]
    built_at: Option<BuiltAt>,
    #[serde(skip)]
    builds: usize,
}

impl<const D: usize> SoilWaterRelation<D> {
    /// The relation with lists of `radius`; never built yet.
    pub fn new(radius: Real) -> Self {
        SoilWaterRelation {
            radius,
            ..Default::default()
        }
    }

    /// The list radius.
    pub fn radius(&self) -> Real {
        self.radius
    }

    /// The rebuild rule (see the module docs), at the families' state `now`.
    pub fn expired(&self, now: BuiltAt) -> bool {
        self.built_at != Some(now)
    }

    /// Whether the lists were built for `fine` soil and `water` particles (their
    /// counts have not changed since).
    pub fn counts_match(&self, fine: usize, water: usize) -> bool {
        self.built_at.is_some_and(|b| b[2] == fine && b[3] == water)
    }

    /// Build the lists of the water at `water` against the soil at `soil` in the box
    /// `lo`–`hi`, at the families' state `now`.
    pub fn rebuild(
        &mut self,
        water: &[Vect<D>],
        soil: &[Vect<D>],
        (lo, hi): (&Vect<D>, &Vect<D>),
        now: BuiltAt,
    ) {
        let radius = self.radius;
        let grid = self
            .grid
            .get_or_insert_with(|| CellGrid::new(lo, hi, radius));
        self.lists.build(water, soil, grid, radius);
        self.built_at = Some(now);
        self.builds += 1;
    }

    /// The cells the soil was binned in at the last build (None before the first).
    pub fn grid(&self) -> Option<&CellGrid<D>> {
        self.grid.as_ref()
    }

    /// The soil particles near water particle `i`.
    #[inline]
    pub fn soil_near(&self, i: usize) -> &[u32] {
        self.lists.a_to_b.of(i)
    }

    /// The water particles near soil particle `j`.
    #[inline]
    pub fn water_near(&self, j: usize) -> &[u32] {
        self.lists.b_to_a.of(j)
    }

    /// Builds so far, and the pairs of the last.
    pub fn stats(&self) -> (usize, usize) {
        (self.builds, self.lists.a_to_b.idx.len())
    }
}
