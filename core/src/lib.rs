//! granmix-core: SPH for binary granular mixtures (seed 000, Zhang et al.).
//!
//! Data flows one way: scene file ([`input`]) → [`scene::Scene`] → [`world::World`] →
//! [`step::Stepper`] → observations ([`sample::Sample`], [`sample::Frame`]). The
//! particle families ([`fine`], [`coarse`]) never import each other; what couples them
//! with each other and with walls is [`interactions`]. `docs/architecture.md` draws
//! the layers.
//! [`AnySimulation`] dispatches on the scene's dimension once, at the top.

pub mod assets;
pub mod budget;
pub mod build_error;
pub mod capped_read;
pub mod coarse;
pub mod cosim;
pub mod cross_lists;
pub mod estimate;
pub mod fine;
pub mod flow_speed;
pub mod geometry;
pub mod guard;
pub mod heightmap;
pub mod input;
pub mod interactions;
pub mod kernel;
pub mod load;
pub mod math;
pub mod mesh;
pub mod neighbors;
pub mod observe;
pub mod oscillation;
pub mod packing;
pub mod pairs;
pub mod panels;
pub mod periodic;
pub mod permute;
pub mod pore_field;
pub mod resolution;
mod restore;
pub mod riemann;
pub mod rng;
pub mod sample;
pub mod scene;
pub mod shape_file;
pub mod simulation;
pub mod solids;
pub mod sparse_cg;
pub mod start_solids;
pub mod step;
pub mod tessellate;
pub mod timers;
pub mod walls;
pub mod water;
pub mod world;

mod any;
pub mod runner;
pub use any::{AnySimulation, SetupError};
pub use guard::Blowup;
pub use restore::StateMismatch;
pub use timers::Stage;
