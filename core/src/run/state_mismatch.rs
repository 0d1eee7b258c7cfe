//! Why a saved state is refused ([`crate::run::restore`], [`crate::run::restore_values`]).

/// A saved state that does not fit the scene it is restored into.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum StateMismatch {
    #[error("the saved state's walls differ from the scene's")]
    Walls,
    #[error("the saved state's barriers or bodies differ from the scene's")]
    BarriersOrBodies,
    #[error(
        "the saved state's {0} fine particles have arrays of other lengths or unknown materials"
    )]
    FineArrays(usize),
    #[error("the saved state's {0} coarse particles have arrays of other lengths")]
    CoarseArrays(usize),
    #[error("the saved state's wall particles are inconsistent")]
    WallParticles,
    #[error(
        "the saved state's {0} water particles have arrays of other lengths, or its water \
         differs from the scene's (water, inflows, outflows)"
    )]
    WaterArrays(usize),
    #[error("the saved state is {state}D, the scene {scene}D")]
    Dimension { state: usize, scene: usize },
    /// What the scene fixes differs from the scene as built with the state's parameters.
    #[error("the saved state's {0} differ from the scene's")]
    Scene(&'static str),
    /// Stored lists or indices that do not fit the particles they index.
    #[error("the saved state's {0} do not fit its particles (an index out of range)")]
    Lists(&'static str),
    /// A value that is not finite or outside its range: which one, and what it is.
    #[error("the saved state holds {0}")]
    Value(String),
}
