//! Pore pressures for the outputs (VTK, recordings, the particle channel): at every
//! fine particle below its column's water surface the water's pressure interpolated
//! there (zero above it, where the grain is dry)
//! ([`soil_water::pore_pressure`](crate::interactions::soil_water::pore_pressure)),
//! and for fine and water particles the excess over the hydrostatic pressure below
//! the water surface of their vertical column, ρ_w g (z_s − z).

use crate::numerics::kernel::WendlandC2;
use crate::numerics::math::{up, Real, Vect};
use crate::step::SoilWater;
use crate::world::{column_key, World};
use std::collections::HashMap;

/// Pore pressure and its excess per fine particle, and the excess per water particle
/// (Pa, single precision as the records carry them).
#[derive(Clone, Debug, Default)]
pub struct PoreField {
    pub fine: Vec<[f32; 2]>,
    pub water: Vec<f32>,
}

impl PoreField {
    /// The field of the world's present state; empty without water. `coupling` holds
    /// the water–soil lists of the last step (None: no soil with pores).
    pub fn of<const D: usize>(
        world: &World<D>,
        coupling: Option<&SoilWater<D>>,
        kernel: &WendlandC2,
    ) -> Self {
        let Some(mat) = world.water.material else {
            return PoreField::default();
        };
        let w = &world.water.particles;
        let g = world.hydrostatic_gravity();
        let (gn, up) = (g.norm(), up(&g));
        let dp = world.resolution.dp;
        let surfaces = Surfaces::of(&w.pos, &up, dp);
        let hydro = |x: &Vect<D>| match surfaces.above(x) {
            Some(zs) => mat.rho0 * gn * (zs - x.dot(&up)).max(0.0),
            None => 0.0,
        };
        let water = w
            .pos
            .iter()
            .zip(&w.rho)
            .map(|(x, &r)| (mat.pressure(r) - hydro(x)) as f32)
            .collect();
        let fine = match coupling {
            Some(c) => c
                .pore_pressures(world, &mat, kernel)
                .iter()
                .zip(&world.fine.pos)
                .map(|(p, x)| match (p, surfaces.above(x)) {
                    // a grain below its column's water surface: the water's pressure
                    // there; above it (or with no water in its column) the grain is
                    // dry and reports none (issue 44: grains above the water table
                    // took 50–100 Pa from the water within their kernel's reach)
                    (Some(p), Some(zs)) if x.dot(&up) < zs => [*p as f32, (p - hydro(x)) as f32],
                    _ => [0.0, 0.0],
                })
                .collect(),
            None => vec![[0.0; 2]; world.fine.len()],
        };
        PoreField { fine, water }
    }
}

/// The water surface of each vertical column dp wide: its highest water particle
/// plus dp/2.
struct Surfaces<const D: usize> {
    up: Vect<D>,
    dp: Real,
    top: HashMap<[i64; 3], Real>,
}

impl<const D: usize> Surfaces<D> {
    fn of(pos: &[Vect<D>], up: &Vect<D>, dp: Real) -> Self {
        let mut s = Surfaces {
            up: *up,
            dp,
            top: HashMap::new(),
        };
        for x in pos {
            let z = x.dot(up) + 0.5 * dp;
            let t = s.top.entry(s.key(x)).or_insert(Real::NEG_INFINITY);
            *t = t.max(z);
        }
        s
    }

    fn key(&self, x: &Vect<D>) -> [i64; 3] {
        column_key(x, &self.up, self.dp)
    }

    /// The surface above `x`, if water stands in its column.
    fn above(&self, x: &Vect<D>) -> Option<Real> {
        self.top.get(&self.key(x)).copied()
    }
}
