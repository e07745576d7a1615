//! One interface to the integrators the run loop steps: diffsol's methods ([`Diffsol`]) and
//! this crate's Radau IIA, with how a step ended and the integrators' counters.

use diffsol::{
    NalgebraContext, NalgebraMat, NalgebraVec, OdeEquationsImplicit, OdeSolverMethod,
    OdeSolverStopReason, Vector, VectorCommon,
};

use crate::error::SimulationError;
use crate::radau::{Radau5, RadauError, RadauStop};

use super::report::SolverStatistics;

/// An integrator's error as the run reports it.
pub(super) fn integrator_error(t: f64, error: impl std::fmt::Display) -> SimulationError {
    SimulationError::Integrator {
        t,
        message: error.to_string(),
    }
}

/// diffsol's implicit equations on `nalgebra` storage in `f64`, the only kind this crate
/// builds: one name for the bound that the wrapper and the loop's dispatch both need.
pub(super) trait NalgebraEquations:
    OdeEquationsImplicit<T = f64, V = NalgebraVec<f64>, M = NalgebraMat<f64>, C = NalgebraContext>
{
}

impl<E> NalgebraEquations for E where
    E: OdeEquationsImplicit<
            T = f64,
            V = NalgebraVec<f64>,
            M = NalgebraMat<f64>,
            C = NalgebraContext,
        >
{
}

/// How an accepted step ended.
#[derive(Debug, Clone, Copy, PartialEq)]
pub(super) enum StepOutcome {
    /// An ordinary step.
    Step,
    /// The step ended at the stop time.
    StopTime,
    /// Root `index` changed sign at the time given, within the step.
    Root(f64, usize),
}

/// What `Run::step_loop` needs of an integrator, so that one loop (outputs, hooks, events,
/// energy audit, limits) serves diffsol's methods ([`Diffsol`]) and [`Radau5`].
pub(super) trait Stepper {
    type Error: std::fmt::Display;
    /// Time of the current state.
    fn t(&self) -> f64;
    /// The current state.
    fn y(&self) -> &[f64];
    /// Time, state and derivative slot, for re-evaluating `dy` after an event.
    fn derivative_mut(&mut self) -> (f64, &[f64], &mut [f64]);
    /// Steps end exactly at `t` rather than pass it.
    fn set_stop_time(&mut self, t: f64) -> Result<(), Self::Error>;
    /// One accepted step.
    fn step(&mut self) -> Result<StepOutcome, Self::Error>;
    /// The dense output of the last step at `t`.
    fn interpolate(&mut self, t: f64, y: &mut [f64]) -> Result<(), Self::Error>;
    /// Moves the state back to `t` (a root) within the last step and restarts there.
    fn state_mut_back(&mut self, t: f64) -> Result<(), Self::Error>;
    /// Writes the integrator's counters into `statistics`.
    fn statistics(&self, statistics: &mut SolverStatistics);
}

/// A diffsol method as a [`Stepper`] (the wrapper names `Eqn`, which the method's trait
/// takes as a parameter), with a buffer for its interpolation into diffsol's vector type.
pub(super) struct Diffsol<'a, Eqn, S> {
    solver: S,
    buffer: NalgebraVec<f64>,
    equations: std::marker::PhantomData<&'a Eqn>,
}

impl<'a, Eqn, S> Diffsol<'a, Eqn, S>
where
    Eqn: NalgebraEquations + 'a,
    S: OdeSolverMethod<'a, Eqn>,
{
    pub(super) fn new(solver: S) -> Self {
        let buffer = solver.state().y.clone();
        Self {
            solver,
            buffer,
            equations: std::marker::PhantomData,
        }
    }
}

impl<'a, Eqn, S> Stepper for Diffsol<'a, Eqn, S>
where
    Eqn: NalgebraEquations + 'a,
    S: OdeSolverMethod<'a, Eqn>,
{
    type Error = diffsol::DiffsolError;

    fn t(&self) -> f64 {
        self.solver.state().t
    }

    fn y(&self) -> &[f64] {
        self.solver.state().y.inner().as_slice()
    }

    fn derivative_mut(&mut self) -> (f64, &[f64], &mut [f64]) {
        let diffsol::StateRefMut { y, dy, t, .. } = self.solver.state_mut();
        let y: &NalgebraVec<f64> = y;
        (*t, y.inner().as_slice(), dy.inner_mut().as_mut_slice())
    }

    fn set_stop_time(&mut self, t: f64) -> Result<(), Self::Error> {
        self.solver.set_stop_time(t)
    }

    fn step(&mut self) -> Result<StepOutcome, Self::Error> {
        Ok(match self.solver.step()? {
            OdeSolverStopReason::RootFound(t, index) => StepOutcome::Root(t, index),
            OdeSolverStopReason::TstopReached => StepOutcome::StopTime,
            OdeSolverStopReason::InternalTimestep => StepOutcome::Step,
        })
    }

    fn interpolate(&mut self, t: f64, y: &mut [f64]) -> Result<(), Self::Error> {
        self.solver.interpolate_inplace(t, &mut self.buffer)?;
        y.copy_from_slice(self.buffer.inner().as_slice());
        Ok(())
    }

    fn state_mut_back(&mut self, t: f64) -> Result<(), Self::Error> {
        self.solver.state_mut_back(t)
    }

    fn statistics(&self, statistics: &mut SolverStatistics) {
        let counts = self.solver.get_statistics();
        statistics.steps = counts.number_of_steps;
        statistics.rejected_steps = counts.number_of_error_test_failures;
        statistics.nonlinear_solver_failures = counts.number_of_nonlinear_solver_fails;
        statistics.nonlinear_iterations = counts.number_of_nonlinear_solver_iterations;
        statistics.factorizations = counts.number_of_linear_solver_setups;
    }
}

impl Stepper for Radau5<'_> {
    type Error = RadauError;

    fn t(&self) -> f64 {
        Radau5::t(self)
    }

    fn y(&self) -> &[f64] {
        Radau5::y(self)
    }

    fn derivative_mut(&mut self) -> (f64, &[f64], &mut [f64]) {
        Radau5::derivative_mut(self)
    }

    fn set_stop_time(&mut self, t: f64) -> Result<(), Self::Error> {
        Radau5::set_stop_time(self, t)
    }

    fn step(&mut self) -> Result<StepOutcome, Self::Error> {
        Ok(match Radau5::step(self)? {
            RadauStop::Step => StepOutcome::Step,
            RadauStop::StopTime => StepOutcome::StopTime,
            RadauStop::Root(t, index) => StepOutcome::Root(t, index),
        })
    }

    fn interpolate(&mut self, t: f64, y: &mut [f64]) -> Result<(), Self::Error> {
        Radau5::interpolate(self, t, y)
    }

    fn state_mut_back(&mut self, t: f64) -> Result<(), Self::Error> {
        self.move_back(t)
    }

    fn statistics(&self, statistics: &mut SolverStatistics) {
        let counts = Radau5::statistics(self);
        statistics.steps = counts.steps;
        statistics.rejected_steps = counts.error_test_failures;
        statistics.nonlinear_solver_failures = counts.nonlinear_failures;
        statistics.nonlinear_iterations = counts.nonlinear_iterations;
        statistics.factorizations = counts.factorizations;
    }
}
