//! Coarse grains (boulders, blocks, rings): total-Lagrangian SPH or rigid bodies
//! (seed 000 §3), their building and
//! relaxation. Their contacts are [`interactions`](crate::interactions), their
//! multi-rate sub-steps (Eqs. 51–60) [`step`](crate::step).

pub mod body;
pub mod build;
pub mod material;
pub mod particles;
pub mod relax;
pub mod rigid;
pub mod tlsph;

pub use body::Body;
pub use material::SolidMaterial;
pub use particles::CoarseParticles;
