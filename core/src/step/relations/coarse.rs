//! The coarse relation of an SPH family (fine–coarse, water–coarse): the coarse
//! particles binned for the family's lists at their half-step positions of the last
//! build, and its rebuild rule (the family's and a coarse particle's displacements
//! since the build together within the skin).

use crate::interactions::fine_coarse::CoarseSource;
use crate::numerics::math::{Real, Vect};
use crate::numerics::neighbors::{Binned, CellGrid};

/// A family's relation with the coarse particles, binned at their half-step positions
/// of the last build.
#[derive(Clone, serde::Serialize, serde::Deserialize)]
pub struct CoarseRelation<const D: usize> {
    /// Binned afresh at every build: a serialised state keeps only its geometry.
    #[serde(with = "crate::numerics::neighbors::geometry_only")]
    grid: CellGrid<D>,
    /// Positions at the last build.
    at_build: Vec<Vect<D>>,
}

impl<const D: usize> CoarseRelation<D> {
    pub fn new(grid: CellGrid<D>) -> Self {
        CoarseRelation {
            grid,
            at_build: Vec::new(),
        }
    }

    /// The cells the coarse particles are binned in.
    pub fn grid(&self) -> &CellGrid<D> {
        &self.grid
    }

    /// Coarse particles at the last build (the lists' coarse entries index them).
    pub fn built_count(&self) -> usize {
        self.at_build.len()
    }

    /// Largest displacement of a coarse particle of `csrc` since the last build;
    /// infinite when the count changed.
    pub fn moved_since_build(&self, csrc: &[CoarseSource<D>]) -> Real {
        if self.at_build.len() != csrc.len() {
            return Real::INFINITY;
        }
        csrc.iter()
            .zip(&self.at_build)
            .map(|(c, b)| (c.pos - b).norm_squared())
            .fold(0.0, Real::max)
            .sqrt()
    }

    /// The rebuild rule: a family particle that moved `moved` and a coarse particle may
    /// have closed the skin (always, once the coarse particles' count changed).
    pub fn expired(&self, moved: Real, csrc: &[CoarseSource<D>], skin: Real) -> bool {
        moved + self.moved_since_build(csrc) > skin
    }

    /// Bin `csrc` for this build.
    pub fn refresh(&mut self, csrc: &[CoarseSource<D>]) {
        self.at_build.clear();
        self.at_build.extend(csrc.iter().map(|c| c.pos));
        if self.at_build.is_empty() {
            // nothing to bin: no cells held (the lists look nothing up in an empty grid)
            self.grid.release();
        } else {
            self.grid.bin(&self.at_build);
        }
    }

    /// Bytes of the binned grid and the positions at the last build.
    pub fn bytes(&self) -> usize {
        self.grid.bytes() + self.at_build.capacity() * std::mem::size_of::<Vect<D>>()
    }

    /// The binned coarse particles, for the lists.
    pub fn binned(&self) -> Binned<'_, D> {
        Binned {
            pos: &self.at_build,
            grid: &self.grid,
        }
    }
}
