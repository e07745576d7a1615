//! Forward dynamics on diffsol: options, the stepping loop (output by interpolation, hooks,
//! events, energy audit) and the run report.
//!
//! What a run is asked to do is in `options`, what it hands out in `report`; `stepper` puts
//! diffsol's methods and Radau IIA behind one interface, which `run` steps (its `record`
//! keeps the frames, drift and energy audit). Only the public types are re-exported here.

mod options;
mod report;
mod run;
mod stepper;

pub use options::{Integrator, JacobianMethod, LinearSolverKind, OutputTimes, SimulationOptions};
pub use report::{
    ConstraintDrift, EnergyAudit, EventRecord, Frame, Observer, SimulationResult, SolverStatistics,
};
