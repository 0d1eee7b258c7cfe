//! `[[rock_fills]]`: random convex rocks placed without overlap inside a region, as in the
//! soil–rock-mixture slopes of seed 000 §6.1 (rock block content, RBC, by area). The
//! rocks become ordinary `[[bodies]]` with polygon shapes before validation, so
//! everything downstream sees plain bodies.

use crate::geometry::Shape;
use crate::numerics::math::Vect;
use crate::scene::{
    validate_shape, BodySpec, KeyError, RockFillReport, RockFillSpec, Scene, ShapeSpec,
};
use std::f64::consts::PI;

use crate::numerics::rng::Rng;

type Fail = KeyError;

/// Largest placement attempts per rock before the fill gives up.
const ATTEMPTS: usize = 20_000;

/// Most rocks one fill may place: each is a body, and placing one tests it against
/// every rock placed before (10,000 rocks take about a second).
pub const MAX_ROCKS: f64 = 10_000.0;

/// Estimate a fill before generating it: the rocks it asks for (content × region area
/// over the mean rock area) must not exceed [`MAX_ROCKS`]. (Their particles are counted
/// against the memory budget with the other bodies, once they are placed.)
fn estimate_fill(p: &str, f: &RockFillSpec, region_area: f64) -> Result<(), Fail> {
    let mean_area = PI / 4.0 * f.size * f.size * (1.0 + f.size_spread * f.size_spread / 3.0);
    let rocks = f.content * region_area / mean_area;
    if rocks.is_nan() || rocks > MAX_ROCKS {
        return Err(KeyError::new(
            format!("{p}.size"),
            format!(
                "rocks of size {:?} m filling {:.1} % of a region of {region_area:.3e} m² \
                 would number about {rocks:.3e}, over the {MAX_ROCKS:.0} one fill may place; \
                 take larger rocks or a lower content",
                f.size,
                100.0 * f.content
            ),
        ));
    }
    Ok(())
}

type P = [f64; 2];

fn cross(o: P, a: P, b: P) -> f64 {
    (a[0] - o[0]) * (b[1] - o[1]) - (a[1] - o[1]) * (b[0] - o[0])
}

/// Convex hull, counter-clockwise (Andrew's monotone chain).
fn hull(mut pts: Vec<P>) -> Vec<P> {
    pts.sort_by(|a, b| a[0].total_cmp(&b[0]).then(a[1].total_cmp(&b[1])));
    let mut lower: Vec<P> = Vec::new();
    for &p in &pts {
        while lower.len() >= 2 && cross(lower[lower.len() - 2], lower[lower.len() - 1], p) <= 0.0 {
            lower.pop();
        }
        lower.push(p);
    }
    let mut upper: Vec<P> = Vec::new();
    for &p in pts.iter().rev() {
        while upper.len() >= 2 && cross(upper[upper.len() - 2], upper[upper.len() - 1], p) <= 0.0 {
            upper.pop();
        }
        upper.push(p);
    }
    lower.pop();
    upper.pop();
    lower.extend(upper);
    lower
}

/// Area and centroid of a simple polygon.
fn area_centroid(v: &[P]) -> (f64, P) {
    let (mut a, mut cx, mut cy) = (0.0, 0.0, 0.0);
    for i in 0..v.len() {
        let (p, q) = (v[i], v[(i + 1) % v.len()]);
        let c = p[0] * q[1] - q[0] * p[1];
        a += c;
        cx += (p[0] + q[0]) * c;
        cy += (p[1] + q[1]) * c;
    }
    let a = 0.5 * a;
    (a.abs(), [cx / (6.0 * a), cy / (6.0 * a)])
}

/// One rock of equivalent diameter `d` centred (centroid) on the origin: points around
/// an ellipse of random aspect, jittered in angle and radius, then their convex hull,
/// scaled to area πd²/4 and turned by a random angle.
fn rock(rng: &mut Rng, d: f64, n: usize, max_aspect: f64) -> Vec<P> {
    let aspect = 1.0 + (max_aspect - 1.0) * rng.uniform();
    let (ax, ay) = (aspect.sqrt(), 1.0 / aspect.sqrt());
    let pts: Vec<P> = (0..n)
        .map(|k| {
            let t = (k as f64 + 0.7 * (rng.uniform() - 0.5)) * 2.0 * PI / n as f64;
            let r = 1.0 + 0.3 * (rng.uniform() - 0.5);
            [r * ax * t.cos(), r * ay * t.sin()]
        })
        .collect();
    let h = hull(pts);
    let (a, c) = area_centroid(&h);
    let s = (PI * d * d / 4.0 / a).sqrt();
    let turn = 2.0 * PI * rng.uniform();
    let (sn, cs) = turn.sin_cos();
    h.iter()
        .map(|p| {
            let (x, y) = ((p[0] - c[0]) * s, (p[1] - c[1]) * s);
            [cs * x - sn * y, sn * x + cs * y]
        })
        .collect()
}

/// Largest separation of two convex polygons along the edge normals of either: a lower
/// bound of their distance (negative when they overlap).
fn gap(a: &[P], b: &[P]) -> f64 {
    let mut best = f64::NEG_INFINITY;
    for (u, w) in [(a, b), (b, a)] {
        for i in 0..u.len() {
            let (p, q) = (u[i], u[(i + 1) % u.len()]);
            let (ex, ey) = (q[0] - p[0], q[1] - p[1]);
            let len = (ex * ex + ey * ey).sqrt();
            if len == 0.0 {
                continue;
            }
            // outward normal of a counter-clockwise polygon
            let n = [ey / len, -ex / len];
            let umax = u
                .iter()
                .map(|v| v[0] * n[0] + v[1] * n[1])
                .fold(f64::NEG_INFINITY, f64::max);
            let wmin = w
                .iter()
                .map(|v| v[0] * n[0] + v[1] * n[1])
                .fold(f64::INFINITY, f64::min);
            best = best.max(wmin - umax);
        }
    }
    best
}

struct Placed {
    verts: Vec<P>,
    center: P,
    radius: f64,
}

/// Expand every `[[rock_fills]]` entry into `[[bodies]]`, at the scene's spacing `dp`
/// (the default clearance is two spacings).
pub fn expand(scene: &mut Scene, dp: f64) -> Result<(), Fail> {
    let fills = scene.rock_fills.clone();
    for (i, f) in fills.iter().enumerate() {
        let (bodies, report) = fill(scene, i, f, dp)?;
        scene.bodies.extend(bodies);
        scene.rock_reports.push(report);
    }
    Ok(())
}

fn check(scene: &Scene, p: &str, f: &RockFillSpec) -> Result<(), Fail> {
    let bad = |k: &str, m: String| Err(KeyError::new(format!("{p}.{k}"), m));
    if scene.simulation.dimension != 2 {
        return bad(
            "region",
            "rock fills are 2D; in 3D place [[bodies]] with polyhedron or mesh shapes".into(),
        );
    }
    if !scene.solids.iter().any(|s| s.name == f.material) {
        return bad("material", crate::scene::unknown_solid(scene, &f.material));
    }
    if !(0.0..=0.5).contains(&f.content) {
        return bad(
            "content",
            format!("must lie in [0, 0.5], found {:?}", f.content),
        );
    }
    if !(f.size.is_finite() && f.size > 0.0) {
        return bad(
            "size",
            format!("must be a positive number, found {:?}", f.size),
        );
    }
    if !(0.0..0.9).contains(&f.size_spread) {
        return bad(
            "size_spread",
            format!("must lie in [0, 0.9), found {:?}", f.size_spread),
        );
    }
    if !(5..=24).contains(&f.vertices) {
        return bad(
            "vertices",
            format!("must lie in 5..=24, found {:?}", f.vertices),
        );
    }
    if !(f.max_aspect.is_finite() && f.max_aspect >= 1.0 && f.max_aspect <= 4.0) {
        return bad(
            "max_aspect",
            format!("must lie in [1, 4], found {:?}", f.max_aspect),
        );
    }
    if let Some(c) = f.clearance {
        if !(c.is_finite() && c >= 0.0) {
            return bad("clearance", format!("must be ≥ 0, found {c:?}"));
        }
    }
    validate_shape(&format!("{p}.region"), &f.region, 2)?;
    if !matches!(
        f.region,
        ShapeSpec::Box { .. } | ShapeSpec::Polygon { .. } | ShapeSpec::Sphere { .. }
    ) {
        return bad(
            "region.type",
            "a rock region must be a box, polygon or sphere".into(),
        );
    }
    Ok(())
}

/// Where the rocks of one fill may go: its region (and the region's bounding box),
/// at least `clearance` inside its boundary.
struct Site {
    region: Shape<2>,
    lo: Vect<2>,
    hi: Vect<2>,
    clearance: f64,
}

impl Site {
    /// Try up to [`ATTEMPTS`] random centres in the bounding box for the rock `shape`
    /// (centred on the origin); the first whose vertices and edge midpoints lie
    /// `clearance` inside the region and which keeps `clearance` from every rock of
    /// `placed` is the rock placed, `None` if none does.
    fn place(&self, rng: &mut Rng, shape: &[P], placed: &[Placed]) -> Option<Placed> {
        let (lo, hi, clearance) = (self.lo, self.hi, self.clearance);
        let radius = shape
            .iter()
            .map(|v| (v[0] * v[0] + v[1] * v[1]).sqrt())
            .fold(0.0, f64::max);
        for _ in 0..ATTEMPTS {
            let c = [
                lo[0] + (hi[0] - lo[0]) * rng.uniform(),
                lo[1] + (hi[1] - lo[1]) * rng.uniform(),
            ];
            let verts: Vec<P> = shape.iter().map(|v| [v[0] + c[0], v[1] + c[1]]).collect();
            let inside = (0..verts.len()).all(|k| {
                let (u, w) = (verts[k], verts[(k + 1) % verts.len()]);
                let mid = [0.5 * (u[0] + w[0]), 0.5 * (u[1] + w[1])];
                self.region.sdf(&u.into()) <= -clearance
                    && self.region.sdf(&mid.into()) <= -clearance
            });
            if !inside {
                continue;
            }
            let free = placed.iter().all(|q| {
                let dc = ((q.center[0] - c[0]).powi(2) + (q.center[1] - c[1]).powi(2)).sqrt();
                dc > q.radius + radius + clearance || gap(&q.verts, &verts) >= clearance
            });
            if free {
                return Some(Placed {
                    verts,
                    center: c,
                    radius,
                });
            }
        }
        None
    }
}

/// Generate the rocks of fill `i` (`f`) at spacing `dp`: random rocks placed one by one
/// until their area reaches the content's share of the region (seed 000 §6.1, RBC);
/// the rocks as bodies and the fill's report.
fn fill(
    scene: &Scene,
    i: usize,
    f: &RockFillSpec,
    dp: f64,
) -> Result<(Vec<BodySpec>, RockFillReport), Fail> {
    let p = format!("rock_fills[{i}]");
    check(scene, &p, f)?;
    let region = Shape::<2>::from_spec(&f.region, &scene.assets);
    let region_area = region.volume().unwrap_or(0.0);
    estimate_fill(&p, f, region_area)?;
    let (lo, hi) = region.bounds();
    let clearance = f.clearance.unwrap_or(2.0 * dp);
    let site = Site {
        region,
        lo,
        hi,
        clearance,
    };
    let target = f.content * region_area;
    let mut rng =
        Rng(f.seed ^ 0x5EED_0000_0000_0000 ^ (i as u64).wrapping_mul(0xA24B_AED4_963E_E407));
    let mut placed: Vec<Placed> = Vec::new();
    let mut area = 0.0;
    loop {
        let d = f.size * (1.0 + f.size_spread * (2.0 * rng.uniform() - 1.0));
        let a = PI * d * d / 4.0;
        if area + 0.5 * a > target {
            break;
        }
        let shape = rock(&mut rng, d, f.vertices, f.max_aspect);
        match site.place(&mut rng, &shape, &placed) {
            Some(r) => {
                area += a;
                placed.push(r);
            }
            None => {
                return Err(KeyError::new(
                    format!("{p}.content"),
                    format!(
                        "could not place rock {} after {ATTEMPTS} tries: {} rocks make {:.1} % of the region, short of {:.1} %; lower content or size, or reduce clearance ({clearance} m)",
                        placed.len() + 1,
                        placed.len(),
                        100.0 * area / region_area,
                        100.0 * f.content
                    ),
                ))
            }
        }
    }
    Ok((
        bodies(f, &placed),
        RockFillReport {
            name: f.name.clone(),
            rocks: placed.len(),
            content: if region_area > 0.0 {
                area / region_area
            } else {
                0.0
            },
        },
    ))
}

/// The rocks of fill `f` as `[[bodies]]`: free polygons of its material and model,
/// named after the fill and numbered in the order placed.
fn bodies(f: &RockFillSpec, placed: &[Placed]) -> Vec<BodySpec> {
    placed
        .iter()
        .enumerate()
        .map(|(k, r)| BodySpec {
            name: format!("{}_{k}", f.name),
            material: f.material.clone(),
            model: f.model,
            shape: ShapeSpec::Polygon {
                vertices: r.verts.iter().map(|v| v.to_vec()).collect(),
            },
            rotation: None,
            velocity: None,
            angular_velocity: None,
            fixed: false,
        })
        .collect()
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn hull_area_and_gap_of_unit_squares() {
        let sq = |x: f64| vec![[x, 0.0], [x + 1.0, 0.0], [x + 1.0, 1.0], [x, 1.0]];
        let h = hull(vec![
            [0.0, 0.0],
            [1.0, 1.0],
            [0.5, 0.5],
            [1.0, 0.0],
            [0.0, 1.0],
        ]);
        assert_eq!(h.len(), 4);
        let (a, c) = area_centroid(&h);
        assert!((a - 1.0).abs() < 1e-15 && (c[0] - 0.5).abs() < 1e-15);
        assert!((gap(&sq(0.0), &sq(1.5)) - 0.5).abs() < 1e-15);
        assert!(gap(&sq(0.0), &sq(0.5)) < 0.0);
    }

    #[test]
    fn rocks_have_the_requested_equivalent_diameter() {
        let mut rng = Rng(7);
        for _ in 0..50 {
            let r = rock(&mut rng, 4.0, 9, 1.6);
            let (a, c) = area_centroid(&r);
            assert!((2.0 * (a / PI).sqrt() - 4.0).abs() < 1e-12);
            assert!(c[0].abs() < 1e-12 && c[1].abs() < 1e-12);
        }
    }
}
