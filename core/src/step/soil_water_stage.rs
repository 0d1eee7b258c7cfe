//! The soil–water coupling in the step ([`interactions::soil_water`]): before the
//! water's sub-steps the soil is frozen at the middle of the step and each water
//! particle's drag coefficients are taken; the sub-steps apply the drag implicitly
//! and keep each particle's share; after them every soil particle gathers the exact
//! opposite of the water's drag impulse and its buoyancy (Eq. 9's pressure term),
//! which its momentum sweep adds; after that sweep the drag is closed implicitly on
//! both sides ([`interactions::seepage_implicit`]), so that no permeability bounds
//! the step.
//!
//! [`interactions::soil_water`]: crate::interactions::soil_water
//! [`interactions::seepage_implicit`]: crate::interactions::seepage_implicit

use super::relations::SoilWaterRelation;
use crate::fine::material::FineMaterial;
use crate::interactions::seepage_implicit::{ChunkRows, Families, ImplicitDrag, SolveStats};
use crate::interactions::soil_water::{
    full_sum, kernel_sum, lattice_sum, pore_pressure, pore_water_inertia, soil_force, Mat, Seepage,
    SoilPoint, WaterAround, WaterDrag,
};
use crate::numerics::kernel::WendlandC2;
use crate::numerics::math::{up, Real, Vect};
use crate::numerics::neighbors::{CellGrid, CHUNK};
use crate::water::material::WaterMaterial;
use crate::water::source::WaterSource;
use crate::world::World;
use rayon::prelude::*;

/// Scratch of the soil–water coupling; the water's force on the soil of the last step.
#[derive(Clone, serde::Serialize, serde::Deserialize)]
pub struct SoilWater<const D: usize> {
    /// The largest Δt at which the soil's side of the drag stays explicit: the least
    /// over the soil particles of ½ ρ_d k / μ
    /// ([`Pores::seepage_dt`](crate::fine::pores::Pores::seepage_dt)) at each one's
    /// density and permeability, taken at [`SoilWater::freeze`]. A longer step closes
    /// the drag implicitly on both sides ([`SoilWater::close`]).
    pub dt_explicit: Real,
    /// Each pair's drag against the soil's velocity at its midpoint
    /// (`numerics.seepage_midpoint`, [`Seepage`]).
    #[serde(default)]
    midpoint: bool,
    /// Whether this step closes the drag implicitly.
    #[serde(skip)]
    implicit_now: bool,
    /// The kernel's least lattice sum and its value at a lattice point
    /// ([`lattice_sum`]).
    #[serde(default = "ones")]
    norm: (Real, Real),
    /// Per soil particle: its own family's kernel sum (at the lists' build).
    #[serde(skip)]
    own: Vec<Real>,
    /// Per water particle near a soil: its own family's kernel sum (at the lists'
    /// build; 0 away from soils).
    #[serde(skip)]
    own_water: Vec<Real>,
    /// The soil–water relation: its lists and rebuild rule.
    pub relation: SoilWaterRelation<D>,
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
    /// Per fine particle: the water's force over the last step (N).
    #[serde(skip)]
    pub force: Vec<Vect<D>>,
    /// Per fine particle: the factor on its geostatic gradient under the water's force
    /// ([`ContinuityParams::weight`]).
    ///
    /// [`ContinuityParams::weight`]: crate::fine::continuity::ContinuityParams::weight
    #[serde(skip)]
    pub weight: Vec<Real>,
    /// The implicit close of the drag: its pair rows and scratch.
    #[serde(skip)]
    implicit: ImplicitDrag<D>,
    /// Per chunk of soil particles: each one's water within its kernel with V_i W_ij,
    /// from the force pass, for [`pore_water_inertia`] at the end of the step.
    #[serde(skip)]
    wet: Vec<ChunkRows>,
    /// The water's velocities at the start of the step; at the close, their change
    /// over the step.
    #[serde(skip)]
    start_vel: Vec<Vect<D>>,
    /// Each water particle's Shepard mean of the soil's velocity gradients
    /// ([`Seepage::grad`]); empty without the midpoint drag.
    #[serde(skip)]
    grads: Vec<Mat<D>>,
    /// Each soil particle's velocity gradient of its last step (L_j); empty without
    /// the midpoint drag.
    #[serde(skip)]
    soil_grads: Vec<Mat<D>>,
    /// The impulse the grains took over from the pore water's surplus mass since the
    /// start ([`pore_water_inertia`], N·s, or N·s/m in 2D): the grains' and the water's
    /// momentum less it is what the seepage exchanges conserve.
    #[serde(default = "Vect::zeros")]
    pub carried: Vect<D>,
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
    /// the particles packed in `src` (density and volume at the half step), and its
    /// share kept; each particle's acceleration by the drag into `accel`.
    pub fn apply(
        &mut self,
        vel: &mut [Vect<D>],
        src: &[WaterSource],
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
                    let s = &src[c * CHUNK + k];
                    let u = a[k].drag(v[k], s.rho, dt);
                    acc[k] = if dt > 0.0 {
                        (u - v[k]) / dt
                    } else {
                        Vect::<D>::zeros()
                    };
                    v[k] = u;
                    d[k].add(s.vol * a[k].inv, &v[k], share);
                }
            });
    }
}

impl<const D: usize> SoilWater<D> {
    /// Whether this coupling, restored from a state, fits `template` (the scene's as
    /// built): the same explicit bound, midpoint rule, lattice sums and list geometry.
    pub fn restored_fits(&self, template: &Self) -> bool {
        let bits = |x: Real| x.to_bits();
        bits(self.dt_explicit) == bits(template.dt_explicit)
            && self.midpoint == template.midpoint
            && (bits(self.norm.0), bits(self.norm.1))
                == (bits(template.norm.0), bits(template.norm.1))
            && self.relation.same_geometry(&template.relation)
    }

    /// The coupling of a world with water and a soil with pores (None otherwise).
    pub fn new(
        world: &World<D>,
        kernel: &WendlandC2,
        (skin, midpoint): (Real, bool),
    ) -> Option<Self> {
        let w = world.water.material?;
        let dt_explicit = world
            .materials
            .iter()
            .filter_map(|m| m.pores.map(|p| p.seepage_dt(m.rho0, w.mu)))
            .reduce(Real::min)?;
        Some(SoilWater {
            dt_explicit,
            midpoint,
            implicit_now: false,
            norm: lattice_sum::<D>(kernel, world.resolution.dp),
            own: Vec::new(),
            own_water: Vec::new(),
            relation: SoilWaterRelation::new(
                kernel.cutoff + 1.5 * skin,
                (&world.domain.0, &world.domain.1),
            ),
            soil: Vec::new(),
            coef: Vec::new(),
            drag: Vec::new(),
            frozen: Vec::new(),
            vol: Vec::new(),
            force: Vec::new(),
            weight: Vec::new(),
            implicit: ImplicitDrag::default(),
            wet: Vec::new(),
            start_vel: Vec::new(),
            grads: Vec::new(),
            soil_grads: Vec::new(),
            carried: Vect::<D>::zeros(),
        })
    }

    /// Freeze the soil at the middle of the step (positions of `world.fine` after the
    /// drift, velocities at the start, volumes m/ρ) and take every water
    /// particle's drag coefficients at its present position. The water–soil lists are
    /// rebuilt when either family rebuilt its own (`builds`: the fine grains' and the
    /// water's list builds so far), with `water_grid` the cells the water was binned
    /// in at its last build.
    pub fn freeze(
        &mut self,
        world: &World<D>,
        (builds, water_grid): ([usize; 2], &CellGrid<D>),
        kernel: &WendlandC2,
        mu: Real,
    ) {
        let (f, mats) = (&world.fine, &world.materials);
        self.soil.clear();
        self.soil.par_extend((0..f.len()).into_par_iter().map(|i| {
            let m: &FineMaterial = &mats[f.material[i] as usize];
            // ρ as m/V, the volume's, as the soil's record has always taken it
            let vol = f.mass[i] / f.rho[i];
            SoilPoint::of(m, mu, (f.pos[i], f.vel[i]), vol, f.mass[i] / vol)
        }));
        self.soil_grads.clear();
        if self.midpoint {
            self.soil_grads
                .par_extend(f.vel_grad.par_iter().map(|l| l.cast::<Real>()));
        }
        self.dt_explicit = self
            .soil
            .iter()
            .zip(&f.mass)
            .filter(|(q, _)| q.drag > 0.0)
            .map(|(q, m)| 0.5 * m / q.vol / q.drag)
            .fold(Real::INFINITY, Real::min);
        let w = &world.water.particles;
        let now = [builds[0], builds[1], f.len(), w.len()];
        if self.relation.expired(now) {
            self.build_lists(world, water_grid, kernel, now);
        }
        let (soil, norm, rel, own) = (&self.soil, self.norm, &self.relation, &self.own_water);
        let soil_grads = &self.soil_grads;
        self.coef.clear();
        self.coef
            .par_extend(w.pos.par_iter().enumerate().map(|(i, x)| {
                let (s, sum) = Seepage::raw(x, soil, rel.soil_near(i), kernel, soil_grads);
                // amid soil: the Shepard mean against the soil's sum in full
                s.normalised(sum, full_sum(norm, own[i]))
            }));
        self.grads.clear();
        if self.midpoint {
            self.grads.extend(self.coef.iter().map(|c| c.grad));
        }
        self.frozen.clear();
        self.frozen.extend_from_slice(&w.pos);
        self.start_vel.clear();
        self.start_vel.extend_from_slice(&w.vel);
        self.drag.clear();
        self.drag.resize(w.len(), WaterDrag::default());
    }

    /// The water–soil lists at the families' state `now`, and each family's own
    /// kernel sum where they meet.
    fn build_lists(
        &mut self,
        world: &World<D>,
        water_grid: &CellGrid<D>,
        kernel: &WendlandC2,
        now: [usize; 4],
    ) {
        let (f, w) = (&world.fine, &world.water.particles);
        self.relation.rebuild(&w.pos, &f.pos, now);
        let grid = self.relation.grid();
        let soil = &self.soil;
        self.own.clear();
        self.own.par_extend(soil.par_iter().map(|q| {
            if q.solid == 0.0 {
                return 0.0;
            }
            kernel_sum(&q.pos, &f.pos, |j| soil[j].vol, grid, kernel)
        }));
        let rel = &self.relation;
        self.own_water.clear();
        self.own_water
            .par_extend(w.pos.par_iter().enumerate().map(|(i, x)| {
                if rel.soil_near(i).is_empty() {
                    return 0.0;
                }
                kernel_sum(x, &w.pos, |j| w.mass[j] / w.rho[j], water_grid, kernel)
            }));
    }

    /// The sub-steps' view of the coupling.
    pub fn step(&mut self, share: Real) -> SeepStep<'_, D> {
        SeepStep {
            coef: &self.coef,
            drag: &mut self.drag,
            share,
        }
    }

    /// After the water's sub-steps of a step of `dt`: every soil particle's force from
    /// the water (the opposite of the drag, and its buoyancy) and its pore pressure;
    /// with a step longer than [`SoilWater::dt_explicit`], each pair's drag coefficient
    /// for the implicit close.
    pub fn gather(&mut self, world: &World<D>, mat: &WaterMaterial, kernel: &WendlandC2, dt: Real) {
        self.implicit_now = dt > self.dt_explicit;
        let w = &world.water.particles;
        self.vol.clear();
        self.vol
            .extend(w.mass.iter().zip(&w.rho).map(|(m, r)| m / r));
        let around = WaterAround {
            frozen: &self.frozen,
            drag: &self.drag,
            vol: &self.vol,
            grad: &self.grads,
            buoyancy: world.hydrostatic_gravity() * (-mat.rho0),
        };
        let (norm, own, rel) = (self.norm, &self.own, &self.relation);
        let (n, soil_grads) = (self.soil.len(), &self.soil_grads);
        let zero = Mat::<D>::zeros();
        self.force.resize(n, Vect::<D>::zeros());
        // the force pass also keeps each soil particle's pairs for the implicit close,
        // and its water with their kernel weights for the pore water's inertia
        let record = self.implicit_now;
        self.wet.resize_with(n.div_ceil(CHUNK), ChunkRows::default);
        self.soil
            .par_chunks(CHUNK)
            .zip(self.force.par_chunks_mut(CHUNK))
            .zip(self.implicit.chunks(n).par_iter_mut())
            .zip(self.wet.par_iter_mut())
            .enumerate()
            .for_each(|(c, (((q, f), rows), wet))| {
                rows.clear();
                wet.clear();
                for k in 0..q.len() {
                    let j = c * CHUNK + k;
                    let full = full_sum(norm, own[j]);
                    let near = rel.water_near(j);
                    let p = (&q[k], soil_grads.get(j).unwrap_or(&zero));
                    f[k] = wet.row(|idx, ws| {
                        let sink = |i, vw| {
                            idx.push(i);
                            ws.push(vw);
                        };
                        if record {
                            rows.row(|ri, rc| {
                                let pair = |i, c| {
                                    ri.push(i);
                                    rc.push(c);
                                };
                                soil_force(p, &around, near, kernel, full, (pair, sink))
                            })
                        } else {
                            soil_force(p, &around, near, kernel, full, (|_, _| {}, sink))
                        }
                    });
                }
            });
        // the vertical gradient a soil rests at: its weight less the water's lift
        let g = world.gravity.norm();
        let up = up(&world.gravity);
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

    /// After the soil's momentum sweep of a step of `dt`: where the step is longer than
    /// the explicit soil side allows ([`SoilWater::dt_explicit`]), the drag closed
    /// implicitly on both sides ([`ImplicitDrag::close`]), the soil's and the water's
    /// velocities receiving the increments (a shorter step keeps the explicit soil
    /// side); then the grains take the inertia of the pore water's surplus mass
    /// ([`pore_water_inertia`]) from the water's velocity change over the whole step.
    /// Returns the close's iterations (none on an explicit step).
    pub fn close(&mut self, world: &mut World<D>, mat: &WaterMaterial, dt: Real) -> SolveStats {
        let stats = if self.implicit_now {
            let f = &mut world.fine;
            let w = &mut world.water.particles;
            let fam = Families {
                soil: &self.soil,
                soil_mass: &f.mass,
                water_mass: &w.mass,
            };
            self.implicit.close(&fam, dt, &mut f.vel, &mut w.vel)
        } else {
            SolveStats::default()
        };
        self.carry_pore_water(world, mat.rho0);
        stats
    }

    /// [`pore_water_inertia`] on every soil particle, from the water's velocity change
    /// since [`SoilWater::freeze`]; its sum joins [`SoilWater::carried`].
    fn carry_pore_water(&mut self, world: &mut World<D>, rho_w: Real) {
        let w = &world.water.particles;
        // the change in place; a particle that joined during the step has none
        let du = &mut self.start_vel;
        du.truncate(w.len());
        for (d, v) in du.iter_mut().zip(&w.vel) {
            *d = v - *d;
        }
        du.resize(w.len(), Vect::<D>::zeros());
        let du = &self.start_vel;
        let (norm, own, soil) = (self.norm, &self.own, &self.soil);
        let impulse: Vec<Vect<D>> = self
            .wet
            .par_iter()
            .enumerate()
            .flat_map_iter(|(c, wet)| {
                wet.rows().enumerate().map(move |(k, pairs)| {
                    let j = c * CHUNK + k;
                    pore_water_inertia(&soil[j], du, pairs, (full_sum(norm, own[j]), rho_w))
                })
            })
            .collect();
        let f = &mut world.fine;
        for (j, p) in impulse.iter().enumerate() {
            if *p != Vect::<D>::zeros() {
                f.vel[j] += p / f.mass[j];
                self.carried += p;
            }
        }
    }

    /// The pore pressure at every fine particle now (Pa; None where no water is
    /// within its kernel), from the water–soil lists of the last step, or from lists
    /// built here before the first step.
    pub fn pore_pressures(
        &self,
        world: &World<D>,
        mat: &WaterMaterial,
        kernel: &WendlandC2,
    ) -> Vec<Option<Real>> {
        let w = &world.water.particles;
        let vol: Vec<Real> = w.mass.iter().zip(&w.rho).map(|(m, r)| m / r).collect();
        let p: Vec<Real> = w.rho.iter().map(|&r| mat.pressure(r)).collect();
        let own;
        let rel = if self.relation.counts_match(world.fine.len(), w.len()) {
            &self.relation
        } else {
            let (lo, hi) = &world.domain;
            let mut l = SoilWaterRelation::new(self.relation.radius(), (lo, hi));
            l.rebuild(&w.pos, &world.fine.pos, [0; 4]);
            own = l;
            &own
        };
        (0..world.fine.len())
            .into_par_iter()
            .map(|j| {
                let near = rel.water_near(j);
                pore_pressure(&world.fine.pos[j], (&w.pos, &vol, &p), near, kernel)
            })
            .collect()
    }
}
