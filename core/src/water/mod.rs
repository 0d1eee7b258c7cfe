//! Water: weakly compressible SPH with the low-dissipation Riemann solver of Zhang,
//! Hu & Adams (2017), the fluid of seed 001 §1.2 (its Eqs. 1–3), and Morris et al.
//! (1997) laminar viscosity.
//!
//! The family holds the water–water terms only. Walls, barriers and (later) coarse and
//! fine grains act on water through [`interactions`](crate::interactions); the stage
//! that steps it is [`step`](crate::step). `docs/method.md` §Water gives the equations
//! and where granmix departs from its sources.

pub mod boundary;
pub mod continuity;
pub mod correction;
pub mod gradient;
pub mod lanes;
pub mod material;
pub mod momentum;
#[cfg(test)]
mod pair_tests;
pub mod source;
pub mod state;
