//! Coarse grains (boulders, blocks, rings): total-Lagrangian SPH or rigid bodies
//! (seed 000 §3), their contacts (seeds 001, 004) and the multi-rate sub-steps
//! (Eqs. 51–60).

pub mod body;
pub mod build;
pub mod contact;
pub mod coupling;
pub mod material;
pub mod particles;
pub mod relax;
pub mod rigid;
pub mod stepper;
pub mod tlsph;

pub use body::Body;
pub use material::SolidMaterial;
pub use particles::CoarseParticles;
