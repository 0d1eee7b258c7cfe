//! Fine grains on walls: the dummy wall particles of seed 000 Eqs. (32)–(35).
//!
//! A wall particle w takes the stress of fine particle i (σ_w = σ_i, no-slip, or the
//! extrapolated deviator of [`WallStrength`]); P*_w solves the one-sided Riemann
//! problem along the wall normal n of Eq. (33), with the mirrored velocity of Eq. (34)
//! and the hydrostatic increase of Eq. (35). The pair's interface stress is cut at the
//! soil's tensile strength ([`wall_contact`](super::wall_contact)): a contact that
//! would pull harder opens. Coulomb friction (`wall_friction`) acts against the slip,
//! bounded by μ times the normal part. In the continuity equation the wall is a
//! no-slip mirror, v_w = 2 u_w − v_i, and U* = u_w.

use super::wall_contact::{self, ClosedPairs};
use crate::fine::material::FineMaterial;
use crate::fine::source::Source;
use crate::geometry::walls::Walls;
use crate::geometry::Shape;
use crate::numerics::kernel::WendlandC2;
use crate::numerics::math::{sub_outer, Real, Vect};
use crate::numerics::periodic::{Separation, Wrap};
use crate::numerics::riemann::Riemann;
use crate::scene::WallStress;
use nalgebra::SMatrix;

/// The fine-grain–wall law of one step.
#[derive(Clone, Copy, Debug)]
pub struct WallLaw<const D: usize> {
    pub kernel: WendlandC2,
    pub riemann: Riemann,
    pub gravity: Vect<D>,
    pub dt: Real,
    /// Coulomb coefficient of fine grains on walls (0: off).
    pub friction: Real,
    /// Deviatoric stress of the dummy wall particles.
    pub stress: WallStress,
    /// The periodic axis, if any: pairs across it take the minimum image.
    pub wrap: Wrap,
}

/// Wall normal at `xi`, Eq. (33): Φ = −Σ_w ∇_i W_iw V_w, normalised (zero where Φ is).
#[inline(always)]
pub fn normal<const D: usize>(
    kernel: &WendlandC2,
    walls: &Walls<D>,
    xi: &Vect<D>,
    wl: &[u32],
    sep: &impl Separation,
) -> Vect<D> {
    let cut2 = kernel.cutoff * kernel.cutoff;
    let mut phi = Vect::<D>::zeros();
    for &w in wl {
        let rij = sep.of(xi - walls.pos[w as usize]);
        let r2 = rij.norm_squared();
        if r2 >= cut2 || r2 == 0.0 {
            continue;
        }
        let r = r2.sqrt();
        phi -= rij * (kernel.dw(r) / r * walls.volume);
    }
    let nrm = phi.norm();
    if nrm > 0.0 {
        phi / nrm
    } else {
        phi
    }
}

/// Most wall objects within one particle's support that get their own contact normal;
/// a particle near more (a spot where five faces meet) uses the normal of Eq. (33) for
/// the others.
const OBJECTS: usize = 4;

/// In one pass over the wall list `wl` of the particle at `xi`: the wall normal of
/// Eq. (33) over all of them (as [`normal`] gives it, bit for bit), and the face
/// normal of each wall object near `xi`. The contact of [`wall_contact`] opens on the
/// traction across the face of the object the pair belongs to, and a closed pair's
/// pull across it is limited there: at a corner the normal of Eq. (33) leans towards
/// the other face, whose compression then kept a receding barrier's contact closed and
/// let it pull.
///
/// An object's face is its shape's outward normal, the signed-distance gradient
/// ([`Shape::normal`]) at `xi` (wrapped into the period) shifted back by the object's
/// displacement. Summing Eq. (33) over the
/// object's own particles instead leans up at a barrier's toe, where its particles stop
/// at the floor, and left a receding barrier a pull of −6.0e-4 N/m (docs/method.md,
/// §Walls). A mesh, whose distance is a sum over all its triangles, and an object
/// without a shape take Eq. (33) over the object's particles.
#[inline(always)]
fn normals<const D: usize>(
    kernel: &WendlandC2,
    walls: &Walls<D>,
    xi: &Vect<D>,
    wl: &[u32],
    wrap: &Wrap,
) -> (Vect<D>, ObjectNormals<D>) {
    let cut2 = kernel.cutoff * kernel.cutoff;
    let mut phi = Vect::<D>::zeros();
    let mut out = ObjectNormals {
        object: [u16::MAX; OBJECTS],
        n: [Vect::<D>::zeros(); OBJECTS],
    };
    for &w in wl {
        let w = w as usize;
        let rij = wrap.of(xi - walls.pos[w]);
        let r2 = rij.norm_squared();
        if r2 >= cut2 || r2 == 0.0 {
            continue;
        }
        let r = r2.sqrt();
        let term = rij * (kernel.dw(r) / r * walls.volume);
        phi -= term;
        let o = walls.object[w];
        if let Some(k) = out.object.iter().position(|&x| x == o || x == u16::MAX) {
            out.object[k] = o;
            out.n[k] -= term;
        }
    }
    // the shapes are those of the domain's own period: the particle's position wrapped
    // into it (between list builds it strays up to a skin beyond)
    let mut at = *xi;
    if let Some(p) = wrap {
        p.wrap_point(&mut at);
    }
    let eps = FACE_STEP * kernel.cutoff;
    for (k, n) in out.n.iter_mut().enumerate() {
        let Some(obj) = walls.objects.get(out.object[k] as usize) else {
            break;
        };
        if let Some(shape) = obj.shape.as_ref().filter(|s| !matches!(s, Shape::Mesh(_))) {
            let face = shape.face_normal(&(at - obj.displacement), eps);
            if face.norm_squared() > 0.0 {
                *n = face;
                continue;
            }
        }
        let nrm = n.norm();
        if nrm > 0.0 {
            *n /= nrm;
        }
    }
    let nrm = phi.norm();
    if nrm > 0.0 {
        phi /= nrm;
    }
    (phi, out)
}

/// The central-difference step of an object's face normal, in kernel cut-offs: well
/// inside a particle spacing, so that a face's normal is its own up to a particle's
/// distance from an edge.
const FACE_STEP: Real = 1e-4;

/// The contact normals of one particle's wall objects ([`normals`]).
#[derive(Clone, Copy, Debug)]
struct ObjectNormals<const D: usize> {
    /// Wall object of each entry (`u16::MAX`: unused).
    object: [u16; OBJECTS],
    n: [Vect<D>; OBJECTS],
}

impl<const D: usize> ObjectNormals<D> {
    /// The entry of object `o`, if it has one.
    #[inline(always)]
    fn slot(&self, o: u16) -> Option<usize> {
        self.object.iter().position(|&x| x == o)
    }
}

/// Fine particle i against the walls of its list, for one step.
pub struct FineAtWall<'a, const D: usize> {
    pub pos: Vect<D>,
    pub vel: Vect<D>,
    pub rho: Real,
    pub src: &'a Source,
    /// 1/c0 of i's material.
    pub inv_c: Real,
    /// Wall normal of Eq. (33) at i.
    pub n: Vect<D>,
    /// The face normal of each wall object near i, across which a contact opens and a
    /// closed one pulls no harder than an open one.
    faces: ObjectNormals<D>,
    /// U_L = −n·v_i, Eq. (32).
    pub ul: Real,
    /// 1 / (walls in i's list): the share of the friction bound of one wall pair.
    pub share: Real,
    pub strength: WallStrength,
    /// Tensile strength of the interface ([`wall_contact::tensile_strength`]).
    pub tensile: Real,
    /// The body acceleration whose hydrostatic increase Eq. (35) extrapolates to the
    /// wall ([`FineAtWall::new`]).
    body: Vect<D>,
    /// 2/ρ_i and the squared kernel cut-off, taken once per particle.
    inv_rho2: Real,
    cut2: Real,
}

impl<'a, const D: usize> FineAtWall<'a, D> {
    /// The state of particle i (material `m`) at the walls `wl` of its list, under
    /// the water's force per unit mass `lift` where a soil exchanges one (seed 001
    /// Eqs. 8–10: buoyancy and seepage).
    ///
    /// Eq. (35) extrapolates the pressure the particle's weight holds: ρ_i g less the
    /// water's vertical force on it, ρ_i (g + ĝ ĝ·f_i/m_i), rather than ρ_i g, so that a
    /// submerged soil rests on its walls at the gradient of its submerged weight ρ' g,
    /// as its interior does (its initial stress, and the stress diffusion's
    /// [`weight`](crate::fine::continuity::ContinuityParams::weight), which takes the
    /// same vertical part). With ρ_i g the floor of Rondon's dense column (ρ_d = 1500,
    /// ρ' = 894 kg/m³) pushed its lowest row up at 0.55 m/s² from rest, and a gated
    /// column lifted off it into −57 Pa of suction by 0.6 s. Without gravity (or
    /// along a periodic axis) there is no hydrostatic increase, nor any lift.
    #[allow(clippy::too_many_arguments)]
    #[inline(always)]
    pub fn new(
        law: &WallLaw<D>,
        walls: &Walls<D>,
        m: &FineMaterial,
        pos: Vect<D>,
        vel: Vect<D>,
        rho: Real,
        src: &'a Source,
        wl: &[u32],
        lift: Option<&Vect<D>>,
    ) -> Self {
        let (n, faces) = normals(&law.kernel, walls, &pos, wl, &law.wrap);
        FineAtWall {
            pos,
            vel,
            rho,
            src,
            inv_c: 1.0 / m.c0,
            n,
            faces,
            ul: -n.dot(&vel),
            share: 1.0 / wl.len() as Real,
            strength: match law.stress {
                WallStress::Extrapolated => WallStrength::new(m, src),
                WallStress::Mirrored => WallStrength::MIRROR,
            },
            tensile: wall_contact::tensile_strength(m),
            // the lift's part along gravity only, as the stress diffusion's `weight`;
            // a dry soil takes gravity as it is
            body: lift
                .and_then(|a| {
                    law.gravity
                        .try_normalize(0.0)
                        .map(|down| down * down.dot(a))
                })
                .map_or(law.gravity, |l| law.gravity + l),
            inv_rho2: 2.0 / rho,
            cut2: law.kernel.cutoff * law.kernel.cutoff,
        }
    }

    /// Acceleration of i from each wall particle of its list `wl` within the kernel,
    /// Eqs. (32)–(35), into `out` (cleared first) in the list's order: (2/ρ_i) σ*·e_iw
    /// ∂W/∂r V_w with σ* = ½(σˢ_i + σˢ_w) − P*_w I cut at the tensile strength, and
    /// Coulomb friction; the closed pairs with each wall object together pull no
    /// harder across its face than open ones ([`ClosedPairs`]), a shortfall shared
    /// among them by their weight.
    #[inline(always)]
    pub fn accelerations(
        &self,
        law: &WallLaw<D>,
        walls: &Walls<D>,
        wl: &[u32],
        out: &mut Vec<WallPair<D>>,
    ) {
        out.clear();
        let mut closed = [ClosedPairs::<D>::zero(); OBJECTS];
        for &w in wl {
            if let Some(p) = self.pair(law, walls, w, &mut closed) {
                out.push(p);
            }
        }
        let mut short = [0.0; OBJECTS];
        let mut any = false;
        for (k, c) in closed.iter().enumerate() {
            short[k] = c.deficit(&self.faces.n[k], self.tensile);
            any |= short[k] > 0.0;
        }
        if any {
            for p in out.iter_mut() {
                let k = p.slot as usize;
                if k < OBJECTS && short[k] > 0.0 {
                    p.a += self.faces.n[k] * (short[k] * closed[k].share(p.weight));
                }
            }
        }
    }

    /// The pair of i with wall particle `w` (None outside the kernel), its closed
    /// contact added to `closed` under its object's entry.
    #[inline(always)]
    fn pair(
        &self,
        law: &WallLaw<D>,
        walls: &Walls<D>,
        w: u32,
        closed: &mut [ClosedPairs<D>; OBJECTS],
    ) -> Option<WallPair<D>> {
        let (wi, si) = (w as usize, self.src);
        let rij = law.wrap.of(self.pos - walls.pos[wi]);
        let r2 = rij.norm_squared();
        if r2 >= self.cut2 || r2 == 0.0 {
            return None;
        }
        let r = r2.sqrt();
        let e = rij * (1.0 / r);
        let dw = law.kernel.dw(r);
        let n = self.n;
        let uw = -n.dot(&walls.velocity(wi));
        // Eq. (34): U_R = −U_L + 2u_w, so U_L − U_R = 2(U_L − u_w).
        let du = 2.0 * (self.ul - uw);
        let pr = wall_pressure(si.p, self.rho, r, self.body.dot(&(-e)));
        let beta = law.riemann.limiter(du, self.inv_c);
        let pstar = 0.5 * (si.p + pr) + 0.5 * beta * si.z * du;
        let mut sstar = si.dev.scale(0.5 * (1.0 + self.strength.ratio(pr)));
        sstar.0[0] -= pstar;
        sstar.0[1] -= pstar;
        sstar.0[2] -= pstar;
        // the contact opens beyond the soil's tensile strength, on the traction across
        // the face of w's own object
        let slot = self.faces.slot(walls.object[wi]);
        let face = slot.map_or(n, |k| self.faces.n[k]);
        let (sstar, open) = wall_contact::cut(sstar, &face, self.tensile);
        let k = self.inv_rho2 * dw * walls.volume;
        let mut a = sstar.dot_vec(&e) * k;
        if law.friction > 0.0 {
            let an = a.dot(&n);
            if an > 0.0 {
                let vrel = self.vel - walls.velocity(wi);
                let vt = vrel - n * vrel.dot(&n);
                let s = vt.norm();
                if s > 0.0 {
                    let mag = (law.friction * an).min(s / law.dt * self.share);
                    a -= vt * (mag / s);
                }
            }
        }
        let (slot, weight) = match slot {
            Some(s) if !open => (s as u8, closed[s].add(&a, &face, &e, k)),
            _ => (u8::MAX, 0.0),
        };
        Some(WallPair { w, a, slot, weight })
    }
}

/// One wall pair's acceleration of a fine particle ([`FineAtWall::accelerations`]).
#[derive(Clone, Copy, Debug)]
pub struct WallPair<const D: usize> {
    /// The wall particle.
    pub w: u32,
    pub a: Vect<D>,
    /// Its object's entry among the particle's faces when the contact is closed
    /// (`u8::MAX`: open, or an object past the first few).
    slot: u8,
    /// Its share of a correction of the closed pairs ([`ClosedPairs::add`]).
    weight: Real,
}

/// Eq. (35): the pressure of wall particle w against fine particle i at pressure
/// `p` and density `rho`, a distance `r` away, with `g_to_wall` = g·e_wi (e_wi the unit
/// vector from i to w): P_w = P_i + ρ_i r max(0, g·e_wi), the hydrostatic increase
/// towards walls below the particle and none towards walls above.
#[inline(always)]
pub fn wall_pressure(p: Real, rho: Real, r: Real, g_to_wall: Real) -> Real {
    p + rho * r * g_to_wall.max(0.0)
}

/// The continuity terms of wall particle `w` on fine particle i at `xi` moving with
/// `vi`, Eqs. (32)–(34): U* = u_w, so only the mirrored velocity enters. Adds to
/// `drho` (Eq. 15) and `grad` (Eq. 24). The hydrostatic jump of Eq. (35) is the
/// geostatic state itself, which the fine–fine pair terms subtract too; it acts in
/// the momentum equation only (kept here, it made every grain resting on a floor gain
/// density exponentially).
#[inline(always)]
#[allow(clippy::too_many_arguments)]
pub fn continuity<const D: usize>(
    kernel: &WendlandC2,
    walls: &Walls<D>,
    sep: &impl Separation,
    xi: &Vect<D>,
    vi: &Vect<D>,
    w: usize,
    drho: &mut Real,
    grad: &mut SMatrix<Real, D, D>,
) {
    let cut2 = kernel.cutoff * kernel.cutoff;
    let rij = sep.of(xi - walls.pos[w]);
    let r2 = rij.norm_squared();
    if r2 >= cut2 || r2 == 0.0 {
        return;
    }
    let r = r2.sqrt();
    let e = rij * (1.0 / r);
    let dwv = kernel.dw(r) * walls.volume;
    let rel = (vi - walls.velocity(w)) * 2.0;
    *drho += rel.dot(&e) * dwv;
    sub_outer(grad, &(rel * dwv), &e);
}

/// The deviatoric stress a dummy wall particle carries against particle i: the
/// particle's σˢ_i at the same share of the Drucker–Prager strength √J2 ≤ 3α_φ P + k_c
/// (Eqs. 4, 6) at the wall's pressure P_w of Eq. (35) as it uses at its own pressure,
/// σˢ_w = m σˢ_i with m = (3α_φ P_w + k_c)/max(3α_φ P_i + k_c, √J2(σˢ_i)). In a
/// frictional layer shear and pressure both grow with depth, so this extrapolates the
/// stress to the wall as Eq. (35) extrapolates the pressure (for c = 0, m = P_w/P_i
/// exactly); seed 000's mirror σˢ_w = σˢ_i gives a particle lying on the wall only the
/// shear at its own centre, half the basal shear of a one-particle-thick layer. The
/// pair term takes the mean ½(σˢ_i + σˢ_w), as Eq. (34) takes ½(P_L + P_R); m never
/// lets the wall exceed the strength at its pressure, and is 1 where neither side
/// has strength (a particle in tension without cohesion carries no shear).
#[derive(Clone, Copy, Debug)]
pub struct WallStrength {
    /// 3α_φ, or 0 for the mirror.
    three_alpha: Real,
    k_c: Real,
    /// 1 / max(3α_φ P_i + k_c, √J2(σˢ_i)), or 0 where that vanishes.
    inv_used: Real,
}

impl WallStrength {
    /// m = 1 everywhere.
    pub const MIRROR: WallStrength = WallStrength {
        three_alpha: 0.0,
        k_c: 0.0,
        inv_used: 0.0,
    };

    /// On the strongest cone of `m` ([`FineMaterial::strongest_cone`]).
    pub fn new(m: &FineMaterial, si: &Source) -> Self {
        let (alpha_phi, k_c) = m.strongest_cone();
        let three_alpha = 3.0 * alpha_phi;
        let used = (three_alpha * si.p + k_c).max(si.dev.j2().sqrt());
        WallStrength {
            three_alpha,
            k_c,
            inv_used: if used > 0.0 { 1.0 / used } else { 0.0 },
        }
    }

    /// m at the wall pressure `pw`.
    #[inline(always)]
    fn ratio(&self, pw: Real) -> Real {
        if self.inv_used > 0.0 {
            (self.three_alpha * pw + self.k_c).max(0.0) * self.inv_used
        } else {
            1.0
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::geometry::walls::{WallKind, WallObject};
    use crate::interactions::symmetric_tests::material;
    use crate::numerics::math::Sym;
    use crate::numerics::riemann::Riemann;

    type V = Vect<2>;

    /// A soil particle at rest at `p` of geostatic pressure, over a floor particle
    /// 0.8 dp below and to the side: its wall acceleration times its density.
    fn traction(rho: Real, lift: Option<&V>) -> V {
        let dp = 0.002;
        let m = material("beads", rho, 5e5);
        let law = WallLaw {
            kernel: WendlandC2::new(1.3 * dp, 2),
            riemann: Riemann { eta: 40.0 },
            gravity: V::new(0.0, -9.81),
            dt: 1e-5,
            friction: 0.0,
            stress: WallStress::Extrapolated,
            wrap: None,
        };
        let walls = Walls::<2> {
            pos: vec![V::new(0.3 * dp, -0.8 * dp)],
            object: vec![0],
            objects: vec![WallObject {
                name: "floor".into(),
                kind: WallKind::default(),
                velocity: V::zeros(),
                prescribed: V::zeros(),
                window: (0.0, Real::INFINITY),
                barrier: None,
                displacement: V::zeros(),
                shape: None,
                driven: false,
                permeable: false,
            }],
            barriers: Vec::new(),
            volume: dp * dp,
            panel: Vec::new(),
        };
        let p = 300.0;
        let src = Source {
            dev: Sym([0.1 * p, -0.1 * p, 0.0, 0.0, 0.0, 0.0]),
            p,
            vol: dp * dp,
            z: rho * m.c0,
            p_rho: 0.0,
        };
        let (x, v) = (V::zeros(), V::zeros());
        let at = FineAtWall::new(&law, &walls, &m, x, v, rho, &src, &[0], lift);
        let mut pairs = Vec::new();
        at.accelerations(&law, &walls, &[0], &mut pairs);
        assert_eq!(pairs.len(), 1, "within the kernel");
        pairs[0].a * rho
    }

    /// Eq. (35) read for a submerged soil: a soil of dry bulk density ρ_d whose grains
    /// the water lifts by (1 − n) ρ_w g per unit volume presses on its floor as a dry
    /// soil of density ρ' = ρ_d − (1 − n) ρ_w at the same stress: the hydrostatic
    /// increase follows the weight the skeleton carries. A seepage force along the
    /// floor adds nothing (only the vertical part enters).
    #[test]
    fn submerged_soil_presses_on_its_floor_with_its_submerged_weight() {
        let (rho_d, n, rho_w) = (1500.0, 0.4, 1010.0);
        let rho_sub = rho_d - (1.0 - n) * rho_w;
        let lift = V::new(0.0, (1.0 - n) * rho_w * 9.81 / rho_d);
        let want = traction(rho_sub, None);
        let got = traction(rho_d, Some(&lift));
        assert!(
            (got - want).norm() < 1e-9 * want.norm(),
            "{got} against {want}"
        );
        let sideways = lift + V::new(3.0, 0.0);
        let got = traction(rho_d, Some(&sideways));
        assert!(
            (got - want).norm() < 1e-9 * want.norm(),
            "{got} against {want}"
        );
        // with ρ_d g, as before, the floor pushes harder than the soil weighs
        let dry = traction(rho_d, None);
        assert!(dry[1] > want[1] * 1.001, "{dry} against {want}");
    }
}
