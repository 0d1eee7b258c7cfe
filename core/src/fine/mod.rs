//! Fine grains: updated-Lagrangian SPH with the Drucker–Prager soil model (seed 000 §2),
//! its cone fits, friction hardening (seed 004 Eq. 43), μ(I) and the dilatancy of a
//! soil in a fluid.

pub mod artificial_stress;
pub mod continuity;
pub mod dilatancy;
pub mod element;
pub mod hardening;
pub mod hourglass;
pub mod lanes;
pub mod material;
pub mod momentum;
pub mod mu_i;
pub mod pair_sums;
pub mod plasticity;
pub mod pores;
pub mod source;
pub mod state;
pub mod yield_surface;
