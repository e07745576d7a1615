//! A trend the paper states, as data: which two cases it compares, the quantities it is about
//! and which way they go. The study judge (crate `analysis`) measures those quantities in our
//! runs and says whether the trend holds; nothing there knows a study by its name.

/// One trend the paper claims: from its first case to its second, the quantities move in
/// `direction`.
#[derive(Debug, Clone, Copy)]
pub struct Claim {
    /// The trend in words, as the report states it.
    pub trend: &'static str,
    /// The two cases, in the paper's order, and what of their responses is compared.
    pub cases: Cases,
    /// Wear quantities compared joint by joint (after the cases' stages).
    pub wear: &'static [WearMeasure],
    /// Which way the quantities go from the first case to the second.
    pub direction: Direction,
}

/// The two cases a claim compares.
#[derive(Debug, Clone, Copy)]
pub enum Cases {
    /// Two scenes (built-in names): their responses on unworn and on worn surfaces, and their
    /// wear after the last stage.
    Scenes {
        /// The paper's first case.
        first: &'static str,
        /// The paper's second case.
        second: &'static str,
        /// Response quantities compared, on unworn and then on worn surfaces.
        response: &'static [ResponseMeasure],
    },
    /// Two wear stages of one scene: the wear after each (a run has no response per stage).
    Stages {
        /// The scene (built-in name), run with at least `second` stages.
        scene: &'static str,
        /// The paper's first case, a 1-based stage number.
        first: usize,
        /// The paper's second case, a 1-based stage number.
        second: usize,
    },
}

impl Cases {
    /// The scenes these cases run.
    pub fn scenes(&self) -> Vec<&'static str> {
        match *self {
            Cases::Scenes { first, second, .. } => vec![first, second],
            Cases::Stages { scene, .. } => vec![scene],
        }
    }
}

/// Which way a claim's quantities go from its first case to its second.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Direction {
    /// They grow.
    Grows,
    /// They shrink.
    Shrinks,
}

/// A response quantity a claim compares between two scenes.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum ResponseMeasure {
    /// Median over cycles of the peak normal force, at every clearance joint (after the
    /// start-up window; its interquartile range is the noise).
    PeakForce,
    /// Largest deviation of the tracked point from the ideal mechanism, in x and in y.
    Deviation,
    /// Energy dissipated per drive cycle.
    Dissipation,
}

/// A wear quantity a claim compares, at every clearance joint.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum WearMeasure {
    /// Volume removed from both surfaces.
    Volume,
    /// Angular width of the worn arc (depth above a fraction of the peak).
    Arc,
    /// Deeper of the two surfaces' peak depths.
    PeakDepth,
    /// Irregularity: coefficient of variation of the depth over the worn arc.
    DepthVariation,
    /// Irregularity: number of separate concentrated ranges.
    ConcentratedRanges,
}
