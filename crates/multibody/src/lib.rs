//! Planar constrained rigid-body dynamics.
//!
//! Placeholder docs; filled in below.

mod constraints;
pub mod drive;
mod dynamics;
mod error;
mod force;
mod linalg;
mod model;
mod system;

pub use constraints::ConstraintOwner;
pub use drive::{Constant, DriveFunction, Harmonic, Ramp};
pub use dynamics::{
    AbsoluteTolerances, ConstraintDrift, EnergyAudit, EventRecord, Frame, Integrator,
    JacobianMethod, Observer, OutputTimes, SimulationOptions, SimulationResult, SolverStatistics,
    Trajectory,
};
pub use error::{AssemblyError, KinematicsError, ModelError, SimulationError};
pub use force::{ElementId, ForceElement, ForcePartials, Gravity};
pub use model::{
    Anchor, Body, BodyId, Coordinate, DriveTarget, Driver, DriverId, Joint, JointId, Model,
    RotationLock,
};
pub use system::{Baumgarte, Evaluator, KinematicSolution, State, System};
