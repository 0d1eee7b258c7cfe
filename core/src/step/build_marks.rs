//! What a family's neighbour lists remember of their last build: the particle
//! positions in single precision (with the bound on their rounding) and the walls,
//! binned and re-binned only once a wall has moved. The fine and the water lists keep
//! one each.

use crate::math::{Real, Vect};
use crate::neighbors::CellGrid;
use crate::walls::Walls;
use nalgebra::SVector;
use rayon::prelude::*;

/// Positions at the last list build, in single precision: only displacements since
/// then are read from them, and `round_off` bounds the rounding.
#[derive(Clone, Default, serde::Serialize, serde::Deserialize)]
pub struct PositionMarks<const D: usize> {
    pub pos: Vec<SVector<f32, D>>,
    /// Largest rounding error of a position stored in `pos` (m).
    pub round_off: Real,
}

impl<const D: usize> PositionMarks<D> {
    /// Mark `pos` as the positions of this build.
    pub fn mark(&mut self, pos: &[Vect<D>]) {
        self.pos.clear();
        self.pos.par_extend(pos.par_iter().map(|x| x.cast::<f32>()));
        // |x − (f32)x| ≤ ½ ulp ≤ |x| ε_f32 / 2 per component
        let reach = pos.par_iter().map(|x| x.amax()).reduce(|| 0.0, Real::max);
        self.round_off = reach * (f32::EPSILON as Real) * (D as Real).sqrt();
    }

    pub fn bytes(&self) -> usize {
        self.pos.capacity() * std::mem::size_of::<SVector<f32, D>>()
    }
}

/// The wall particles binned for a family's lists.
#[derive(Clone, serde::Serialize, serde::Deserialize)]
pub struct WallBins<const D: usize> {
    /// Binned when the walls moved since the last build: serialised in full.
    pub grid: CellGrid<D>,
    binned: bool,
    /// Each wall object's displacement at the last build.
    disp_at_build: Vec<Vect<D>>,
}

impl<const D: usize> WallBins<D> {
    pub fn new(grid: CellGrid<D>) -> Self {
        WallBins {
            grid,
            binned: false,
            disp_at_build: Vec::new(),
        }
    }

    /// Largest rigid displacement of any wall object since the last build.
    pub fn moved_since_build(&self, walls: &Walls<D>) -> Real {
        walls.max_displacement_since(&self.disp_at_build)
    }

    /// Bin the walls if they are not binned yet or moved since the last build, and mark
    /// their displacements for this build.
    pub fn refresh(&mut self, walls: &Walls<D>) {
        let moved = walls
            .objects
            .iter()
            .zip(&self.disp_at_build)
            .any(|(o, d)| o.displacement != *d);
        if !self.binned || moved {
            self.grid.bin(&walls.pos);
            self.binned = true;
        }
        self.disp_at_build.clear();
        self.disp_at_build
            .extend(walls.objects.iter().map(|o| o.displacement));
    }
}
