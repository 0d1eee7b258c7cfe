//! Where regions lie: a region that no container can hold is refused at load.

use crate::geometry::Shape;
use crate::scene::{ContainerSpec, KeyError, Scene};

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
