//! The checks of a restored state's world ([`crate::run::restore`]): what the scene
//! fixes against the template built from it ([`scene_constants`]), and every value
//! finite and in its range ([`finite_in_range`]), each refusal naming the particle,
//! body or wall and the value.

use crate::numerics::math::{Real, Vect};
use crate::run::state_mismatch::StateMismatch;
use crate::world::World;

/// What the scene fixes, against `template`, the world the scene builds with the
/// state's parameters: materials, resolution, domain, gravity, periodic axis, probes and
/// gauges, wall objects and barriers (all but their motion), bodies' constants, solids,
/// water material, inflows (all but their fill) and outflows.
pub(super) fn scene_constants<const D: usize>(
    w: &World<D>,
    t: &World<D>,
) -> Result<(), StateMismatch> {
    let differs = |what: &'static str| Err(StateMismatch::Scene(what));
    if w.materials != t.materials || w.coarse.solids != t.coarse.solids {
        return differs("materials");
    }
    if w.resolution != t.resolution || w.domain != t.domain || w.periodic != t.periodic {
        return differs("resolution or domain");
    }
    if w.gravity != t.gravity {
        return differs("gravity");
    }
    if w.probes != t.probes || w.gauges != t.gauges {
        return differs("probes or gauges");
    }
    let same_object = |(a, b): (
        &crate::geometry::walls::WallObject<D>,
        &crate::geometry::walls::WallObject<D>,
    )| {
        a.name == b.name
            && a.kind == b.kind
            && a.prescribed == b.prescribed
            && a.window == b.window
            && a.barrier == b.barrier
            && a.driven == b.driven
            && a.permeable == b.permeable
    };
    // a barrier's moment point moves with it
    let same_barrier = |(a, b): (
        &crate::geometry::walls::Barrier<D>,
        &crate::geometry::walls::Barrier<D>,
    )| {
        (a.name == b.name && a.object == b.object && a.slot0 == b.slot0)
            && (a.panels == b.panels && a.panel_axes == b.panel_axes)
            && (a.panel_lo == b.panel_lo && a.panel_hi == b.panel_hi)
    };
    let (wo, to) = (&w.walls.objects, &t.walls.objects);
    let (wb, tb) = (&w.walls.barriers, &t.walls.barriers);
    if wo.len() != to.len()
        || !wo.iter().zip(to).all(same_object)
        || wb.len() != tb.len()
        || !wb.iter().zip(tb).all(same_barrier)
        || w.walls.volume.to_bits() != t.walls.volume.to_bits()
    {
        return differs("walls or barriers");
    }
    let same_body = |(a, b): (&crate::coarse::Body<D>, &crate::coarse::Body<D>)| {
        a.name == b.name
            && a.model == b.model
            && a.material == b.material
            && (a.start, a.end) == (b.start, b.end)
            && a.fixed == b.fixed
            && a.mass.to_bits() == b.mass.to_bits()
            && a.inertia == b.inertia
            && a.inv_inertia == b.inv_inertia
    };
    let (wb, tb) = (&w.coarse.bodies, &t.coarse.bodies);
    if wb.len() != tb.len() || !wb.iter().zip(tb).all(same_body) {
        return differs("bodies");
    }
    let (ww, tw) = (&w.water, &t.water);
    let same_inflow = |(a, b): (
        &crate::water::boundary::Inflow<D>,
        &crate::water::boundary::Inflow<D>,
    )| {
        a.name == b.name
            && (a.lo, a.hi, a.axis) == (b.lo, b.hi, b.axis)
            && a.sign.to_bits() == b.sign.to_bits()
            && a.speed == b.speed
            && a.stop.to_bits() == b.stop.to_bits()
    };
    if ww.material != tw.material
        || ww.outflows != tw.outflows
        || ww.inflows.len() != tw.inflows.len()
        || !ww.inflows.iter().zip(&tw.inflows).all(same_inflow)
    {
        return differs("water, inflows or outflows");
    }
    Ok(())
}

/// `what` holds `value`, outside its range `range` (a description of it).
fn refuse(what: String, value: impl std::fmt::Debug, range: &str) -> StateMismatch {
    StateMismatch::Value(format!("{what} = {value:?} (must be {range})"))
}

fn positive(x: Real) -> bool {
    x.is_finite() && x > 0.0
}

fn finite<const N: usize>(v: &Vect<N>) -> bool {
    v.iter().all(|x| x.is_finite())
}

/// Every value of the world finite and in its range: time; positions, velocities (at
/// most `max_speed`, the stability guard's bound, which every completed step keeps),
/// densities and masses (positive) and stresses of the fine and water particles; the
/// coarse particles' positions, velocities, masses and bodies (each within its body's
/// range); the bodies' motion; the wall particles and the wall objects' motion; an
/// inflow's fill. The first value out of range is named.
pub(super) fn finite_in_range<const D: usize>(
    w: &World<D>,
    max_speed: Real,
) -> Result<(), StateMismatch> {
    if !(w.time.is_finite() && w.time >= 0.0) {
        return Err(refuse("the time".into(), w.time, "finite and not negative"));
    }
    // a speed the guard let through, with the rounding of its check
    let fast = |v: &Vect<D>| !finite(v) || v.norm() > max_speed * (1.0 + 1e-12);
    let speed_range = format!("finite, at most simulation.max_speed = {max_speed:?} m/s");
    let f = &w.fine;
    for i in 0..f.len() {
        let at = |q: &str| format!("fine particle {i}: {q}");
        let kinematics = (&f.pos[i], &f.vel[i], f.rho[i], f.drho[i], f.mass[i]);
        sph_particle(&at, kinematics, &fast, &speed_range)?;
        if !f.stress[i].0.iter().all(|s| s.is_finite()) || !f.plastic_strain[i].is_finite() {
            return Err(refuse(at("stress"), f.stress[i].0, "finite"));
        }
        let gradients = f.vel_grad[i].iter().chain(f.hourglass[i].iter());
        if !gradients
            .chain([&f.hourglass_kept[i]])
            .all(|x| x.is_finite())
        {
            return Err(refuse(
                at("velocity gradient"),
                f.vel_grad[i].as_slice(),
                "finite",
            ));
        }
    }
    let wa = &w.water.particles;
    for i in 0..wa.len() {
        let at = |q: &str| format!("water particle {i}: {q}");
        let kinematics = (&wa.pos[i], &wa.vel[i], wa.rho[i], wa.drho[i], wa.mass[i]);
        sph_particle(&at, kinematics, &fast, &speed_range)?;
    }
    coarse_in_range(w, &speed_range, fast)?;
    let walls = &w.walls;
    if let Some(i) = walls.pos.iter().position(|x| !finite(x)) {
        let what = format!("wall particle {i}: position");
        return Err(refuse(what, walls.pos[i].as_slice(), "finite"));
    }
    if let Some(b) = walls.barriers.iter().find(|b| !finite(&b.reference)) {
        let what = format!("barrier `{}`: moment point", b.name);
        return Err(refuse(what, b.reference.as_slice(), "finite"));
    }
    for o in &walls.objects {
        if !finite(&o.displacement) || !finite(&o.velocity) {
            let what = format!("wall `{}`: displacement and velocity", o.name);
            let value = (o.displacement.as_slice(), o.velocity.as_slice());
            return Err(refuse(what, value, "finite"));
        }
    }
    for inflow in &w.water.inflows {
        if !(inflow.fill.is_finite() && inflow.fill >= 0.0) {
            let what = format!("inflow `{}`: length let in", inflow.name);
            return Err(refuse(what, inflow.fill, "finite and not negative"));
        }
    }
    Ok(())
}

/// What a fine and a water particle share in [`finite_in_range`]: its position
/// finite, its speed in range, its density positive (and its rate finite), its mass
/// positive; `at` names the particle and the quantity.
fn sph_particle<const D: usize>(
    at: &dyn Fn(&str) -> String,
    (pos, vel, rho, drho, mass): (&Vect<D>, &Vect<D>, Real, Real, Real),
    fast: &dyn Fn(&Vect<D>) -> bool,
    speed_range: &str,
) -> Result<(), StateMismatch> {
    if !finite(pos) {
        return Err(refuse(at("position"), pos.as_slice(), "finite"));
    }
    if fast(vel) {
        return Err(refuse(at("velocity"), vel.as_slice(), speed_range));
    }
    if !(positive(rho) && drho.is_finite()) {
        return Err(refuse(at("density"), rho, "positive and finite"));
    }
    if !positive(mass) {
        return Err(refuse(at("mass"), mass, "positive and finite"));
    }
    Ok(())
}

/// The coarse particles and bodies of [`finite_in_range`].
fn coarse_in_range<const D: usize>(
    w: &World<D>,
    speed_range: &str,
    fast: impl Fn(&Vect<D>) -> bool,
) -> Result<(), StateMismatch> {
    let (c, bodies) = (&w.coarse.particles, &w.coarse.bodies);
    for i in 0..c.pos.len() {
        let at = |q: &str| format!("coarse particle {i}: {q}");
        if !finite(&c.pos[i]) || !finite(&c.pos_start[i]) {
            return Err(refuse(at("position"), c.pos[i].as_slice(), "finite"));
        }
        if fast(&c.vel[i]) || !finite(&c.vbar[i]) {
            return Err(refuse(at("velocity"), c.vel[i].as_slice(), speed_range));
        }
        if !positive(c.mass[i]) {
            return Err(refuse(at("mass"), c.mass[i], "positive and finite"));
        }
        let b = &bodies[c.body[i] as usize];
        if !(b.start..b.end).contains(&i) {
            let range = format!("the body whose particles {}..{} hold it", b.start, b.end);
            return Err(refuse(at("body"), &b.name, &range));
        }
    }
    for b in bodies {
        let at = |q: &str| format!("body `{}`: {q}", b.name);
        let motion = [b.com, b.vel, b.ang_mom, b.omega, b.force, b.torque];
        if !motion.iter().all(|v| v.iter().all(|x| x.is_finite()))
            || !b.orientation.coords.iter().all(|x| x.is_finite())
        {
            return Err(refuse(at("motion"), (b.com, b.vel, b.omega), "finite"));
        }
        let mut v = Vect::<D>::zeros();
        for k in 0..D {
            v[k] = b.vel[k];
        }
        if fast(&v) {
            return Err(refuse(at("velocity"), b.vel.as_slice(), speed_range));
        }
    }
    Ok(())
}
