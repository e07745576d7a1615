//! Errors of the wear crate. Each names the offending parameter and its value; numbers given
//! are written with `{:?}`, the shortest form that reads back (`1e300`, not 301 digits), and
//! numbers computed to five significant digits.

/// Invalid wear parameter, grid or wear record.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum WearError {
    /// A scalar parameter outside its allowed range (or not finite).
    #[error("{name} = {value:?} is invalid: must be {requirement}")]
    InvalidParameter {
        /// Parameter name, e.g. `"wear_coefficient"`, `"hinge_width"`, `"amplification"`.
        name: &'static str,
        /// The rejected value.
        value: f64,
        /// What the value must satisfy.
        requirement: &'static str,
    },
    /// A surface grid needs at least one cell.
    #[error("cells = 0 is invalid: a surface grid needs at least one cell")]
    ZeroCells,
    /// The pin does not fit in the bearing.
    #[error("pin radius {pin:?} m must be smaller than bearing radius {bearing:?} m")]
    RadiiInconsistent {
        /// Pin radius (m).
        pin: f64,
        /// Bearing radius (m).
        bearing: f64,
    },
    /// A profile passed as the bearing is a pin profile, or the other way round.
    #[error("the {name} profile is for the other side of the joint")]
    WrongSide {
        /// `"bearing"` or `"pin"`: the role the profile was passed in.
        name: &'static str,
    },
    /// A wear-depth entry is negative or not finite.
    #[error("{name}[{index}] = {value:?} is invalid: wear depth must be finite and >= 0")]
    InvalidDepth {
        /// Which buffer, e.g. `"pin depth"`.
        name: &'static str,
        /// Cell index.
        index: usize,
        /// The rejected value.
        value: f64,
    },
    /// A wear record does not belong to this joint's grids.
    #[error("{name} has {found} cells, the joint's grid has {expected}")]
    GridMismatch {
        /// Which buffer.
        name: &'static str,
        /// Cells of the joint's surface.
        expected: usize,
        /// Cells of the offered buffer.
        found: usize,
    },
    /// Applying the wear would remove the whole pin (its worn radius would reach zero).
    #[error("pin of radius {radius:?} m would be worn through: its depth would reach {depth:?} m")]
    PinWornThrough {
        /// Nominal pin radius (m).
        radius: f64,
        /// Largest pin wear depth `h/2` after the update (m).
        depth: f64,
    },
    /// A bearing worn deeper than its own radius: no longer a joint (e.g. a corrupt wear file).
    #[error(
        "bearing of radius {radius:?} m worn deeper than its own radius: its depth reaches \
         {depth:?} m"
    )]
    BearingTooDeep {
        /// Nominal bearing radius (m).
        radius: f64,
        /// Largest bearing wear depth `h/2` (m).
        depth: f64,
    },
    /// The stage runner returned a different number of wear records than there are joints.
    #[error("stage runner returned {found} wear records for {expected} joints")]
    JointCount {
        /// Number of joints being staged.
        expected: usize,
        /// Number of records returned.
        found: usize,
    },
    /// Adaptive extrapolation hit its sub-step limit before spending the stage's amplification.
    #[error(
        "stage {}: adaptive extrapolation used max_substeps = {limit} sub-steps and still has \
         amplification {remaining:.4e} left (run.max_substeps)",
        stage + 1
    )]
    SubstepLimit {
        /// Stage index (0-based).
        stage: usize,
        /// The configured limit.
        limit: usize,
        /// Amplification not yet applied.
        remaining: f64,
    },
}

/// Returns `value` if `ok`, else the named [`WearError::InvalidParameter`].
pub(crate) fn require(
    name: &'static str,
    value: f64,
    ok: bool,
    requirement: &'static str,
) -> Result<f64, WearError> {
    if ok {
        Ok(value)
    } else {
        Err(WearError::InvalidParameter {
            name,
            value,
            requirement,
        })
    }
}

/// `value` must be finite and > 0.
pub(crate) fn positive(name: &'static str, value: f64) -> Result<f64, WearError> {
    require(
        name,
        value,
        value.is_finite() && value > 0.0,
        "finite and > 0",
    )
}

/// `value` must be finite and >= 0.
pub(crate) fn non_negative(name: &'static str, value: f64) -> Result<f64, WearError> {
    require(
        name,
        value,
        value.is_finite() && value >= 0.0,
        "finite and >= 0",
    )
}

/// `value` must be finite.
pub(crate) fn finite(name: &'static str, value: f64) -> Result<f64, WearError> {
    require(name, value, value.is_finite(), "finite")
}

/// Every entry of `depths` must be finite and >= 0.
pub(crate) fn check_depths(name: &'static str, depths: &[f64]) -> Result<(), WearError> {
    match depths.iter().position(|h| !(h.is_finite() && *h >= 0.0)) {
        None => Ok(()),
        Some(index) => Err(WearError::InvalidDepth {
            name,
            index,
            value: depths[index],
        }),
    }
}
