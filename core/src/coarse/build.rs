//! Building coarse grains from the scene: lattice fill of each body's shape, rotation,
//! mass properties, surface normals, and trimming of rigid interiors.

use super::body::Body;
use super::material::SolidMaterial;
use super::particles::CoarseParticles;
use crate::geometry::Shape;
use crate::numerics::math::{from3, to3, Real, Vect};
use crate::scene::build_error::BuildError;
use crate::scene::resolution::Resolution;
use crate::scene::{spec_rotation, BodyModel, BodySpec, Scene};
use nalgebra::{Matrix3, Rotation3, UnitQuaternion, Vector3};

/// Coarse grains of a scene.
#[derive(Clone, Debug, Default, serde::Serialize, serde::Deserialize)]
pub struct Coarse<const D: usize> {
    pub solids: Vec<SolidMaterial>,
    pub particles: CoarseParticles<D>,
    pub bodies: Vec<Body<D>>,
}

impl<const D: usize> Coarse<D> {
    pub fn is_empty(&self) -> bool {
        self.bodies.is_empty()
    }

    /// Build all bodies of `scene` at resolution `res`. Rigid-body particles deeper than
    /// `res.trim` below the surface are dropped after the mass properties are taken
    /// (they never meet a fine particle or a contact).
    pub fn build(scene: &Scene, res: &Resolution) -> Result<Self, BuildError> {
        let (dp, vol, trim_depth) = (res.dp, res.volume, res.trim);
        let solids: Vec<SolidMaterial> =
            scene.solids.iter().map(SolidMaterial::from_spec).collect();
        let mut particles = CoarseParticles::<D>::default();
        let mut bodies = Vec::new();
        for (bi, b) in scene.bodies.iter().enumerate() {
            let mi = scene
                .solids
                .iter()
                .position(|m| m.name == b.material)
                .expect("validated");
            let m = &solids[mi];
            let (shape, pts) = body_points::<D>(scene, (bi, b), dp)?;
            let centre = to3(&shape.center());
            let rot = spec_rotation(b, D);
            // particle mass: the exact body mass shared out, where the volume is known
            let mass = shape
                .volume()
                .map(|v| m.rho0 * v)
                .unwrap_or(m.rho0 * vol * pts.len() as Real);
            let pm = mass / pts.len() as Real;
            let (com_local, inertia) = mass_properties(&pts, &centre, pm, dp);
            let com = centre + rot * com_local;
            let (vel, omega) = initial_motion(b);
            let start = particles.len();
            let placement = Placement {
                centre,
                com_local,
                com,
                rot,
                vel,
                omega,
                pm,
                body: bi as u32,
                rigid: b.model == BodyModel::Rigid,
            };
            placement.push(&mut particles, &shape, &pts, (dp, trim_depth));
            let orientation = UnitQuaternion::from_rotation_matrix(&rot);
            let inv_inertia = inertia.try_inverse().ok_or_else(|| BuildError {
                path: format!("bodies[{bi}].shape"),
                message: format!("body `{}` has a singular inertia tensor", b.name),
            })?;
            let r = *rot.matrix();
            let ang_mom = r * inertia * r.transpose() * omega;
            bodies.push(Body {
                name: b.name.clone(),
                model: b.model,
                material: mi,
                start,
                end: particles.len(),
                fixed: b.fixed,
                mass,
                com,
                vel,
                orientation,
                ang_mom,
                omega,
                inertia,
                inv_inertia,
                force: Vector3::zeros(),
                torque: Vector3::zeros(),
                fine_force: Vector3::zeros(),
                water_force: Vector3::zeros(),
                contacts: 0,
                uplift: Vector3::zeros(),
                gaps: 0,
            });
        }
        Ok(Coarse {
            solids,
            particles,
            bodies,
        })
    }

    /// Largest sound speed of the solids of elastic bodies (0 without elastic bodies).
    pub fn max_elastic_c0(&self) -> Real {
        self.bodies
            .iter()
            .filter(|b| !b.is_rigid())
            .map(|b| self.solids[b.material].c0)
            .fold(0.0, Real::max)
    }
}

/// Body `b` (number `bi`) of the scene: its shape and its particles, the shape's
/// lattice fill at spacing `dp`, relaxed; refused with fewer than 2 particles.
fn body_points<const D: usize>(
    scene: &Scene,
    (bi, b): (usize, &BodySpec),
    dp: Real,
) -> Result<(Shape<D>, Vec<Vect<D>>), BuildError> {
    let shape = Shape::<D>::from_spec(&b.shape, &scene.assets);
    let mut pts = shape.body_fill(dp);
    super::relax::relax(&shape, &mut pts, dp);
    if pts.len() < 2 {
        return Err(BuildError {
            path: format!("bodies[{bi}].shape"),
            message: format!(
                "body `{}` holds {} particle(s) at dp = {dp} m; it needs at least 2 \
                 (enlarge it or refine dp)",
                b.name,
                pts.len()
            ),
        });
    }
    Ok((shape, pts))
}

/// Where a body's particles go: the shape's centre, the centre of mass relative to it
/// and in the world, the rotation, the initial velocity and angular velocity, the
/// particle mass, the body's number and whether it is rigid.
struct Placement {
    centre: Vector3<Real>,
    com_local: Vector3<Real>,
    com: Vector3<Real>,
    rot: Rotation3<Real>,
    vel: Vector3<Real>,
    omega: Vector3<Real>,
    pm: Real,
    body: u32,
    rigid: bool,
}

impl Placement {
    /// Push the body's particles `pts` (in the frame of `shape`) onto `particles`,
    /// placed, moving and with their surface normals; a rigid body's particles deeper
    /// than `trim_depth` are left out. `dp` is the particle spacing.
    fn push<const D: usize>(
        &self,
        particles: &mut CoarseParticles<D>,
        shape: &Shape<D>,
        pts: &[Vect<D>],
        (dp, trim_depth): (Real, Real),
    ) {
        let (rot, com) = (self.rot, self.com);
        for p in pts {
            let depth = -shape.sdf(p);
            let rigid = self.rigid;
            if rigid && depth > trim_depth {
                continue;
            }
            // outward normal of the nearest surface, for every particle a fine
            // particle can see (Eq. 48)
            let n_local = shape.normal(p, 1e-3 * dp);
            let off = to3(p) - self.centre - self.com_local;
            let x = com + rot * off;
            let v = self.vel + self.omega.cross(&(x - com));
            let n = from3::<D>(&(rot * to3(&n_local)));
            let (local, local_normal) = if rigid {
                (from3::<D>(&off), n_local)
            } else {
                (from3::<D>(&x), n)
            };
            particles.push(
                from3::<D>(&x),
                from3::<D>(&v),
                local,
                local_normal,
                n,
                self.pm,
                self.body,
                depth,
                dp,
            );
        }
    }
}

fn v3(x: &[f64]) -> Vector3<Real> {
    let mut o = Vector3::zeros();
    for (k, v) in x.iter().enumerate().take(3) {
        o[k] = *v;
    }
    o
}

/// Centre of mass (relative to the shape's centre) and inertia tensor about it, in the
/// body frame (the unrotated shape), of particles of mass `pm`, each a cube (square) of
/// side `dp`.
fn mass_properties<const D: usize>(
    pts: &[Vect<D>],
    centre: &Vector3<Real>,
    pm: Real,
    dp: Real,
) -> (Vector3<Real>, Matrix3<Real>) {
    let com_local = pts
        .iter()
        .fold(Vector3::zeros(), |a, p| a + to3(p) - centre)
        / pts.len() as Real;
    let mut inertia = Matrix3::<Real>::zeros();
    for p in pts {
        let r = to3(p) - centre - com_local;
        inertia += (Matrix3::identity() * r.norm_squared() - r * r.transpose()) * pm;
    }
    inertia += Matrix3::identity() * (pm * dp * dp / 6.0);
    (com_local, inertia)
}

/// Initial velocity and angular velocity of body `b` (zero when it is fixed; a 2D
/// angular velocity is about z).
fn initial_motion(b: &BodySpec) -> (Vector3<Real>, Vector3<Real>) {
    if b.fixed {
        return (Vector3::zeros(), Vector3::zeros());
    }
    let vel = b.velocity.as_deref().map(v3).unwrap_or_else(Vector3::zeros);
    let omega = match b.angular_velocity.as_deref() {
        Some([w]) => Vector3::new(0.0, 0.0, *w),
        Some(w) => v3(w),
        None => Vector3::zeros(),
    };
    (vel, omega)
}
