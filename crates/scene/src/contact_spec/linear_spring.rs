//! The linear-spring test model's scene value: its stiffness.

use serde::{Deserialize, Serialize};

use super::super::error::Validator;
use super::super::{ClearanceJointSpec, RunSettings};
use super::model::ModelSpec;

/// `contact = { model = "linear-spring", stiffness = 1e8 }`: a linear spring on the line of
/// centres, `F = k δ` (`contact::LinearSpring`), the test model of the contact-model
/// interface.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct LinearSpringSpec {
    /// Its stiffness `k`, N/m.
    pub stiffness: f64,
}

impl LinearSpringSpec {
    /// Stiffest spring, N/m: the stiffest solid (diamond, ~1.2e12 Pa) over a contact a metre
    /// wide and deep. Stiffer springs only shorten the integrator's steps, as stiffer layers
    /// do.
    pub const MAX_STIFFNESS: f64 = 1e13;
}

impl ModelSpec for LinearSpringSpec {
    fn build(
        &self,
        _joint: &ClearanceJointSpec,
    ) -> Result<contact::ContactModelKind, contact::ContactError> {
        Ok(contact::LinearSpring::new(self.stiffness)?.into())
    }

    fn describe(&self, _joint: &ClearanceJointSpec) -> String {
        format!(
            "linear-spring contact (k = {} N/m; no damping, no friction: the test model of the \
             contact-model interface)",
            self.stiffness
        )
    }

    fn check(&self, v: &mut Validator, p: &str, joint: &ClearanceJointSpec, _: &RunSettings) {
        let field = format!("{p}.contact.stiffness");
        if v.number(&field, self.stiffness, true) {
            v.at_most(
                &field,
                self.stiffness,
                Self::MAX_STIFFNESS,
                "N/m (stiffer springs only shorten the integrator's steps)",
            );
        }
        if joint.wear.is_some() {
            v.push(
                format!("{p}.wear"),
                "…",
                "the linear-spring test model is exact on round surfaces only: it takes no wear",
            );
        }
    }
}
