//! Scenes for planar mechanisms with worn clearance joints.
//!
//! This crate will hold the serde scene format and its validation, the force element that adapts
//! `contact` and `wear` to `multibody`, the shipped scenes (the landing-gear
//! retraction/extension system of Ma, Jiang & Yin, *Aerospace* 2026, and a slider-crank), the
//! paper's studies, recorders and reports.
