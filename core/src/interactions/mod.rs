//! What couples the particle families with each other and with walls, above the
//! families themselves (`fine/` and `coarse/` never import each other):
//! - [`fine_wall`] and [`wall_contact`]: fine grains on walls, seed 000 Eqs. (32)–(35);
//! - [`fine_coarse`]: fine grains on coarse grains, Eqs. (48)–(50), (60) and μ_cf;
//! - [`contact`]: coarse grains on each other and on walls (seeds 001, 004);
//! - [`barrier_load`]: the reactions that add up to barrier loads;
//! - [`momentum_pass`] and [`continuity_pass`]: the fine sweeps' particle passes, which
//!   fuse the fine–fine sums with the interactions above, one formula per module;
//! - [`water_wall`]: water on walls, the fluid form of Eqs. (32)–(35);
//! - [`water_coarse`]: water on coarse grains, the same law on moving particles;
//! - [`water_pass`]: the water sweeps' particle passes;
//! - [`soil_water`]: soil and water, the seepage and pore-pressure forces of seed 001
//!   Eqs. (8)–(10);
//! - [`seepage_implicit`]: the seepage drag closed implicitly on both sides;
//! - [`wall_pressure`]: the pressure the wall particles carry, from the fine grains'
//!   and the water's wall laws, for output.

pub mod barrier_load;
pub mod contact;
pub mod continuity_pass;
pub mod fine_coarse;
pub mod fine_wall;
pub mod gap_water;
pub mod momentum_pass;
pub mod seepage_implicit;
pub mod soil_water;
#[cfg(test)]
mod symmetric_tests;
pub mod wall_contact;
pub mod wall_pressure;
pub mod water_buoyancy;
pub mod water_coarse;
pub mod water_pass;
pub mod water_start;
pub mod water_wall;
