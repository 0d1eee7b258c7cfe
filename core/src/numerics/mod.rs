//! What every family and interaction shares: vectors and tensors ([`math`]), the
//! Wendland kernel ([`kernel`], seed 000 Eq. 61), the Riemann solver ([`riemann`],
//! Eqs. 17–23), forces and moments ([`load`]), neighbour lists ([`neighbors`],
//! [`cross_lists`]) and the pair executor ([`pairs`]), periodic images ([`periodic`]),
//! reordering ([`permute`]), the stability guard ([`guard`]), stage timers ([`timers`]),
//! and small tools: a seeded generator ([`rng`]), a conjugate-gradient solver
//! ([`sparse_cg`]), a bounded file read ([`capped_read`]), particle packing
//! ([`packing`]) and the index invariants of stored lists ([`index_rows`]). It knows no family, schedule or world.

pub mod capped_read;
pub mod cross_lists;
pub mod guard;
pub mod index_rows;
pub mod kernel;
pub mod load;
pub mod math;
pub mod neighbors;
pub mod packing;
pub mod pairs;
pub mod periodic;
pub mod permute;
pub mod riemann;
pub mod rng;
pub mod sleep;
pub mod sparse_cg;
pub mod timers;
