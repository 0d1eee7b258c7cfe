//! What a family's neighbour lists remember of their last build: the particle
//! positions in single precision (with the bound on their rounding), the walls, binned
//! and re-binned only once a wall has moved, and the coarse particles, binned at their
//! half-step positions. The fine and the water lists keep one of each.

use crate::interactions::fine_coarse::CoarseSource;
use crate::math::{Real, Vect};
use crate::neighbors::{Binned, CellGrid};
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

    /// Eq. (56) for one particle: x and ρ to the end of the step by `half` with v and
    /// dρ/dt; returns |v|² and the squared displacement since the build of particle
    /// `k`.
    #[inline(always)]
    pub fn close_step(
        &self,
        k: usize,
        (x, rho): (&mut Vect<D>, &mut Real),
        (v, drho): (&Vect<D>, Real),
        half: Real,
    ) -> (Real, Real) {
        *x += v * half;
        *rho += drho * half;
        (
            v.norm_squared(),
            (*x - self.pos[k].cast::<Real>()).norm_squared(),
        )
    }
}

/// The coarse particles binned for a family's lists, at their half-step positions of
/// the last build.
#[derive(Clone, serde::Serialize, serde::Deserialize)]
pub struct CoarseBins<const D: usize> {
    /// Binned afresh at every build: a serialised state keeps only its geometry.
    #[serde(with = "crate::neighbors::geometry_only")]
    grid: CellGrid<D>,
    /// Positions at the last build.
    at_build: Vec<Vect<D>>,
}

impl<const D: usize> CoarseBins<D> {
    pub fn new(grid: CellGrid<D>) -> Self {
        CoarseBins {
            grid,
            at_build: Vec::new(),
        }
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

    /// Bin `csrc` for this build.
    pub fn refresh(&mut self, csrc: &[CoarseSource<D>]) {
        self.at_build.clear();
        self.at_build.extend(csrc.iter().map(|c| c.pos));
        self.grid.bin(&self.at_build);
    }

    /// The binned coarse particles, for the lists.
    pub fn binned(&self) -> Binned<'_, D> {
        Binned {
            pos: &self.at_build,
            grid: &self.grid,
        }
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
    /// The water's bins: permeable walls are left out.
    #[serde(default)]
    water: bool,
    /// The wall positions the lists see when some are left out (those far away).
    #[serde(skip)]
    masked: Vec<Vect<D>>,
}

impl<const D: usize> WallBins<D> {
    pub fn new(grid: CellGrid<D>) -> Self {
        WallBins {
            grid,
            binned: false,
            disp_at_build: Vec::new(),
            water: false,
            masked: Vec::new(),
        }
    }

    /// The bins of the water's lists, which leave permeable walls out.
    pub fn for_water(grid: CellGrid<D>) -> Self {
        WallBins {
            water: true,
            ..Self::new(grid)
        }
    }

    /// Largest rigid displacement of any wall object since the last build.
    pub fn moved_since_build(&self, walls: &Walls<D>) -> Real {
        walls.max_displacement_since(&self.disp_at_build)
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
