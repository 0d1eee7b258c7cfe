//! The fine grains of a scene: each region's shape filled on the lattice of spacing dp
//! (seed 000 §5.2), jittered if asked, less what lies inside a solid (walls, barriers,
//! buried boulders), with its initial velocity and stress.

use super::{geostatic_tensor, v, Pose};
use crate::build_error::BuildError;
use crate::fine::material::FineMaterial;
use crate::fine::state::FineParticles;
use crate::geometry::Shape;
use crate::math::{from3, to3, Real, Sym, Vect};
use crate::scene::{spec_rotation, InitialStress, Scene, ShapeSpec};

/// The fine particles of every region, and the particle count of each (scene order).
pub(super) fn fill<const D: usize>(
    scene: &Scene,
    materials: &[FineMaterial],
    up: &Vect<D>,
    dp: Real,
    vol: Real,
) -> Result<(FineParticles<D>, Vec<(String, usize)>), BuildError> {
    let gnorm = v::<D>(&scene.simulation.gravity).norm();
    // a saturated soil starts at the effective stress of its submerged weight
    let rho_w = scene.water.as_ref().map_or(1000.0, |w| w.density);
    let solids = Solids::<D>::of(scene, false);
    let inside_solid = |p: &Vect<D>| solids.holds(p, dp);
    let mut fine = FineParticles::<D>::default();
    let mut region_counts = Vec::new();
    for (ri, r) in scene.regions.iter().enumerate() {
        let mi = scene
            .materials
            .iter()
            .position(|m| m.name == r.material)
            .expect("validated") as u16;
        let m = &materials[mi as usize];
        let shape = Shape::<D>::from_spec(&r.shape, &scene.assets);
        let mut pts = shape.fill(dp);
        if r.jitter > 0.0 {
            let mut rng = crate::rng::Rng(r.jitter_seed ^ (ri as u64).wrapping_mul(0x9E37_79B9));
            for p in &mut pts {
                for k in 0..D {
                    p[k] += (2.0 * rng.uniform() - 1.0) * r.jitter * dp;
                }
            }
        }
        if !solids.is_empty() {
            pts.retain(|p| !inside_solid(p));
        }
        if pts.is_empty() {
            return Err(BuildError {
                path: format!("regions[{ri}].shape"),
                message: format!(
                    "region `{}` holds no particle at dp = {dp:?} m; enlarge it or refine dp",
                    r.name
                ),
            });
        }
        let vel = r
            .velocity
            .as_deref()
            .map(v::<D>)
            .unwrap_or_else(Vect::<D>::zeros);
        let top = pts
            .iter()
            .map(|p| p.dot(up))
            .fold(Real::NEG_INFINITY, Real::max)
            + 0.5 * dp;
        for p in &pts {
            let stress = match r.initial_stress {
                InitialStress::Zero => Sym::ZERO,
                InitialStress::Geostatic => {
                    let sv = -m.skeleton_density(Some(rho_w)) * gnorm * (top - p.dot(up));
                    geostatic_tensor::<D>(up, m.k0).scale(sv)
                }
            };
            fine.push(*p, vel, m.rho0, m.rho0 * vol, stress, mi);
        }
        region_counts.push((r.name.clone(), pts.len()));
    }
    Ok((fine, region_counts))
}

/// Solids that displace particles at start-up: walls and barriers (not planes, whose
/// patch is not a solid; for water not the permeable ones) and bodies (buried
/// boulders).
pub(super) struct Solids<const D: usize>(Vec<(Shape<D>, Option<Pose>)>);

impl<const D: usize> Solids<D> {
    pub(super) fn of(scene: &Scene, water: bool) -> Self {
        let mut solids: Vec<(Shape<D>, Option<Pose>)> = Vec::new();
        for w in scene.walls.iter().chain(&scene.barriers) {
            let passes = water && w.permeable;
            if !matches!(w.shape, ShapeSpec::Plane { .. }) && !passes {
                solids.push((Shape::<D>::from_spec(&w.shape, &scene.assets), None));
            }
        }
        for b in &scene.bodies {
            let shape = Shape::<D>::from_spec(&b.shape, &scene.assets);
            let c = to3(&shape.center());
            solids.push((shape, Some((c, spec_rotation(b, D)))));
        }
        Solids(solids)
    }

    pub(super) fn is_empty(&self) -> bool {
        self.0.is_empty()
    }

    /// A particle at `p` is not created: it lies closer than dp/2 (the lattice
    /// half-spacing) to a solid's surface, or inside it.
    pub(super) fn holds(&self, p: &Vect<D>, dp: Real) -> bool {
        self.0.iter().any(|(shape, pose)| {
            let q = match pose {
                Some((c, r)) => from3::<D>(&(c + r.inverse() * (to3(p) - c))),
                None => *p,
            };
            shape.sdf(&q) < 0.5 * dp * (1.0 - 1e-6)
        })
    }
}
