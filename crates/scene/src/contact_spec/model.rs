//! What the scene asks of a contact model's scene value: its build, its words, its checks.

use super::super::error::Validator;
use super::super::{ClearanceJointSpec, RunSettings};

/// A contact model's fields as a scene holds them (one variant of [`super::ContactSpec`]).
pub(super) trait ModelSpec {
    /// The model, its defaults filled in from `joint` (the joint whose `contact` this is).
    fn build(
        &self,
        joint: &ClearanceJointSpec,
    ) -> Result<contact::ContactModelKind, contact::ContactError>;

    /// The model and the normal law as it applies it, in words (friction is added by the
    /// caller), e.g. `line-of-centres contact, Hertz (undamped), no damping`.
    fn describe(&self, joint: &ClearanceJointSpec) -> String;

    /// Adds to `v` the problems of its fields (under `{p}.contact`) against `joint` and the
    /// run's settings `run`: values out of range, values the joint or the run cannot take,
    /// and the numeric limits of [`crate::limits`]'s kind.
    fn check(&self, v: &mut Validator, p: &str, joint: &ClearanceJointSpec, run: &RunSettings);
}

/// The normal law of `joint` in words with how it damps: `damping`'s words (given the law's
/// onset-velocity floor) where the law dissipates, `no damping` where it is elastic.
pub(super) fn law_with_damping(
    joint: &ClearanceJointSpec,
    damping: impl FnOnce(f64) -> String,
) -> String {
    let law = joint.normal_law.description();
    match joint.normal_law.damping_onset_floor() {
        Some(floor) => format!("{law}, {}", damping(floor)),
        None => format!("{law}, no damping"),
    }
}
