//! Semantic checks on a deserialised scene. Errors carry the key path.

use super::error::KeyError;
use super::types::*;
use std::collections::HashSet;

pub(super) type Check = Result<(), KeyError>;

pub(super) fn fail<T>(path: impl Into<String>, msg: impl Into<String>) -> Result<T, KeyError> {
    Err(KeyError::new(path, msg))
}

pub(super) fn vec_len(path: &str, v: &[f64], d: usize) -> Check {
    if v.len() != d {
        return fail(
            path,
            format!(
                "expected {d} components for a {d}D scene, found {:?}",
                v.len()
            ),
        );
    }
    if let Some(k) = v.iter().position(|x| !x.is_finite()) {
        return fail(format!("{path}[{k}]"), "must be a finite number");
    }
    Ok(())
}

/// The least friction angle (degrees) a soil may have: far below it, tan φ and the
/// Drucker–Prager constants underflow (φ = 1e-300° gave a NaN density at step 2).
pub const MIN_FRICTION_ANGLE: f64 = 1e-3;

/// Lengths a direction (a plane's or an outflow's normal) may have: it is normalised
/// before use, which a length beyond this range would turn into zeros or infinities
/// (|[1e200, 1e200]|² overflows, and the wall collapsed to a point).
pub const DIRECTION_LENGTH: [f64; 2] = [1e-10, 1e10];

/// A direction of `d` finite components whose length lies in [`DIRECTION_LENGTH`].
pub(super) fn direction(path: &str, v: &[f64], d: usize) -> Check {
    vec_len(path, v, d)?;
    let len = v.iter().map(|x| x * x).sum::<f64>().sqrt();
    let [lo, hi] = DIRECTION_LENGTH;
    if len == 0.0 {
        return fail(path, "must not be zero: it is a direction, e.g. [0.0, 1.0]");
    }
    if !(len >= lo && len <= hi) {
        return fail(
            path,
            format!(
                "a direction of length {len:?}: give one of ordinary size (between {lo:?} and \
                 {hi:?}, e.g. [0.0, 1.0]); it is normalised before use"
            ),
        );
    }
    Ok(())
}

/// An initial velocity (of a region, a body or water): `d` finite components, its
/// speed within `simulation.max_speed`, which the stability guard would stop the first
/// step at.
pub(super) fn initial_velocity(path: &str, v: &[f64], s: &Scene) -> Check {
    vec_len(path, v, s.simulation.dimension)?;
    let speed = v.iter().map(|x| x * x).sum::<f64>().sqrt();
    if speed > s.simulation.max_speed {
        return fail(
            path,
            format!(
                "speed {speed} m/s exceeds simulation.max_speed = {} m/s (the stability \
                 guard's bound, which would stop the first step); raise max_speed for a \
                 faster start",
                s.simulation.max_speed
            ),
        );
    }
    Ok(())
}

/// A positive, finite number of normal size (a sub-normal value such as 1e-310 has
/// lost its precision and is no length, time or speed the solver can work with).
pub(super) fn positive(path: &str, x: f64) -> Check {
    if !(x.is_finite() && x > 0.0) {
        return fail(path, format!("must be a positive number, found {x:?}"));
    }
    if !x.is_normal() {
        return fail(
            path,
            format!("must be a positive number of normal size (≥ 2.2e-308), found {x:?}"),
        );
    }
    Ok(())
}

/// Densities the solver accepts (kg/m³): every real material, from light foams to the
/// densest metals (22,590 kg/m³), lies well inside. Far outside, the products the solver
/// forms (ρ², ρ c0², the particle mass ρ dp^D and its kernel sums) leave the range of
/// floating-point numbers and the run stops at its first step.
pub const DENSITY_RANGE: [f64; 2] = [1e-2, 1e5];

/// A density within [`DENSITY_RANGE`].
pub(super) fn density(path: &str, x: f64) -> Check {
    let [lo, hi] = DENSITY_RANGE;
    if !(x >= lo && x <= hi) {
        return fail(
            path,
            format!(
                "must lie in [{lo:?}, {hi:?}] kg/m³ (every real material does; far outside, \
                 the solver's products of densities overflow), found {x:?}"
            ),
        );
    }
    Ok(())
}

/// Check a shape against the scene dimension.
pub fn validate_shape(path: &str, s: &ShapeSpec, d: usize) -> Check {
    match s {
        ShapeSpec::Box { min, max } => {
            vec_len(&format!("{path}.min"), min, d)?;
            vec_len(&format!("{path}.max"), max, d)?;
            extents(path, min, max, d)?;
        }
        ShapeSpec::Cylinder {
            base,
            radius,
            height,
        } => {
            if d != 3 {
                return fail(
                    format!("{path}.type"),
                    "a cylinder needs a 3D scene; use a box in 2D",
                );
            }
            vec_len(&format!("{path}.base"), base, d)?;
            positive(&format!("{path}.radius"), *radius)?;
            positive(&format!("{path}.height"), *height)?;
        }
        ShapeSpec::Ring {
            center,
            inner_radius,
            radius,
        } => {
            vec_len(&format!("{path}.center"), center, d)?;
            positive(&format!("{path}.inner_radius"), *inner_radius)?;
            if !(radius.is_finite() && radius > inner_radius) {
                return fail(
                    format!("{path}.radius"),
                    format!("must exceed inner_radius = {inner_radius:?}, found {radius:?}"),
                );
            }
        }
        ShapeSpec::Sphere { center, radius } => {
            vec_len(&format!("{path}.center"), center, d)?;
            positive(&format!("{path}.radius"), *radius)?;
        }
        ShapeSpec::Polygon { vertices } => validate_polygon(path, vertices, d)?,
        ShapeSpec::Polyhedron { vertices } => {
            if d != 3 {
                return fail(
                    format!("{path}.type"),
                    "a polyhedron needs a 3D scene; use a polygon in 2D",
                );
            }
            if vertices.len() < 4 {
                return fail(
                    format!("{path}.vertices"),
                    "a polyhedron needs at least 4 vertices",
                );
            }
            for (i, v) in vertices.iter().enumerate() {
                vec_len(&format!("{path}.vertices[{i}]"), v, 3)?;
            }
        }
        ShapeSpec::Mesh {
            file,
            scale,
            offset,
        } => {
            if d != 3 {
                return fail(
                    format!("{path}.type"),
                    "a mesh needs a 3D scene; use a polygon in 2D",
                );
            }
            if file.is_empty() {
                return fail(format!("{path}.file"), "empty file name");
            }
            positive(&format!("{path}.scale"), *scale)?;
            if let Some(o) = offset {
                vec_len(&format!("{path}.offset"), o, 3)?;
            }
        }
        ShapeSpec::Heightmap { file, offset } => {
            if d != 3 {
                return fail(format!("{path}.type"), "a heightmap needs a 3D scene");
            }
            if file.is_empty() {
                return fail(format!("{path}.file"), "empty file name");
            }
            if let Some(o) = offset {
                vec_len(&format!("{path}.offset"), o, 3)?;
            }
        }
        ShapeSpec::Plane {
            point,
            normal,
            half_extent,
        } => validate_plane(path, point, normal, half_extent, d)?,
    }
    Ok(())
}

/// A box from `min` to `max` at `path`: each edge `max[k] − min[k]` positive, finite
/// and of normal size.
fn extents(path: &str, min: &[f64], max: &[f64], d: usize) -> Check {
    for k in 0..d {
        let size = max[k] - min[k];
        if max[k] <= min[k] {
            return fail(
                format!("{path}.max[{k}]"),
                format!("must exceed min[{k}] = {:?}", min[k]),
            );
        }
        if !(size.is_finite() && size.is_normal()) {
            return fail(
                format!("{path}.max[{k}]"),
                format!(
                    "the edge max[{k}] − min[{k}] = {size:?} m is not a finite length of \
                     normal size"
                ),
            );
        }
    }
    Ok(())
}

/// A polygon: a 2D scene, three vertices or more, simple (no edges crossing), non-zero
/// area.
fn validate_polygon(path: &str, vertices: &[Vec<f64>], d: usize) -> Check {
    if d != 2 {
        return fail(format!("{path}.type"), "a polygon needs a 2D scene");
    }
    if vertices.len() < 3 {
        return fail(
            format!("{path}.vertices"),
            "a polygon needs at least 3 vertices",
        );
    }
    for (i, v) in vertices.iter().enumerate() {
        vec_len(&format!("{path}.vertices[{i}]"), v, 2)?;
    }
    if let Some((i, j)) = super::polygon_check::crossing_edges(vertices) {
        let n = vertices.len();
        return fail(
            format!("{path}.vertices"),
            format!(
                "the polygon intersects itself: its edge from vertex {i} to {} meets its \
                 edge from vertex {j} to {}; list the vertices in order around the outline",
                (i + 1) % n,
                (j + 1) % n
            ),
        );
    }
    let mut area = 0.0;
    for i in 0..vertices.len() {
        let (a, b) = (&vertices[i], &vertices[(i + 1) % vertices.len()]);
        area += a[0] * b[1] - b[0] * a[1];
    }
    if area.abs() < 1e-300 {
        return fail(format!("{path}.vertices"), "polygon has zero area");
    }
    Ok(())
}

/// A plane patch: point, non-zero normal and D − 1 positive half extents.
fn validate_plane(
    path: &str,
    point: &[f64],
    normal: &[f64],
    half_extent: &[f64],
    d: usize,
) -> Check {
    vec_len(&format!("{path}.point"), point, d)?;
    direction(&format!("{path}.normal"), normal, d)?;
    if half_extent.len() != d - 1 {
        return fail(
            format!("{path}.half_extent"),
            format!(
                "expected {} value(s) for a {d}D plane patch, found {:?}",
                d - 1,
                half_extent.len()
            ),
        );
    }
    for (k, h) in half_extent.iter().enumerate() {
        positive(&format!("{path}.half_extent[{k}]"), *h)?;
    }
    Ok(())
}

/// A shape that must enclose particles (a region or a body): not a plane or terrain.
pub(super) fn validate_solid_shape(path: &str, s: &ShapeSpec, d: usize, role: &str) -> Check {
    validate_shape(path, s, d)?;
    if matches!(s, ShapeSpec::Plane { .. } | ShapeSpec::Heightmap { .. }) {
        return fail(
            format!("{path}.type"),
            format!(
                "a plane or heightmap cannot {role}; use box, cylinder, sphere, ring, polygon, polyhedron or mesh"
            ),
        );
    }
    Ok(())
}

/// Density, Young's modulus and Poisson's ratio of a material at `p`.
fn elastic_constants(p: &str, density: f64, youngs: f64, poisson: f64) -> Check {
    self::density(&format!("{p}.density"), density)?;
    positive(&format!("{p}.youngs_modulus"), youngs)?;
    if !(poisson > -1.0 && poisson < 0.5) {
        return fail(
            format!("{p}.poisson_ratio"),
            format!("must lie in (−1, 0.5), found {poisson:?}"),
        );
    }
    Ok(())
}

const FACES: [&str; 6] = ["-x", "+x", "-y", "+y", "-z", "+z"];

/// Validate the scene but its `[water]` table (`water_check`).
pub fn validate_grains(s: &Scene) -> Check {
    validate_simulation(s)?;
    validate_numerics(s)?;
    validate_contents(s)?;
    let names = validate_materials_and_regions(s)?;
    validate_walls(s)?;
    let d = s.simulation.dimension;
    validate_coarse(s, &names)?;
    for (i, pr) in s.probes.iter().enumerate() {
        vec_len(&format!("probes[{i}].position"), &pr.position, d)?;
    }
    for (i, g) in s.gauges.iter().enumerate() {
        vec_len(&format!("gauges[{i}].position"), &g.position, d)?;
        if s.water.is_none() {
            return fail(
                format!("gauges[{i}]"),
                "a water-level gauge reads water: the scene has no [water]",
            );
        }
    }
    if let Some(o) = &s.observe.runout_origin {
        vec_len("observe.runout_origin", o, d - 1)?;
    }
    if let Some(dir) = s.observe.runout_direction {
        if d != 2 || (dir != 1.0 && dir != -1.0) {
            return fail(
                "observe.runout_direction",
                "only for 2D scenes, and must be 1 or -1",
            );
        }
    }
    Ok(())
}

/// `[simulation]`: dimension, spacing, times and ratios.
fn validate_simulation(s: &Scene) -> Check {
    let sim = &s.simulation;
    let d = sim.dimension;
    if d != 2 && d != 3 {
        return fail(
            "simulation.dimension",
            format!("must be 2 or 3, found {d:?}"),
        );
    }
    vec_len("simulation.gravity", &sim.gravity, d)?;
    positive("simulation.end_time", sim.end_time)?;
    positive("simulation.dp", sim.dp)?;
    let volume = sim.dp.powi(d as i32);
    if volume < f64::MIN_POSITIVE {
        return fail(
            "simulation.dp",
            format!(
                "dp = {:?} m gives a particle volume dp^{d} = {volume:?}, below the smallest \
                 normal number: no scene holds so many particles; coarsen dp",
                sim.dp
            ),
        );
    }
    if !(sim.memory_budget.is_finite() && sim.memory_budget >= 0.0) {
        return fail(
            "simulation.memory_budget".to_string(),
            format!(
                "must be a size in bytes ≥ 0 (0: 80 % of the available memory), got {}",
                sim.memory_budget
            ),
        );
    }
    positive("simulation.output_interval", sim.output_interval)?;
    positive("simulation.max_speed", sim.max_speed)?;
    if !(sim.cfl > 0.0 && sim.cfl <= 2.0) {
        return fail(
            "simulation.cfl",
            format!(
                "must lie in (0, 2], found {:?} (0.4 is the default; the stable limit is \
                 measured by `granmix bench --suite stability`)",
                sim.cfl
            ),
        );
    }
    if let Some(r) = sim.settle_ratio {
        if !(r > 0.0 && r < 1.0) {
            return fail(
                "simulation.settle_ratio",
                format!("must lie in (0, 1), found {r:?}"),
            );
        }
    }
    if sim.settle_window.is_nan() || sim.settle_window < 0.0 {
        return fail("simulation.settle_window", "must be ≥ 0");
    }
    if sim.settle_min_time.is_nan() || sim.settle_min_time < 0.0 {
        return fail("simulation.settle_min_time", "must be ≥ 0");
    }
    if !(sim.gravity_ramp >= 0.0 && sim.gravity_ramp.is_finite()) {
        return fail("simulation.gravity_ramp", "must be ≥ 0 (seconds)");
    }
    if let Some(p) = &sim.perturbation {
        // ε ≥ 0.5 dp would let neighbours pass each other (their gap is dp)
        if !(p.amplitude > 0.0 && p.amplitude < 0.5 && p.amplitude.is_normal()) {
            return fail(
                "simulation.perturbation.amplitude",
                format!(
                    "must lie in (0, 0.5) (a fraction of dp; 1e-6 is the default, 1e-12 a \
                     round-off-level change), found {:?}",
                    p.amplitude
                ),
            );
        }
    }
    Ok(())
}

/// `[numerics]`.
fn validate_numerics(s: &Scene) -> Check {
    let n = &s.numerics;
    if let Some(eta) = n.eta {
        if !(eta >= 0.0 && eta.is_finite()) {
            return fail("numerics.eta", format!("must be ≥ 0, found {eta:?}"));
        }
    }
    if !(n.wall_friction >= 0.0 && n.wall_friction.is_finite()) {
        return fail(
            "numerics.wall_friction",
            format!(
                "must be ≥ 0 (a Coulomb coefficient μ_w; 0: frictionless walls), found {:?}",
                n.wall_friction
            ),
        );
    }
    if !(n.stress_diffusion >= 0.0 && n.stress_diffusion.is_finite()) {
        return fail("numerics.stress_diffusion", "must be ≥ 0");
    }
    if !(n.hourglass >= 0.0 && n.hourglass.is_finite()) {
        return fail("numerics.hourglass", "must be ≥ 0");
    }
    if n.hourglass_memory.is_nan() || n.hourglass_memory < 1.0 {
        return fail(
            "numerics.hourglass_memory",
            "must be ≥ 1 (acoustic times h/c0; inf keeps the penalty)",
        );
    }
    if !(n.smoothing_ratio >= 1.0 && n.smoothing_ratio <= 2.0) {
        return fail(
            "numerics.smoothing_ratio",
            format!("must lie in [1, 2], found {:?}", n.smoothing_ratio),
        );
    }
    if !(n.neighbor_skin >= 0.0 && n.neighbor_skin <= 2.0) {
        return fail(
            "numerics.neighbor_skin",
            format!(
                "must lie in [0, 2] (units of dp), found {:?}",
                n.neighbor_skin
            ),
        );
    }
    positive(
        "numerics.artificial_stress_exponent",
        n.artificial_stress_exponent,
    )?;
    if n.artificial_stress_epsilon.is_nan() || n.artificial_stress_epsilon < 0.0 {
        return fail("numerics.artificial_stress_epsilon", "must be ≥ 0");
    }
    validate_sleep(s)?;
    let need = (2.0 * n.smoothing_ratio).ceil() as usize;
    if n.wall_layers < need {
        return fail(
            "numerics.wall_layers",
            format!(
                "{} layer(s) do not cover the kernel support 2h = {:.2} dp; use at least {need}",
                n.wall_layers,
                2.0 * n.smoothing_ratio
            ),
        );
    }
    Ok(())
}

/// `numerics.sleep` and its thresholds.
fn validate_sleep(s: &Scene) -> Check {
    let n = &s.numerics;
    if let Some(v) = n.sleep_speed {
        positive("numerics.sleep_speed", v)?;
    }
    if let Some(a) = n.sleep_acceleration {
        positive("numerics.sleep_acceleration", a)?;
    }
    if let Some(k) = n.sleep_steps {
        if !(2..=u16::MAX as u32).contains(&k) {
            return fail(
                "numerics.sleep_steps",
                format!("must lie in [2, 65535] (steps), found {k}"),
            );
        }
    }
    // a gravity of NaN is refused with `simulation.gravity` before this
    if n.sleep && s.simulation.gravity_norm() == 0.0 {
        if n.sleep_speed.is_none() {
            return fail(
                "numerics.sleep_speed",
                "the default speed, 0.005 √(g dp), needs gravity; set the speed below \
                 which a particle may rest (m/s)",
            );
        }
        if n.sleep_acceleration.is_none() {
            return fail(
                "numerics.sleep_acceleration",
                "the default acceleration, |g|, needs gravity; set the acceleration \
                 below which a particle may rest (m/s²)",
            );
        }
    }
    if n.sleep && s.water.is_some() {
        return fail(
            "numerics.sleep",
            "resting particles do not sleep yet in a scene with water (the water's and \
             the pore water's sleep is still to come); remove `sleep = true`",
        );
    }
    Ok(())
}

/// Something to simulate, with what it needs.
fn validate_contents(s: &Scene) -> Check {
    let sim = &s.simulation;
    let water = s
        .water
        .as_ref()
        .is_some_and(|w| !w.regions.is_empty() || !w.inflows.is_empty());
    if s.regions.is_empty() && s.bodies.is_empty() && !water {
        return fail(
            "regions",
            "the scene holds nothing to simulate: add [[regions]] (fine grains), [[bodies]] (coarse grains) or [[water.regions]] (water)",
        );
    }
    if !s.regions.is_empty() && s.materials.is_empty() {
        return fail("materials", "at least one [[materials]] entry is required");
    }
    if !(sim.cfl_coarse > 0.0 && sim.cfl_coarse <= 1.0) {
        return fail(
            "simulation.cfl_coarse",
            format!("must lie in (0, 1], found {:?}", sim.cfl_coarse),
        );
    }
    Ok(())
}

/// `[[materials]]` and `[[regions]]`; the material names.
fn validate_materials_and_regions(s: &Scene) -> Result<HashSet<&str>, KeyError> {
    let d = s.simulation.dimension;
    let mut names = HashSet::new();
    for (i, m) in s.materials.iter().enumerate() {
        let p = format!("materials[{i}]");
        if !names.insert(m.name.as_str()) {
            return fail(
                format!("{p}.name"),
                format!("duplicate material name `{}`", m.name),
            );
        }
        elastic_constants(&p, m.density, m.youngs_modulus, m.poisson_ratio)?;
        match (m.friction_angle, &m.mu_i) {
            (None, None) => {
                return fail(
                    format!("{p}.friction_angle"),
                    "missing: give the friction angle φ in degrees (or a [materials.mu_i] \
                     block, whose μ_s sets it)",
                )
            }
            (Some(phi), _) if !(MIN_FRICTION_ANGLE..90.0).contains(&phi) => {
                return fail(
                    format!("{p}.friction_angle"),
                    format!(
                        "must lie in [{MIN_FRICTION_ANGLE:?}, 90) degrees (below, the yield \
                         surface's products underflow and the first step gives NaN), found \
                         {phi:?}"
                    ),
                );
            }
            _ => {}
        }
        if !(m.cohesion >= 0.0 && m.cohesion.is_finite()) {
            return fail(
                format!("{p}.cohesion"),
                format!("must be ≥ 0 Pa, found {:?}", m.cohesion),
            );
        }
        let phi = m.static_friction_angle();
        if m.friction_angle.is_none() && (phi.is_nan() || phi < MIN_FRICTION_ANGLE) {
            return fail(
                format!("{p}.mu_i.mu_s"),
                format!(
                    "gives a friction angle of {phi:?} degrees, below {MIN_FRICTION_ANGLE:?} \
                     (the yield surface's products underflow and the first step gives NaN)"
                ),
            );
        }
        if !(m.dilation_angle >= 0.0 && m.dilation_angle <= phi) {
            return fail(
                format!("{p}.dilation_angle"),
                format!(
                    "must lie in [0, friction_angle = {phi:?}] degrees, found {:?}",
                    m.dilation_angle
                ),
            );
        }
    }

    for (i, r) in s.regions.iter().enumerate() {
        let p = format!("regions[{i}]");
        if !(0.0..=0.3).contains(&r.jitter) {
            return fail(
                format!("{p}.jitter"),
                format!(
                    "must lie in [0, 0.3] (a fraction of dp), found {:?}",
                    r.jitter
                ),
            );
        }
        if !names.contains(r.material.as_str()) {
            let known: Vec<_> = s.materials.iter().map(|m| m.name.as_str()).collect();
            return fail(
                format!("{p}.material"),
                format!(
                    "unknown material `{}` (known: {})",
                    r.material,
                    known.join(", ")
                ),
            );
        }
        validate_solid_shape(&format!("{p}.shape"), &r.shape, d, "hold particles")?;
        if let Some(v) = &r.velocity {
            initial_velocity(&format!("{p}.velocity"), v, s)?;
        }
    }
    Ok(names)
}

/// `[[walls]]`, `[[barriers]]` and `[[containers]]`.
fn validate_walls(s: &Scene) -> Check {
    let d = s.simulation.dimension;
    let mut wall_names = HashSet::new();
    for (list, key) in [(&s.walls, "walls"), (&s.barriers, "barriers")] {
        for (i, w) in list.iter().enumerate() {
            let p = format!("{key}[{i}]");
            if !wall_names.insert(w.name.clone()) {
                return fail(
                    format!("{p}.name"),
                    format!("duplicate wall/barrier name `{}`", w.name),
                );
            }
            validate_shape(&format!("{p}.shape"), &w.shape, d)?;
            if let Some(v) = &w.velocity {
                vec_len(&format!("{p}.velocity"), v, d)?;
            }
            if let Some(m) = &w.move_between {
                if m.len() != 2 || m.iter().any(|t| !t.is_finite()) || m[0] >= m[1] {
                    return fail(
                        format!("{p}.move_between"),
                        "expected [start, stop] with start < stop (s)",
                    );
                }
                if w.velocity.is_none() {
                    return fail(
                        format!("{p}.move_between"),
                        "needs a `velocity` to move with",
                    );
                }
            }
            if let Some(v) = &w.reference_point {
                vec_len(&format!("{p}.reference_point"), v, d)?;
            }
            if let Some(n) = &w.panels {
                if key != "barriers" {
                    return fail(format!("{p}.panels"), "only barriers have panels");
                }
                if n.len() != d - 1 || n.iter().any(|&k| k == 0 || k > 64) {
                    return fail(
                        format!("{p}.panels"),
                        format!("expected {} panel count(s), each 1 to 64", d - 1),
                    );
                }
            }
            if w.input.is_some() {
                if key != "barriers" {
                    return fail(
                        format!("{p}.input"),
                        "only barriers can be driven by co-simulation inputs",
                    );
                }
                if w.velocity.is_some() {
                    return fail(
                        format!("{p}.input"),
                        "an input-driven barrier takes no prescribed `velocity`",
                    );
                }
            }
        }
    }
    for (i, c) in s.containers.iter().enumerate() {
        let p = format!("containers[{i}]");
        if !wall_names.insert(c.name.clone()) {
            return fail(
                format!("{p}.name"),
                format!("duplicate wall/barrier name `{}`", c.name),
            );
        }
        vec_len(&format!("{p}.min"), &c.min, d)?;
        vec_len(&format!("{p}.max"), &c.max, d)?;
        extents(&p, &c.min, &c.max, d)?;
        if let Some(open) = &c.open {
            for (k, f) in open.iter().enumerate() {
                let ok = FACES[..2 * d].contains(&f.as_str());
                if !ok {
                    return fail(
                        format!("{p}.open[{k}]"),
                        format!(
                            "unknown face `{f}`; use one of {}",
                            FACES[..2 * d].join(", ")
                        ),
                    );
                }
            }
        }
    }
    Ok(())
}

/// Solids, bodies and contact settings.
fn validate_coarse(s: &Scene, fine_names: &HashSet<&str>) -> Check {
    let d = s.simulation.dimension;
    let mut solids = HashSet::new();
    for (i, m) in s.solids.iter().enumerate() {
        let p = format!("solids[{i}]");
        if !solids.insert(m.name.as_str()) || fine_names.contains(m.name.as_str()) {
            return fail(
                format!("{p}.name"),
                format!("duplicate material name `{}`", m.name),
            );
        }
        elastic_constants(&p, m.density, m.youngs_modulus, m.poisson_ratio)?;
    }
    let mut names = HashSet::new();
    for (i, b) in s.bodies.iter().enumerate() {
        let p = format!("bodies[{i}]");
        if !names.insert(b.name.as_str()) {
            return fail(
                format!("{p}.name"),
                format!("duplicate body name `{}`", b.name),
            );
        }
        if !solids.contains(b.material.as_str()) {
            return fail(format!("{p}.material"), unknown_solid(s, &b.material));
        }
        validate_solid_shape(&format!("{p}.shape"), &b.shape, d, "be a body")?;
        if let Some(r) = &b.rotation {
            vec_len(&format!("{p}.rotation"), r, if d == 2 { 1 } else { 3 })?;
        }
        if let Some(v) = &b.velocity {
            initial_velocity(&format!("{p}.velocity"), v, s)?;
        }
        if let Some(w) = &b.angular_velocity {
            vec_len(
                &format!("{p}.angular_velocity"),
                w,
                if d == 2 { 1 } else { 3 },
            )?;
        }
        if b.fixed && b.model == BodyModel::Elastic {
            return fail(
                format!("{p}.fixed"),
                "only rigid bodies can be fixed; use model = \"rigid\" or a wall",
            );
        }
    }
    let c = &s.contact;
    if !(c.friction >= 0.0 && c.friction.is_finite()) {
        return fail(
            "contact.friction",
            format!("must be ≥ 0, found {:?}", c.friction),
        );
    }
    if !(c.mu_cf >= 0.0 && c.mu_cf.is_finite()) {
        return fail("contact.mu_cf", format!("must be ≥ 0, found {:?}", c.mu_cf));
    }
    if !(c.restitution > 0.0 && c.restitution <= 1.0) {
        return fail(
            "contact.restitution",
            format!("must lie in (0, 1], found {:?}", c.restitution),
        );
    }
    if let Some(k) = c.stiffness {
        positive("contact.stiffness", k)?;
        if c.model == ContactModel::HertzMindlin {
            return fail(
                "contact.stiffness",
                "a stiffness override applies to the spring-dashpot model only; Hertz–Mindlin takes its stiffness from the solids",
            );
        }
    }
    Ok(())
}

/// "unknown solid `name` (known solids: …)", with a hint when `name` is a fine-grain
/// material: bodies and rock fills take a `[[solids]]` entry.
pub fn unknown_solid(s: &Scene, name: &str) -> String {
    let known: Vec<_> = s.solids.iter().map(|m| m.name.as_str()).collect();
    let hint = if s.materials.iter().any(|m| m.name == name) {
        " (it is a fine-grain [[materials]] entry; bodies take a [[solids]] entry)"
    } else {
        ""
    };
    format!(
        "unknown solid `{name}`{hint} (known solids: {})",
        if known.is_empty() {
            "none".to_string()
        } else {
            known.join(", ")
        }
    )
}
