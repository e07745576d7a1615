//! Errors, each naming the body, joint or constraint at fault and the offending value.

use thiserror::Error;

/// A model that cannot describe a physical planar mechanism.
#[derive(Debug, Clone, PartialEq, Error)]
pub enum ModelError {
    /// A body's mass is not positive and finite (kg).
    #[error("body '{body}': mass must be positive and finite, got {value}")]
    InvalidMass {
        /// The body's name.
        body: String,
        /// The rejected mass (kg).
        value: f64,
    },
    /// A body's centroidal inertia is not positive and finite (kg m²).
    #[error("body '{body}': centroidal inertia must be positive and finite, got {value}")]
    InvalidInertia {
        /// The body's name.
        body: String,
        /// The rejected inertia (kg m²).
        value: f64,
    },
    /// A body's initial pose or velocity guess has a NaN or infinite entry.
    #[error("body '{body}': initial pose and velocity must be finite")]
    NonFiniteBodyState {
        /// The body's name.
        body: String,
    },
    /// A joint or driver refers to a [`crate::BodyId`] that was not returned by this model.
    #[error("{owner} '{name}' refers to body #{index}, but the model has only {count} bodies")]
    MissingBody {
        /// `"joint"` or `"driver"`.
        owner: &'static str,
        /// The joint's or driver's name.
        name: String,
        /// The body index given.
        index: usize,
        /// Bodies in the model.
        count: usize,
    },
    /// A joint connects ground to ground or a body to itself, so it constrains nothing.
    #[error("joint '{joint}' connects {what}")]
    DegenerateJoint {
        /// The joint's name.
        joint: String,
        /// What it connects.
        what: &'static str,
    },
    /// A joint's anchor point, axis or locked angle is not finite.
    #[error("joint '{joint}': {what} must be finite, got ({x}, {y})")]
    NonFiniteJointGeometry {
        /// The joint's name.
        joint: String,
        /// Which quantity (e.g. `"anchor i"`, `"axis"`).
        what: &'static str,
        /// Its first component (the angle for a locked angle).
        x: f64,
        /// Its second component (0 for a locked angle).
        y: f64,
    },
    /// A prismatic joint's axis has zero length, so it has no direction.
    #[error("prismatic joint '{joint}': the sliding axis must be a nonzero vector, got ({x}, {y})")]
    ZeroAxis {
        /// The joint's name.
        joint: String,
        /// The axis's x component.
        x: f64,
        /// The axis's y component.
        y: f64,
    },
    /// A driver refers to a [`crate::JointId`] that was not returned by this model.
    #[error("driver '{driver}' refers to joint #{index}, but the model has only {count} joints")]
    MissingJoint {
        /// The driver's name.
        driver: String,
        /// The joint index given.
        index: usize,
        /// Joints in the model.
        count: usize,
    },
    /// A driver prescribes an angle of a prismatic joint or the slide of a revolute one.
    #[error("driver '{driver}' drives {target} of joint '{joint}', which is a {kind} joint")]
    WrongJointKind {
        /// The driver's name.
        driver: String,
        /// The joint's name.
        joint: String,
        /// `"the angle"` or `"the slide"`.
        target: &'static str,
        /// The joint's kind, `"revolute"` or `"prismatic"`.
        kind: &'static str,
    },
    /// A drive function or one of its derivatives is not finite at `t = 0`.
    #[error("driver '{driver}': the drive function is not finite at t = 0 (value {value})")]
    NonFiniteDrive {
        /// The driver's name.
        driver: String,
        /// The offending value, first derivative or second derivative.
        value: f64,
    },
    /// A model without bodies has nothing to simulate.
    #[error("the model has no bodies")]
    Empty,
}

/// Failure to find a configuration (or velocities) that satisfies the constraints.
#[derive(Debug, Clone, PartialEq, Error)]
pub enum AssemblyError {
    /// Newton's method did not bring the constraints within tolerance.
    #[error(
        "position analysis did not converge in {iterations} Newton iterations at t = {t}: \
         residual {residual:.3e}; largest violations: {worst}"
    )]
    NotConverged {
        /// Time of the analysis (s).
        t: f64,
        /// Newton iterations made.
        iterations: usize,
        /// Largest constraint violation left (m or rad).
        residual: f64,
        /// The most violated constraints, formatted "name = value".
        worst: String,
    },
    /// `Φ_q` lost rank: some equations are redundant or the mechanism is locked.
    #[error(
        "the constraint Jacobian is rank deficient at t = {t}: constraints [{dependent}] depend \
         on the others (redundant or locked-up mechanism)"
    )]
    RankDeficient {
        /// Time of the analysis (s).
        t: f64,
        /// Labels of the dependent constraint equations, comma-separated.
        dependent: String,
    },
    /// More constraint equations than coordinates: no configuration can satisfy them in general.
    #[error("{equations} constraint equations for {coordinates} coordinates: overconstrained")]
    Overconstrained {
        /// Constraint equations (joints and drivers).
        equations: usize,
        /// Coordinates, `3 × bodies`.
        coordinates: usize,
    },
    /// A `q` or `q̇` given to the analysis does not have one entry per coordinate.
    #[error("a state vector has length {actual}, expected {expected}")]
    WrongLength {
        /// Coordinates of the system.
        expected: usize,
        /// Length given.
        actual: usize,
    },
    /// A `q` or `q̇` given to the analysis has a NaN or infinite entry.
    #[error("the {what} vector contains a non-finite value")]
    NonFinite {
        /// `"position guess"` or `"velocity guess"`.
        what: &'static str,
    },
}

/// Failure to evaluate the equations of motion at one state.
#[derive(Debug, Clone, PartialEq, Error)]
pub enum EvaluationError {
    /// `Φ_q` lost rank at this state, so accelerations and multipliers are not unique.
    #[error(
        "the augmented matrix [M Φ_qᵀ; Φ_q 0] is singular: constraints [{dependent}] depend on \
         the others (singular position or redundant constraints)"
    )]
    Singular {
        /// Labels of the dependent constraint equations, comma-separated.
        dependent: String,
    },
    /// An input or output slice does not match the system's dimensions.
    #[error("{what} has length {actual}, expected {expected}")]
    WrongLength {
        /// Which slice.
        what: &'static str,
        /// Length the system needs.
        expected: usize,
        /// Length given.
        actual: usize,
    },
}

/// Failure of a kinematic analysis.
#[derive(Debug, Clone, PartialEq, Error)]
pub enum KinematicsError {
    /// Kinematic analysis needs every degree of freedom driven: as many equations as coordinates.
    #[error(
        "kinematic analysis needs as many independent constraints as coordinates; the mechanism \
         has {coordinates} coordinates and {equations} constraint equations"
    )]
    NotFullyDriven {
        /// Coordinates, `3 × bodies`.
        coordinates: usize,
        /// Constraint equations (joints and drivers).
        equations: usize,
    },
    /// Positions or velocities could not be found at one of the requested times.
    #[error(transparent)]
    Assembly(#[from] AssemblyError),
    /// Accelerations or multipliers could not be solved for at one of the requested times.
    #[error("at t = {t}: {error}")]
    Evaluation {
        /// The time (s).
        t: f64,
        /// What failed.
        error: EvaluationError,
    },
}

/// Failure of a dynamic simulation.
#[derive(Debug, Clone, PartialEq, Error)]
pub enum SimulationError {
    /// The start state, or the state after an event, does not satisfy the constraints.
    #[error(transparent)]
    Assembly(#[from] AssemblyError),
    /// A [`crate::SimulationOptions`] field is out of range; the message names it.
    #[error("invalid simulation option: {0}")]
    InvalidOptions(String),
    /// The equations of motion could not be evaluated (singular position).
    #[error("at t = {t}: {error}")]
    Evaluation {
        /// Time of the failing evaluation (s).
        t: f64,
        /// What failed.
        error: EvaluationError,
    },
    /// diffsol gave up (step too small, too many failures).
    #[error("the integrator failed at t = {t}: {message}")]
    Integrator {
        /// Time reached (s).
        t: f64,
        /// diffsol's message.
        message: String,
    },
    /// The run used up [`crate::SimulationOptions::max_steps`].
    #[error("stopped at t = {t} after {steps} accepted steps (the max_steps budget)")]
    StepLimit {
        /// Time reached (s).
        t: f64,
        /// Accepted steps.
        steps: usize,
    },
    /// The run used up [`crate::SimulationOptions::max_wall_time`].
    #[error(
        "stopped at t = {t} after {steps} accepted steps: the wall-time budget of {seconds} s \
         (max_wall_time) ran out"
    )]
    WallTimeLimit {
        /// Time reached (s).
        t: f64,
        /// Accepted steps.
        steps: usize,
        /// The budget (s of wall time).
        seconds: f64,
    },
}

/// Which way a simulation failed, without its numbers: what a caller that tallies failures
/// (a stress battery, a step budget) matches on.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub enum SimulationErrorKind {
    /// [`SimulationError::Assembly`].
    Assembly,
    /// [`SimulationError::InvalidOptions`].
    InvalidOptions,
    /// [`SimulationError::Evaluation`].
    Evaluation,
    /// [`SimulationError::Integrator`].
    Integrator,
    /// [`SimulationError::StepLimit`].
    StepLimit,
    /// [`SimulationError::WallTimeLimit`].
    WallTimeLimit,
}

impl SimulationErrorKind {
    /// The variant's name, e.g. `StepLimit`.
    pub fn name(self) -> &'static str {
        match self {
            Self::Assembly => "Assembly",
            Self::InvalidOptions => "InvalidOptions",
            Self::Evaluation => "Evaluation",
            Self::Integrator => "Integrator",
            Self::StepLimit => "StepLimit",
            Self::WallTimeLimit => "WallTimeLimit",
        }
    }
}

impl SimulationError {
    /// Which way the simulation failed.
    pub fn kind(&self) -> SimulationErrorKind {
        match self {
            Self::Assembly(_) => SimulationErrorKind::Assembly,
            Self::InvalidOptions(_) => SimulationErrorKind::InvalidOptions,
            Self::Evaluation { .. } => SimulationErrorKind::Evaluation,
            Self::Integrator { .. } => SimulationErrorKind::Integrator,
            Self::StepLimit { .. } => SimulationErrorKind::StepLimit,
            Self::WallTimeLimit { .. } => SimulationErrorKind::WallTimeLimit,
        }
    }
}

/// `Ok` when `values` has `expected` entries, else the error naming `what`.
pub(crate) fn check_len(
    what: &'static str,
    values: &[f64],
    expected: usize,
) -> Result<(), EvaluationError> {
    if values.len() == expected {
        Ok(())
    } else {
        Err(EvaluationError::WrongLength {
            what,
            expected,
            actual: values.len(),
        })
    }
}
