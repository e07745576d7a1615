//! The line-of-centres model's scene value: it takes no field.

use serde::{Deserialize, Serialize};

use super::super::error::Validator;
use super::super::{ClearanceJointSpec, RunSettings};
use super::model::{ModelSpec, law_with_damping};

/// `contact = { model = "line-of-centres" }`: one contact point on the line of centres,
/// Hertz law on the local radii (`contact::LineOfCentres`).
#[derive(Debug, Clone, Copy, Default, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct LineOfCentresSpec {}

impl ModelSpec for LineOfCentresSpec {
    fn build(
        &self,
        _joint: &ClearanceJointSpec,
    ) -> Result<contact::ContactModelKind, contact::ContactError> {
        Ok(contact::LineOfCentres.into())
    }

    fn describe(&self, joint: &ClearanceJointSpec) -> String {
        format!(
            "line-of-centres contact, {}",
            law_with_damping(joint, |floor| format!(
                "damping on the impact's onset velocity (floor {floor} m/s)"
            ))
        )
    }

    fn check(&self, _: &mut Validator, _: &str, _: &ClearanceJointSpec, _: &RunSettings) {}
}
