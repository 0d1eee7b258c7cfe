//! Issue 45's measurement of cluster pairs: one pass of a 2D water-like momentum pair
//! term (Wendland C2 gradient, the acoustic Riemann pressure of seed 000 Eq. (20)
//! with its limiter, Morris' viscosity), taken two ways over the same particles:
//!
//! - **half lists** as the solver's sweeps take them: each pair once, one at a time
//!   in f64, its two halves added to both particles (the scatter);
//! - **4×4 cluster pairs** (GROMACS' NxM scheme): four consecutive particles form a
//!   cluster, the list holds cluster pairs, and the sixteen particle pairs of a
//!   cluster pair are taken four at a time on f64x4 lanes (`pulp`, AVX2 where the CPU
//!   has it), the neighbours' data loaded from one array per component without a
//!   gather, the pairs beyond the cut-off masked out.
//!
//! Two particle orders: the solver's (by cell of the list radius) and columns two
//! spacings wide along x, sorted along y, so that a cluster is a compact 2×2 block.
//! The passes alternate 40 times in one process (the machine's speed drifts between
//! runs); the medians and their ratio are printed. Run with
//! `cargo run --release -p granmix-core --example cluster_pairs`.

use granmix_core::numerics::rng::Rng;
use pulp::{Simd, WithSimd};
use std::time::Instant;

/// Smoothing length, cut-off 2h and list radius (cut-off + skin), in particle spacings.
const H: f64 = 1.3;
const CUT: f64 = 2.0 * H;
const RADIUS: f64 = CUT + 0.3;
/// Sound speed, density, viscosity, the limiter's η and the viscosity's regulariser.
const C0: f64 = 20.0;
const RHO0: f64 = 1000.0;
const MU: f64 = 1e-3;
const ETA: f64 = 3.0;
const REG: f64 = 0.01;
/// Particles per side of the square lattice.
const SIDE: usize = 220;

/// The particles, one array per component, padded to a multiple of four with
/// particles far from all others.
struct Particles {
    x: Vec<f64>,
    y: Vec<f64>,
    vx: Vec<f64>,
    vy: Vec<f64>,
    p: Vec<f64>,
    vol: Vec<f64>,
    /// Real particles (the rest is padding).
    n: usize,
}

/// ∂W/∂r = coef q (1 − q/2)³ of the 2D Wendland C2 kernel, q = r/h.
fn dw_coef() -> f64 {
    -5.0 * 7.0 / (4.0 * std::f64::consts::PI * H * H) / H
}

/// The cell of the list radius that `(x, y)` lies in, cells `nc` to a row.
fn cell(x: f64, y: f64, nc: usize) -> usize {
    (((y + 0.5) / RADIUS) as usize) * nc + ((x + 0.5) / RADIUS) as usize
}

/// A jittered lattice with random velocities and pressures, in `columns` order or
/// the solver's cell order.
fn particles(columns: bool, nc: usize) -> Particles {
    let mut rng = Rng(7);
    let mut pts: Vec<[f64; 6]> = Vec::new();
    for a in 0..SIDE {
        for b in 0..SIDE {
            let x = a as f64 + 0.2 * (rng.uniform() - 0.5);
            let y = b as f64 + 0.2 * (rng.uniform() - 0.5);
            let (u, v) = (rng.uniform() - 0.5, rng.uniform() - 0.5);
            let p = 1000.0 * rng.uniform();
            pts.push([x, y, u, v, p, 1.0 + 0.01 * rng.uniform()]);
        }
    }
    if columns {
        pts.sort_by_key(|q| (((q[0] + 0.5) / 2.0) as usize, ((q[1] + 0.5) * 1e3) as usize));
    } else {
        pts.sort_by_key(|q| cell(q[0], q[1], nc));
    }
    let n = pts.len();
    let mut p = Particles {
        x: vec![],
        y: vec![],
        vx: vec![],
        vy: vec![],
        p: vec![],
        vol: vec![],
        n,
    };
    for k in 0..n.div_ceil(4) * 4 {
        let far = [1e6 + 10.0 * k as f64, 1e6, 0.0, 0.0, 0.0, 0.0];
        let q = pts.get(k).copied().unwrap_or(far);
        p.x.push(q[0]);
        p.y.push(q[1]);
        p.vx.push(q[2]);
        p.vy.push(q[3]);
        p.p.push(q[4]);
        p.vol.push(q[5]);
    }
    p
}

/// Compressed rows: row k is `idx[off[k]..off[k + 1]]`.
struct Rows {
    off: Vec<u32>,
    idx: Vec<u32>,
}

impl Rows {
    fn of(&self, k: usize) -> &[u32] {
        &self.idx[self.off[k] as usize..self.off[k + 1] as usize]
    }
}

/// The half lists (j > i within the list radius, ascending) and the cluster-pair
/// lists (for cluster I, the clusters J ≥ I holding a neighbour of one of its members).
fn lists(p: &Particles, nc: usize) -> (Rows, Rows) {
    let n = p.n;
    let mut start = vec![0usize; nc * nc + 1];
    for k in 0..n {
        start[cell(p.x[k], p.y[k], nc) + 1] += 1;
    }
    for c in 0..nc * nc {
        start[c + 1] += start[c];
    }
    let mut items = vec![0usize; n];
    let mut fill = start.clone();
    for k in 0..n {
        let c = cell(p.x[k], p.y[k], nc);
        items[fill[c]] = k;
        fill[c] += 1;
    }
    let r2 = RADIUS * RADIUS;
    let mut half = Rows {
        off: vec![0],
        idx: vec![],
    };
    let mut full: Vec<Vec<u32>> = vec![vec![]; n];
    for (i, near) in full.iter_mut().enumerate() {
        let c = cell(p.x[i], p.y[i], nc);
        let (cx, cy) = (c % nc, c / nc);
        for row in cy.saturating_sub(1)..=(cy + 1).min(nc - 1) {
            let a = start[row * nc + cx.saturating_sub(1)];
            let b = start[row * nc + (cx + 1).min(nc - 1) + 1];
            for &j in &items[a..b] {
                let d2 = (p.x[i] - p.x[j]).powi(2) + (p.y[i] - p.y[j]).powi(2);
                if d2 < r2 && j != i {
                    near.push(j as u32);
                }
            }
        }
        near.sort_unstable();
        half.idx.extend(near.iter().filter(|&&j| j as usize > i));
        half.off.push(half.idx.len() as u32);
    }
    let mut clusters = Rows {
        off: vec![0],
        idx: vec![],
    };
    for ci in 0..p.x.len() / 4 {
        let mut js: Vec<u32> = vec![ci as u32];
        for near in full.iter().skip(4 * ci).take(4) {
            js.extend(near.iter().map(|j| j / 4).filter(|&cj| cj as usize >= ci));
        }
        js.sort_unstable();
        js.dedup();
        clusters.idx.extend(js);
        clusters.off.push(clusters.idx.len() as u32);
    }
    (half, clusters)
}

/// One pair's term on particle i (the negated one on j), before the partner's volume.
#[inline(always)]
fn pair_term(p: &Particles, i: usize, j: usize, kd: f64) -> Option<(f64, f64)> {
    let (dx, dy) = (p.x[i] - p.x[j], p.y[i] - p.y[j]);
    let rr = dx * dx + dy * dy;
    if rr >= CUT * CUT {
        return None;
    }
    let r = rr.sqrt();
    let inv_r = 1.0 / r;
    let (ex, ey) = (dx * inv_r, dy * inv_r);
    let q = r * (1.0 / H);
    let t = 1.0 - 0.5 * q;
    let dw = kd * q * t * t * t;
    let (vx, vy) = (p.vx[i] - p.vx[j], p.vy[i] - p.vy[j]);
    let du = -(vx * ex + vy * ey);
    let beta = (ETA * du / C0).clamp(0.0, 1.0);
    let ps = 0.5 * (p.p[i] + p.p[j]) + 0.5 * beta * RHO0 * C0 * du;
    let visc = MU * r * dw / (rr + REG);
    Some((-ps * dw * ex + visc * vx, -ps * dw * ey + visc * vy))
}

/// The pass over half lists, one pair at a time, scattered to both particles.
fn half_pass(p: &Particles, half: &Rows, (ax, ay): (&mut [f64], &mut [f64])) {
    let kd = dw_coef();
    for i in 0..p.n {
        let (mut sx, mut sy) = (0.0, 0.0);
        for &j in half.of(i) {
            let j = j as usize;
            if let Some((fx, fy)) = pair_term(p, i, j, kd) {
                sx += fx * p.vol[j];
                sy += fy * p.vol[j];
                ax[j] -= fx * p.vol[i];
                ay[j] -= fy * p.vol[i];
            }
        }
        ax[i] += sx;
        ay[i] += sy;
    }
}

/// The pass over 4×4 cluster pairs on the widest vectors the CPU has.
struct ClusterPass<'a> {
    p: &'a Particles,
    clusters: &'a Rows,
    ax: &'a mut [f64],
    ay: &'a mut [f64],
}

impl WithSimd for ClusterPass<'_> {
    type Output = ();

    // inlined into each dispatch level's copy; no closures inside, which would be
    // compiled apart from it
    #[inline(always)]
    fn with_simd<S: Simd>(self, s: S) {
        let ClusterPass {
            p,
            clusters,
            ax,
            ay,
        } = self;
        assert_eq!(S::F64_LANES, 4, "the experiment takes four lanes (AVX2)");
        let (cut2, one, half, zero) = (
            s.splat_f64s(CUT * CUT),
            s.splat_f64s(1.0),
            s.splat_f64s(0.5),
            s.splat_f64s(0.0),
        );
        let (inv_h, kd, eta_c, z) = (
            s.splat_f64s(1.0 / H),
            s.splat_f64s(dw_coef()),
            s.splat_f64s(ETA / C0),
            s.splat_f64s(RHO0 * C0),
        );
        let (mu, reg) = (s.splat_f64s(MU), s.splat_f64s(REG));
        let lane = s.partial_load_f64s(&[0.0, 1.0, 2.0, 3.0]);
        let n = s.splat_f64s(p.n as f64);
        for ci in 0..clusters.off.len() - 1 {
            let (mut aix, mut aiy) = ([zero; 4], [zero; 4]);
            let ib = 4 * ci;
            for &cj in clusters.of(ci) {
                let jb = 4 * cj as usize;
                let xj = s.partial_load_f64s(&p.x[jb..jb + 4]);
                let yj = s.partial_load_f64s(&p.y[jb..jb + 4]);
                let vxj = s.partial_load_f64s(&p.vx[jb..jb + 4]);
                let vyj = s.partial_load_f64s(&p.vy[jb..jb + 4]);
                let pj = s.partial_load_f64s(&p.p[jb..jb + 4]);
                let volj = s.partial_load_f64s(&p.vol[jb..jb + 4]);
                let jidx = s.add_f64s(s.splat_f64s(jb as f64), lane);
                let real = s.less_than_f64s(jidx, n);
                let (mut ajx, mut ajy) = (zero, zero);
                for k in 0..4 {
                    let i = ib + k;
                    if i >= p.n {
                        break;
                    }
                    let dx = s.sub_f64s(s.splat_f64s(p.x[i]), xj);
                    let dy = s.sub_f64s(s.splat_f64s(p.y[i]), yj);
                    let rr = s.add_f64s(s.mul_f64s(dx, dx), s.mul_f64s(dy, dy));
                    let mut m = s.and_m64s(s.less_than_f64s(rr, cut2), real);
                    if jb == ib {
                        // the diagonal cluster pair: each pair once, j > i
                        m = s.and_m64s(m, s.greater_than_f64s(jidx, s.splat_f64s(i as f64)));
                    }
                    let rr = s.select_f64s(m, rr, one);
                    let r = s.sqrt_f64s(rr);
                    let inv_r = s.div_f64s(one, r);
                    let (ex, ey) = (s.mul_f64s(dx, inv_r), s.mul_f64s(dy, inv_r));
                    let q = s.mul_f64s(r, inv_h);
                    let t = s.sub_f64s(one, s.mul_f64s(half, q));
                    let dw = s.mul_f64s(s.mul_f64s(s.mul_f64s(s.mul_f64s(kd, q), t), t), t);
                    let vx = s.sub_f64s(s.splat_f64s(p.vx[i]), vxj);
                    let vy = s.sub_f64s(s.splat_f64s(p.vy[i]), vyj);
                    let du = s.neg_f64s(s.add_f64s(s.mul_f64s(vx, ex), s.mul_f64s(vy, ey)));
                    let beta = s.max_f64s(s.min_f64s(s.mul_f64s(eta_c, du), one), zero);
                    let mean = s.mul_f64s(half, s.add_f64s(s.splat_f64s(p.p[i]), pj));
                    let jump = s.mul_f64s(s.mul_f64s(s.mul_f64s(half, beta), z), du);
                    let ps = s.add_f64s(mean, jump);
                    let visc = s.div_f64s(s.mul_f64s(s.mul_f64s(mu, r), dw), s.add_f64s(rr, reg));
                    let pd = s.mul_f64s(s.neg_f64s(ps), dw);
                    let fx = s.add_f64s(s.mul_f64s(pd, ex), s.mul_f64s(visc, vx));
                    let fy = s.add_f64s(s.mul_f64s(pd, ey), s.mul_f64s(visc, vy));
                    let (fx, fy) = (s.select_f64s(m, fx, zero), s.select_f64s(m, fy, zero));
                    aix[k] = s.add_f64s(aix[k], s.mul_f64s(fx, volj));
                    aiy[k] = s.add_f64s(aiy[k], s.mul_f64s(fy, volj));
                    let voli = s.splat_f64s(p.vol[i]);
                    ajx = s.sub_f64s(ajx, s.mul_f64s(fx, voli));
                    ajy = s.sub_f64s(ajy, s.mul_f64s(fy, voli));
                }
                let sx = s.add_f64s(s.partial_load_f64s(&ax[jb..jb + 4]), ajx);
                s.partial_store_f64s(&mut ax[jb..jb + 4], sx);
                let sy = s.add_f64s(s.partial_load_f64s(&ay[jb..jb + 4]), ajy);
                s.partial_store_f64s(&mut ay[jb..jb + 4], sy);
            }
            for k in 0..4 {
                ax[ib + k] += s.reduce_sum_f64s(aix[k]);
                ay[ib + k] += s.reduce_sum_f64s(aiy[k]);
            }
        }
    }
}

/// Seconds of one pass into zeroed `ax`, `ay`.
fn timed(ax: &mut [f64], ay: &mut [f64], pass: &mut dyn FnMut(&mut [f64], &mut [f64])) -> f64 {
    ax.fill(0.0);
    ay.fill(0.0);
    let t = Instant::now();
    pass(ax, ay);
    t.elapsed().as_secs_f64()
}

fn median(mut v: Vec<f64>) -> f64 {
    v.sort_by(f64::total_cmp);
    v[v.len() / 2]
}

fn main() {
    let arch = pulp::Arch::new();
    let nc = ((SIDE as f64 + 1.0) / RADIUS).ceil() as usize + 1;
    if !std::arch::is_x86_feature_detected!("avx2") {
        println!("the cluster pass takes four f64 lanes: this CPU has no AVX2");
        return;
    }
    for (name, columns) in [("cell order", false), ("columns", true)] {
        let p = particles(columns, nc);
        let (half, clusters) = lists(&p, nc);
        let within = (0..p.n)
            .map(|i| {
                let near = half.of(i).iter();
                near.filter(|&&j| pair_term(&p, i, j as usize, 1.0).is_some())
                    .count()
            })
            .sum::<usize>();
        let lanes = 16 * clusters.idx.len();
        let (mut ax, mut ay) = (vec![0.0; p.x.len()], vec![0.0; p.x.len()]);
        let (mut bx, mut by) = (ax.clone(), ay.clone());
        let (mut th, mut tc) = (vec![], vec![]);
        for _ in 0..40 {
            th.push(timed(&mut ax, &mut ay, &mut |ax, ay| {
                half_pass(&p, &half, (ax, ay))
            }));
            tc.push(timed(&mut bx, &mut by, &mut |ax, ay| {
                let clusters = &clusters;
                arch.dispatch(ClusterPass {
                    p: &p,
                    clusters,
                    ax,
                    ay,
                })
            }));
        }
        // the two orders of summation agree to rounding
        let scale = ax.iter().map(|a| a.abs()).fold(0.0, f64::max);
        let diff = ax
            .iter()
            .zip(&bx)
            .chain(ay.iter().zip(&by))
            .map(|(a, b)| (a - b).abs())
            .fold(0.0, f64::max);
        let (mh, mc) = (median(th), median(tc));
        println!(
            "{name}: {} particles, {} pairs within the cut-off; {} cluster pairs, {:.0} % \
             of their lanes within the cut-off; half lists {:.2} ms ({:.1} ns a pair), \
             clusters {:.2} ms ({:.1} ns a pair): {:.2}x; largest difference {:.1e} of \
             the largest term",
            p.n,
            within,
            clusters.idx.len(),
            100.0 * within as f64 / lanes as f64,
            mh * 1e3,
            mh * 1e9 / within as f64,
            mc * 1e3,
            mc * 1e9 / within as f64,
            mh / mc,
            diff / scale,
        );
    }
}
