//! A run: the simulation that builds, steps, lands on sample times and samples
//! ([`simulation`]), its 2D/3D dispatch ([`any`]), what it observes ([`observe`],
//! [`oscillation`], [`pore_field`]) and hands out ([`sample`]), its state saved and
//! restored ([`restore`]), barriers driven by a master ([`cosim`]) and the CLI's run
//! loop ([`runner`]).

pub(crate) mod any;
pub mod cosim;
pub mod observables;
pub mod observe;
pub mod oscillation;
pub mod pore_field;
pub(crate) mod restore;
mod restore_values;
pub mod runner;
pub mod sample;
pub mod simulation;
mod state_mismatch;
