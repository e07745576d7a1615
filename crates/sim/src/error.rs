//! Why a run failed ([`RunError`]), with the hint that names the scene field behind a
//! simulation's budget.

use multibody::{AssemblyError, KinematicsError, SimulationError};

use crate::build::BuildError;

/// Why a run failed.
#[derive(Debug, thiserror::Error)]
pub enum RunError {
    /// The scene does not make a valid system (field named).
    #[error(transparent)]
    Build(#[from] BuildError),
    /// The initial poses do not assemble.
    #[error(
        "{what}: the initial poses (bodies[*].x, y, theta_deg) do not assemble at t = 0: {source}"
    )]
    Assembly {
        /// Which system.
        what: String,
        /// Cause, naming the constraints.
        source: AssemblyError,
    },
    /// The worker threads of a wear sub-step's trajectories could not be started.
    #[error(
        "the {threads} worker thread(s) of the wear trajectories could not be started: {message}"
    )]
    Threads {
        /// How many were asked for.
        threads: usize,
        /// The system's reason.
        message: String,
    },
    /// The trajectories of a wear sub-step do not divide its simulated cycles.
    #[error(
        "run.trajectories = {trajectories} must divide the simulated cycles per wear stage \
         K = {cycles_per_stage} (--cycles-per-stage, run.cycles_per_stage): each trajectory \
         simulates whole drive cycles"
    )]
    Trajectories {
        /// `run.trajectories`.
        trajectories: u32,
        /// `K` after the overrides.
        cycles_per_stage: u32,
    },
    /// The ideal mechanism's kinematic analysis failed.
    #[error(
        "kinematic analysis of the ideal mechanism (clearance joints {joints} made ideal \
         revolute joints; drivers {drivers}): {source}; the drivers must fix every degree of \
         freedom the ideal mechanism has"
    )]
    Kinematics {
        /// The clearance joints, by name.
        joints: String,
        /// The drivers, by name.
        drivers: String,
        /// Cause.
        source: KinematicsError,
    },
    /// The integrator failed or ran out of its budget (the hint names the scene field).
    #[error("{what}: {source}{}", budget_hint(source))]
    Simulation {
        /// Which run.
        what: String,
        /// Cause.
        source: SimulationError,
    },
    /// Wear staging failed (e.g. a pin worn through, too many sub-steps).
    #[error("wear staging: {0}")]
    Wear(#[from] wear::WearError),
    /// A wear stage's run ended without the wear record of a worn joint (an internal error:
    /// the element was built without one, or it was taken twice).
    #[error("{what}: clearance joint {joint} has no wear record after its run (internal error)")]
    LostWearBuffer {
        /// Which run.
        what: String,
        /// The joint.
        joint: String,
    },
    /// The worn surfaces to start from could not be loaded (file and joint named).
    #[error(transparent)]
    Surfaces(#[from] crate::surfaces::SurfacesError),
    /// The scene has no drive period (validation normally catches this).
    #[error("run.period: no drive period; give run.period")]
    NoPeriod,
    /// The scene has no body to record.
    #[error("run.response_body: no body to record")]
    NoResponseBody,
    /// The scene (with the run's overrides applied) is not valid.
    #[error(transparent)]
    Scene(#[from] scene::SceneError),
    /// A pin starts outside its bearing after assembly at t = 0.
    #[error(
        "{what}: clearance_joints[{index}] ({joint}): after assembly at t = 0 the pin centre is \
         {eccentricity:.6e} m from the bearing centre, beyond the clearance ({clearance:e} m): \
         the pin starts outside its bearing (check the bodies' initial poses and the joint's \
         pin_point, bearing_point)"
    )]
    PinOutsideBearing {
        /// Which system.
        what: String,
        /// Index into `clearance_joints`.
        index: usize,
        /// Joint name.
        joint: String,
        /// Initial eccentricity, m.
        eccentricity: f64,
        /// Nominal clearance, m.
        clearance: f64,
    },
    /// A contact penetrated beyond [`MAX_PENETRATION_FRACTION`](scene::limits::MAX_PENETRATION_FRACTION) of its
    /// clearance (or pin radius): the contact law is outside its validity.
    #[error(
        "{what}: clearance joint {joint}: peak penetration {penetration:.3e} m exceeds {limit:.3e} m \
         (half the smaller of clearance and pin radius): the contact law is outside its validity \
         (material too soft, load too high or tolerances too loose); forces are not trusted"
    )]
    PenetrationBeyondLimit {
        /// Which run.
        what: String,
        /// Clearance joint name.
        joint: String,
        /// Peak penetration, m.
        penetration: f64,
        /// The limit, m.
        limit: f64,
    },
    /// A run produced a non-finite value.
    #[error("{what}: the solution became non-finite (NaN or infinite) at t = {t}")]
    NonFinite {
        /// Which run.
        what: String,
        /// First bad output time.
        t: f64,
    },
}

impl RunError {
    /// Whether the scene itself is at fault (exit code 2) rather than the run (1).
    pub fn is_bad_input(&self) -> bool {
        matches!(
            self,
            RunError::Build(_)
                | RunError::Surfaces(_)
                | RunError::Scene(_)
                | RunError::Kinematics { .. }
                | RunError::Assembly { .. }
                | RunError::PinOutsideBearing { .. }
                | RunError::NoPeriod
                | RunError::NoResponseBody
                | RunError::Trajectories { .. }
        )
    }
}

/// Names the scene field behind a simulation's budget error (empty for other errors).
fn budget_hint(e: &multibody::SimulationError) -> &'static str {
    match e {
        multibody::SimulationError::StepLimit { .. } => {
            " (solver.max_steps; raise it, or --max-steps, if the run is expected to be long)"
        }
        multibody::SimulationError::WallTimeLimit { .. } => {
            " (solver.max_wall_time; raise it, or --max-wall-time, if the run is expected to be \
             long)"
        }
        _ => "",
    }
}
