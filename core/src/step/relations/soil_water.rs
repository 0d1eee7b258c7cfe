//! The soil–water relation (seed 001 Eqs. 8–10): for each water particle the soil
//! particles within the kernel cut-off plus 1.5 skins, and the transpose. Its rebuild
//! rule: the lists hold until either family rebuilds its own lists or its particle
//! count changes, since each family moves at most a skin from its place at the
//! other's build, and half a skin after its own.

use crate::numerics::cross_lists::CrossLists;
use crate::numerics::math::{Real, Vect};
use crate::numerics::neighbors::CellGrid;

/// The families' list builds and particle counts a build of the relation was made at:
/// `[fine builds, water builds, fine count, water count]`.
pub type BuiltAt = [usize; 4];

/// The water–soil pairs (see the module docs).
/// A restored state keeps the radius and the grid's geometry: its first step builds the
/// lists.
#[derive(Clone, serde::Serialize, serde::Deserialize)]
pub struct SoilWaterRelation<const D: usize> {
    #[serde(skip)]
    lists: CrossLists,
    /// Cells of the soil for the lists' build, `radius` wide (binned at every build).
    #[serde(with = "crate::numerics::neighbors::geometry_only")]
    grid: CellGrid<D>,
    radius: Real,
    #[serde(skip)]
    built_at: Option<BuiltAt>,
    #[serde(skip)]
    builds: usize,
}

impl<const D: usize> SoilWaterRelation<D> {
    /// Whether `other` has this relation's radius and grid geometry, bit for bit.
    pub fn same_geometry(&self, other: &Self) -> bool {
        self.radius.to_bits() == other.radius.to_bits() && self.grid.same_geometry(&other.grid)
    }

    /// The relation with lists of `radius` over the box `lo`–`hi`; never built yet.
    pub fn new(radius: Real, (lo, hi): (&Vect<D>, &Vect<D>)) -> Self {
        SoilWaterRelation {
            lists: CrossLists::default(),
            grid: CellGrid::new(lo, hi, radius),
            radius,
            built_at: None,
            builds: 0,
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

    /// Build the lists of the water at `water` against the soil at `soil`, at the
    /// families' state `now`.
    pub fn rebuild(&mut self, water: &[Vect<D>], soil: &[Vect<D>], now: BuiltAt) {
        self.lists.build(water, soil, &mut self.grid, self.radius);
        self.built_at = Some(now);
        self.builds += 1;
    }

    /// The cells the soil was binned in at the last build.
    pub fn grid(&self) -> &CellGrid<D> {
        &self.grid
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
