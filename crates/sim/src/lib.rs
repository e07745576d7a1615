//! Building and running a scene, between the scene format (the `scene` crate) and what is made
//! of a run (crate `output`'s files, figures and reports; crate `analysis`'s studies): a
//! validated scene → a `multibody` system ([`build`]), one run of it ([`run_scene`]), one
//! integration of it for an analysis that measures the integrator ([`integrate`]: the stress
//! battery, the work–precision sweep), the validity of its worn geometry ([`validity`]), the
//! run settings given outside the scene file ([`overrides`]) and the worn surfaces a run starts
//! from, handed over in memory ([`surfaces`]). No file is read or written here.
//!
//! One run of a scene: the response over `cycles` drive periods against the ideal mechanism,
//! then the wear stages, with every summary number kept in memory ([`RunOutcome`]).
//!
//! [`run_scene`] is what the CLI's `run` calls and what a study loop can call repeatedly; it
//! writes nothing (`output::artifacts` does) and reports progress through [`Progress`].
//!
//! ```
//! const CRANK: &str = r#"
//! description = "A driven crank"
//! inertia_convention = "centroidal"
//! gravity = [0.0, -9.81]
//!
//! [[bodies]]
//! name = "crank"
//! mass = 0.3
//! inertia = 1e-4
//! x = 0.025
//! y = 0.0
//! theta_deg = 0.0
//!
//! [[revolute_joints]]
//! name = "O"
//! body = "crank"
//! point = [-0.025, 0.0]
//! other = "ground"
//! other_point = [0.0, 0.0]
//!
//! [[drivers]]
//! name = "speed"
//! target = { kind = "body-coordinate", body = "crank", coordinate = "theta" }
//! law = { kind = "ramp", value = 0.0, rate = 6.283 }
//! "#;
//! let crank = scene::load_str(CRANK, "crank", &[])?;
//! let options = sim::RunOptions::default();
//! let outcome = sim::run_scene("crank", &crank, &options, &mut ())?;
//! // No clearance joint: the response is the ideal mechanism's, nothing wears.
//! assert!(!outcome.response.times.is_empty());
//! assert!(outcome.response.contact.is_empty());
//! # Ok::<(), sim::RunError>(())
//! ```
//!
//! - **Response run**: assembled from the scene's initial poses (pins concentric), integrated
//!   over `run.cycles` periods on unworn surfaces, sampled every `solver.output_interval`.
//! - **Reference**: the all-ideal mechanism ([`Scene::idealized`]) by kinematic analysis at the
//!   same times, on its own thread while the response is integrated (after a check at the
//!   first output time, so that a mechanism that does not assemble is refused before any
//!   simulation). A scene without active clearance joints runs this kinematic path only.
//! - **Wear stages** ([`wear::run_stage`]): each sub-step rebuilds the system on the current
//!   (frozen) worn surfaces and integrates `run.transient_window + K` periods, gathering wear
//!   over the last `K` only: the concentric start-up impact (docs/model.md §8) is not amplified, and a
//!   periodic drive makes any `K` consecutive periods `K` full cycles. With
//!   `run.trajectories = M ≥ 2` the `K` periods are spread over `M` trajectories on threads
//!   that continue from sub-step to sub-step, so only the first sub-step integrates the
//!   start-up window ([`clearance::Ensemble`]). After the stages the response is simulated
//!   once more on the worn surfaces.
//! - **Peaks** are statistics over cycles, with and without the start-up window (docs/model.md §8:
//!   the clearance dynamics are chaotic, single peaks are not reproducible).
//!
//! Here: the options and errors; `run` is the driver (the scene as run, its plan, the response
//! beside the ideal mechanism, the wear, the outcome), `ideal` the ideal mechanism the response
//! is compared with, `outcome` the result types, `record` the response run and its recording
//! observer, `summary` the statistics and energy books, `stages` the wear stages, `life` the
//! joints' life curves over the stages' drive cycles and their lives to the clearance limit,
//! [`life_distribution`] the distribution of those lives under the wear coefficients' scatter
//! (B10, B50, mixtures), [`validity`] the worn geometry's
//! validity measures and [`integrate`] one integration for the analyses that measure the
//! integrator.

#![warn(missing_docs)]

pub mod build;
mod error;
mod ideal;
pub mod integrate;
mod life;
pub mod life_distribution;
mod options;
mod outcome;
pub mod overrides;
mod progress;
mod record;
mod run;
mod stages;
mod summary;
pub mod surfaces;
pub mod validity;

pub use error::RunError;
pub use integrate::{Integrated, Integration, IntegrationError, IntegrationErrorKind, integrate};
pub use life::{LIFE_DISTRIBUTION_POINTS, crossing_noise, cycles_to_reach, life_distributions};
pub use options::{RunOptions, simulation_options};
pub use outcome::{
    ClearanceLimitReport, ContactSeries, Deviation, JointSummary, JointWearHistory,
    JointWearSummary, LifePoint, LifeSummary, MechanismFrames, Motion, Numerics, PeakStats,
    Response, ResponseSummary, RunOutcome, SubstepSummary, Summary, WearSummary,
};
pub use progress::Progress;
pub use run::{AssemblyCheck, MAX_ANIMATION_FRAMES, check_assembly, run_scene, scene_as_run};
pub use summary::{
    ENERGY_BOOKS_TOLERANCE_J, STAGE_HALVES_TOLERANCE, median_bootstrap_noise, peak_stats,
};
pub use validity::MIN_ELASTIC_SHARE;
