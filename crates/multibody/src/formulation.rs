//! The choice of coordinates the equations of motion are integrated in, and the interface the
//! integration loop drives either formulation through.
//!
//! Each formulation implements [`Equations`] (public: the right-hand side and its Jacobians)
//! and `Integrated` (what the loop needs besides) next to its evaluator: the Cartesian one in
//! `system` ([`crate::Evaluator`]), the joint-coordinate one in `joint_coordinates::evaluator`.
//! What they share is here too (the forward-difference Jacobian, the first-order form
//! `ẋ = (v, a)`). This module builds only on `error`, `force` and `state`, so both evaluators
//! and the integration loop (`dynamics`) sit above it.

use nalgebra::DMatrix;

use crate::error::{EvaluationError, check_len};
use crate::force::ForceElement;
use crate::state::{AbsoluteTolerances, State};

/// Which coordinates [`crate::System::simulate`] integrates. Either way the trajectory,
/// observers, force elements and the energy audit see Cartesian body coordinates `q, q̇, q̈`
/// and the multipliers of every constraint equation. Named `cartesian` and `joint` in scene
/// files.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default, serde::Serialize, serde::Deserialize)]
#[serde(rename_all = "kebab-case")]
pub enum Formulation {
    /// Body coordinates `(x, y, θ)` with every ideal joint and driver a constraint with a
    /// multiplier and Baumgarte stabilisation (the augmented formulation of the paper). The
    /// default here because it takes any mechanism as it is assembled, with nothing to choose;
    /// scenes default to [`Formulation::JointCoordinates`] instead, which needs a spanning tree
    /// of the ideal joints and does about half the work per LGRES drive cycle.
    #[default]
    Cartesian,
    /// Relative coordinates of a spanning tree of the ideal joints; drivers prescribe their
    /// coordinate; only joints that close loops (and drivers that prescribe no tree coordinate)
    /// remain constraints ([`crate::joint_coordinates`] docs).
    #[serde(rename = "joint", alias = "joint-coordinates")]
    JointCoordinates,
}

impl Formulation {
    /// The scene-file spelling.
    pub fn name(self) -> &'static str {
        match self {
            Self::Cartesian => "cartesian",
            Self::JointCoordinates => "joint",
        }
    }
}

/// Equations of motion in first-order form `ẋ = f(t, x)` with their exact Jacobian, as the
/// integrators evaluate them: [`crate::Evaluator`] (from [`crate::System::evaluator`]) is the
/// Cartesian formulation's, `x = (q, q̇)`. Each evaluation takes the force elements, which the
/// system owns, and works in the implementor's preallocated storage.
pub trait Equations {
    /// Length of the state `x`.
    fn size(&self) -> usize;
    /// `ẋ = f(t, x)`. A singular system (dependent constraints, a degenerate mass matrix)
    /// yields NaN accelerations, so that an integrator rejects the step, and an `Err` naming
    /// the cause.
    fn rhs(
        &mut self,
        elements: &[Box<dyn ForceElement>],
        t: f64,
        x: &[f64],
        dx: &mut [f64],
    ) -> Result<(), EvaluationError>;
    /// The exact Jacobian `∂f/∂x` (`size × size`) at `(t, x)`; NaN and an `Err` where
    /// [`Equations::rhs`] fails.
    fn jacobian(
        &mut self,
        elements: &[Box<dyn ForceElement>],
        t: f64,
        x: &[f64],
        jacobian: &mut DMatrix<f64>,
    ) -> Result<(), EvaluationError>;
    /// The forward-difference Jacobian (`size + 1` right-hand sides), the reference the exact
    /// one is measured against.
    fn finite_difference_jacobian(
        &mut self,
        elements: &[Box<dyn ForceElement>],
        t: f64,
        x: &[f64],
        jacobian: &mut DMatrix<f64>,
    ) -> Result<(), EvaluationError>;
    /// Right-hand sides and Jacobians evaluated so far.
    fn evaluations(&self) -> (usize, usize);
}

/// What the integration loop needs of a formulation besides its [`Equations`]: the map between
/// its integrated state and the Cartesian one, its tolerances, and what it can report cheaper.
pub(crate) trait Integrated: Equations {
    /// `x` of an assembled Cartesian state.
    fn initial_state(&mut self, state: &State) -> Vec<f64>;
    /// Absolute tolerances of `x`.
    fn tolerances(&self, atol: &AbsoluteTolerances) -> Vec<f64>;
    /// The Cartesian `(q, q̇)` of `x` at `t`: `x` itself, or `scratch` (length `2n`) filled.
    fn cartesian<'a>(&mut self, t: f64, x: &'a [f64], scratch: &'a mut [f64]) -> &'a [f64];
    /// The constraint equations that can drift (`None`: all); the others hold by construction
    /// up to round-off, so the drift report skips them.
    fn drifting(&self) -> Option<&[usize]> {
        None
    }
    /// The power of each element (`F·q̇`, 0 for elements with a potential energy) into
    /// `element_powers` and of each driver into `driver_powers` (driver order) at `(t, x)`,
    /// when the formulation has a cheaper way than mapping to Cartesian coordinates and
    /// solving for the multipliers (`None`: it has not).
    fn powers(
        &mut self,
        _elements: &[Box<dyn ForceElement>],
        _t: f64,
        _x: &[f64],
        _element_powers: &mut [f64],
        _driver_powers: &mut [f64],
    ) -> Option<Result<(), EvaluationError>> {
        None
    }
}

/// Scratch of a forward-difference Jacobian ([`ForwardDifferences::jacobian`]), kept by each
/// evaluator so the fallback Jacobian does not allocate.
#[derive(Clone, Debug, Default)]
pub(crate) struct ForwardDifferences {
    base: Vec<f64>,
    shifted: Vec<f64>,
    work: Vec<f64>,
}

impl ForwardDifferences {
    /// Scratch for states of length `size`.
    pub(crate) fn new(size: usize) -> Self {
        Self {
            base: vec![0.0; size],
            shifted: vec![0.0; size],
            work: vec![0.0; size],
        }
    }

    /// Forward-difference Jacobian of `rhs` at `x` (`size + 1` evaluations, steps
    /// `√ε · max(|x_c|, 1)`). Stops at the first failed evaluation and returns its error.
    pub(crate) fn jacobian(
        &mut self,
        mut rhs: impl FnMut(&[f64], &mut [f64]) -> Result<(), EvaluationError>,
        x: &[f64],
        jacobian: &mut DMatrix<f64>,
    ) -> Result<(), EvaluationError> {
        let Self {
            base,
            shifted,
            work,
        } = self;
        work.copy_from_slice(x);
        let mut result = rhs(x, base);
        for c in 0..x.len() {
            if result.is_err() {
                break;
            }
            let step = f64::EPSILON.sqrt() * x[c].abs().max(1.0);
            work[c] = x[c] + step;
            result = rhs(work, shifted);
            work[c] = x[c];
            for r in 0..x.len() {
                jacobian[(r, c)] = (shifted[r] - base[r]) / step;
            }
        }
        result
    }
}

/// Checks the state `x` and the Jacobian's storage of a call to equations of size `size`.
pub(crate) fn check_jacobian_call(
    size: usize,
    x: &[f64],
    jacobian: &DMatrix<f64>,
) -> Result<(), EvaluationError> {
    check_len("x", x, size)?;
    check_len("Jacobian entries", jacobian.as_slice(), size * size)
}

/// Starts the Jacobian of a first-order form `ẋ = (v, a)` with `x = (p, v)`: the top half is
/// `[0, I]` whatever the forces, the bottom half zeroed for the caller to fill.
pub(crate) fn kinematic_rows(jacobian: &mut DMatrix<f64>, half: usize) {
    jacobian.as_mut_slice().fill(0.0);
    for i in 0..half {
        jacobian[(i, half + i)] = 1.0;
    }
}

/// [`Equations::finite_difference_jacobian`] of `equations`, whose scratch `scratch` picks
/// out: the scratch is taken out for the call, since the differences evaluate `equations`.
pub(crate) fn finite_difference_jacobian<E: Equations + ?Sized>(
    equations: &mut E,
    scratch: fn(&mut E) -> &mut ForwardDifferences,
    elements: &[Box<dyn ForceElement>],
    t: f64,
    x: &[f64],
    jacobian: &mut DMatrix<f64>,
) -> Result<(), EvaluationError> {
    check_jacobian_call(equations.size(), x, jacobian)?;
    let mut differences = std::mem::take(scratch(equations));
    let result = differences.jacobian(|v, dv| equations.rhs(elements, t, v, dv), x, jacobian);
    *scratch(equations) = differences;
    result
}

/// `ẏ = (v, a)` of a second-order system from its velocities and the accelerations of a
/// solve; a failed solve gives NaN accelerations, which the integrator rejects.
pub(crate) fn first_order<E>(
    derivative: &mut [f64],
    velocities: &[f64],
    solve: &Result<(), E>,
    accelerations: &[f64],
) {
    let (dq, dv) = derivative.split_at_mut(velocities.len());
    dq.copy_from_slice(velocities);
    match solve {
        Ok(()) => dv.copy_from_slice(accelerations),
        Err(_) => dv.fill(f64::NAN),
    }
}
