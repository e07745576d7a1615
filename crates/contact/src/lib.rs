//! Planar clearance revolute joints: kinematics, contact and friction laws, exact Jacobians.

pub mod diagnostics;
pub mod error;
pub mod friction;
pub mod joint;
pub mod normal;
pub mod surface;

pub use diagnostics::ContactDiagnostics;
pub use error::ContactError;
pub use friction::{
    Ambrosio, AmbrosioParams, Coulomb, CoulombParams, FrictionForce, FrictionLaw, FrictionLawKind,
    Frictionless,
};
pub use joint::{
    BodyState, ClearanceJoint, ContactForces, ContactJacobian, JointKinematics, JointSurface,
    Material, MaterialParams,
};
pub use normal::{
    DEFAULT_HERTZ_EXPONENT, DEFAULT_ONSET_VELOCITY_FLOOR, DampedHertzParams, Flores, Hertz,
    HertzParams, HuntCrossley, ImpactMemory, LankaraniNikravesh, NormalForce, NormalLaw,
    NormalLawKind,
};
pub use surface::{CircularProfile, RadiusSample, SurfaceProfile};
