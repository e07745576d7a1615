//! Scenes for planar mechanisms with worn clearance joints: the landing-gear
//! retraction/extension system of Ma, Jiang & Yin (*Aerospace* 2026), its variants and a
//! slider-crank, as data, and everything around simulating them.
//!
//! The layout follows the data flow of a run:
//! - the `scene` crate below: the TOML scene format — its types ([`scene::Scene`]; laws,
//!   materials, the integrator and driven coordinates are `contact`'s and `multibody`'s own
//!   serde types), validation with field-named issues, `extends` variants, the numeric limits
//!   ([`scene::limits`]) and the file-name rules ([`scene::file_names`]). [`scenes`] holds the
//!   shipped scenes (the list `extends` resolves names against) and the paper's studies.
//! - the `sim` crate below: a validated scene → a `multibody` system whose clearance joints
//!   are [`clearance::ClearanceForce`] elements ([`sim::build`]), one run ([`sim::run_scene`]):
//!   the response against the ideal mechanism, the wear stages, the validity of the worn
//!   geometry ([`sim::validity`]), every summary number in memory ([`sim::RunOutcome`]);
//!   nothing is written.
//! - [`analysis`]: the paper's studies and their report, the work–precision sweep and the
//!   stress battery, each engine apart from its rendering.
//! - [`io`]: atomic output writers, a run's files ([`write_run`]: CSV, JSON, PNG), figures
//!   and reports.
//!
//! The paper's reported numbers are data (`data/paper.toml`), not code.
//!
//! ```
//! use scene::BodyRef;
//!
//! let scene = lgres::scenes::builtin("lgres")?; // parsed and validated
//! assert_eq!(scene.bodies.len(), 5);
//! for joint in &scene.revolute_joints {
//!     assert!(scene.resolve(&joint.body).is_some());
//! }
//! let a = &scene.clearance_joints[0];
//! assert_eq!(scene.resolve(&a.bearing_body), Some(BodyRef::Body(2)));
//! assert!((a.pin_radius() - 0.0495).abs() < 1e-12);
//! // 15 coordinates, 11 constraint equations: A and B are force elements.
//! assert_eq!(scene.degrees_of_freedom(), 4);
//! # Ok::<(), scene::SceneError>(())
//! ```

#![warn(missing_docs)]

pub mod analysis;
pub mod family;
pub mod scenes;

pub use output::write_run;
