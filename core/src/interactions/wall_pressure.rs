//! The pressure the wall particles carry, for output (VTK's walls part): at every wall
//! particle w, the kernel-weighted (Shepard) mean over the particles i of one family
//! within the kernel of the pressure each extrapolates to w,
//!
//!   P̄_w = Σ_i P_w(i) W_wi V_i / Σ_i W_wi V_i,
//!
//! with P_w(i) the wall pressure of the family's wall law: Eq. (35) of seed 000 for the
//! fine grains ([`fine_wall::wall_pressure`]), the hydrostatic extrapolation of
//! [`water_wall::wall_pressure`] for the water. The solver forms P_w per pair and
//! stores none, so this is taken at output time only, in one serial pass over the
//! particles (deterministic), never in the step. A wall particle no particle of the
//! family reaches (the inner layers, walls away from the flow) gets 0.

use super::{fine_wall, water_wall};
use crate::geometry::walls::Walls;
use crate::numerics::kernel::WendlandC2;
use crate::numerics::math::{Real, Vect};
use crate::numerics::neighbors::CellGrid;
use crate::numerics::periodic::Separation;

/// One family's particles as the wall pressure reads them.
pub struct Family<'a, const D: usize> {
    pub pos: &'a [Vect<D>],
    pub rho: &'a [Real],
    pub mass: &'a [Real],
    /// P_i (Pa): −tr σ/3 of the fine grains (effective in a saturated soil), the
    /// water's pressure from its equation of state.
    pub p: &'a [Real],
}

/// Which wall law extrapolates P_i to the wall.
#[derive(Clone, Copy, Debug)]
pub enum Law<const D: usize> {
    /// Fine grains, Eq. (35) with gravity g.
    Fine { gravity: Vect<D> },
    /// Water: its hydrostatic gravity; permeable walls let water through and get none.
    Water { hydrostatic: Vect<D> },
}

/// P̄_w of every wall particle from `family` (module notes). `grid` holds the wall
/// particles binned with cells no smaller than the kernel's cut-off.
pub fn shepard<const D: usize>(
    walls: &Walls<D>,
    grid: &CellGrid<D>,
    kernel: &WendlandC2,
    sep: &impl Separation,
    family: &Family<'_, D>,
    law: Law<D>,
) -> Vec<Real> {
    let n = walls.len();
    let (mut num, mut den) = (vec![0.0; n], vec![0.0; n]);
    let cut2 = kernel.cutoff * kernel.cutoff;
    for (i, xi) in family.pos.iter().enumerate() {
        let (p, rho) = (family.p[i], family.rho[i]);
        let vol = family.mass[i] / rho;
        grid.for_each_near(xi, |w| {
            let w = w as usize;
            let rij = sep.of(xi - walls.pos[w]);
            let r2 = rij.norm_squared();
            if r2 >= cut2 {
                return;
            }
            let pw = match law {
                Law::Fine { gravity } => {
                    let r = r2.sqrt();
                    let g_to_wall = if r > 0.0 { -gravity.dot(&rij) / r } else { 0.0 };
                    fine_wall::wall_pressure(p, rho, r, g_to_wall)
                }
                Law::Water { hydrostatic } => {
                    if walls.objects[walls.object[w] as usize].permeable {
                        return;
                    }
                    water_wall::wall_pressure(p, rho * hydrostatic.dot(&(-rij)))
                }
            };
            let wgt = kernel.w(r2.sqrt()) * vol;
            num[w] += wgt * pw;
            den[w] += wgt;
        });
    }
    num.iter()
        .zip(&den)
        .map(|(s, d)| if *d > 0.0 { s / d } else { 0.0 })
        .collect()
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::numerics::periodic::Open;

    /// A resting column over a floor: the fine law adds ρ g (y_i − y_w) to each P_i
    /// and the water law the same, so a hydrostatic P_i = ρ g (H − y_i) extrapolates
    /// to ρ g (H − y_w) at every floor particle, whatever the weights.
    #[test]
    fn a_hydrostatic_column_extrapolates_exactly_to_the_floor() {
        let dp = 0.01;
        let (rho, g, h) = (1000.0, 9.81, 0.2);
        let kernel = WendlandC2::new(1.3 * dp, 2);
        let mut walls = Walls::<2>::default();
        for i in 0..20 {
            for l in 0..4 {
                walls.pos.push(Vect::<2>::new(
                    (i as Real + 0.5) * dp,
                    -(l as Real + 0.5) * dp,
                ));
                walls.object.push(0);
            }
        }
        walls.objects.push(crate::geometry::walls::WallObject {
            name: "floor".into(),
            kind: Default::default(),
            velocity: Vect::<2>::zeros(),
            prescribed: Vect::<2>::zeros(),
            window: (0.0, 0.0),
            barrier: None,
            displacement: Vect::<2>::zeros(),
            shape: None,
            driven: false,
            permeable: false,
        });
        let pos: Vec<Vect<2>> = (0..20)
            .flat_map(|i| {
                (0..20).map(move |j| Vect::<2>::new((i as Real + 0.5) * dp, (j as Real + 0.5) * dp))
            })
            .collect();
        let p: Vec<Real> = pos.iter().map(|x| rho * g * (h - x[1])).collect();
        let (rhos, mass) = (vec![rho; pos.len()], vec![rho * dp * dp; pos.len()]);
        let fam = Family {
            pos: &pos,
            rho: &rhos,
            mass: &mass,
            p: &p,
        };
        let lo = Vect::<2>::new(-0.1, -0.1);
        let hi = Vect::<2>::new(0.3, 0.3);
        let mut grid = CellGrid::new(&lo, &hi, kernel.cutoff);
        grid.bin(&walls.pos);
        let gv = Vect::<2>::new(0.0, -g);
        for law in [Law::Fine { gravity: gv }, Law::Water { hydrostatic: gv }] {
            let pw = shepard(&walls, &grid, &kernel, &Open, &fam, law);
            for (w, x) in walls.pos.iter().enumerate() {
                let reached = pos.iter().any(|y| (y - x).norm() < kernel.cutoff);
                let want = if reached { rho * g * (h - x[1]) } else { 0.0 };
                assert!(
                    (pw[w] - want).abs() < 1e-9 * rho * g * h,
                    "{law:?} {w}: {} vs {want}",
                    pw[w]
                );
            }
        }
    }
}
