//! Planar clearance revolute joints: kinematics, contact and friction laws, exact Jacobians.

pub mod diagnostics;
pub mod surface;

pub use diagnostics::ContactDiagnostics;
pub use surface::{CircularProfile, RadiusSample, SurfaceProfile};
