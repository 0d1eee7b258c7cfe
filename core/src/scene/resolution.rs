//! The spatial resolution of a run, derived once from the scene: the particle spacing
//! dp, the particle volume dp^D, the smoothing length h (seed 000 §5.2: h = 1.3 dp by
//! default) and the neighbour search's skin. The world, the step and the estimates read
//! these values and never the scene's spacing again.

use crate::numerics::math::Real;
use crate::scene::Scene;

/// Spacing, volume, smoothing length and skin of a run.
#[derive(Clone, Copy, Debug, PartialEq, serde::Serialize, serde::Deserialize)]
pub struct Resolution {
    /// Particle spacing dp (m).
    pub dp: Real,
    /// Particle volume dp^D (m³; m² per metre in 2D).
    pub volume: Real,
    /// Smoothing length h = `numerics.smoothing_ratio` · dp.
    pub h: Real,
    /// Verlet skin = `numerics.neighbor_skin` · dp.
    pub skin: Real,
    /// Depth below a rigid body's surface beyond which no fine particle or contact
    /// reaches its particles: the kernel support 2h, the skin and one spacing.
    pub trim: Real,
}

impl Resolution {
    /// The resolution of `scene` in `D` dimensions.
    pub fn of<const D: usize>(scene: &Scene) -> Self {
        Self::in_dimension(scene, D)
    }

    /// The resolution of `scene` in its own dimension (`simulation.dimension`), for
    /// what runs before the build: the load checks and the estimates.
    pub fn of_scene(scene: &Scene) -> Self {
        Self::in_dimension(scene, scene.simulation.dimension)
    }

    fn in_dimension(scene: &Scene, d: usize) -> Self {
        let dp = scene.simulation.dp;
        let n = &scene.numerics;
        Resolution {
            dp,
            volume: dp.powi(d as i32),
            h: n.smoothing_ratio * dp,
            skin: n.neighbor_skin * dp,
            trim: (2.0 * n.smoothing_ratio + n.neighbor_skin + 1.0) * dp,
        }
    }
}
