//! Scenes for planar mechanisms with worn clearance joints.
//!
//! This crate holds the serde scene format and its validation ([`scene`]), the shipped scenes
//! and the paper's studies ([`scenes`]: the landing-gear retraction/extension system of Ma,
//! Jiang & Yin, *Aerospace* 2026, its variants, and a slider-crank), atomic output writers
//! ([`output`]) and figures ([`plot`]). [`build`] turns a scene into a `multibody` system whose
//! clearance joints are [`clearance::ClearanceForce`] elements (the `contact` kernel, with `wear`
//! accumulation when a joint wears). [`run::run_scene`] simulates a scene (response against the
//! ideal mechanism, wear stages) and returns every summary number in memory;
//! [`artifacts::write_run`] writes its CSV, JSON and PNG files.
//!
//! ```
//! use lgres::scene::BodyRef;
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
//! # Ok::<(), lgres::scene::SceneError>(())
//! ```

pub mod artifacts;
pub mod build;
pub mod clearance;
pub mod limits;
pub mod output;
pub mod overrides;
pub mod plot;
pub mod precision;
pub mod report;
pub mod run;
pub mod scene;
pub mod scenes;
pub mod stress;
pub mod study;
pub mod surfaces;
pub mod validity;
