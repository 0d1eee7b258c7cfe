//! The wall relation of an SPH family (fine–wall, water–wall): the wall particles
//! binned for the family's lists (re-binned only once a wall has moved; the water's
//! leave permeable walls out), and its rebuild rule (the family's and a wall's
//! displacements since the build together within the skin).

use crate::geometry::walls::Walls;
use crate::numerics::math::{Real, Vect};
use crate::numerics::neighbors::{Binned, CellGrid};

/// A family's relation with the walls, binned for its lists.
#[derive(Clone, serde::Serialize, serde::Deserialize)]
pub struct WallRelation<const D: usize> {
    /// Binned when the walls moved since the last build: serialised in full.
    pub grid: CellGrid<D>,
    binned: bool,
    /// Each wall object's displacement at the last build.
    disp_at_build: Vec<Vect<D>>,
    /// The water's bins: permeable walls are left out.
    #[serde(default)]
    water: bool,
    /// The wall positions the lists see when some are left out (those far away).
    #[serde(skip)]
    masked: Vec<Vect<D>>,
}

impl<const D: usize> WallRelation<D> {
    pub fn new(grid: CellGrid<D>) -> Self {
        WallRelation {
            grid,
            binned: false,
            disp_at_build: Vec::new(),
            water: false,
            masked: Vec::new(),
        }
    }

    /// The bins of the water's lists, which leave permeable walls out.
    pub fn for_water(grid: CellGrid<D>) -> Self {
        WallRelation {
            water: true,
            ..Self::new(grid)
        }
    }

    /// Largest rigid displacement of any wall object since the last build.
    pub fn moved_since_build(&self, walls: &Walls<D>) -> Real {
        walls.max_displacement_since(&self.disp_at_build)
    }

    /// The rebuild rule: a family particle that moved `moved` and a wall object may
    /// have closed the skin.
    pub fn expired(&self, moved: Real, walls: &Walls<D>, skin: Real) -> bool {
        moved + self.moved_since_build(walls) > skin
    }

    /// The binned walls of `walls`, for the lists.
    pub fn binned<'a>(&'a self, walls: &'a Walls<D>) -> Binned<'a, D> {
        Binned {
            pos: if self.masked.is_empty() {
                &walls.pos
            } else {
                &self.masked
            },
            grid: &self.grid,
        }
    }

    /// Bin the walls if they are not binned yet or moved since the last build, and mark
    /// their displacements for this build.
    pub fn refresh(&mut self, walls: &Walls<D>) {
        let moved = walls
            .objects
            .iter()
            .zip(&self.disp_at_build)
            .any(|(o, d)| o.displacement != *d);
        // a restored state has no mask yet
        let unmasked = self.water && walls.any_permeable() && self.masked.len() != walls.len();
        if !self.binned || moved || unmasked {
            if self.water && walls.any_permeable() {
                // a permeable wall's particles lie far away for the water's lists
                let far = Vect::<D>::repeat(1e30);
                self.masked.clear();
                self.masked
                    .extend(walls.pos.iter().zip(&walls.object).map(|(x, &o)| {
                        if walls.objects[o as usize].permeable {
                            far
                        } else {
                            *x
                        }
                    }));
                self.grid.bin(&self.masked);
            } else {
                self.grid.bin(&walls.pos);
            }
            self.binned = true;
        }
        self.disp_at_build.clear();
        self.disp_at_build
            .extend(walls.objects.iter().map(|o| o.displacement));
    }
}
