//! Triangle meshes (OBJ, STL) as solid shapes: signed distance from the nearest
//! triangle, with the sign from the generalised winding number (robust to small gaps
//! and any orientation of the triangles), and the enclosed volume.

use crate::numerics::math::Real;
use crate::shapes::shape_file::{FormatError, ShapeFileError};
use nalgebra::Vector3;
use std::f64::consts::PI;

type V3 = Vector3<Real>;

/// A closed triangle mesh in 3D.
#[derive(Clone, Debug)]
pub struct TriMesh {
    pub tris: Vec<[V3; 3]>,
    pub lo: V3,
    pub hi: V3,
}

impl TriMesh {
    fn new(tris: Vec<[V3; 3]>) -> Result<Self, FormatError> {
        if tris.len() < 4 {
            return Err(FormatError::Whole(format!(
                "a closed mesh needs at least 4 triangles, found {}",
                tris.len()
            )));
        }
        let mut lo = V3::repeat(Real::INFINITY);
        let mut hi = V3::repeat(Real::NEG_INFINITY);
        for t in &tris {
            for v in t {
                if !v.iter().all(|x| x.is_finite()) {
                    return Err(FormatError::Whole(
                        "a vertex coordinate is not a finite number".into(),
                    ));
                }
                lo = lo.inf(v);
                hi = hi.sup(v);
            }
        }
        Ok(TriMesh { tris, lo, hi })
    }

    /// Read an `.obj` or `.stl` (ASCII or binary) file, chosen by extension (a regular
    /// file of at most [`MAX_SHAPE_FILE_BYTES`](crate::numerics::capped_read::MAX_SHAPE_FILE_BYTES)).
    pub fn load(path: &std::path::Path) -> Result<Self, ShapeFileError> {
        let file = path.display().to_string();
        let cap = crate::numerics::capped_read::MAX_SHAPE_FILE_BYTES;
        let bytes = crate::numerics::capped_read::read_capped(path, cap).map_err(|source| {
            ShapeFileError::Read {
                file: file.clone(),
                source,
            }
        })?;
        let ext = path
            .extension()
            .and_then(|e| e.to_str())
            .unwrap_or("")
            .to_ascii_lowercase();
        match ext.as_str() {
            "obj" => parse_obj(&String::from_utf8_lossy(&bytes)),
            "stl" => parse_stl(&bytes),
            _ => return Err(ShapeFileError::UnknownFormat { file, ext }),
        }
        .map_err(|error| ShapeFileError::Format { file, error })
    }

    /// Generalised winding number at `p` (≈ 1 inside, 0 outside).
    pub fn winding(&self, p: &V3) -> Real {
        let mut w = 0.0;
        for t in &self.tris {
            let (a, b, c) = (t[0] - p, t[1] - p, t[2] - p);
            let (la, lb, lc) = (a.norm(), b.norm(), c.norm());
            let num = a.dot(&b.cross(&c));
            let den = la * lb * lc + a.dot(&b) * lc + a.dot(&c) * lb + b.dot(&c) * la;
            w += 2.0 * num.atan2(den);
        }
        w / (4.0 * PI)
    }

    /// Signed distance (negative inside).
    pub fn sdf(&self, p: &V3) -> Real {
        let d = self
            .tris
            .iter()
            .map(|t| point_triangle_distance2(p, t))
            .fold(Real::INFINITY, Real::min)
            .sqrt();
        if self.winding(p).abs() > 0.5 {
            -d
        } else {
            d
        }
    }

    /// Enclosed volume (divergence theorem; orientation-independent magnitude).
    pub fn volume(&self) -> Real {
        self.tris
            .iter()
            .map(|t| t[0].dot(&t[1].cross(&t[2])) / 6.0)
            .sum::<Real>()
            .abs()
    }

    /// The mesh scaled about the origin, then shifted.
    pub fn transformed(&self, scale: Real, offset: &V3) -> Self {
        let f = |v: &V3| v * scale + offset;
        let tris: Vec<[V3; 3]> = self
            .tris
            .iter()
            .map(|t| [f(&t[0]), f(&t[1]), f(&t[2])])
            .collect();
        let (lo, hi) = if scale >= 0.0 {
            (f(&self.lo), f(&self.hi))
        } else {
            (f(&self.hi), f(&self.lo))
        };
        TriMesh { tris, lo, hi }
    }
}

/// Squared distance from `p` to a triangle (Ericson, Real-Time Collision Detection).
fn point_triangle_distance2(p: &V3, t: &[V3; 3]) -> Real {
    let (a, b, c) = (t[0], t[1], t[2]);
    let ab = b - a;
    let ac = c - a;
    let ap = p - a;
    let d1 = ab.dot(&ap);
    let d2 = ac.dot(&ap);
    if d1 <= 0.0 && d2 <= 0.0 {
        return ap.norm_squared();
    }
    let bp = p - b;
    let d3 = ab.dot(&bp);
    let d4 = ac.dot(&bp);
    if d3 >= 0.0 && d4 <= d3 {
        return bp.norm_squared();
    }
    let vc = d1 * d4 - d3 * d2;
    if vc <= 0.0 && d1 >= 0.0 && d3 <= 0.0 {
        let v = d1 / (d1 - d3);
        return (p - (a + ab * v)).norm_squared();
    }
    let cp = p - c;
    let d5 = ab.dot(&cp);
    let d6 = ac.dot(&cp);
    if d6 >= 0.0 && d5 <= d6 {
        return cp.norm_squared();
    }
    let vb = d5 * d2 - d1 * d6;
    if vb <= 0.0 && d2 >= 0.0 && d6 <= 0.0 {
        let w = d2 / (d2 - d6);
        return (p - (a + ac * w)).norm_squared();
    }
    let va = d3 * d6 - d5 * d4;
    if va <= 0.0 && (d4 - d3) >= 0.0 && (d5 - d6) >= 0.0 {
        let w = (d4 - d3) / ((d4 - d3) + (d5 - d6));
        return (p - (b + (c - b) * w)).norm_squared();
    }
    let denom = 1.0 / (va + vb + vc);
    let v = vb * denom;
    let w = vc * denom;
    (p - (a + ab * v + ac * w)).norm_squared()
}

/// The three coordinates that follow a vertex keyword on line index `ln`.
fn vertex<'a>(it: impl Iterator<Item = &'a str>, ln: usize) -> Result<V3, FormatError> {
    let c: Vec<Real> = it
        .take(3)
        .map(|s| s.parse::<Real>())
        .collect::<Result<_, _>>()
        .map_err(|e| FormatError::at(ln, format!("bad vertex: {e}")))?;
    if c.len() != 3 {
        return Err(FormatError::at(ln, "a vertex needs 3 coordinates"));
    }
    Ok(V3::new(c[0], c[1], c[2]))
}

/// Wavefront OBJ: `v x y z` and `f i j k …` (polygons fanned into triangles; `i/t/n`
/// and negative indices accepted).
pub fn parse_obj(text: &str) -> Result<TriMesh, FormatError> {
    let mut verts: Vec<V3> = Vec::new();
    let mut tris = Vec::new();
    for (ln, line) in text.lines().enumerate() {
        let mut it = line.split_whitespace();
        match it.next() {
            Some("v") => verts.push(vertex(it, ln)?),
            Some("f") => {
                let mut idx = Vec::new();
                for tok in it {
                    let first = tok.split('/').next().unwrap_or("");
                    let i: i64 = first
                        .parse()
                        .map_err(|_| FormatError::at(ln, format!("bad face index `{tok}`")))?;
                    let k = if i < 0 { verts.len() as i64 + i } else { i - 1 };
                    if k < 0 || k as usize >= verts.len() {
                        return Err(FormatError::at(ln, format!("face index {i} out of range")));
                    }
                    idx.push(k as usize);
                }
                if idx.len() < 3 {
                    return Err(FormatError::at(ln, "a face needs 3 vertices"));
                }
                for k in 1..idx.len() - 1 {
                    tris.push([verts[idx[0]], verts[idx[k]], verts[idx[k + 1]]]);
                }
            }
            _ => {}
        }
    }
    TriMesh::new(tris)
}

/// STL, binary or ASCII.
pub fn parse_stl(bytes: &[u8]) -> Result<TriMesh, FormatError> {
    if bytes.len() >= 84 {
        let n = u32::from_le_bytes([bytes[80], bytes[81], bytes[82], bytes[83]]) as usize;
        if 84 + 50 * n == bytes.len() {
            let mut tris = Vec::with_capacity(n);
            for k in 0..n {
                let base = 84 + 50 * k + 12;
                let f = |o: usize| {
                    let s = base + 4 * o;
                    f32::from_le_bytes([bytes[s], bytes[s + 1], bytes[s + 2], bytes[s + 3]]) as Real
                };
                tris.push([
                    V3::new(f(0), f(1), f(2)),
                    V3::new(f(3), f(4), f(5)),
                    V3::new(f(6), f(7), f(8)),
                ]);
            }
            return TriMesh::new(tris);
        }
    }
    let text = String::from_utf8_lossy(bytes);
    let mut tris = Vec::new();
    let mut cur: Vec<V3> = Vec::new();
    for (ln, line) in text.lines().enumerate() {
        let mut it = line.split_whitespace();
        if it.next() == Some("vertex") {
            cur.push(vertex(it, ln)?);
            if cur.len() == 3 {
                tris.push([cur[0], cur[1], cur[2]]);
                cur.clear();
            }
        }
    }
    TriMesh::new(tris)
}

#[cfg(test)]
mod tests {
    use super::*;

    const CUBE: &str = "v 0 0 0\nv 1 0 0\nv 1 1 0\nv 0 1 0\nv 0 0 1\nv 1 0 1\nv 1 1 1\nv 0 1 1\n\
f 1 3 2\nf 1 4 3\nf 5 6 7\nf 5 7 8\nf 1 2 6\nf 1 6 5\nf 2 3 7\nf 2 7 6\nf 3 4 8\nf 3 8 7\nf 4 1 5\nf 4 5 8\n";

    #[test]
    fn unit_cube_distance_sign_and_volume() {
        let m = parse_obj(CUBE).unwrap();
        assert!((m.volume() - 1.0).abs() < 1e-12);
        assert!((m.sdf(&V3::new(0.5, 0.5, 0.5)) + 0.5).abs() < 1e-12);
        assert!((m.sdf(&V3::new(0.5, 0.5, 1.25)) - 0.25).abs() < 1e-12);
        assert!((m.sdf(&V3::new(0.5, 0.2, 0.5)) + 0.2).abs() < 1e-12);
        assert!((m.sdf(&V3::new(2.0, 2.0, 0.5)) - 2f64.sqrt()).abs() < 1e-12);
    }

    #[test]
    fn bad_obj_is_an_error() {
        assert!(parse_obj("v 0 0 0\nf 1 2 3\n").is_err());
        assert!(parse_obj("v 0 0 x\n").is_err());
    }
}
