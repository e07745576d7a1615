//! Is the worn geometry still inside what the contact model describes? Measured at the
//! contacts of every response run, per joint.
//!
//! **Elastic foundation** (the default model): it resolves any outline, so what limits it is
//! the thin layer and the grid:
//! - **overlap** `max d / c0`: the deepest overlap of the outlines against the nominal
//!   clearance. The layer is calibrated on round surfaces, where its force stays within 4 % of
//!   Hertz up to `d = 0.06 c0` and within 11 % at `0.2 c0` (docs/model.md §10); beyond that a
//!   thin linear layer no longer stands for the bodies' elasticity. Limit 0.2.
//! - **zone resolution**: the error of the normal load that the grid's resolution of the
//!   contact zones implies, `Σ share · 0.96/n²` over zones of `n` nodes (the linear
//!   interpolation between nodes misses `0.96/n²` of a smooth cap's load: measured on round
//!   surfaces, docs/model.md §10.2), over frames whose overlap exceeds 1 % of the clearance (a
//!   light touch always begins with one node). Limit 2 %; the narrowest zone carrying a tenth
//!   of the load is reported beside it.
//! - **unloaded penetration** is counted as below but has no limit here: on the foundation it
//!   only shows the damped law's own clamp (the pin leaving faster than `δ̇⁻/χ`), which the
//!   line-of-centres model shares on round surfaces, not a shape the model misreads.
//!
//! **Line of centres**: the penetration is measured along the line
//! through the two centres, and the pin is assumed to reach the bottom of whatever the bearing
//! offers there. A worn profile breaks that when it is steep or rough against the clearance.
//! Four measures, each with a limit ([`ValidityLimits`]):
//! - **slope** `|R_i' − R_j'|/|e|` at loaded frames: the tilt of the contact normal from the
//!   line of centres (the tangential part of the force direction `m`). Above 0.3 the contact
//!   normal is more than 17° off and `δ` overstates the normal gap by more than 4 %.
//! - **conformity** `(R_j'' − R_i'')/c` at loaded frames (small-slope form of "the pin's
//!   curvature exceeds the bearing's"): at 1 the worn dent is as curved as the pin, beyond it
//!   the pin touches the dent's flanks instead of its bottom.
//! - **unloaded penetration**: frames whose penetration exceeds 1 % of the clearance but carry no
//!   force (the damped law clamped), as a fraction of the frames with that penetration.
//! - **outline overlap**: the true overlap of the worn outlines
//!   ([`contact::ClearanceJoint::outline_overlap`]) against the line-of-centres `δ`, at a subset
//!   of frames: the largest difference, relative to the clearance, and the frames where the
//!   outlines overlap while `δ < 0` (contacts the model misses).
//!
//! The checks of a run's results live here too: the response run's peak penetration
//! ([`check_penetration`], against [`MAX_PENETRATION_FRACTION`]) and a pin that starts outside
//! its bearing ([`check_initial_penetration`]).

mod measures;

pub use measures::{MIN_ELASTIC_SHARE, Validity, ValidityLimits, ValidityTally};

use super::{ContactSeries, RunError};
use crate::build::BuiltScene;
use scene::ClearanceJointSpec;
use scene::Scene;
use scene::limits::MAX_PENETRATION_FRACTION;

/// The response run's peak penetration against [`MAX_PENETRATION_FRACTION`] of the smaller of
/// clearance and pin radius, per joint: `Err` names the first joint beyond it. `what` labels
/// the run. Joints are looked up in `scene` by name for their pin radius.
pub fn check_penetration(
    scene: &Scene,
    what: &str,
    contact: &[ContactSeries],
) -> Result<(), RunError> {
    for series in contact {
        let pin_radius = scene
            .clearance_joints
            .iter()
            .find(|c| c.name == series.name)
            .map_or(f64::INFINITY, ClearanceJointSpec::pin_radius);
        let limit = MAX_PENETRATION_FRACTION * series.clearance.min(pin_radius);
        let penetration = series.penetration.iter().copied().fold(f64::MIN, f64::max);
        if penetration > limit {
            return Err(RunError::PenetrationBeyondLimit {
                what: what.to_string(),
                joint: series.name.clone(),
                penetration,
                limit,
            });
        }
    }
    Ok(())
}

/// A pin must start inside its bearing once the mechanism is assembled at t = 0: outside, the
/// first contact force is the elastic force of a penetration far beyond anything Hertz contact
/// describes (a probe reported 5e10 N). Checked after assembly, which may move the file's poses.
pub fn check_initial_penetration(
    built: &BuiltScene,
    state: &multibody::State,
    what: &str,
) -> Result<(), RunError> {
    for joint in &built.joints {
        let Some(probe) = joint.probe(built.system.elements()) else {
            continue;
        };
        let d = probe.contact(&state.q, &state.qd).diagnostics;
        if d.penetration > 0.0 {
            return Err(RunError::PinOutsideBearing {
                what: what.to_string(),
                index: joint.scene_index,
                joint: joint.name.clone(),
                eccentricity: d.eccentricity,
                clearance: joint.clearance,
            });
        }
    }
    Ok(())
}
