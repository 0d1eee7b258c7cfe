//! Simple polygons: no two edges of a polygon may cross or touch except adjacent edges
//! at their shared vertex. A self-intersecting polygon (a bow tie) has no inside that
//! the particle fill could agree on with its area, so it is refused with that reason.

/// The first pair of edges (i, j), i < j, that cross or touch, where edge k runs from
/// vertex k to vertex k + 1 (wrapping). Edges are swept in order of their lowest x, so
/// only edges whose x ranges overlap are compared.
pub fn crossing_edges(v: &[Vec<f64>]) -> Option<(usize, usize)> {
    let n = v.len();
    let p = |k: usize| [v[k % n][0], v[k % n][1]];
    let mut order: Vec<usize> = (0..n).collect();
    let xmin = |k: usize| p(k)[0].min(p(k + 1)[0]);
    let xmax = |k: usize| p(k)[0].max(p(k + 1)[0]);
    order.sort_by(|&a, &b| xmin(a).total_cmp(&xmin(b)));
    for (oi, &a) in order.iter().enumerate() {
        for &b in &order[oi + 1..] {
            if xmin(b) > xmax(a) {
                break;
            }
            let (i, j) = (a.min(b), a.max(b));
            let adjacent = j == i + 1 || (i == 0 && j == n - 1);
            let hit = if adjacent {
                // adjacent edges share a vertex; they meet elsewhere only when one
                // runs back along the other
                let (s, a, b) = if j == i + 1 {
                    (p(j), p(i), p(j + 1))
                } else {
                    (p(0), p(1), p(n - 1))
                };
                folds_back(s, a, b)
            } else {
                segments_meet(p(i), p(i + 1), p(j), p(j + 1))
            };
            if hit {
                return Some((i, j));
            }
        }
    }
    None
}

type P = [f64; 2];

fn cross(o: P, a: P, b: P) -> f64 {
    (a[0] - o[0]) * (b[1] - o[1]) - (a[1] - o[1]) * (b[0] - o[0])
}

/// Whether q, collinear with segment [a, b], lies on it.
fn on_segment(a: P, b: P, q: P) -> bool {
    q[0] >= a[0].min(b[0])
        && q[0] <= a[0].max(b[0])
        && q[1] >= a[1].min(b[1])
        && q[1] <= a[1].max(b[1])
}

/// Whether the closed segments [a, b] and [c, d] have a point in common.
fn segments_meet(a: P, b: P, c: P, d: P) -> bool {
    let (d1, d2) = (cross(c, d, a), cross(c, d, b));
    let (d3, d4) = (cross(a, b, c), cross(a, b, d));
    if ((d1 > 0.0 && d2 < 0.0) || (d1 < 0.0 && d2 > 0.0))
        && ((d3 > 0.0 && d4 < 0.0) || (d3 < 0.0 && d4 > 0.0))
    {
        return true;
    }
    (d1 == 0.0 && on_segment(c, d, a))
        || (d2 == 0.0 && on_segment(c, d, b))
        || (d3 == 0.0 && on_segment(a, b, c))
        || (d4 == 0.0 && on_segment(a, b, d))
}

/// Whether the edges from the shared vertex `s` to `a` and to `b` lie along one ray.
fn folds_back(s: P, a: P, b: P) -> bool {
    let (u, w) = ([a[0] - s[0], a[1] - s[1]], [b[0] - s[0], b[1] - s[1]]);
    u[0] * w[1] - u[1] * w[0] == 0.0 && u[0] * w[0] + u[1] * w[1] > 0.0
}

#[cfg(test)]
mod tests {
    use super::crossing_edges;

    fn poly(v: &[[f64; 2]]) -> Vec<Vec<f64>> {
        v.iter().map(|p| p.to_vec()).collect()
    }

    #[test]
    fn bow_ties_cross_and_simple_polygons_do_not() {
        let square = poly(&[[0.0, 0.0], [1.0, 0.0], [1.0, 1.0], [0.0, 1.0]]);
        assert_eq!(crossing_edges(&square), None);
        let slope = poly(&[[0.0, 0.0], [110.0, 0.0], [80.0, 40.0], [0.0, 40.0]]);
        assert_eq!(crossing_edges(&slope), None);
        let bow = poly(&[[0.0, 0.0], [0.2, 0.1], [0.2, 0.0], [0.0, 0.05]]);
        assert_eq!(crossing_edges(&bow), Some((0, 2)));
        let symmetric = poly(&[[0.0, 0.0], [0.2, 0.1], [0.2, 0.0], [0.0, 0.1]]);
        assert!(crossing_edges(&symmetric).is_some());
        // a spike folding back along its own edge
        let spike = poly(&[[0.0, 0.0], [2.0, 0.0], [1.0, 0.0], [1.0, 1.0]]);
        assert!(crossing_edges(&spike).is_some());
        // a vertex touching a non-adjacent edge
        let touch = poly(&[[0.0, 0.0], [2.0, 0.0], [1.0, 1.0], [1.0, 0.0], [0.0, 1.0]]);
        assert!(crossing_edges(&touch).is_some());
    }
}
