//! The soil–water coupling in the step ([`interactions::soil_water`]): before the
//! water's sub-steps the soil is frozen at the middle of the step and each water
//! particle's drag coefficients are taken; the sub-steps apply the drag implicitly
//! and keep each particle's share; after them every soil particle gathers the exact
//! opposite of the water's drag impulse and its pore-pressure force, which its
//! momentum sweep adds.
//!
//! [`interactions::soil_water`]: crate::interactions::soil_water

use crate::fine::material::FineMaterial;
use crate::fine::source::Source;
use crate::interactions::soil_water::{
    full_sum, kernel_sum, lattice_sum, soil_force, Seepage, SoilPoint, WaterAround, WaterDrag,
};
use crate::kernel::WendlandC2;
use crate::math::{Real, Vect};
use crate::neighbors::{CellGrid, CHUNK};
use crate::water::material::WaterMaterial;
use crate::world::World;
use rayon::prelude::*;

/// Scratch of the soil–water coupling; the water's force on the soil of the last step.
#[derive(Clone, serde::Serialize, serde::Deserialize)]
pub struct SoilWater<const D: usize> {
    /// Largest Δt of the explicit soil side of the drag: 0.5 min ρ_d k / μ.
    pub dt_max: Real,
    /// The kernel's least lattice sum and its value at a lattice point
    /// ([`lattice_sum`]).
    #[serde(default = "ones")]
    norm: (Real, Real),
    /// Per soil particle: its own family's kernel sum at the middle of the step.
    #[serde(skip)]
    own: Vec<Real>,
    #[serde(skip)]
    soil: Vec<SoilPoint<D>>,
    #[serde(skip)]
    coef: Vec<Seepage<D>>,
    #[serde(skip)]
    drag: Vec<WaterDrag<D>>,
    #[serde(skip)]
    frozen: Vec<Vect<D>>,
    #[serde(skip)]
    vol: Vec<Real>,
    #[serde(skip)]
    p: Vec<Real>,
    /// Per fine particle: the water's force over the last step (N).
    #[serde(skip)]
    pub force: Vec<Vect<D>>,
    /// Per fine particle: the pore pressure at the end of the last step (Pa).
    #[serde(skip)]
    pub pore_pressure: Vec<Real>,
    /// Per fine particle: the factor on its geostatic gradient under the water's force
    /// ([`ContinuityParams::weight`]).
    ///
    /// [`ContinuityParams::weight`]: crate::fine::continuity::ContinuityParams::weight
    #[serde(skip)]
    pub weight: Vec<Real>,
}

fn ones() -> (Real, Real) {
    (1.0, 1.0)
}

/// What the water's sub-steps need of the coupling: each particle's drag
/// coefficients, and its share of the drag to keep, with weight `share` (1/κ_w).
pub struct SeepStep<'a, const D: usize> {
    pub coef: &'a [Seepage<D>],
    pub drag: &'a mut [WaterDrag<D>],
    pub share: Real,
}

impl<'a, const D: usize> SeepStep<'a, D> {
    /// The drag over `dt` on the velocities `vel` (after the water's other forces) of
    /// particles of density `rho` and volume `vol`, and its share kept; each
    /// particle's acceleration by the drag into `accel`.
    pub fn apply(
        &mut self,
        vel: &mut [Vect<D>],
        rho_vol: impl Fn(usize) -> (Real, Real) + Sync,
        dt: Real,
        accel: &mut Vec<Vect<D>>,
    ) {
        let share = self.share;
        accel.resize(vel.len(), Vect::<D>::zeros());
        vel.par_chunks_mut(CHUNK)
            .zip(accel.par_chunks_mut(CHUNK))
            .zip(self.coef.par_chunks(CHUNK))
            .zip(self.drag.par_chunks_mut(CHUNK))
            .enumerate()
            .for_each(|(c, (((v, acc), a), d))| {
                for k in 0..a.len() {
                    let (rho, vol) = rho_vol(c * CHUNK + k);
                    let u = a[k].drag(v[k], rho, dt);
                    acc[k] = if dt > 0.0 {
                        (u - v[k]) / dt
                    } else {
                        Vect::<D>::zeros()
                    };
                    v[k] = u;
                    d[k].add(vol * a[k].inv, &v[k], share);
                }
            });
    }
}

impl<const D: usize> SoilWater<D> {
    /// The coupling of a world with water and a soil with pores (None otherwise).
    pub fn new(world: &World<D>, kernel: &WendlandC2) -> Option<Self> {
        let w = world.water_material?;
        let dt_max = world
            .materials
            .iter()
            .filter_map(|m| m.pores.map(|p| 0.5 * m.rho0 * p.permeability / w.mu))
            .reduce(Real::min)?;
        Some(SoilWater {
            dt_max,
            norm: lattice_sum::<D>(kernel, world.resolution.dp),
            own: Vec::new(),
            soil: Vec::new(),
            coef: Vec::new(),
            drag: Vec::new(),
            frozen: Vec::new(),
            vol: Vec::new(),
            p: Vec::new(),
            force: Vec::new(),
            pore_pressure: Vec::new(),
            weight: Vec::new(),
        })
    }

    /// Freeze the soil at the middle of the step (positions of `world.fine` after the
    /// drift, velocities at the start, volumes from `src`) and take every water
    /// particle's drag coefficients at its present position, with `grids` the cells
    /// the fine grains and the water were binned in.
    pub fn freeze(
        &mut self,
        world: &World<D>,
        src: &[Source],
        (fine_grid, water_grid): (&CellGrid<D>, &CellGrid<D>),
        kernel: &WendlandC2,
        mu: Real,
    ) {
        let (f, mats) = (&world.fine, &world.materials);
        self.soil.clear();
        self.soil.par_extend((0..f.len()).into_par_iter().map(|i| {
            let m: &FineMaterial = &mats[f.material[i] as usize];
            SoilPoint::of(m, mu, f.pos[i], f.vel[i], src[i].vol)
        }));
        let (soil, norm) = (&self.soil, self.norm);
        // each soil particle's own support, for its buoyancy after the sub-steps
        self.own.clear();
        self.own.par_extend(soil.par_iter().map(|q| {
            if q.solid == 0.0 {
                return 0.0;
            }
            kernel_sum(&q.pos, &f.pos, |j| src[j].vol, fine_grid, kernel)
        }));
        let w = &world.water;
        self.coef.clear();
        self.coef.par_extend(w.pos.par_iter().map(|x| {
            let (s, sum) = Seepage::raw(x, soil, fine_grid, kernel);
            if s.a == 0.0 {
                return s;
            }
            // amid soil: the Shepard mean against the soil's sum in full
            let own = kernel_sum(x, &w.pos, |j| w.mass[j] / w.rho[j], water_grid, kernel);
            s.normalised(sum, full_sum(norm, own))
        }));
        self.frozen.clear();
        self.frozen.extend_from_slice(&world.water.pos);
        self.drag.clear();
        self.drag.resize(world.water.len(), WaterDrag::default());
    }

    /// The sub-steps' view of the coupling.
    pub fn step(&mut self, share: Real) -> SeepStep<'_, D> {
        SeepStep {
            coef: &self.coef,
            drag: &mut self.drag,
            share,
        }
    }

    /// After the water's sub-steps: every soil particle's force from the water (the
    /// opposite of the drag, and the pore pressure) and its pore pressure, the water
    /// binned in `water_grid` (within half a skin of its binning).
    pub fn gather(
        &mut self,
        world: &World<D>,
        mat: &WaterMaterial,
        water_grid: &CellGrid<D>,
        kernel: &WendlandC2,
    ) {
        let w = &world.water;
        self.vol.clear();
        self.vol
            .extend(w.mass.iter().zip(&w.rho).map(|(m, r)| m / r));
        self.p.clear();
        self.p.extend(w.rho.iter().map(|&r| mat.pressure(r)));
        let around = WaterAround {
            frozen: &self.frozen,
            drag: &self.drag,
            pos: &w.pos,
            vol: &self.vol,
            p: &self.p,
            buoyancy: world.hydrostatic_gravity() * (-mat.rho0),
        };
        let (norm, own) = (self.norm, &self.own);
        let n = self.soil.len();
        self.force.resize(n, Vect::<D>::zeros());
        self.pore_pressure.resize(n, 0.0);
        self.soil
            .par_chunks(CHUNK)
            .zip(self.force.par_chunks_mut(CHUNK))
            .zip(self.pore_pressure.par_chunks_mut(CHUNK))
            .enumerate()
            .for_each(|(c, ((q, f), pp))| {
                for k in 0..q.len() {
                    let full = full_sum(norm, own[c * CHUNK + k]);
                    (f[k], pp[k]) = soil_force(&q[k], &around, water_grid, kernel, full);
                }
            });
        // the vertical gradient a soil rests at: its weight less the water's lift
        let g = world.gravity.norm();
        let up = if g > 0.0 {
            -world.gravity / g
        } else {
            Vect::<D>::zeros()
        };
        let (f, mats) = (&world.fine, &world.materials);
        let rho_w = Some(mat.rho0);
        self.weight.clear();
        self.weight.par_extend((0..n).into_par_iter().map(|i| {
            let m = &mats[f.material[i] as usize];
            let held = m.skeleton_density(rho_w) * g;
            if m.pores.is_none() || held <= 0.0 {
                return 1.0;
            }
            (m.rho0 * g - self.force[i].dot(&up) / self.soil[i].vol) / held
        }));
    }
}
