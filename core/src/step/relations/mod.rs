//! The relations the step's passes run over, after SPHinXsys's inner and contact
//! relations: each owns what its lists are built from and its rebuild rule.
//!
//! | relation | owner | lists | rebuild rule |
//! |---|---|---|---|
//! | fine–fine, water–water | [`InnerRelation`] | the family's own pairs, j > i | 2 (d_max + ½ Δt v_max) > skin |
//! | fine–wall, water–wall | [`WallRelation`] | wall particles near each particle | d + (largest wall displacement) > skin |
//! | fine–coarse, water–coarse | [`CoarseRelation`] | coarse particles near each particle | d + (largest coarse displacement) > skin, or their count changed |
//! | soil–water | [`SoilWaterRelation`] | soil near each water particle, and the transpose | either family rebuilt, or a count changed |
//!
//! A family's inner, wall and coarse relations are built together, in one sweep over
//! its cells, into fused per-chunk lists ([`ChunkList`](crate::numerics::neighbors::ChunkList)):
//! a pass that runs over several of them reads each particle's record once. Each pass
//! reads a relation through its own accessor (`inner`, `wall`, `coarse`).

mod coarse;
mod inner;
mod soil_water;
mod wall;

pub use coarse::CoarseRelation;
pub use inner::InnerRelation;
pub use soil_water::SoilWaterRelation;
pub use wall::WallRelation;

/// The relations between families, by name.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Relation {
    FineFine,
    FineWall,
    FineCoarse,
    WaterWater,
    WaterWall,
    WaterCoarse,
    SoilWater,
}

impl Relation {
    /// Its name in summaries (`fine-fine`, …).
    pub fn name(self) -> &'static str {
        match self {
            Relation::FineFine => "fine-fine",
            Relation::FineWall => "fine-wall",
            Relation::FineCoarse => "fine-coarse",
            Relation::WaterWater => "water-water",
            Relation::WaterWall => "water-wall",
            Relation::WaterCoarse => "water-coarse",
            Relation::SoilWater => "soil-water",
        }
    }
}

/// What one relation's lists hold: builds so far and pairs at the last build.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, serde::Serialize)]
pub struct RelationStats {
    pub builds: usize,
    pub pairs: usize,
}
