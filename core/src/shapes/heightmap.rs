//! Terrain from ESRI ASCII grids (`.asc`): bilinear heights and a signed distance
//! (negative below the ground), for terrain walls.

use crate::numerics::math::Real;
use crate::shapes::shape_file::{FormatError, ShapeFileError};

/// A regular elevation grid.
#[derive(Clone, Debug)]
pub struct Heightmap {
    pub ncols: usize,
    pub nrows: usize,
    /// Centre of the south-west cell (m).
    pub x0: Real,
    pub y0: Real,
    pub cell: Real,
    /// Elevations, row 0 = southernmost.
    pub z: Vec<Real>,
    pub zmin: Real,
    pub zmax: Real,
}

impl Heightmap {
    /// Read an ESRI ASCII grid (a regular file of at most
    /// [`MAX_SHAPE_FILE_BYTES`](crate::numerics::capped_read::MAX_SHAPE_FILE_BYTES)).
    pub fn load(path: &std::path::Path) -> Result<Self, ShapeFileError> {
        let file = path.display().to_string();
        let cap = crate::numerics::capped_read::MAX_SHAPE_FILE_BYTES;
        let text = crate::numerics::capped_read::read_capped_text(path, cap).map_err(|source| {
            ShapeFileError::Read {
                file: file.clone(),
                source,
            }
        })?;
        parse_esri_ascii(&text).map_err(|error| ShapeFileError::Format { file, error })
    }

    /// Height at (x, y), bilinear, clamped to the grid's edge beyond it.
    pub fn height(&self, x: Real, y: Real) -> Real {
        let fx = ((x - self.x0) / self.cell).clamp(0.0, (self.ncols - 1) as Real);
        let fy = ((y - self.y0) / self.cell).clamp(0.0, (self.nrows - 1) as Real);
        let (i, j) = (
            (fx.floor() as usize).min(self.ncols.saturating_sub(2)),
            (fy.floor() as usize).min(self.nrows.saturating_sub(2)),
        );
        let (tx, ty) = (fx - i as Real, fy - j as Real);
        let at = |i: usize, j: usize| self.z[j * self.ncols + i];
        let i1 = (i + 1).min(self.ncols - 1);
        let j1 = (j + 1).min(self.nrows - 1);
        (1.0 - ty) * ((1.0 - tx) * at(i, j) + tx * at(i1, j))
            + ty * ((1.0 - tx) * at(i, j1) + tx * at(i1, j1))
    }

    /// Signed distance to the ground, (z − h)/√(1 + |∇h|²): exact on planes.
    pub fn sdf(&self, x: Real, y: Real, z: Real) -> Real {
        let e = 0.25 * self.cell;
        let gx = (self.height(x + e, y) - self.height(x - e, y)) / (2.0 * e);
        let gy = (self.height(x, y + e) - self.height(x, y - e)) / (2.0 * e);
        (z - self.height(x, y)) / (1.0 + gx * gx + gy * gy).sqrt()
    }

    /// The ground's upward unit normal under (x, y), (−∂h/∂x, −∂h/∂y, 1)/√(1 + |∇h|²)
    /// with the slopes [`sdf`](Self::sdf) takes: the direction of its gradient on the
    /// surface, in four height lookups where central differences of the distance take
    /// thirty.
    pub fn normal(&self, x: Real, y: Real) -> [Real; 3] {
        let e = 0.25 * self.cell;
        let gx = (self.height(x + e, y) - self.height(x - e, y)) / (2.0 * e);
        let gy = (self.height(x, y + e) - self.height(x, y - e)) / (2.0 * e);
        let n = (1.0 + gx * gx + gy * gy).sqrt();
        [-gx / n, -gy / n, 1.0 / n]
    }

    /// Horizontal extent [x_lo, x_hi] × [y_lo, y_hi] of the cell centres.
    pub fn extent(&self) -> (Real, Real, Real, Real) {
        (
            self.x0,
            self.x0 + (self.ncols - 1) as Real * self.cell,
            self.y0,
            self.y0 + (self.nrows - 1) as Real * self.cell,
        )
    }
}

/// Parse the ESRI ASCII grid format: a header (`ncols`, `nrows`, `xllcorner` or
/// `xllcenter`, `yllcorner` or `yllcenter`, `cellsize`, optional `nodata_value`) and
/// `nrows` rows of `ncols` values, north first. NODATA cells are not allowed in
/// terrain walls.
pub fn parse_esri_ascii(text: &str) -> Result<Heightmap, FormatError> {
    let whole = FormatError::Whole;
    let mut tokens = text.split_whitespace().peekable();
    let mut head = std::collections::BTreeMap::new();
    while let Some(t) = tokens.peek() {
        if t.parse::<f64>().is_ok() {
            break;
        }
        let key = tokens.next().unwrap_or_default().to_ascii_lowercase();
        let val: f64 = tokens
            .next()
            .ok_or_else(|| whole(format!("header `{key}` has no value")))?
            .parse()
            .map_err(|_| whole(format!("header `{key}` is not a number")))?;
        head.insert(key, val);
    }
    let get = |k: &str| head.get(k).copied();
    let ncols = get("ncols").ok_or_else(|| whole("missing header `ncols`".into()))? as usize;
    let nrows = get("nrows").ok_or_else(|| whole("missing header `nrows`".into()))? as usize;
    let cell = get("cellsize").ok_or_else(|| whole("missing header `cellsize`".into()))?;
    if ncols < 2 || nrows < 2 || cell.is_nan() || cell <= 0.0 {
        return Err(whole("need ncols ≥ 2, nrows ≥ 2 and cellsize > 0".into()));
    }
    let x0 = match (get("xllcenter"), get("xllcorner")) {
        (Some(c), _) => c,
        (None, Some(c)) => c + 0.5 * cell,
        _ => return Err(whole("missing header `xllcorner` or `xllcenter`".into())),
    };
    let y0 = match (get("yllcenter"), get("yllcorner")) {
        (Some(c), _) => c,
        (None, Some(c)) => c + 0.5 * cell,
        _ => return Err(whole("missing header `yllcorner` or `yllcenter`".into())),
    };
    let nodata = get("nodata_value");
    let vals: Vec<f64> = tokens
        .map(|t| {
            t.parse::<f64>()
                .map_err(|_| whole(format!("bad elevation `{t}`")))
        })
        .collect::<Result<_, _>>()?;
    if vals.len() != ncols * nrows {
        return Err(whole(format!(
            "expected {} elevations ({nrows} rows × {ncols} columns), found {}",
            ncols * nrows,
            vals.len()
        )));
    }
    let mut z = vec![0.0; ncols * nrows];
    for r in 0..nrows {
        for c in 0..ncols {
            let v = vals[r * ncols + c];
            if Some(v) == nodata || !v.is_finite() {
                return Err(whole(format!("NODATA at row {}, column {}", r + 1, c + 1)));
            }
            // file row 0 is the north edge
            z[(nrows - 1 - r) * ncols + c] = v;
        }
    }
    let zmin = z.iter().copied().fold(Real::INFINITY, Real::min);
    let zmax = z.iter().copied().fold(Real::NEG_INFINITY, Real::max);
    Ok(Heightmap {
        ncols,
        nrows,
        x0,
        y0,
        cell,
        z,
        zmin,
        zmax,
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn tilted_plane_heights_and_distance() {
        // z = 0.5 x over a 3 × 3 grid of 1 m cells, corner at (0, 0)
        let g = "ncols 3\nnrows 3\nxllcorner 0\nyllcorner 0\ncellsize 1\nNODATA_value -9999\n\
                 0.25 0.75 1.25\n0.25 0.75 1.25\n0.25 0.75 1.25\n";
        let h = parse_esri_ascii(g).unwrap();
        assert!((h.height(1.0, 1.5) - 0.5).abs() < 1e-12);
        let d = h.sdf(1.0, 1.5, 1.5);
        assert!((d - 1.0 / (1.25f64).sqrt()).abs() < 1e-9, "{d}");
        assert!(parse_esri_ascii("ncols 2\nnrows 2\ncellsize 1\n1 2 3 4").is_err());
        // the plane's normal (−0.5, 0, 1)/√1.25, and the distance's gradient agrees
        let n = h.normal(1.0, 1.5);
        let s = 1.25f64.sqrt();
        for (a, b) in n.iter().zip([-0.5 / s, 0.0, 1.0 / s]) {
            assert!((a - b).abs() < 1e-12, "{n:?}");
        }
        let e = 1e-6;
        let g = [
            (h.sdf(1.0 + e, 1.5, 1.5) - h.sdf(1.0 - e, 1.5, 1.5)) / (2.0 * e),
            (h.sdf(1.0, 1.5 + e, 1.5) - h.sdf(1.0, 1.5 - e, 1.5)) / (2.0 * e),
            (h.sdf(1.0, 1.5, 1.5 + e) - h.sdf(1.0, 1.5, 1.5 - e)) / (2.0 * e),
        ];
        for (a, b) in n.iter().zip(g) {
            assert!((a - b).abs() < 1e-6, "{n:?} against {g:?}");
        }
    }
}
