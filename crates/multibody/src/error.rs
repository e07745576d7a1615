//! Errors, each naming the body, joint or constraint at fault and the offending value.

use thiserror::Error;

/// A model that cannot describe a physical planar mechanism.
#[derive(Debug, Clone, PartialEq, Error)]
pub enum ModelError {
    #[error("body '{body}': mass must be positive and finite, got {value}")]
    InvalidMass { body: String, value: f64 },
    #[error("body '{body}': centroidal inertia must be positive and finite, got {value}")]
    InvalidInertia { body: String, value: f64 },
    #[error("body '{body}': initial pose and velocity must be finite")]
    NonFiniteBodyState { body: String },
    #[error("{owner} '{name}' refers to body #{index}, but the model has only {count} bodies")]
    MissingBody {
        owner: &'static str,
        name: String,
        index: usize,
        count: usize,
    },
    #[error("joint '{joint}' connects {what}")]
    DegenerateJoint { joint: String, what: &'static str },
    #[error("joint '{joint}': {what} must be finite, got ({x}, {y})")]
    NonFiniteJointGeometry {
        joint: String,
        what: &'static str,
        x: f64,
        y: f64,
    },
    #[error("prismatic joint '{joint}': the sliding axis must be a nonzero vector, got ({x}, {y})")]
    ZeroAxis { joint: String, x: f64, y: f64 },
    #[error("driver '{driver}' refers to joint #{index}, but the model has only {count} joints")]
    MissingJoint {
        driver: String,
        index: usize,
        count: usize,
    },
    #[error("driver '{driver}' drives {target} of joint '{joint}', which is a {kind} joint")]
    WrongJointKind {
        driver: String,
        joint: String,
        target: &'static str,
        kind: &'static str,
    },
    #[error("driver '{driver}': the drive function is not finite at t = 0 (value {value})")]
    NonFiniteDrive { driver: String, value: f64 },
    #[error("the model has no bodies")]
    Empty,
}

/// Failure to find a configuration (or velocities) that satisfies the constraints.
#[derive(Debug, Clone, PartialEq, Error)]
pub enum AssemblyError {
    #[error(
        "position analysis did not converge in {iterations} Newton iterations at t = {t}: \
         residual {residual:.3e}; largest violations: {worst}"
    )]
    NotConverged {
        t: f64,
        iterations: usize,
        residual: f64,
        /// The most violated constraints, formatted "name = value".
        worst: String,
    },
    #[error(
        "the constraint Jacobian is rank deficient at t = {t}: constraints [{dependent}] depend \
         on the others (redundant or locked-up mechanism)"
    )]
    RankDeficient { t: f64, dependent: String },
    #[error("{equations} constraint equations for {coordinates} coordinates: overconstrained")]
    Overconstrained {
        equations: usize,
        coordinates: usize,
    },
    #[error("a state vector has length {actual}, expected {expected}")]
    WrongLength { expected: usize, actual: usize },
    #[error("the {what} vector contains a non-finite value")]
    NonFinite { what: &'static str },
}

/// Failure to evaluate the equations of motion at one state.
#[derive(Debug, Clone, PartialEq, Error)]
pub enum EvaluationError {
    #[error(
        "the augmented matrix [M Φ_qᵀ; Φ_q 0] is singular: constraints [{dependent}] depend on \
         the others (singular position or redundant constraints)"
    )]
    Singular { dependent: String },
    #[error("{what} has length {actual}, expected {expected}")]
    WrongLength {
        what: &'static str,
        expected: usize,
        actual: usize,
    },
}

/// Failure of a kinematic analysis.
#[derive(Debug, Clone, PartialEq, Error)]
pub enum KinematicsError {
    #[error(
        "kinematic analysis needs as many independent constraints as coordinates; the mechanism \
         has {coordinates} coordinates and {equations} constraint equations"
    )]
    NotFullyDriven {
        coordinates: usize,
        equations: usize,
    },
    #[error(transparent)]
    Assembly(#[from] AssemblyError),
    #[error("at t = {t}: {error}")]
    Evaluation { t: f64, error: EvaluationError },
}

/// Failure of a dynamic simulation.
#[derive(Debug, Clone, PartialEq, Error)]
pub enum SimulationError {
    #[error(transparent)]
    Assembly(#[from] AssemblyError),
    #[error("invalid simulation option: {0}")]
    InvalidOptions(String),
    #[error("at t = {t}: {error}")]
    Evaluation { t: f64, error: EvaluationError },
    #[error("the integrator failed at t = {t}: {message}")]
    Integrator { t: f64, message: String },
    #[error("stopped at t = {t} after {steps} accepted steps (the max_steps budget)")]
    StepLimit { t: f64, steps: usize },
    #[error(
        "stopped at t = {t} after {steps} accepted steps: the wall-time budget of {seconds} s \
         (max_wall_time) ran out"
    )]
    WallTimeLimit { t: f64, steps: usize, seconds: f64 },
}
