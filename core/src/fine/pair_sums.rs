//! The fine–fine pair sums of one particle, filled by the pair passes of both sweeps
//! and read (and zeroed) by their particle passes.
//!
//! The momentum sweep's pair pass also takes the continuity sweep's terms that need no
//! velocity (the pressure jump of Eq. (19) and the stress diffusion of Eqs. (25)–(26)):
//! positions and σ_n do not change between the two sweeps, and it has each pair's
//! distance and kernel gradient at hand. The continuity sweep's pair pass then adds
//! only the terms in v_{n+1}.

use super::continuity::ContinuitySums;
use super::momentum::MomentumSums;

/// Both sweeps' pair sums of one particle.
#[derive(Clone, Copy, Debug)]
pub struct PairSums<const D: usize> {
    pub momentum: MomentumSums<D>,
    pub continuity: ContinuitySums<D>,
}

impl<const D: usize> PairSums<D> {
    pub fn zero() -> Self {
        PairSums {
            momentum: MomentumSums::zero(),
            continuity: ContinuitySums::zero(),
        }
    }
}
