//! Validation errors: every constructor that takes user numbers checks them and names the culprit.

/// A rejected contact parameter.
#[derive(Clone, Debug, PartialEq, thiserror::Error)]
pub enum ContactError {
    /// A parameter is NaN or infinite.
    #[error("{parameter} must be finite, got {value}")]
    NonFinite {
        /// Name of the parameter.
        parameter: &'static str,
        /// The rejected value.
        value: f64,
    },
    /// A parameter is finite but outside its physical range.
    #[error("{parameter} = {value} is out of range: expected {expected}")]
    OutOfRange {
        /// Name of the parameter.
        parameter: &'static str,
        /// The rejected value.
        value: f64,
        /// The admissible range, in words.
        expected: &'static str,
    },
    /// The pin is not smaller than the bearing in some direction: the clearance must be positive.
    #[error(
        "clearance must be positive: pin radius {pin_radius} m is not smaller than bearing radius \
         {bearing_radius} m (body-frame angle {angle} rad)"
    )]
    NonPositiveClearance {
        /// Bearing radius in that direction (m).
        bearing_radius: f64,
        /// Pin radius in that direction (m).
        pin_radius: f64,
        /// Body-frame angle at which the check failed (rad).
        angle: f64,
    },
}

/// Rejects NaN and infinities.
pub(crate) fn finite(parameter: &'static str, value: f64) -> Result<f64, ContactError> {
    if value.is_finite() {
        Ok(value)
    } else {
        Err(ContactError::NonFinite { parameter, value })
    }
}

/// Checks a finite value against a predicate, naming the admissible range on failure.
pub(crate) fn in_range(
    parameter: &'static str,
    value: f64,
    admissible: impl FnOnce(f64) -> bool,
    expected: &'static str,
) -> Result<f64, ContactError> {
    finite(parameter, value)?;
    if admissible(value) {
        Ok(value)
    } else {
        Err(ContactError::OutOfRange {
            parameter,
            value,
            expected,
        })
    }
}

/// A finite value `> 0`.
pub(crate) fn positive(parameter: &'static str, value: f64) -> Result<f64, ContactError> {
    in_range(parameter, value, |v| v > 0.0, "> 0")
}

/// A finite value `≥ 0`.
pub(crate) fn non_negative(parameter: &'static str, value: f64) -> Result<f64, ContactError> {
    in_range(parameter, value, |v| v >= 0.0, ">= 0")
}

/// A law as scene files read and write it, through its parameters: `TryFrom` validates them
/// (its `from_params`), `From` gives them back (its `params`).
macro_rules! through_params {
    ($law:ty, $params:ty) => {
        impl TryFrom<$params> for $law {
            type Error = ContactError;
            fn try_from(params: $params) -> Result<Self, ContactError> {
                Self::from_params(params)
            }
        }

        impl From<$law> for $params {
            fn from(law: $law) -> Self {
                law.params()
            }
        }
    };
}
pub(crate) use through_params;
