//! The inner relation of an SPH family (fine–fine, water–water): its cell grid, the
//! positions of its last list build, the skin and the list radius, and its rebuild
//! rule (seed 000 §4.3, Verlet lists with a skin): a pair can close by at most twice
//! the largest displacement since the build, so the lists hold while that stays
//! within the skin.

use crate::numerics::math::{Real, Vect};
use crate::numerics::neighbors::CellGrid;
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

/// A family's relation with itself (see the module docs).
#[derive(Clone, serde::Serialize, serde::Deserialize)]
pub struct InnerRelation<const D: usize> {
    /// Binned afresh at every list build: a serialised state keeps only its geometry.
    #[serde(with = "crate::numerics::neighbors::geometry_only")]
    pub(in crate::step) grid: CellGrid<D>,
    pub(in crate::step) marks: PositionMarks<D>,
    /// Largest displacement since the last list build (end of the last step).
    max_disp: Real,
    /// Largest speed at the end of the last step.
    vmax: Real,
    pub(in crate::step) skin: Real,
    /// List radius: kernel cut-off plus skin.
    pub(in crate::step) radius: Real,
}

impl<const D: usize> InnerRelation<D> {
    /// The relation over the cells of `grid`, with lists of `radius` (kernel cut-off
    /// plus `skin`); never built yet.
    pub fn new(grid: CellGrid<D>, radius: Real, skin: Real) -> Self {
        InnerRelation {
            grid,
            marks: PositionMarks::default(),
            max_disp: Real::INFINITY,
            vmax: 0.0,
            skin,
            radius,
        }
    }

    /// Whether the motion since the build that the rebuild rule and Δt read (the
    /// largest speed and displacement) is finite, not negative and (the speed) at most
    /// `max_speed`; the displacement is infinite before the first build.
    pub fn motion_in_range(&self, max_speed: Real) -> bool {
        let speed = self.vmax.is_finite() && (0.0..=max_speed).contains(&self.vmax);
        speed && self.max_disp >= 0.0
    }

    /// Bound on any particle's displacement since the build by the middle of a step of
    /// `dt` (where the lists are read).
    pub fn moved(&self, dt: Real) -> Real {
        self.max_disp + 0.5 * dt * self.vmax
    }

    /// The rebuild rule: two particles moving `moved` each may have closed the skin.
    pub fn expired(&self, moved: Real) -> bool {
        2.0 * moved > self.skin
    }

    /// Largest speed at the end of the last step.
    pub fn vmax(&self) -> Real {
        self.vmax
    }

    /// The end of a step whose largest squared speed and squared displacement since the
    /// build were `vmax2` and `disp2` (the marks' rounding added); returns the speed.
    pub fn end_step(&mut self, vmax2: Real, disp2: Real) -> Real {
        self.vmax = vmax2.sqrt();
        self.max_disp = disp2.sqrt() + self.marks.round_off;
        self.vmax
    }

    /// Bin `pos` (the family re-sorted by cell) and mark it as this build's positions.
    pub fn mark(&mut self, pos: &[Vect<D>]) {
        self.grid.bin(pos);
        self.marks.mark(pos);
        self.max_disp = 0.0;
    }

    /// Bytes of the grid and the marks.
    pub fn bytes(&self) -> usize {
        self.marks.bytes() + self.grid.bytes()
    }
}
