//! Fine grains: updated-Lagrangian SPH with the Drucker–Prager soil model (seed 000 §2).

pub mod artificial_stress;
pub mod continuity;
pub mod hourglass;
pub mod material;
pub mod momentum;
pub mod pair_sums;
pub mod plasticity;
pub mod pores;
pub mod source;
pub mod state;
