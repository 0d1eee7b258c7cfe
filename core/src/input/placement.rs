//! Where regions lie: a region that no container can hold is refused at load, and so
//! are two regions of the same family (fine grains, or water) that overlap: each
//! fills its own lattice, so the overlap would hold two particles on every site, and
//! the first step blows up on pairs at zero distance.

use super::grid_probe;
use crate::geometry::Shape;
use crate::scene::{ContainerSpec, KeyError, Scene, ShapeSpec};

const AXES: [&str; 3] = ["x", "y", "z"];

/// Refuse a region lying entirely beyond a closed face of every container (its grains
/// could never reach any container's inside). A region above an open face (poured in)
/// or straddling a wall is accepted. Scenes without containers are not checked.
pub fn check_regions(scene: &Scene) -> Result<(), KeyError> {
    match scene.simulation.dimension {
        2 => check_in::<2>(scene),
        _ => check_in::<3>(scene),
    }
}

fn check_in<const D: usize>(scene: &Scene) -> Result<(), KeyError> {
    let fine: Vec<(String, &str, &ShapeSpec)> = (scene.regions.iter().enumerate())
        .map(|(i, r)| (format!("regions[{i}]"), r.name.as_str(), &r.shape))
        .collect();
    overlaps::<D>(scene, &fine)?;
    if let Some(w) = &scene.water {
        let water: Vec<(String, &str, &ShapeSpec)> = (w.regions.iter().enumerate())
            .map(|(i, r)| (format!("water.regions[{i}]"), r.name.as_str(), &r.shape))
            .collect();
        overlaps::<D>(scene, &water)?;
    }
    if scene.containers.is_empty() {
        return Ok(());
    }
    for (i, r) in scene.regions.iter().enumerate() {
        let (lo, hi) = Shape::<D>::from_spec(&r.shape, &scene.assets).bounds();
        let beyond: Vec<String> = scene
            .containers
            .iter()
            .filter_map(|c| closed_face_beyond(c, lo.as_slice(), hi.as_slice(), D))
            .collect();
        if beyond.len() == scene.containers.len() {
            return Err(KeyError::new(
                format!("regions[{i}].shape"),
                format!(
                    "region `{}` lies entirely outside {}; move it inside or open that face",
                    r.name,
                    beyond.join(" and ")
                ),
            ));
        }
    }
    Ok(())
}

/// Refuse the first two of `regions` (key path, name, shape) that overlap: a point of
/// a grid over the overlap of their bounding boxes deeper than dp/2 inside both.
/// Regions that only touch (a layer on a layer) pass.
fn overlaps<const D: usize>(
    scene: &Scene,
    regions: &[(String, &str, &ShapeSpec)],
) -> Result<(), KeyError> {
    let margin = 0.5 * scene.simulation.dp;
    let shapes: Vec<Shape<D>> = regions
        .iter()
        .map(|r| Shape::<D>::from_spec(r.2, &scene.assets))
        .collect();
    let bounds: Vec<_> = shapes.iter().map(|s| s.bounds()).collect();
    for i in 0..shapes.len() {
        for j in i + 1..shapes.len() {
            let lo = bounds[i].0.sup(&bounds[j].0);
            let hi = bounds[i].1.inf(&bounds[j].1);
            if (0..D).any(|k| hi[k] - lo[k] <= 2.0 * margin) {
                continue;
            }
            let (a, b) = (&shapes[i], &shapes[j]);
            let hit = grid_probe::first((lo, hi), |p| a.sdf(p) < -margin && b.sdf(p) < -margin);
            if let Some(p) = hit {
                return Err(KeyError::new(
                    format!("{}.shape", regions[j].0),
                    format!(
                        "regions `{}` and `{}` overlap (at {:?}): each fills its own lattice, \
                         so the overlap would hold two particles on every site; make them \
                         meet at a face, or cut one out of the other",
                        regions[i].1,
                        regions[j].1,
                        p.as_slice()
                    ),
                ));
            }
        }
    }
    Ok(())
}

/// The closed face of `c` that the box [lo, hi] lies wholly beyond, described.
fn closed_face_beyond(c: &ContainerSpec, lo: &[f64], hi: &[f64], d: usize) -> Option<String> {
    let default_open = [if d == 2 { "+y" } else { "+z" }.to_string()];
    let open = c.open.as_deref().unwrap_or(&default_open);
    for a in 0..d {
        for (side, beyond, at) in [
            ("-", hi[a] <= c.min[a], c.min[a]),
            ("+", lo[a] >= c.max[a], c.max[a]),
        ] {
            let face = format!("{side}{}", AXES[a]);
            if beyond && !open.contains(&face) {
                return Some(format!(
                    "container `{}` (beyond its closed {face} face at {} = {at})",
                    c.name, AXES[a]
                ));
            }
        }
    }
    None
}
