//! The LGRES model: the landing-gear retraction/extension system of Ma, Jiang & Yin
//! (*Aerospace* 2026) with its variants and a slider-crank, as data in the `scene` crate's
//! format, and the paper's own studies and numbers.
//!
//! - [`scenes`]: the shipped scenes (`scenes/*.toml`, embedded; the list `extends` resolves
//!   names against, [`scenes::BUILTINS`]). The reconstructed geometry lives in
//!   `scenes/lgres.toml` only; the variants override a few values.
//! - [`studies`]: the paper's studies (Sec. 4.2) as values, [`studies::STUDIES`]: the scenes
//!   each runs, the trend the paper claims for them ([`claim`]) and, for a study in the paper's
//!   wear formulation, the physical study it mirrors.
//! - [`paper`]: the numbers the paper reports, kept as data (`data/paper.toml`).
//!
//! Running a scene is crate `sim`'s, writing its files crate `output`'s, and running a study
//! and judging it against these numbers crate `analysis`'s; this crate needs only `scene`.
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

pub mod claim;
pub mod paper;
pub mod scenes;
pub mod studies;
