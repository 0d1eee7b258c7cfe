//! A shape filled column by column (`fill = "columns"` of a water region): each
//! vertical column of width dp of the lattice fill is re-spaced evenly between the
//! shape's bottom and top in that column, so that the particles meet a sloping or wavy
//! surface exactly instead of to within a spacing. A standing wave's initial
//! elevation A cos(kx) with A ~ dp is then the mode itself, not a staircase.

use crate::geometry::Shape;
use crate::numerics::math::{Real, Vect};

/// One particle of a column fill: its position, its volume (dp^(d−1) times the
/// column's spacing) and the height of its column's surface.
#[derive(Clone, Copy, Debug, PartialEq)]
pub(super) struct ColumnParticle<const D: usize> {
    pub pos: Vect<D>,
    pub volume: Real,
    pub surface: Real,
}

/// The column fill of `shape` at spacing `dp`, columns along `axis` (the vertical).
/// Each run of lattice points in a column (consecutive points at most 1.5 dp apart)
/// becomes n = max(1, round(depth/dp)) particles spaced depth/n, where the run's
/// bottom and top are where the shape's signed distance changes sign within a spacing
/// of its outermost lattice points (bisection).
pub(super) fn column_fill<const D: usize>(
    shape: &Shape<D>,
    dp: Real,
    axis: usize,
) -> Vec<ColumnParticle<D>> {
    let mut pts = shape.fill(dp);
    // columns in lattice order: by the other coordinates, then upwards
    pts.sort_by(|a, b| {
        (0..D)
            .filter(|&k| k != axis)
            .map(|k| a[k].total_cmp(&b[k]))
            .chain([a[axis].total_cmp(&b[axis])])
            .find(|o| o.is_ne())
            .unwrap_or(std::cmp::Ordering::Equal)
    });
    let same_column = |a: &Vect<D>, b: &Vect<D>| (0..D).all(|k| k == axis || a[k] == b[k]);
    let mut out = Vec::with_capacity(pts.len());
    let mut start = 0;
    while start < pts.len() {
        let mut end = start + 1;
        while end < pts.len()
            && same_column(&pts[start], &pts[end])
            && pts[end][axis] - pts[end - 1][axis] <= 1.5 * dp
        {
            end += 1;
        }
        let (lo, hi) = (pts[start], pts[end - 1]);
        let bottom = boundary(shape, &lo, axis, -dp);
        let top = boundary(shape, &hi, axis, dp);
        let n = ((top - bottom) / dp).round().max(1.0) as usize;
        let spacing = (top - bottom) / n as Real;
        let volume = dp.powi(D as i32 - 1) * spacing;
        for j in 0..n {
            let mut pos = lo;
            pos[axis] = bottom + (j as Real + 0.5) * spacing;
            out.push(ColumnParticle {
                pos,
                volume,
                surface: top,
            });
        }
        start = end;
    }
    out
}

/// Where the shape's surface lies along `axis` between the inside point `x` and
/// `x + step` (outside, or the farthest the shape reaches there): 60 bisections.
fn boundary<const D: usize>(shape: &Shape<D>, x: &Vect<D>, axis: usize, step: Real) -> Real {
    let (mut inside, mut outside) = (0.0, step);
    let at = |s: Real| {
        let mut p = *x;
        p[axis] += s;
        shape.sdf(&p)
    };
    if at(outside) < 0.0 {
        return x[axis] + step;
    }
    for _ in 0..60 {
        let mid = 0.5 * (inside + outside);
        if at(mid) < 0.0 {
            inside = mid;
        } else {
            outside = mid;
        }
    }
    x[axis] + 0.5 * (inside + outside)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::scene::ShapeSpec;

    fn polygon(v: Vec<[f64; 2]>) -> Shape<2> {
        let vertices = v.into_iter().map(|p| p.to_vec()).collect();
        Shape::<2>::from_spec(&ShapeSpec::Polygon { vertices }, &Default::default())
    }

    /// A box fills as the lattice does: the same count, spacing dp, the box's top.
    #[test]
    fn a_box_fills_as_the_lattice() {
        let b = polygon(vec![[0.0, 0.0], [0.1, 0.0], [0.1, 0.05], [0.0, 0.05]]);
        let c = column_fill(&b, 0.01, 1);
        assert_eq!(c.len(), 50);
        for p in &c {
            assert!((p.volume - 1e-4).abs() < 1e-15, "{p:?}");
            assert!((p.surface - 0.05).abs() < 1e-12);
        }
        let mut ys: Vec<f64> = c
            .iter()
            .filter(|p| p.pos[0] < 0.01)
            .map(|p| p.pos[1])
            .collect();
        ys.sort_by(f64::total_cmp);
        assert!((ys[0] - 0.005).abs() < 1e-12 && (ys[4] - 0.045).abs() < 1e-12);
    }

    /// A sloping surface is met exactly: each column's particles fill its depth, their
    /// volumes add up to the shape's area, and the top particle lies half a spacing
    /// below the surface.
    #[test]
    fn a_sloping_surface_is_met() {
        // a trapezoid 0.1 wide, 0.050 deep at x = 0 and 0.056 at x = 0.1
        let t = polygon(vec![[0.0, 0.0], [0.1, 0.0], [0.1, 0.056], [0.0, 0.05]]);
        let c = column_fill(&t, 0.01, 1);
        let area: f64 = c.iter().map(|p| p.volume).sum();
        assert!((area - 0.0053).abs() < 1e-12, "{area}");
        for p in &c {
            let surface = 0.05 + 0.06 * p.pos[0];
            assert!((p.surface - surface).abs() < 1e-12, "{p:?}");
        }
        let top = c
            .iter()
            .filter(|p| p.pos[0] > 0.09)
            .map(|p| p.pos[1])
            .fold(0.0, f64::max);
        let spacing = (0.05 + 0.06 * 0.095) / 6.0;
        assert!((top - (0.0557 - 0.5 * spacing)).abs() < 1e-12, "{top}");
    }
}
