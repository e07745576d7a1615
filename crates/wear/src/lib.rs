//! Archard wear on body-fixed pin and bearing grids.
//!
//! A clearance revolute joint wears where the pin presses and slides on the bearing. This
//! crate holds the worn surfaces as data and evolves them (docs/model.md §3, §8):
//!
//! - [`WornProfile`]: one surface, `N` body-fixed cells over 360° holding the accumulated
//!   Archard depth `h_k`; the bearing's radius is `R_i + h/2`, the pin's `R_j − h/2`. It
//!   implements [`contact::SurfaceProfile`] with a periodic cubic B-spline (C², local, never
//!   negative, O(1) per sample), so the contact kernel sees a smooth worn radius and its exact
//!   slope.
//! - [`WornJoint`]: bearing + pin + wear parameters; serializable so a stage can be saved and
//!   resumed. A joint value always wears; [`WornJoint::if_wearing`] returns `None` for
//!   `K_d = 0`, so a caller holding `Option<WornJoint>` with wear off allocates no grid and
//!   calls no wear code.
//! - [`StageWear`]: the depth one stage gathers from **accepted** integration steps
//!   ([`StageWear::accumulate_step`] for a one-point contact, [`StageWear::accumulate_nodes`]
//!   from the pressure of the elastic-foundation contact's nodes; allocation-free), kept apart
//!   from the surfaces so the geometry stays frozen within the stage; [`StageWear::smooth`]
//!   turns a few chaotic cycles' wear into an estimate of its expectation, and
//!   [`WornJoint::apply`] moves it in, amplified.
//! - [`run_stages`]: the staged extrapolation (K cycles → ×factor → update → next stage),
//!   adaptive by default so no sub-step grows a local clearance by more than 10 %, or
//!   error-controlled ([`Extrapolation::Controlled`]: a predictor–corrector in cycles whose
//!   error estimate discounts the sampling noise the runner's [`WearSample`] halves measure);
//!   the caller's integrator is a closure.
//! - [`NoiseBatches`]: the sampling noise of the staged wear, a jackknife over the runs'
//!   independent halves ([`Replicas`] of the surfaces, one batch left out each), scaled by
//!   what of it the worn geometry's levelling leaves ([`levelling`], read from the life curve).
//!
//! ```
//! use contact::{ContactDiagnostics, SurfaceProfile};
//! use wear::{WearParams, WornJoint};
//!
//! // LGRES joint B: bearing 80 mm, clearance 0.5 mm, hinge 0.1 m, K_d = 1.8e-13 m²/N.
//! let params = WearParams::archard(1.8e-13).with_hinge_width(0.1).with_cells(1000);
//! let mut joint = WornJoint::new(&params, 0.080, 0.0795)?;
//!
//! // One stage: the caller's integrator reports each accepted step's end states.
//! let mut stage = joint.start_stage();
//! let state = |t: f64| ContactDiagnostics {
//!     in_contact: true,
//!     eccentricity: 0.0005 + 10e-6, // 10 µm penetration
//!     bearing_radius: 0.080,
//!     pin_radius: 0.0795,
//!     normal_force: 3000.0,
//!     tangential_velocity: 0.05,
//!     pin_angle: 1.5,
//!     bearing_angle: 1.5 - 0.6 * t, // the bearing turns under the load
//!     ..Default::default()
//! };
//! let dt = 1e-3;
//! for step in 0..1000 {
//!     let t = step as f64 * dt;
//!     stage.accumulate_step(&state(t), &state(t + dt), dt)?;
//! }
//! // Volume in the grids matches Archard's K_d F s (up to the arc/chord ratio).
//! assert!((stage.worn_volume() / stage.archard_volume() - 1.0).abs() < 0.01);
//!
//! // End of stage: amplify ×20,000 and update the surfaces.
//! joint.apply(&stage, 20_000.0)?;
//! let worn = joint.pin().sample(1.5);
//! assert!(worn.radius < 0.0795); // the pin shrank where it was loaded
//! assert_eq!(joint.pin().sample(4.6).radius, 0.0795); // and nowhere else
//! # Ok::<(), wear::WearError>(())
//! ```

#![warn(missing_docs)]

mod accumulate;
mod controlled;
mod error;
mod implicit;
mod joint;
mod noise;
mod profile;
mod run;
mod staging;

pub use accumulate::StageWear;
pub use error::WearError;
pub use implicit::ContactZone;
pub use joint::{ContactArc, DEFAULT_CELLS, ShapeBound, WearParams, WornJoint};
pub use noise::{
    JointNoise, JointResults, LEVELLING_MIN_STEPS, Levelling, NOISE_GROUPS, NOISE_WARM_UP,
    NoiseBatches, PERSISTENCE_TREND_DEGREE, Replicas, discrete_noise, jackknife_error, levelling,
    persistence,
};
pub use profile::{AngularRange, Peak, Side, WornProfile};
pub use run::{run_stage, run_stages};
pub use staging::{
    ClearanceStop, Extrapolation, ExtrapolationWarning, FormingBound, GeometryLimits, JointSubstep,
    NOISE_MAX_FRACTION, RunContext, StagePlan, StageReport, StagingError, SubstepReport,
    WearSample, WearStepping,
};
