//! The clearance force element lives in the `clearance` crate; re-exported here so that
//! `lgres::clearance::…` paths keep working.

pub use ::clearance::{ClearanceForce, ClearanceProbe, RoundClearanceForce, WornClearanceForce};
