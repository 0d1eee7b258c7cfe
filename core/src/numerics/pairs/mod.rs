//! How the same-family pair passes (fine–fine, water–water) are run: which pairs, in
//! what order, on how many lanes. The terms themselves belong to the families
//! ([`fine`](crate::fine), [`water`](crate::water)); this module holds only their
//! schedule and shape, so that every pass takes its sums in an order fixed by the
//! lists, never by the threads or the instruction set.
//!
//! - [`slabs`]: the two-phase schedule over the lists' slabs (each pair once, no locks);
//! - [`clusters`]: clusters of four consecutive particles and their lists;
//! - [`quad`]: four f64 lanes on the instruction set chosen at run time;
//! - [`cluster_pass`]: a cluster's four particles against one neighbour at a time on
//!   those lanes, the skeleton every cluster-pair pass shares.

pub mod cluster_pass;
pub mod clusters;
pub mod quad;
pub mod slabs;
