//! The fine grains of a scene: each region's shape filled on the lattice of spacing dp
//! (seed 000 §5.2), jittered if asked, less what lies inside a solid (walls, barriers,
//! buried boulders), with its initial velocity and stress.

use super::{geostatic_tensor, v};
use crate::fine::material::FineMaterial;
use crate::fine::state::FineParticles;
use crate::geometry::start_solids::Solids;
use crate::geometry::Shape;
use crate::numerics::math::{extent, Real, Sym, Vect};
use crate::scene::build_error::{empty_region_message, BuildError};
use crate::scene::{InitialStress, Scene};

/// The fine particles of every region, and the particle count of each (scene order),
/// geostatic under the hydrostatic gravity `g_hyd` (the scene's, less its component
/// along a periodic axis).
pub(super) fn fill<const D: usize>(
    scene: &Scene,
    materials: &[FineMaterial],
    g_hyd: &Vect<D>,
    dp: Real,
    vol: Real,
) -> Result<(FineParticles<D>, Vec<(String, usize)>), BuildError> {
    let (gnorm, up) = (g_hyd.norm(), &crate::numerics::math::up(g_hyd));
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
            let mut rng =
                crate::numerics::rng::Rng(r.jitter_seed ^ (ri as u64).wrapping_mul(0x9E37_79B9));
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
                message: empty_region_message("region", &r.name, dp),
            });
        }
        let vel = r
            .velocity
            .as_deref()
            .map(v::<D>)
            .unwrap_or_else(Vect::<D>::zeros);
        let top = extent(&pts, up, dp).1;
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
