//! The simulated world built from a scene: particles, materials, walls and probes.

use crate::build_error::BuildError;
use crate::coarse::build::Coarse;
use crate::fine::material::FineMaterial;
use crate::fine::state::FineParticles;
use crate::geometry::Shape;
use crate::math::{from3, to3, Real, Sym, Vect};
use crate::scene::spec_rotation;
use crate::scene::{InitialStress, Scene, ShapeSpec};
use crate::walls::{Barrier, WallObject, Walls};
use nalgebra::{Rotation3, Vector3};

/// A body's rotation about a centre.
type Pose = (Vector3<Real>, Rotation3<Real>);

/// A probe point sampled into the time series.
#[derive(Clone, Debug, serde::Serialize, serde::Deserialize)]
pub struct Probe<const D: usize> {
    pub name: String,
    pub position: Vect<D>,
}

/// Everything that evolves or is looked up during a run.
#[derive(Clone, Debug, serde::Serialize, serde::Deserialize)]
pub struct World<const D: usize> {
    pub fine: FineParticles<D>,
    pub materials: Vec<FineMaterial>,
    pub walls: Walls<D>,
    /// Coarse grains (boulders): bodies, their particles and solids.
    pub coarse: Coarse<D>,
    pub gravity: Vect<D>,
    pub dp: Real,
    pub time: Real,
    pub steps: u64,
    /// Fixed neighbour-search box (particles outside are clamped into border cells).
    pub domain: (Vect<D>, Vect<D>),
    pub probes: Vec<Probe<D>>,
    /// Per-region particle counts, in scene order.
    pub region_counts: Vec<(String, usize)>,
}

fn v<const D: usize>(x: &[f64]) -> Vect<D> {
    Vect::<D>::from_iterator(x.iter().copied())
}

impl<const D: usize> World<D> {
    /// Build from a validated scene.
    pub fn build(scene: &Scene) -> Result<Self, BuildError> {
        // refuse a scene too large for memory before allocating anything
        crate::budget::enforce(scene).map_err(|message| BuildError {
            path: "simulation.dp".into(),
            message,
        })?;
        let sim = &scene.simulation;
        let dp = sim.dp;
        let gravity = v::<D>(&sim.gravity);
        let gnorm = gravity.norm();
        let up = if gnorm > 0.0 {
            -gravity / gnorm
        } else {
            Vect::<D>::zeros()
        };
        let materials: Vec<FineMaterial> = scene
            .materials
            .iter()
            .map(FineMaterial::from_spec)
            .collect();
        let vol = dp.powi(D as i32);

        // Solids that displace fine grains: walls and barriers (not planes, whose patch
        // is not a solid) and bodies (buried boulders). Fine particles closer than dp/2
        // to their surface (less than the lattice half-spacing) are not created.
        let mut solids: Vec<(Shape<D>, Option<Pose>)> = Vec::new();
        for w in scene.walls.iter().chain(&scene.barriers) {
            if !matches!(w.shape, ShapeSpec::Plane { .. }) {
                solids.push((Shape::<D>::from_spec(&w.shape, &scene.assets), None));
            }
        }
        for b in &scene.bodies {
            let shape = Shape::<D>::from_spec(&b.shape, &scene.assets);
            let c = to3(&shape.center());
            solids.push((shape, Some((c, spec_rotation(b, D)))));
        }
        let inside_solid = |p: &Vect<D>| {
            solids.iter().any(|(shape, pose)| {
                let q = match pose {
                    Some((c, r)) => from3::<D>(&(c + r.inverse() * (to3(p) - c))),
                    None => *p,
                };
                shape.sdf(&q) < 0.5 * dp * (1.0 - 1e-6)
            })
        };
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
                    crate::rng::Rng(r.jitter_seed ^ (ri as u64).wrapping_mul(0x9E37_79B9));
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
                .map(|p| p.dot(&up))
                .fold(Real::NEG_INFINITY, Real::max)
                + 0.5 * dp;
            for p in &pts {
                let stress = match r.initial_stress {
                    InitialStress::Zero => Sym::ZERO,
                    InitialStress::Geostatic => {
                        let sv = -m.rho0 * gnorm * (top - p.dot(&up));
                        geostatic_tensor::<D>(&up, m.k0).scale(sv)
                    }
                };
                fine.push(*p, vel, m.rho0, m.rho0 * vol, stress, mi);
            }
            region_counts.push((r.name.clone(), pts.len()));
        }

        let layers = scene.numerics.wall_layers;
        let mut walls = Walls::<D> {
            volume: vol,
            ..Default::default()
        };
        let add_object = |walls: &mut Walls<D>,
                          name: &str,
                          pts: Vec<Vect<D>>,
                          vel: Vect<D>,
                          window: (Real, Real),
                          barrier: Option<Vect<D>>,
                          shape: Shape<D>| {
            let o = walls.objects.len() as u16;
            let b = barrier.map(|reference| {
                walls.barriers.push(Barrier {
                    name: name.to_string(),
                    object: o as usize,
                    reference,
                    panels: Vec::new(),
                    slot0: walls.barriers.len(),
                    panel_axes: Vec::new(),
                    panel_lo: Vect::<D>::zeros(),
                    panel_hi: Vect::<D>::zeros(),
                });
                walls.barriers.len() - 1
            });
            walls.objects.push(WallObject {
                name: name.to_string(),
                velocity: vel,
                prescribed: vel,
                window,
                barrier: b,
                displacement: Vect::<D>::zeros(),
                shape: Some(shape),
                driven: false,
            });
            for p in pts {
                walls.pos.push(p);
                walls.object.push(o);
            }
        };
        for (list, key, is_barrier) in [
            (&scene.walls, "walls", false),
            (&scene.barriers, "barriers", true),
        ] {
            for (wi, w) in list.iter().enumerate() {
                let shape = Shape::<D>::from_spec(&w.shape, &scene.assets);
                let pts = shape.wall_fill(dp, layers);
                if pts.is_empty() {
                    return Err(BuildError {
                        path: format!("{key}[{wi}].shape"),
                        message: format!("`{}` holds no wall particle at dp = {dp:?} m", w.name),
                    });
                }
                let vel = w
                    .velocity
                    .as_deref()
                    .map(v::<D>)
                    .unwrap_or_else(Vect::<D>::zeros);
                let reference =
                    w.reference_point
                        .as_deref()
                        .map(v::<D>)
                        .unwrap_or_else(|| match &w.shape {
                            ShapeSpec::Plane { point, .. } => v::<D>(point),
                            _ => shape.center(),
                        });
                let window = match w.move_between.as_deref() {
                    Some([t0, t1]) => (*t0, *t1),
                    _ => (Real::NEG_INFINITY, Real::INFINITY),
                };
                add_object(
                    &mut walls,
                    &w.name,
                    pts,
                    vel,
                    window,
                    is_barrier.then_some(reference),
                    shape,
                );
                if let Some(o) = walls.objects.last_mut() {
                    o.driven = w.input.is_some();
                }
            }
        }
        for c in &scene.containers {
            let (lo, hi) = (v::<D>(&c.min), v::<D>(&c.max));
            let open: Vec<String> = c
                .open
                .clone()
                .unwrap_or_else(|| vec![if D == 2 { "+y".into() } else { "+z".into() }]);
            let t = layers as Real * dp;
            for a in 0..D {
                for (side, sign) in [("-", -1.0), ("+", 1.0)] {
                    let face = format!("{side}{}", ["x", "y", "z"][a]);
                    if open.contains(&face) {
                        continue;
                    }
                    let mut fmin = lo;
                    let mut fmax = hi;
                    if sign < 0.0 {
                        fmin[a] = lo[a] - t;
                        fmax[a] = lo[a];
                    } else {
                        fmin[a] = hi[a];
                        fmax[a] = hi[a] + t;
                    }
                    // Faces on lower axes span the interior; higher axes take the corners.
                    for b in 0..a {
                        fmin[b] = lo[b] - t;
                        fmax[b] = hi[b] + t;
                    }
                    let shape = Shape::<D>::Box {
                        min: fmin,
                        max: fmax,
                    };
                    let pts = shape.fill(dp);
                    let name = format!("{}.{}", c.name, face_name(&face, D));
                    let solid = shape.clone();
                    let mut reference = (lo + hi) * 0.5;
                    reference[a] = if sign < 0.0 { lo[a] } else { hi[a] };
                    add_object(
                        &mut walls,
                        &name,
                        pts,
                        Vect::<D>::zeros(),
                        (Real::NEG_INFINITY, Real::INFINITY),
                        c.report_loads.then_some(reference),
                        solid,
                    );
                }
            }
        }

        crate::panels::split_scene_panels(&mut walls, scene);
        let n = &scene.numerics;
        let trim = (2.0 * n.smoothing_ratio + n.neighbor_skin + 1.0) * dp;
        let coarse = Coarse::<D>::build(scene, trim)?;

        // Domain: everything, plus a margin for the flow to spread into.
        let mut lo = Vect::<D>::repeat(Real::INFINITY);
        let mut hi = Vect::<D>::repeat(Real::NEG_INFINITY);
        for p in fine
            .pos
            .iter()
            .chain(walls.pos.iter())
            .chain(coarse.particles.pos.iter())
        {
            lo = lo.inf(p);
            hi = hi.sup(p);
        }
        let margin = (hi - lo).max() * 0.1 + 8.0 * dp;
        let domain = (lo.add_scalar(-margin), hi.add_scalar(margin));

        let probes = scene
            .probes
            .iter()
            .map(|p| Probe {
                name: p.name.clone(),
                position: v::<D>(&p.position),
            })
            .collect();
        // the arrays grew by doubling while the regions were filled
        fine.shrink_to_fit();
        Ok(World {
            fine,
            materials,
            walls,
            coarse,
            gravity,
            dp,
            time: 0.0,
            steps: 0,
            domain,
            probes,
            region_counts,
        })
    }

    /// Largest sound speed over fine materials.
    pub fn max_c0(&self) -> Real {
        self.materials.iter().map(|m| m.c0).fold(0.0, Real::max)
    }
}

/// Human name of a container face: the vertical axis gives bottom/top.
fn face_name(face: &str, dim: usize) -> &'static str {
    match (face, dim) {
        ("-x", _) => "left",
        ("+x", _) => "right",
        ("-y", 2) | ("-z", 3) => "bottom",
        ("+y", 2) | ("+z", 3) => "top",
        ("-y", _) => "front",
        _ => "back",
    }
}

/// K0 (I − n n) + n n for the vertical unit vector n: the geostatic stress per unit
/// vertical stress (Eq. 26, Jaky's K0 on the horizontal axes, including the
/// out-of-plane axis in plane strain).
pub fn geostatic_tensor<const D: usize>(up: &Vect<D>, k0: Real) -> Sym {
    let mut n = [0.0; 3];
    for k in 0..D {
        n[k] = up[k];
    }
    let mut s = [0.0; 6];
    let idx = [(0, 0), (1, 1), (2, 2), (0, 1), (0, 2), (1, 2)];
    for (c, (a, b)) in idx.iter().enumerate() {
        let delta = if a == b { 1.0 } else { 0.0 };
        s[c] = k0 * (delta - n[*a] * n[*b]) + n[*a] * n[*b];
    }
    Sym(s)
}
