//! granmix-core: SPH for binary granular mixtures (seed 000, Zhang et al.).
//!
//! Data flows one way: scene file → [`scene::Scene`] → [`world::World`] →
//! [`stepper::Stepper`] → observations ([`simulation::Sample`], [`simulation::Frame`]).
//! [`AnySimulation`] dispatches on the scene's dimension once, at the top.

pub mod assets;
pub mod budget;
pub mod build_error;
pub mod coarse;
pub mod cosim;
pub mod estimate;
pub mod fine;
pub mod geometry;
pub mod guard;
pub mod heightmap;
pub mod kernel;
pub mod load;
pub mod math;
pub mod mesh;
pub mod neighbors;
pub mod observe;
pub mod panels;
mod restore;
pub mod riemann;
pub mod rng;
pub mod scene;
pub mod simulation;
pub mod slabs;
pub mod stepper;
pub mod timers;
pub mod walls;
pub mod world;

mod any;
pub mod runner;
pub use any::{AnySimulation, SetupError};
