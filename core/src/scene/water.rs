//! The `[water]` table of the scene schema: the water family's fluid and its regions
//! (seed 001 §1.2; the Riemann-solver WCSPH of Zhang, Hu & Adams 2017). Documented for
//! users in `docs/scenes.md`.

use super::ShapeSpec;
use serde::Deserialize;

/// `[water]`: one Newtonian fluid, weakly compressible, and where it starts.
#[derive(Debug, Clone, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct WaterSpec {
    /// Reference density ρ_w (kg/m³). Default 1000.
    #[serde(default = "default_density")]
    pub density: f64,
    /// Dynamic viscosity μ (Pa·s), Morris et al. (1997) laminar form. Default 1e-3.
    #[serde(default = "default_viscosity")]
    pub viscosity: f64,
    /// Artificial sound speed c0 (m/s). Default 10 × `speed_scale`, which keeps the
    /// density within about 1 % of ρ_w.
    #[serde(default)]
    pub sound_speed: Option<f64>,
    /// The largest flow speed expected (m/s). Default: √(2 |g| H) over the tallest
    /// water region's height H, or the largest initial speed if that is higher.
    #[serde(default)]
    pub speed_scale: Option<f64>,
    /// `"linear"`, p = c0² (ρ − ρ_w) (seed 001 Eq. 3), or `"tait"`,
    /// p = ρ_w c0²/7 ((ρ/ρ_w)⁷ − 1). Default linear.
    #[serde(default)]
    pub equation_of_state: EquationOfState,
    /// Water on walls and barriers: `"no-slip"` (default) or `"free-slip"`.
    #[serde(default)]
    pub wall: WallSlip,
    /// Coefficient η of a limiter on the Riemann solver's dissipation,
    /// β = min(η max(U_L − U_R, 0)/c0, 1) (Zhang et al. 2017 use η = 3). Default: no
    /// limiter, β = 1 under compression (docs/method.md §Water has the measurements).
    #[serde(default)]
    pub limiter: Option<f64>,
    /// Kernel gradient correction of the pressure force (`water::correction`): exact
    /// for linear pressure fields, which a resting tank needs. Default true.
    #[serde(default = "yes")]
    pub gradient_correction: bool,
    /// MUSCL reconstruction of the Riemann dissipation: each pair's velocities taken to
    /// its midpoint with the corrected velocity gradient, minmod-limited. Default false.
    #[serde(default)]
    pub muscl: bool,
    /// A settling phase (s): over [0, settle_time) the water's velocities are damped
    /// at the rate 10/settle_time, so that a state built at rest comes to rest in
    /// its own discrete equilibrium. Default 0 (off).
    #[serde(default)]
    pub settle_time: f64,
    /// Start from the hydrostatic pressure of each region (density from the equation
    /// of state). Default true; false starts at ρ_w everywhere.
    #[serde(default = "yes")]
    pub hydrostatic_start: bool,
    /// Start from the pressure of an incompressible fluid released at rest (the
    /// Laplace problem of `interactions::water_start`), which a dam break's column
    /// takes the instant its gate vanishes. Default true, except with a saturated
    /// soil, whose pore water starts hydrostatic; needs `hydrostatic_start`.
    #[serde(default)]
    pub incompressible_start: Option<bool>,
    /// Where the water starts.
    #[serde(default)]
    pub regions: Vec<WaterRegionSpec>,
    /// Where water enters during the run.
    #[serde(default)]
    pub inflows: Vec<InflowSpec>,
    /// Where water leaves.
    #[serde(default)]
    pub outflows: Vec<OutflowSpec>,
}

/// `[[water.regions]]`: a block of water particles.
#[derive(Debug, Clone, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct WaterRegionSpec {
    pub name: String,
    pub shape: ShapeSpec,
    /// Initial velocity (m/s). Default at rest.
    #[serde(default)]
    pub velocity: Option<Vec<f64>>,
    /// How the shape is filled: on the lattice (the default) or column by column up to
    /// its surface.
    #[serde(default)]
    pub fill: WaterFill,
}

/// How a water region's shape is filled with particles.
#[derive(Debug, Clone, Copy, serde::Deserialize, PartialEq, Eq, Default)]
#[serde(rename_all = "kebab-case")]
pub enum WaterFill {
    /// The lattice of spacing dp, every particle of volume dp^d; the surface is
    /// followed to within a spacing.
    #[default]
    Lattice,
    /// Each vertical column of width dp filled evenly from the shape's bottom to its
    /// top with round(depth/dp) particles, so that a sloping or wavy surface is
    /// followed exactly (a standing wave's initial elevation).
    Columns,
}

/// Equation of state of the water.
#[derive(Debug, Clone, Copy, serde::Serialize, serde::Deserialize, PartialEq, Eq, Default)]
#[serde(rename_all = "kebab-case")]
pub enum EquationOfState {
    #[default]
    Linear,
    Tait,
}

/// Tangential condition of water on walls and barriers.
#[derive(Debug, Clone, Copy, serde::Serialize, serde::Deserialize, PartialEq, Eq, Default)]
#[serde(rename_all = "kebab-case")]
pub enum WallSlip {
    #[default]
    NoSlip,
    FreeSlip,
}

fn default_density() -> f64 {
    1000.0
}
fn default_viscosity() -> f64 {
    1.0e-3
}
fn yes() -> bool {
    true
}

/// `[[water.inflows]]`: water entering through a box, from its face against
/// `direction`, at a prescribed speed (seed 001 §6).
#[derive(Debug, Clone, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct InflowSpec {
    pub name: String,
    /// The inlet: an axis-aligned box at least three particle spacings long along
    /// `direction`. Particles inside it move at the inflow speed; new layers enter at its
    /// upstream face, and particles leave it downstream as free water.
    pub shape: ShapeSpec,
    /// Flow direction: `"+x"`, `"-x"`, `"+y"`, `"-y"`, `"+z"` or `"-z"`.
    pub direction: String,
    /// Constant inflow speed (m/s); give this or `hydrograph`.
    #[serde(default)]
    pub speed: Option<f64>,
    /// Inflow speed against time.
    #[serde(default)]
    pub hydrograph: Option<Hydrograph>,
    /// The inflow stops at this time (s). Default: never.
    #[serde(default)]
    pub stop: Option<f64>,
}

/// An inflow speed against time.
#[derive(Debug, Clone, Copy, Deserialize, serde::Serialize, PartialEq)]
#[serde(tag = "type", rename_all = "lowercase", deny_unknown_fields)]
pub enum Hydrograph {
    /// Seed 001 Eq. (36): u(t) = (a/β) exp(−(t − μ)/β) exp(−exp(−(t − μ)/β)).
    Gumbel { a: f64, beta: f64, mu: f64 },
}

impl Hydrograph {
    /// u(t) (m/s).
    pub fn speed(&self, t: f64) -> f64 {
        match *self {
            Hydrograph::Gumbel { a, beta, mu } => {
                let z = (t - mu) / beta;
                a / beta * (-z).exp() * (-(-z).exp()).exp()
            }
        }
    }

    /// The length of water let in from t = 0 to `t` (m), ∫₀ᵗ u dt: a (F(t) − F(0))
    /// with the Gumbel distribution F(t) = exp(−exp(−(t − μ)/β)).
    pub fn length(&self, t: f64) -> f64 {
        match *self {
            Hydrograph::Gumbel { a, beta, mu } => {
                let f = |t: f64| (-(-(t - mu) / beta).exp()).exp();
                a * (f(t) - f(0.0))
            }
        }
    }

    /// The largest speed (m/s): the Gumbel peak, a/(β e) at t = μ.
    pub fn peak(&self) -> f64 {
        match *self {
            Hydrograph::Gumbel { a, beta, .. } => a / (beta * std::f64::consts::E),
        }
    }
}

/// `[[water.outflows]]`: water particles past a plane are removed.
#[derive(Debug, Clone, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct OutflowSpec {
    pub name: String,
    /// A point of the plane.
    pub point: Vec<f64>,
    /// The plane's normal, pointing out of the domain: particles on its side leave.
    pub normal: Vec<f64>,
}

#[cfg(test)]
mod tests {
    use super::Hydrograph;

    /// Seed 001 Eq. (36) with a = 35, β = 2, μ = 3: the peak u(3) = 6.4379 m/s and the
    /// values the extract derives.
    #[test]
    fn gumbel_hydrograph_of_seed_001() {
        let h = Hydrograph::Gumbel {
            a: 35.0,
            beta: 2.0,
            mu: 3.0,
        };
        for (t, u) in [
            (3.0, 6.4379),
            (0.0, 0.887),
            (1.0, 3.139),
            (5.0, 4.456),
            (10.0, 0.513),
        ] {
            assert!((h.speed(t) - u).abs() < 5e-3 * u, "u({t}) = {}", h.speed(t));
        }
        // the length let in is the speed's integral (trapezoids of 1 ms)
        let n = 10_000;
        let trapezoids: f64 = (0..n)
            .map(|k| 0.5e-3 * (h.speed(k as f64 * 1e-3) + h.speed((k + 1) as f64 * 1e-3)))
            .sum();
        assert!((h.length(10.0) - trapezoids).abs() < 1e-6 * trapezoids);
        // all of it: a (1 − F(0)), F(0) = exp(−e^{1.5})
        let all = 35.0 * (1.0 - (-(1.5f64).exp()).exp());
        assert!((h.length(1e3) - all).abs() < 1e-9 * all);
    }
}
