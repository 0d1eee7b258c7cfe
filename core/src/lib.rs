//! granmix-core: SPH for binary granular mixtures (seed 000, Zhang et al.).
//!
//! Data flows one way: scene file ([`input`]) → [`scene::Scene`] → [`world::World`] →
//! [`step::Stepper`] → observations ([`run::sample::Sample`], [`run::sample::Frame`]).
//! The particle families ([`fine`], [`coarse`], [`water`]) never import each other;
//! what couples them with each other and with walls is [`interactions`].
//! `docs/architecture.md` draws the layers, each a folder:
//!
//! - [`numerics`]: kernel, Riemann solver, vectors, lists and the pair executor;
//! - [`scene`] and [`shapes`]: the scene as data and the shape files it names;
//! - [`geometry`]: shapes, walls, barriers and panels;
//! - [`estimate`]: what a scene costs and needs before anything is built;
//! - [`input`]: reading a scene file;
//! - the families, [`interactions`], [`world`] and [`step`];
//! - [`run`]: simulation, sampling, restore and co-simulation.
//!
//! [`AnySimulation`] dispatches on the scene's dimension once, at the top.

pub mod coarse;
pub mod estimate;
pub mod fine;
pub mod geometry;
pub mod input;
pub mod interactions;
pub mod numerics;
pub mod run;
pub mod scene;
pub mod shapes;
pub mod step;
pub mod water;
pub mod world;

pub use numerics::guard::Blowup;
pub use numerics::timers::Stage;
pub use run::any::{AnySimulation, SetupError};
pub use run::restore::StateMismatch;
