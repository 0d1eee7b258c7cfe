//! Wall boundaries: layers of dummy particles (seed 000 §2.4) grouped into objects.
//! An object is a wall, a barrier or one face of a container; barriers report loads.

use crate::geometry::Shape;
use crate::numerics::math::{Real, Vect};
use crate::scene::ContainerSpec;

/// What a wall object is in the scene: viewers colour by it.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, serde::Serialize, serde::Deserialize)]
pub enum WallKind {
    /// An entry of `[[walls]]` (a slope, a floor, a plane patch).
    #[default]
    Wall,
    /// An entry of `[[walls]]` whose shape is a heightmap.
    Terrain,
    /// An entry of `[[barriers]]`.
    Barrier,
    /// One face of a `[[containers]]` entry.
    Container,
}

impl WallKind {
    /// Lower-case name (`wall`, `terrain`, `barrier`, `container`).
    pub fn name(self) -> &'static str {
        match self {
            WallKind::Wall => "wall",
            WallKind::Terrain => "terrain",
            WallKind::Barrier => "barrier",
            WallKind::Container => "container",
        }
    }
}

/// One rigid wall object.
#[derive(Clone, Debug, serde::Serialize, serde::Deserialize)]
pub struct WallObject<const D: usize> {
    pub name: String,
    /// Where it comes from in the scene.
    #[serde(default)]
    pub kind: WallKind,
    /// Current rigid velocity (m/s): `prescribed` inside the motion window, else zero.
    pub velocity: Vect<D>,
    /// Prescribed rigid velocity (m/s).
    pub prescribed: Vect<D>,
    /// The object moves for start ≤ t < stop.
    pub window: (Real, Real),
    /// Index into the barrier list when this object reports its load.
    pub barrier: Option<usize>,
    /// Rigid displacement since the start (m).
    pub displacement: Vect<D>,
    /// The solid shape at t = 0 (coarse grains contact it exactly; shifted by
    /// `displacement`).
    /// Not serialised: a restored state takes it back from a simulation of the same
    /// scene (`Simulation::take_shapes_from`).
    #[serde(skip)]
    pub shape: Option<Shape<D>>,
    /// Driven by a co-simulation partner: `velocity` is set through [`Walls::drive`] and
    /// kept across steps instead of following `prescribed`.
    pub driven: bool,
    /// Water passes through it (`permeable = true`): only the grains see it.
    #[serde(default)]
    pub permeable: bool,
}

/// A barrier: a wall object whose load is summed every step.
#[derive(Clone, Debug, serde::Serialize, serde::Deserialize)]
pub struct Barrier<const D: usize> {
    pub name: String,
    pub object: usize,
    /// Point about which the moment is taken; moves with the barrier.
    pub reference: Vect<D>,
    /// Panel counts along the split axes (empty: one panel); see `crate::geometry::panels`.
    pub panels: Vec<usize>,
    /// First load slot of this barrier: its panels use slots `slot0..slot0 + n`.
    pub slot0: usize,
    /// Axes the panels split and the extent of the barrier's wall particles along
    /// them (set by `Walls::split_panels`).
    pub panel_axes: Vec<usize>,
    pub panel_lo: Vect<D>,
    pub panel_hi: Vect<D>,
}

/// All dummy wall particles.
#[derive(Clone, Debug, Default, serde::Serialize, serde::Deserialize)]
pub struct Walls<const D: usize> {
    pub pos: Vec<Vect<D>>,
    pub object: Vec<u16>,
    pub objects: Vec<WallObject<D>>,
    pub barriers: Vec<Barrier<D>>,
    /// Volume of one wall particle, dp^D.
    pub volume: Real,
    /// Panel of each wall particle within its barrier (empty when no barrier has panels).
    pub panel: Vec<u32>,
}

impl<const D: usize> Walls<D> {
    pub fn len(&self) -> usize {
        self.pos.len()
    }
    pub fn is_empty(&self) -> bool {
        self.pos.is_empty()
    }
    /// Number of panels of barrier `b`.
    pub fn panel_count(&self, b: usize) -> usize {
        self.barriers[b].panels.iter().product()
    }
    /// Load slots of all barriers (one per panel; one per barrier without panels).
    pub fn load_slots(&self) -> usize {
        self.barriers
            .last()
            .map_or(0, |l| l.slot0 + l.panels.iter().product::<usize>())
    }
    /// Load slot of wall particle `w` of barrier `b`.
    #[inline(always)]
    pub fn load_slot(&self, b: usize, w: usize) -> usize {
        self.barriers[b].slot0 + self.panel.get(w).map_or(0, |&p| p as usize)
    }
    /// True when water passes through any wall object.
    pub fn any_permeable(&self) -> bool {
        self.objects.iter().any(|o| o.permeable)
    }
    /// True when object `o` can move during the run: a prescribed velocity or a
    /// co-simulation input drives it.
    pub fn can_move(&self, o: usize) -> bool {
        let o = &self.objects[o];
        o.driven || o.prescribed.norm_squared() > 0.0
    }
    /// True when any wall object moves.
    pub fn any_moving(&self) -> bool {
        self.objects.iter().any(|o| o.velocity.norm_squared() > 0.0)
    }
    /// Velocity of wall particle `w`.
    #[inline(always)]
    pub fn velocity(&self, w: usize) -> Vect<D> {
        self.objects[self.object[w] as usize].velocity
    }
    /// Set the current velocities for a step that starts at time `t`.
    pub fn set_time(&mut self, t: Real) {
        for o in self.objects.iter_mut().filter(|o| !o.driven) {
            let on = t >= o.window.0 && t < o.window.1;
            o.velocity = if on { o.prescribed } else { Vect::<D>::zeros() };
        }
    }
    /// Largest rigid speed of any object over a step that starts at `t`: a driven
    /// object's current velocity, a prescribed one's inside its motion window. It bounds
    /// the time step so that no wall moves more than a fraction of h per step
    /// ([`crate::step::Stepper::stable_dt`]).
    pub fn max_speed_at(&self, t: Real) -> Real {
        self.objects
            .iter()
            .map(|o| {
                if o.driven {
                    o.velocity.norm()
                } else if t >= o.window.0 && t < o.window.1 {
                    o.prescribed.norm()
                } else {
                    0.0
                }
            })
            .fold(0.0, Real::max)
    }
    /// The first object whose motion fails the stability guard: a non-finite velocity
    /// or displacement, or a speed beyond `max_speed`. Returns (object, quantity, value,
    /// is-speed).
    pub fn check(&self, max_speed: Real) -> Option<(usize, &'static str, Real, bool)> {
        self.objects.iter().enumerate().find_map(|(i, o)| {
            let v = o.velocity.norm();
            let d = o.displacement.norm();
            if !v.is_finite() {
                Some((i, "velocity", v, false))
            } else if !d.is_finite() {
                Some((i, "displacement", d, false))
            } else if v > max_speed {
                Some((i, "speed", v, true))
            } else {
                None
            }
        })
    }
    /// Set the velocity of driven object `object` for the following steps.
    pub fn drive(&mut self, object: usize, velocity: Vect<D>) {
        debug_assert!(self.objects[object].driven);
        self.objects[object].velocity = velocity;
    }
    /// Move moving objects rigidly by their velocity over `dt`.
    pub fn advance(&mut self, dt: Real) {
        if !self.any_moving() {
            return;
        }
        for o in &mut self.objects {
            o.displacement += o.velocity * dt;
        }
        for b in &mut self.barriers {
            b.reference += self.objects[b.object].velocity * dt;
        }
        let objects = &self.objects;
        for (p, &o) in self.pos.iter_mut().zip(&self.object) {
            *p += objects[o as usize].velocity * dt;
        }
    }
    /// Largest rigid displacement of any object since `since` (per-object snapshot).
    pub fn max_displacement_since(&self, since: &[Vect<D>]) -> Real {
        self.objects
            .iter()
            .zip(since)
            .map(|(o, s)| (o.displacement - s).norm())
            .fold(0.0, Real::max)
    }
}

/// One closed face of a `[[containers]]` entry: its name ("-x", "+y", …), its axis and
/// side (−1 or +1), and its box.
pub struct ContainerFace<const D: usize> {
    pub face: String,
    pub axis: usize,
    pub sign: Real,
    pub min: Vect<D>,
    pub max: Vect<D>,
}

/// The closed faces of container `c` as boxes `t` thick outside it (the open ones
/// default to the top). Faces on lower axes span the interior; higher axes take the
/// corners.
pub fn container_faces<const D: usize>(c: &ContainerSpec, t: Real) -> Vec<ContainerFace<D>> {
    let v = |x: &[f64]| Vect::<D>::from_iterator(x.iter().copied());
    let (lo, hi) = (v(&c.min), v(&c.max));
    let open: Vec<String> = c
        .open
        .clone()
        .unwrap_or_else(|| vec![if D == 2 { "+y".into() } else { "+z".into() }]);
    let mut faces = Vec::new();
    for a in 0..D {
        for (side, sign) in [("-", -1.0), ("+", 1.0)] {
            let face = format!("{side}{}", ["x", "y", "z"][a]);
            if open.contains(&face) {
                continue;
            }
            let mut fmin = lo;
            let mut fmax = hi;
            if sign < 0.0 {
                fmin[a] = lo[a] - t;
                fmax[a] = lo[a];
            } else {
                fmin[a] = hi[a];
                fmax[a] = hi[a] + t;
            }
            for b in 0..a {
                fmin[b] = lo[b] - t;
                fmax[b] = hi[b] + t;
            }
            faces.push(ContainerFace {
                face,
                axis: a,
                sign,
                min: fmin,
                max: fmax,
            });
        }
    }
    faces
}
