//! The fine grains' pair laws on the clusters' lanes (each pair once, added to both
//! particles) against a direct evaluation of Eqs. (15)–(20), (24)–(27), the hourglass
//! penalty and the MUSCL reconstruction, summed for each particle over all its
//! neighbours, on a disordered cloud of one or two soils with moving, stressed
//! particles: the two agree to round-off, on both instruction sets.

use super::continuity_pass::continuity_sweep;
use super::fine_coarse::{CoarseSide, Coupling};
use super::fine_wall::WallLaw;
use super::momentum_pass::momentum_sweep;
use crate::fine::continuity::{ContinuityOut, ContinuityParams, JumpDiffusion};
use crate::fine::hourglass::{non_affine, pair_weight};
use crate::fine::lanes::{FineLanes, FinePairs};
use crate::fine::material::uniform_acoustics;
use crate::fine::material::FineMaterial;
use crate::fine::momentum::ArtificialStress;
use crate::fine::momentum::MomentumParams;
use crate::fine::pair_sums::PairSums;
use crate::fine::plasticity::constitutive_step;
use crate::fine::source::Source;
use crate::fine::state::FineParticles;
use crate::geometry::walls::Walls;
use crate::numerics::kernel::WendlandC2;
use crate::numerics::load::Load;
use crate::numerics::math::{sub_outer, Real, Sym, Vect};
use crate::numerics::neighbors::{Binned, CellGrid, NeighborLists};
use crate::numerics::pairs::clusters::ClusterPairs;
use crate::numerics::pairs::quad::Lanes;
use crate::numerics::riemann::{pair_reciprocals, Riemann, Side};
use crate::scene::{ContinuityJump, WallStress};
use nalgebra::{Matrix3, SMatrix, SVector};

struct Rng(u64);
impl Rng {
    fn next(&mut self) -> Real {
        self.0 = self
            .0
            .wrapping_mul(6364136223846793005)
            .wrapping_add(1442695040888963407);
        (self.0 >> 11) as Real / (1u64 << 53) as Real - 0.5
    }
}

/// A cohesionless soil of density `rho0` and Young's modulus `e` (φ = 30°, ν = 0.3);
/// also the wall tests' soil.
pub(super) fn material(name: &str, rho0: Real, e: Real) -> FineMaterial {
    let nu: Real = 0.3;
    let phi: Real = 30f64.to_radians();
    let t = phi.tan();
    let a = t / (9.0 + 12.0 * t * t).sqrt();
    FineMaterial {
        name: name.into(),
        rho0,
        shear: e / (2.0 * (1.0 + nu)),
        bulk: e / (3.0 * (1.0 - 2.0 * nu)),
        c0: (e / (3.0 * (1.0 - 2.0 * nu) * rho0)).sqrt(),
        alpha_phi: a,
        k_c: 0.0,
        alpha_psi: 0.0,
        k0: 1.0 - phi.sin(),
        phi,
        cohesion: 0.0,
        pores: None,
        surface: Default::default(),
        hardening: None,
        mu_i: None,
        dilatancy: None,
    }
}

/// A jittered lattice of `side`^D particles, spacing `dp`, sorted by cell, with lists.
struct Cloud<const D: usize> {
    p: FineParticles<D>,
    mats: Vec<FineMaterial>,
    lists: NeighborLists,
    kernel: WendlandC2,
}

fn cloud<const D: usize>(side: usize, two_soils: bool) -> Cloud<D> {
    let dp = 0.01;
    let kernel = WendlandC2::new(1.3 * dp, D);
    let mats = if two_soils {
        vec![material("a", 2000.0, 5e6), material("b", 2600.0, 2e7)]
    } else {
        vec![material("a", 2000.0, 5e6)]
    };
    let mut rng = Rng(7);
    let mut p = FineParticles::<D>::default();
    let count = side.pow(D as u32);
    for n in 0..count {
        let mut x = Vect::<D>::zeros();
        let mut v = Vect::<D>::zeros();
        let mut m = n;
        for k in 0..D {
            x[k] = ((m % side) as Real + 0.3 * rng.next()) * dp;
            v[k] = rng.next();
            m /= side;
        }
        let mat = if two_soils { (n % 3 == 0) as u16 } else { 0 };
        let rho0 = mats[mat as usize].rho0;
        let mut s = Sym::iso(-2e4 * (1.0 + rng.next()));
        for c in 0..6 {
            if D == 3 || !matches!(c, 4 | 5) {
                s.0[c] += 3e3 * rng.next();
            }
        }
        p.push(
            x,
            v,
            rho0 * (1.0 + 0.01 * rng.next()),
            rho0 * dp.powi(D as i32),
            s,
            mat,
        );
    }
    for i in 0..count {
        p.hourglass_kept[i] = match i % 4 {
            0 => 0.0,
            1 => 0.7,
            _ => 1.0,
        };
        for a in 0..D {
            p.hourglass[i][a] = rng.next() as f32;
            for b in 0..D {
                p.vel_grad[i][(a, b)] = (50.0 * rng.next()) as f32;
            }
        }
    }
    let radius = kernel.cutoff + 0.3 * dp;
    let lo = Vect::<D>::repeat(-2.0 * dp);
    let mut hi = Vect::<D>::repeat(side as Real * dp + 2.0 * dp);
    hi[0] *= 1.5; // a longer axis first, so slabs cut across it
    let mut grid = CellGrid::new(&lo, &hi, radius);
    grid.bin(&p.pos);
    let order = grid.order().to_vec();
    p.permute(&order, &mut Default::default());
    grid.bin(&p.pos);
    let empty = CellGrid::new(&lo, &hi, radius);
    let mut lists = NeighborLists::default();
    lists.build(
        &p.pos,
        &grid,
        Binned {
            pos: &[],
            grid: &empty,
        },
        Binned {
            pos: &[],
            grid: &empty,
        },
        radius,
        &crate::numerics::periodic::Open,
    );
    Cloud {
        p,
        mats,
        lists,
        kernel,
    }
}

fn close(a: Real, b: Real, scale: Real, what: &str, i: usize) {
    assert!(
        (a - b).abs() <= 1e-11 * scale,
        "{what} of particle {i}: sweep {a:e}, direct {b:e}"
    );
}

/// The sweeps' fine–fine pairs on the clusters' lanes (the buffers carry the state the
/// momentum sweep packs to the continuity sweep).
struct Pairing<const D: usize> {
    lanes: Lanes,
    buf: FineLanes<D>,
    cp: ClusterPairs,
}

impl<const D: usize> Pairing<D> {
    fn new(cloud: &Cloud<D>, lanes: Lanes) -> Self {
        let cp = cloud.lists.clusters.clone();
        Pairing {
            lanes,
            buf: FineLanes::default(),
            cp,
        }
    }

    fn pairs(&mut self) -> FinePairs<'_, D> {
        (&mut self.buf, &self.cp, self.lanes)
    }
}

/// Continuity parameters of the cloud: gravity along −y (or −z), ζ = 0.1.
fn continuity_params<'a, const D: usize>(
    kernel: WendlandC2,
    jump: ContinuityJump,
    mats: &[FineMaterial],
    geostatic: &'a [Sym],
    pgeo: &'a [Real],
) -> ContinuityParams<'a, D> {
    let mut up = Vect::<D>::zeros();
    up[D - 1] = 1.0;
    ContinuityParams {
        kernel,
        gravity: up * -9.81,
        dt: 1e-5,
        zeta: 0.1,
        geostatic,
        geostatic_pressure: pgeo,
        geostatic_scale: 1.0,
        weight: &[],
        up,
        jump,
        uniform: uniform_acoustics(mats),
        wrap: None,
    }
}

/// The geostatic gradients of Eq. (26) and their pressures, per material.
fn geostatic(mats: &[FineMaterial]) -> (Vec<Sym>, Vec<Real>) {
    let geo: Vec<Sym> = mats
        .iter()
        .map(|m| Sym::iso(m.rho0 * 9.81 * (1.0 + m.k0) / 2.0))
        .collect();
    let pgeo = geo.iter().map(|g| g.trace() / 3.0).collect();
    (geo, pgeo)
}

/// The optional terms of the momentum law: the MUSCL reconstruction and artificial
/// stress (Eq. 27, exponent 4, one stress per particle).
#[derive(Clone, Copy, Default)]
struct Options {
    muscl: bool,
    artificial: bool,
}

/// The artificial stresses of the cloud's particles, and their settings.
fn artificial<const D: usize>(cloud: &Cloud<D>) -> (ArtificialStress, Vec<Sym>) {
    let mut rng = Rng(11);
    let art = (0..cloud.p.len())
        .map(|_| {
            let mut s = Sym::ZERO;
            for c in 0..6 {
                if D == 3 || !matches!(c, 4 | 5) {
                    s.0[c] = 2e3 * rng.next();
                }
            }
            s
        })
        .collect();
    let a = ArtificialStress {
        exponent: 4.0,
        w_dp: cloud.kernel.w(0.01),
    };
    (a, art)
}

/// The momentum sweep on the cloud: v_{n+1}, the hourglass acceleration, and the pair
/// sums it leaves for the continuity sweep.
fn momentum<const D: usize>(
    cloud: &Cloud<D>,
    cprm: &ContinuityParams<'_, D>,
    how: &mut Pairing<D>,
    opt: Options,
) -> (Vec<Vect<D>>, Vec<SVector<f32, D>>, Vec<PairSums<D>>) {
    let (p, mats, lists, kernel) = (&cloud.p, &cloud.mats, &cloud.lists, cloud.kernel);
    let n = p.len();
    let hourglass: Vec<Real> = mats.iter().map(|m| 0.1 * m.shear).collect();
    let leak = vec![0.9f32; mats.len()];
    let tension = vec![false; mats.len()];
    let riemann = Riemann {
        eta: 20.0 * D as Real,
    };
    let (a, art) = artificial(cloud);
    let prm = MomentumParams {
        kernel,
        riemann,
        gravity: cprm.gravity,
        dt: cprm.dt,
        artificial: opt.artificial.then_some(a),
        hourglass: &hourglass,
        hourglass_leak: &leak,
        materials: mats,
        uniform: uniform_acoustics(mats),
        wrap: None,
        muscl: opt.muscl,
    };
    let walls = Walls::<D>::default();
    let mut vel_new = vec![Vect::<D>::zeros(); n];
    let mut hg = p.hourglass.clone();
    let mut loads = vec![Load::default(); lists.chunks.len()];
    let mut reactions = vec![Vec::new(); lists.chunks.len()];
    let mut sums = vec![PairSums::<D>::zero(); n];
    let side = CoarseSide {
        src: &[],
        coupling: Coupling {
            kernel,
            riemann,
            mu_cf: 0.0,
            dt: cprm.dt,
            dp: 0.01,
        },
        tension: &tension,
        reactions: &mut reactions,
    };
    let wall = WallLaw {
        kernel,
        riemann,
        gravity: cprm.gravity,
        dt: cprm.dt,
        friction: 0.0,
        stress: WallStress::Extrapolated,
        wrap: None,
    };
    momentum_sweep(
        p,
        &walls,
        lists,
        &art,
        &prm,
        &wall,
        &mut vel_new,
        &mut hg,
        &mut loads,
        side,
        &JumpDiffusion::new(cprm),
        &mut sums,
        &[],
        how.pairs(),
        super::momentum_pass::FineSleep {
            asleep: crate::numerics::sleep::Asleep {
                rule: None,
                quiet: &[],
            },
            waking_walls: &[],
            flags: &mut vec![0; p.len()],
        },
    );
    (vel_new, hg, sums)
}

fn momentum_matches<const D: usize>(two_soils: bool, lanes: Lanes, opt: Options) {
    let cloud = cloud::<D>(if D == 2 { 30 } else { 11 }, two_soils);
    let (p, mats, kernel) = (&cloud.p, &cloud.mats, cloud.kernel);
    let n = p.len();
    let src: Vec<Source> = (0..p.len()).map(|i| Source::of(p, mats, i)).collect();
    let (geo, pgeo) = geostatic(mats);
    let cprm = continuity_params::<D>(kernel, ContinuityJump::Stress, mats, &geo, &pgeo);
    let mut how = Pairing::new(&cloud, lanes);
    let (vel_new, hg, sums) = momentum(&cloud, &cprm, &mut how, opt);
    let (art_prm, art) = artificial(&cloud);
    let hourglass: Vec<Real> = mats.iter().map(|m| 0.1 * m.shear).collect();
    let riemann = Riemann {
        eta: 20.0 * D as Real,
    };
    let (g, dt) = (cprm.gravity, cprm.dt);
    assert_eq!(cprm.uniform, !two_soils);
    assert!(sums.iter().all(|s| s.momentum.acc == Vect::<D>::zeros()));
    let cut = kernel.cutoff;
    let mut pairs = 0;
    for i in 0..n {
        let (si, mi) = (&src[i], &mats[p.material[i] as usize]);
        let mut acc = Vect::<D>::zeros();
        let mut dhg = Vect::<D>::zeros();
        for j in (0..n).filter(|&j| j != i) {
            let rij = p.pos[i] - p.pos[j];
            let r = rij.norm();
            if r >= cut {
                continue;
            }
            pairs += 1;
            let (sj, mj) = (&src[j], &mats[p.material[j] as usize]);
            let e = rij / r;
            let dw = kernel.dw(r);
            let (mut ul, ur) = (-p.vel[i].dot(&e), -p.vel[j].dot(&e));
            if opt.muscl {
                // U_L − U_R between v_i − ½ L_i r e and v_j + ½ L_j r e, minmod-limited
                let l = p.vel_grad[i].cast::<Real>() + p.vel_grad[j].cast::<Real>();
                let du = ul - ur;
                let rec = du + 0.5 * r * e.dot(&(l * e));
                let m = if du * rec > 0.0 {
                    du.signum() * du.abs().min(rec.abs())
                } else {
                    0.0
                };
                ul = ur + m;
            }
            let pstar = riemann.p_star(
                Side::new(si.z, ul, si.p),
                Side::new(sj.z, ur, sj.p),
                1.0 / (si.z + sj.z),
                2.0 / (mi.c0 + mj.c0),
            );
            // Eq. (16): (σ̄ˢ_ij − P* I)·∇_i W_ij V_j
            let sbar = si.dev.add(&sj.dev).scale(0.5);
            let mut t = sbar.dot_vec(&e) - e * pstar;
            if opt.artificial {
                // Eq. (27): f^n R̄_ij·e, f = W(r)/W(dp)
                let f = (kernel.w(r) / art_prm.w_dp).powf(art_prm.exponent);
                t += art[i].add(&art[j]).scale(0.5 * f).dot_vec(&e);
            }
            acc += t * (dw * sj.vol);
            if p.hourglass_kept[i] > 0.0 {
                let s = pair_weight(p.hourglass_kept[i], p.hourglass_kept[j])
                    * 0.5
                    * (hourglass[p.material[i] as usize] + hourglass[p.material[j] as usize]);
                let vc = non_affine(&(p.vel[i] - p.vel[j]), &rij, &p.vel_grad[i], &p.vel_grad[j]);
                dhg += vc * (s * dw / r * sj.vol);
            }
        }
        let hg_i: SVector<f32, D> = if p.hourglass_kept[i] > 0.0 {
            p.hourglass[i] * (p.hourglass_kept[i] * 0.9) + (dhg * (dt / p.rho[i])).cast::<f32>()
        } else {
            SVector::zeros()
        };
        let a = acc * (2.0 / p.rho[i]) + hg_i.cast::<Real>() + g;
        let want = p.vel[i] + a * dt;
        // the pressure term's scale: P/(ρ h) dt
        let scale = 2e4 / (p.rho[i] * kernel.h) * dt;
        for k in 0..D {
            close(vel_new[i][k], want[k], scale, "v_{n+1}", i);
            assert!((hg[i][k] - hg_i[k]).abs() <= 1e-5 * (1.0 + hg_i[k].abs()));
        }
    }
    // a full neighbourhood inside the cloud (about 20 in 2D, 60 in 3D)
    let mean = pairs as Real / n as Real;
    assert!(
        mean > if D == 2 { 15.0 } else { 40.0 },
        "{mean} pairs a particle"
    );
}

fn continuity_matches<const D: usize>(two_soils: bool, jump: ContinuityJump, lanes: Lanes) {
    let cloud = cloud::<D>(if D == 2 { 30 } else { 11 }, two_soils);
    let (p, mats, lists, kernel) = (&cloud.p, &cloud.mats, &cloud.lists, cloud.kernel);
    let n = p.len();
    let src: Vec<Source> = (0..p.len()).map(|i| Source::of(p, mats, i)).collect();
    let (geostatic, pgeo) = geostatic(mats);
    let prm = continuity_params::<D>(kernel, jump, mats, &geostatic, &pgeo);
    let (up, dt, zeta) = (prm.up, prm.dt, prm.zeta);
    // the momentum sweep takes the terms without velocity (same positions and σ_n)
    let mut how = Pairing::new(&cloud, lanes);
    let (_, _, mut sums) = momentum(&cloud, &prm, &mut how, Options::default());
    let walls = Walls::<D>::default();
    let mut drho = vec![0.0; n];
    let mut stress = p.stress.clone();
    let mut eps = vec![0.0; n];
    let mut lg = vec![SMatrix::<f32, D, D>::zeros(); n];
    let mut kept = vec![0.0f32; n];
    continuity_sweep(
        p,
        mats,
        &walls,
        lists,
        &prm,
        &[],
        ContinuityOut {
            sums: &mut sums,
            drho: &mut drho,
            stress: &mut stress,
            plastic_strain: &mut eps,
            vel_grad: &mut lg,
            hourglass_kept: &mut kept,
        },
        how.pairs(),
        (
            crate::numerics::sleep::Asleep {
                rule: None,
                quiet: &[],
            },
            &mut vec![0; n],
        ),
    );
    assert!(sums
        .iter()
        .all(|s| s.continuity.drho == 0.0 && s.continuity.w == 0.0));
    let (cut, h) = (kernel.cutoff, kernel.h);
    for i in 0..n {
        let (si, mi) = (&src[i], &mats[p.material[i] as usize]);
        let geo = geostatic[p.material[i] as usize];
        let mut d = 0.0;
        let mut grad = SMatrix::<Real, D, D>::zeros();
        let mut psi = Sym::ZERO;
        for j in (0..n).filter(|&j| j != i) {
            let rij = p.pos[i] - p.pos[j];
            let r = rij.norm();
            if r >= cut {
                continue;
            }
            let (sj, mj) = (&src[j], &mats[p.material[j] as usize]);
            let e = rij / r;
            let dwv = kernel.dw(r) * sj.vol;
            let (ul, ur) = (-p.vel[i].dot(&e), -p.vel[j].dot(&e));
            // Eq. (19), the jump taken from density or from the stress relative to
            // the geostatic state of particle i
            let (pl, pr) = match jump {
                ContinuityJump::Density => (si.p_rho, sj.p_rho),
                _ => (si.p, sj.p - rij.dot(&up) * geo.trace() / 3.0),
            };
            let (inv_z, _) = pair_reciprocals(si.z, sj.z, mi.c0, mj.c0, 0.5 / si.z, 1.0 / mi.c0);
            let ustar = Riemann::u_star(Side::new(si.z, ul, pl), Side::new(sj.z, ur, pr), inv_z);
            d += 2.0 * (ustar - ul) * dwv;
            sub_outer(&mut grad, &((p.vel[i] - p.vel[j]) * dwv), &e);
            // Eq. (26): Ψ_ij = σ_i − σ_j − (geostatic difference), weighted as Eq. (25)
            let w = r * dwv / (r * r + 0.01 * h * h);
            let mut dsig = p.stress[i].sub(&p.stress[j]);
            dsig.axpy(-rij.dot(&up), &geo);
            psi.axpy(w, &dsig);
        }
        close(drho[i], p.rho[i] * d, p.rho[i] * 5.0 / kernel.h, "dρ/dt", i);
        for a in 0..D {
            for b in 0..D {
                let (got, want) = (lg[i][(a, b)] as Real, grad[(a, b)]);
                assert!((got - want).abs() <= 1e-6 * (1.0 + want.abs()), "L of {i}");
            }
        }
        let mut l = Matrix3::zeros();
        for a in 0..D {
            for b in 0..D {
                l[(a, b)] = grad[(a, b)];
            }
        }
        let diffusion = psi.scale(2.0 * zeta * h * mi.c0);
        let u = constitutive_step(mi, &l, &p.stress[i], 0.0, &diffusion, dt, p.rho[i]);
        for c in 0..6 {
            close(stress[i].0[c], u.stress.0[c], 2e4, "stress", i);
        }
    }
}

fn levels() -> [Lanes; 2] {
    [Lanes::portable(), Lanes::best()]
}

#[test]
fn momentum_one_soil() {
    for lanes in levels() {
        momentum_matches::<2>(false, lanes, Options::default());
        momentum_matches::<3>(false, lanes, Options::default());
    }
}

#[test]
fn momentum_two_soils() {
    for lanes in levels() {
        momentum_matches::<2>(true, lanes, Options::default());
        momentum_matches::<3>(true, lanes, Options::default());
    }
}

/// The MUSCL reconstruction and artificial stress, each alone and together, with one
/// soil and two.
#[test]
fn momentum_muscl_and_artificial_stress() {
    for lanes in levels() {
        for (muscl, artificial) in [(true, false), (false, true), (true, true)] {
            let opt = Options { muscl, artificial };
            momentum_matches::<2>(false, lanes, opt);
            momentum_matches::<2>(true, lanes, opt);
            momentum_matches::<3>(muscl, lanes, opt);
        }
    }
}

#[test]
fn continuity_one_soil_both_jumps() {
    for lanes in levels() {
        continuity_matches::<2>(false, ContinuityJump::Stress, lanes);
        continuity_matches::<2>(false, ContinuityJump::Density, lanes);
        continuity_matches::<3>(false, ContinuityJump::Stress, lanes);
        continuity_matches::<3>(false, ContinuityJump::Density, lanes);
    }
}

#[test]
fn continuity_two_soils_both_jumps() {
    for lanes in levels() {
        continuity_matches::<2>(true, ContinuityJump::Stress, lanes);
        continuity_matches::<3>(true, ContinuityJump::Density, lanes);
    }
}

/// The two instruction sets give the same bits: the momentum sweep's velocities,
/// hourglass accelerations and the continuity sums it leaves.
#[test]
fn lanes_levels_agree_bitwise() {
    fn bits<const D: usize>(lanes: Lanes) -> Vec<u64> {
        let cloud = cloud::<D>(if D == 2 { 30 } else { 11 }, D == 3);
        let (geo, pgeo) = geostatic(&cloud.mats);
        let prm = continuity_params::<D>(
            cloud.kernel,
            ContinuityJump::Stress,
            &cloud.mats,
            &geo,
            &pgeo,
        );
        let mut how = Pairing::new(&cloud, lanes);
        let opt = Options {
            muscl: true,
            artificial: true,
        };
        let (v, hg, sums) = momentum(&cloud, &prm, &mut how, opt);
        let mut out: Vec<u64> = v
            .iter()
            .flat_map(|x| x.iter().map(|c| c.to_bits()))
            .collect();
        out.extend(hg.iter().flat_map(|x| x.iter().map(|c| c.to_bits() as u64)));
        for s in &sums {
            let c = &s.continuity;
            out.extend([c.drho, c.w, c.wz, c.wp].map(f64::to_bits));
            out.extend(c.wdev.0.map(f64::to_bits));
        }
        out
    }
    assert_eq!(bits::<2>(Lanes::portable()), bits::<2>(Lanes::best()));
    assert_eq!(bits::<3>(Lanes::portable()), bits::<3>(Lanes::best()));
}
