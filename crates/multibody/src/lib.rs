//! Planar constrained rigid-body dynamics.
//!
//! This crate will hold bodies, ideal joints, drivers and force elements; assembly, kinematic
//! analysis, and dynamics integrated by diffsol's BDF.
