//! The thin-gap model's scene value: the foundation's layer fields, the same defaults.

use serde::{Deserialize, Serialize};

use super::super::error::Validator;
use super::super::{ClearanceJointSpec, RunSettings};
use super::foundation::FoundationSpec;
use super::model::ModelSpec;

/// `contact = { model = "thin-gap", … }`: the foundation's layer with the thin-gap overlap on
/// nodes fixed in the bearing's frame (`contact::ThinGap`). Its fields are the foundation's
/// (`layer_modulus`, `layer`, `width`, `cells`, `quadrature`, `reference_speed`), with their
/// defaults and checks.
#[derive(Debug, Clone, Copy, Default, PartialEq, Serialize, Deserialize)]
#[serde(transparent)]
pub struct ThinGapSpec(pub FoundationSpec);

impl ModelSpec for ThinGapSpec {
    fn build(
        &self,
        joint: &ClearanceJointSpec,
    ) -> Result<contact::ContactModelKind, contact::ContactError> {
        Ok(contact::ThinGap::new(self.0.foundation(joint)?).into())
    }

    fn describe(&self, joint: &ClearanceJointSpec) -> String {
        let (layer, law) = self.0.describe_layer(joint);
        format!("thin-gap contact ({layer}, nodes in the bearing's frame), {law}")
    }

    fn check(&self, v: &mut Validator, p: &str, joint: &ClearanceJointSpec, run: &RunSettings) {
        self.0.check(v, p, joint, run);
    }
}
