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
    /// The coarse grain the particle belongs to, if any.
    pub body: Option<String>,
    /// The particle's family.
    pub family: Family,
    pub position: Vec<f64>,
    /// Quantity that failed, e.g. `velocity`, `stress`, `speed`.
    pub quantity: String,
    pub value: f64,
    /// What the value was compared with (for the speed bound).
    pub limit: Option<f64>,
}

impl fmt::Display for Blowup {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        write!(
            f,
            "numerical blow-up at step {} (t = {:.6e} s): ",
            self.step, self.time
        )?;
        match &self.body {
            Some(b) => write!(f, "particle {} of body `{b}`", self.particle)?,
            None => write!(f, "{} particle {}", self.family.name(), self.particle)?,
        }
        write!(
            f,
            " at {:?}: {} = {:e}",
            self.position, self.quantity, self.value
        )?;
        if let Some(l) = self.limit {
            write!(f, " exceeds the bound simulation.max_speed = {l} m/s")?;
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
}

impl Family {
    pub fn name(self) -> &'static str {
        match self {
            Family::Fine => "fine",
            Family::Coarse => "coarse",
            Family::Water => "water",
        }
    }
}

/// First failure found in a chunk: (particle index, quantity, value, is-speed).
pub type ChunkFailure = Option<(usize, &'static str, f64, bool)>;
