//! The clearance joint as a [`multibody::ForceElement`]: the `contact` kernel between two
//! bodies, with optional Archard wear accumulation from the `wear` crate.
//!
//! Anyone who builds a mechanism in Rust code uses this crate without scene files, plots or
//! reports (the `lgres` crate adds those). [`ClearanceProbe`] reads an element's contact
//! state and energy books whatever its surfaces.
//!
//! A joint without wear is a [`RoundClearanceForce`] (`CircularProfile` on both sides) with no
//! wear buffer: it allocates no grid and calls no wear code. A worn joint
//! ([`WornClearanceForce`]) samples [`WornProfile`]s that stay frozen for the whole run (a wear
//! stage) and accumulates the stage's depth into a [`StageWear`] on **accepted** steps only, so
//! rejected trial steps never wear the surfaces. No method allocates once the element is built.
//!
//! [`run_wear_stages`] drives the wear stages of any mechanism the caller builds; with
//! [`run_ensemble_stages`] a sub-step's cycles run as an [`Ensemble`] of trajectories on
//! threads, each continuing from where it ended, with results independent of the threads.
//!
//! [`family`] builds a mechanism of any size from these elements (a ladder of four-bar loops
//! with a clearance joint every few joints), for measuring how the cost of a run grows.

#![warn(missing_docs)]

mod builder;
pub mod family;
mod force;
mod stages;

pub use builder::{ClearanceError, ClearanceJointBuilder, JointSide};
pub use force::{
    ClearanceForce, ClearanceProbe, RoundClearanceForce, WornClearanceForce, as_probe,
};
pub use stages::{
    Ensemble, StageHalves, StageRuns, StageSimulation, WearStages, WearStagesError,
    halves_difference, run_ensemble_stages, run_wear_stages,
};

// The crates a clearance joint is made of, and their names a mechanism with worn joints uses
// most, so that depending on this crate alone is enough.
pub use contact::{
    self, Ambrosio, FrictionLawKind, LankaraniNikravesh, Material, NormalLawKind, SlidingVelocity,
};
pub use multibody;
pub use wear::{self, StagePlan, StageWear, WearParams, WornJoint, WornProfile};
