//! Force and moment that one family, or a wall, exerts on a barrier or a body: the
//! shared kind that the fine sweeps (wall pairs, seed 000 Eqs. 32–35), the coarse
//! contact and the coupling (Eqs. 48–50) accumulate, and that panels and samples
//! report. It belongs to no particle family.

use crate::numerics::math::Real;
use nalgebra::Vector3;

/// Force and moment on a barrier (3D components; in 2D z-force is 0 and only the
/// z-moment is non-zero).
#[derive(Clone, Copy, Debug, Default, PartialEq, serde::Serialize, serde::Deserialize)]
pub struct Load {
    pub force: Vector3<Real>,
    pub moment: Vector3<Real>,
}

impl Load {
    pub fn add(&mut self, o: &Load) {
        self.force += o.force;
        self.moment += o.moment;
    }

    /// The load times `s`.
    pub fn scaled(&self, s: Real) -> Load {
        Load {
            force: self.force * s,
            moment: self.moment * s,
        }
    }
}
