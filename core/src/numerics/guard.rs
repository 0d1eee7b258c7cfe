//! The stability guard: non-finite state or runaway speed stops the run with a
//! diagnostic instead of producing silent NaNs.

use std::fmt;

/// A numerical blow-up detected at the end of a step.
#[derive(Clone, Debug, PartialEq)]
pub struct Blowup {
    pub step: u64,
    pub time: f64,
    /// Stable particle id (fine grains), or the particle index within `body`.
    pub particle: u32,
    /// The coarse grain the particle belongs to, or the wall object that failed.
    pub body: Option<String>,
    /// The particle's family (for a wall, `body` names the wall object and `position`
    /// is its displacement).
    pub family: Family,
    pub position: Vec<f64>,
    /// Quantity that failed, e.g. `velocity`, `stress`, `speed`.
    pub quantity: String,
    pub value: f64,
    /// What the value was compared with (for the speed bound).
    pub limit: Option<f64>,
}

impl Blowup {
    /// The blow-up of particle `particle` of a family (not a body) at `position`, from
    /// its [`Failure`], at step `step` and time `time`.
    pub fn of_particle(
        (step, time): (u64, f64),
        family: Family,
        particle: u32,
        position: Vec<f64>,
        (_, quantity, value, speed): Failure,
        max_speed: f64,
    ) -> Self {
        Blowup {
            step,
            time,
            particle,
            body: None,
            family,
            position,
            quantity: quantity.to_string(),
            value,
            limit: speed.then_some(max_speed),
        }
    }
}

impl fmt::Display for Blowup {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        write!(
            f,
            "numerical blow-up at step {} (t = {:.6e} s): ",
            self.step, self.time
        )?;
        match (&self.body, self.family) {
            (Some(w), Family::Wall) => write!(f, "wall object `{w}`")?,
            (Some(b), _) => write!(f, "particle {} of body `{b}`", self.particle)?,
            (None, _) => write!(f, "{} particle {}", self.family.name(), self.particle)?,
        }
        write!(
            f,
            " at {:?}: {} = {:e}",
            self.position, self.quantity, self.value
        )?;
        if let Some(l) = self.limit {
            write!(f, " exceeds the bound simulation.max_speed = {l} m/s")?;
        } else if self.quantity == DENSITY_CHANGE && self.value.is_finite() {
            write!(
                f,
                " exceeds {DENSITY_CHANGE_LIMIT}: the particles outran the sound speed (a wall \
                 or body driven faster than the material's waves, or a step too long)"
            )?;
        } else if self.value.is_finite() {
            // a finite value only fails the guard for being ≤ 0 (density)
            write!(f, " is not positive")?;
        } else {
            write!(f, " is not finite")?;
        }
        write!(
            f,
            "; reduce simulation.cfl or check material stiffness and initial overlaps"
        )
    }
}

impl std::error::Error for Blowup {}

/// The particle family of a [`Blowup`].
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Family {
    Fine,
    Coarse,
    Water,
    /// A wall or barrier object (its rigid motion).
    Wall,
}

impl Family {
    pub fn name(self) -> &'static str {
        match self {
            Family::Fine => "fine",
            Family::Coarse => "coarse",
            Family::Water => "water",
            Family::Wall => "wall",
        }
    }
}

/// A failing particle: (particle index, quantity, value, is-speed).
pub type Failure = (usize, &'static str, f64, bool);

/// First failure found in a chunk.
pub type ChunkFailure = Option<Failure>;

/// The quantity of a [`Blowup`] whose density changed by more than
/// [`DENSITY_CHANGE_LIMIT`] of itself within one step.
pub const DENSITY_CHANGE: &str = "density change over one step, relative";

/// |dρ/dt| Δt / ρ beyond which a step has outrun the sound speed. A step of Δt =
/// CFL h/(c0 + |v|) changes a density by about CFL |Δv|/c0 (Eqs. 15, 51); 0.5 needs
/// neighbours closing or parting faster than the material's waves (a wall or body
/// driven faster than them, or a Δt too long). It stops such a run where the density
/// floor of the soil (`numerics.density_floor`) would hide the density's fall.
pub const DENSITY_CHANGE_LIMIT: f64 = 0.5;

/// The first problem of particle `i` at the end of a step, in this order: a non-finite
/// velocity (`v2` = |v|²), position or density, a density ≤ 0, a density that changed
/// by more than [`DENSITY_CHANGE_LIMIT`] of itself over the step (`change`,
/// |dρ/dt| Δt/ρ), the family's own check `more` (e.g. a non-finite stress), a speed
/// beyond `max_speed`.
#[inline(always)]
pub fn check<const D: usize>(
    i: usize,
    (v2, x): (f64, &nalgebra::SVector<f64, D>),
    (rho, change): (f64, f64),
    more: impl FnOnce() -> Option<(&'static str, f64)>,
    max_speed: f64,
) -> ChunkFailure {
    if !v2.is_finite() {
        Some((i, "velocity", v2.sqrt(), false))
    } else if !x.iter().all(|q| q.is_finite()) {
        Some((i, "position", x.norm(), false))
    } else if !(rho.is_finite() && rho > 0.0) {
        Some((i, "density", rho, false))
    } else if change.is_nan() || change > DENSITY_CHANGE_LIMIT {
        Some((i, DENSITY_CHANGE, change, false))
    } else if let Some((q, v)) = more() {
        Some((i, q, v, false))
    } else if v2 > max_speed * max_speed {
        Some((i, "speed", v2.sqrt(), true))
    } else {
        None
    }
}

/// The step's largest squared speed and squared displacement over the chunks'
/// (speed², displacement², failure) records, or the first failure in chunk order.
pub fn reduce(chunks: &[(f64, f64, ChunkFailure)]) -> Result<(f64, f64), Failure> {
    let (mut v2, mut d2): (f64, f64) = (0.0, 0.0);
    for (v, d, fail) in chunks {
        if let Some(f) = fail {
            return Err(*f);
        }
        v2 = v2.max(*v);
        d2 = d2.max(*d);
    }
    Ok((v2, d2))
}

#[cfg(test)]
mod tests {
    use super::*;
    use nalgebra::Vector2;

    #[test]
    fn a_density_that_halves_in_one_step_stops_the_run() {
        let x = Vector2::new(0.1, 0.2);
        let ok = check(3, (1.0, &x), (2000.0, 0.49), || None, 100.0);
        assert_eq!(ok, None);
        let f = check(3, (1.0, &x), (2000.0, 0.51), || None, 100.0).unwrap();
        assert_eq!((f.0, f.1, f.3), (3, DENSITY_CHANGE, false));
        // a density that is not positive is named first
        let f = check(3, (1.0, &x), (-1.0, 0.9), || None, 100.0).unwrap();
        assert_eq!(f.1, "density");
        let b = Blowup::of_particle(
            (7, 0.5),
            Family::Fine,
            42,
            vec![0.1, 0.2],
            (3, DENSITY_CHANGE, 0.51, false),
            100.0,
        );
        let text = b.to_string();
        assert!(
            text.contains("exceeds 0.5") && text.contains("sound speed"),
            "{text}"
        );
    }
}
