//! One run: the state the step loop carries, the loop itself (limits, hooks, events,
//! restarts) and the setup and report around it.
//!
//! What the closures share with the loop (and the Jacobian cache) is `shared`; what the loop
//! records between step ends, `record`.

use std::cell::RefCell;
use std::time::Instant;

use diffsol::{NalgebraMat, OdeBuilder, OdeSolverProblem};
use nalgebra::DMatrix;

use crate::error::{EvaluationError, SimulationError};
use crate::force::ForceElement;
use crate::formulation::{Formulation, Integrated};
use crate::iteration::SecondOrderLu;
use crate::joint_coordinates::{JointEvaluator, Tree};
use crate::radau::{Radau5, RadauLimits, VectorFunction};
use crate::sparse_iteration::SparseSecondOrderLu;
use crate::state::State;
use crate::system::System;
use crate::system::evaluator::Evaluator;
use crate::trajectory::Trajectory;

use super::options::{Integrator, LinearSolverKind, SimulationOptions};
use super::report::{ConstraintDrift, EventRecord, Observer, SimulationResult, SolverStatistics};
use super::stepper::{Diffsol, NalgebraEquations, StepOutcome, Stepper, integrator_error};

mod record;
mod shared;

use shared::{JacobianCache, Shared};

/// Shared state of one run: what the closures read and the loop updates.
struct Run<'s, 'o, 'c> {
    system: &'s System,
    options: &'s SimulationOptions,
    elements: &'s RefCell<Vec<Box<dyn ForceElement>>>,
    jacobian_cache: &'c RefCell<JacobianCache<'s>>,
    /// Cartesian evaluator for outputs and energy quadrature.
    evaluator: Evaluator<'s>,
    /// The integrated formulation's equations, for restarts and for mapping its states to
    /// Cartesian ones (not the integrator's instance).
    equations: Box<dyn Integrated + 's>,
    /// Scratch of that mapping, length `2n`.
    mapped: Vec<f64>,
    /// Scratch: the power of each driver at a quadrature node.
    driver_power: Vec<f64>,
    /// Scratch of the elements' powers at one quadrature node.
    element_power: Vec<f64>,
    observer: &'o mut dyn Observer,
    final_state: Option<State>,
    /// Copy of the state after the last accepted step.
    current: Vec<f64>,
    output_times: Vec<f64>,
    next_output: usize,
    event_owner: Vec<(usize, usize)>,
    trajectory: Trajectory,
    drift: ConstraintDrift,
    peak_kinetic: f64,
    statistics: SolverStatistics,
    events: Vec<EventRecord>,
    /// Work of non-conservative elements and drivers, integrated step by step.
    element_work: Vec<f64>,
    driver_work: Vec<f64>,
    scratch: Vec<f64>,
    /// An interpolated state, as a plain slice.
    frame_buffer: Vec<f64>,
    /// The first evaluation failure since the last accepted step.
    singular: &'c RefCell<Option<(f64, EvaluationError)>>,
}

impl<'s, 'o, 'c> Run<'s, 'o, 'c> {
    /// The loop's state before the first step, with `equations` (the integrated formulation's,
    /// for restarts and mapping to Cartesian coordinates) at the initial state `x0`.
    fn new(
        system: &'s System,
        options: &'s SimulationOptions,
        shared: &'c Shared<'s>,
        mut equations: Box<dyn Integrated + 's>,
        initial: (f64, &[f64]),
        observer: &'o mut dyn Observer,
        output_times: Vec<f64>,
    ) -> Self {
        let n = system.coordinate_count();
        let (t0, x0) = initial;
        let mut mapped = vec![0.0; 2 * n];
        let y0 = equations.cartesian(t0, x0, &mut mapped).to_vec();
        let elements = shared.elements;
        let element_count = elements.borrow().len();
        let driver_count = system.driver_names().len();
        // Root `i` of diffsol's concatenated root function is event `local` of `element`.
        let event_owner = elements
            .borrow()
            .iter()
            .enumerate()
            .flat_map(|(e, element)| (0..element.event_count()).map(move |i| (e, i)))
            .collect();
        Self {
            system,
            options,
            elements,
            jacobian_cache: &shared.jacobian,
            evaluator: system.evaluator(options.baumgarte),
            equations,
            mapped,
            driver_power: vec![0.0; driver_count],
            element_power: vec![0.0; element_count],
            observer,
            final_state: None,
            current: y0,
            output_times,
            next_output: 0,
            event_owner,
            trajectory: Trajectory {
                coordinates: n,
                constraints: system.constraint_count(),
                ..Trajectory::default()
            },
            drift: ConstraintDrift::default(),
            peak_kinetic: 0.0,
            statistics: SolverStatistics {
                smallest_step: f64::INFINITY,
                ..SolverStatistics::default()
            },
            events: Vec::new(),
            element_work: vec![0.0; element_count],
            driver_work: vec![0.0; driver_count],
            scratch: vec![0.0; n],
            frame_buffer: vec![0.0; 2 * n],
            singular: &shared.singular,
        }
    }
}

impl System {
    /// Integrates the equations of motion from the assembled `initial` state to
    /// `options.t_end`. The force elements are lent to the integrator and are back in the
    /// system afterwards (also on error), with whatever their hooks accumulated.
    pub fn simulate(
        &mut self,
        initial: &State,
        options: &SimulationOptions,
        observer: &mut dyn Observer,
    ) -> Result<SimulationResult, SimulationError> {
        let n = self.coordinate_count();
        if initial.q.len() != n || initial.qd.len() != n {
            return Err(crate::error::AssemblyError::WrongLength {
                expected: n,
                actual: initial.q.len().min(initial.qd.len()),
            }
            .into());
        }
        let elements = RefCell::new(std::mem::take(&mut self.elements));
        let result = self.run(initial, options, observer, &elements);
        self.elements = elements.into_inner();
        result
    }

    /// A run in named steps: the formulation's equations and what the closures share, the
    /// loop's state, the frames at the start, the integration, the report.
    fn run(
        &self,
        initial: &State,
        options: &SimulationOptions,
        observer: &mut dyn Observer,
        elements: &RefCell<Vec<Box<dyn ForceElement>>>,
    ) -> Result<SimulationResult, SimulationError> {
        let started = Instant::now();
        let output_times = options.output_times(initial.t)?;
        let tree = (options.formulation == Formulation::JointCoordinates)
            .then(|| Tree::new(self.bodies().len(), self.joints(), self.constraints()));
        let equations = || -> Box<dyn Integrated + '_> {
            match &tree {
                None => Box::new(self.evaluator(options.baumgarte)),
                Some(tree) => Box::new(JointEvaluator::new(self, tree, options.baumgarte)),
            }
        };
        let mut restart = equations();
        let size = restart.size();
        let x0 = restart.initial_state(initial);
        let atol = restart.tolerances(&options.atol);
        let n = self.coordinate_count();
        let shared = Shared::new(elements, equations, options.jacobian, size, n);
        let start = (initial.t, x0.as_slice());
        let mut run = Run::new(
            self,
            options,
            &shared,
            restart,
            start,
            observer,
            output_times,
        );
        let initial_potential = run.record_start(initial)?;
        run.integrate(&shared, start, &atol)?;
        let mut result = run.report(initial, &initial_potential);
        shared.count(&mut result.statistics);
        result.statistics.wall_time = started.elapsed();
        Ok(result)
    }
}

fn configure<Eqn>(
    mut problem: OdeSolverProblem<Eqn>,
    options: &SimulationOptions,
) -> OdeSolverProblem<Eqn>
where
    Eqn: diffsol::OdeEquations<T = f64>,
{
    problem.ode_options.max_nonlinear_solver_failures = options.max_nonlinear_solver_failures;
    problem.ode_options.max_error_test_failures = options.max_error_test_failures;
    problem.ode_options.min_timestep = options.min_step;
    problem
}

impl Run<'_, '_, '_> {
    /// The output frames due at the start, and the start's drift; returns the elements'
    /// potential energies there, for the energy audit.
    fn record_start(&mut self, initial: &State) -> Result<Vec<Option<f64>>, SimulationError> {
        let y0 = self.current.clone();
        let initial_potential = self.potentials(initial.t, &initial.q);
        while self.next_output < self.output_times.len()
            && self.output_times[self.next_output] <= initial.t
        {
            self.emit_frame(initial.t, &y0)?;
        }
        self.track_drift(initial.t, &y0);
        Ok(initial_potential)
    }

    /// Integrates from `start = (t0, x0)` with the selected integrator, whose closures
    /// evaluate through `shared`.
    fn integrate(
        &mut self,
        shared: &Shared<'_>,
        start: (f64, &[f64]),
        atol: &[f64],
    ) -> Result<(), SimulationError> {
        let (t0, x0) = start;
        let options = self.options;
        let event_count = self.event_owner.len();
        let rhs = |y: &[f64], _p: &[f64], t: f64, dy: &mut [f64]| shared.rhs(y, t, dy);
        let roots = |x: &[f64], _p: &[f64], t: f64, g: &mut [f64]| shared.event_functions(x, t, g);
        if options.integrator == Integrator::Radau5 {
            let jacobian = |y: &[f64], t: f64, out: &mut DMatrix<f64>| shared.jacobian(y, t, out);
            let limits = RadauLimits {
                min_step: options.min_step,
                max_error_test_failures: options.max_error_test_failures,
                max_nonlinear_failures: options.max_nonlinear_solver_failures,
            };
            let roots = (event_count > 0).then_some((&roots as VectorFunction, event_count));
            let stepper = Radau5::new(&rhs, &jacobian, roots, t0, x0, options.rtol, atol, limits);
            return self.step_loop(stepper);
        }
        let jacobian_vector = |y: &[f64], _p: &[f64], t: f64, v: &[f64], jv: &mut [f64]| {
            shared.jacobian_vector(y, t, v, jv);
        };
        let init = |_p: &[f64], _t: f64, x: &mut [f64]| x.copy_from_slice(x0);
        let builder = OdeBuilder::<NalgebraMat<f64>>::new()
            .t0(t0)
            .rtol(options.rtol)
            .atol(atol.to_vec())
            .rhs_implicit(&rhs, &jacobian_vector)
            .init(&init, x0.len());
        if event_count == 0 {
            self.integrate_problem(t0, builder.build())
        } else {
            self.integrate_problem(t0, builder.root(&roots, event_count).build())
        }
    }

    /// Steps a diffsol problem built at `t0` (its limits set from the options) with the
    /// selected method and linear solver.
    fn integrate_problem<Eqn>(
        &mut self,
        t0: f64,
        problem: Result<OdeSolverProblem<Eqn>, diffsol::DiffsolError>,
    ) -> Result<(), SimulationError>
    where
        Eqn: NalgebraEquations,
    {
        let problem = problem.map_err(|e| integrator_error(t0, e))?;
        let problem = configure(problem, self.options);
        match self.options.linear_solver {
            LinearSolverKind::Dense => self.solve::<Eqn, SecondOrderLu>(&problem),
            LinearSolverKind::SparseFaer => self.solve::<Eqn, SparseSecondOrderLu>(&problem),
        }
    }

    /// Steps `problem` with the selected diffsol method, its Newton iterations on `LS`.
    fn solve<Eqn, LS>(&mut self, problem: &OdeSolverProblem<Eqn>) -> Result<(), SimulationError>
    where
        Eqn: NalgebraEquations,
        LS: diffsol_la::LinearSolver<NalgebraMat<f64>>,
    {
        let error = |e| integrator_error(problem.t0, e);
        match self.options.integrator {
            Integrator::Bdf => self.step_loop(Diffsol::new(problem.bdf::<LS>().map_err(error)?)),
            Integrator::TrBdf2 => {
                self.step_loop(Diffsol::new(problem.tr_bdf2::<LS>().map_err(error)?))
            }
            Integrator::Esdirk34 => {
                self.step_loop(Diffsol::new(problem.esdirk34::<LS>().map_err(error)?))
            }
            Integrator::Tsit45 => self.step_loop(Diffsol::new(problem.tsit45().map_err(error)?)),
            // `integrate` steps Radau IIA itself: it needs no diffsol problem.
            Integrator::Radau5 => Err(SimulationError::InvalidOptions(
                "Radau IIA is not a diffsol method".into(),
            )),
        }
    }

    /// Everything the run reports but the evaluation counters and the wall time.
    fn report(&mut self, initial: &State, initial_potential: &[Option<f64>]) -> SimulationResult {
        let final_state = self.final_state.take().unwrap_or_else(|| initial.clone());
        let energy = self
            .options
            .energy_audit
            .then(|| self.energy_audit(initial, &final_state, initial_potential));
        let events = std::mem::take(&mut self.events);
        let mut statistics = self.statistics.clone();
        statistics.events = events.len();
        SimulationResult {
            final_state,
            trajectory: std::mem::take(&mut self.trajectory),
            statistics,
            drift: self.drift,
            energy,
            events,
        }
    }

    /// The end of the run, or one maximal step ahead (never leaving a sliver before the end).
    fn next_stop(&self, t: f64) -> f64 {
        let t_end = self.options.t_end;
        match self.options.max_step {
            Some(h) if t + 1.001 * h < t_end => t + h,
            _ => t_end,
        }
    }

    fn failure(&self, t: f64, error: impl std::fmt::Display) -> SimulationError {
        match self.singular.borrow_mut().take() {
            Some((t, error)) => SimulationError::Evaluation { t, error },
            None => integrator_error(t, error),
        }
    }

    fn step_loop<S: Stepper>(&mut self, mut solver: S) -> Result<(), SimulationError> {
        let t_end = self.options.t_end;
        let n = self.system.coordinate_count();
        let mut t_previous = solver.t();
        let mut interpolated = solver.y().to_vec();
        let mut accepted = 0_usize;
        let started = Instant::now();
        let outcome = loop {
            if let Some(limit) = self.options.max_steps
                && accepted >= limit
            {
                break Err(SimulationError::StepLimit {
                    t: t_previous,
                    steps: accepted,
                });
            }
            if let Some(limit) = self.options.max_wall_time
                && started.elapsed() >= limit
            {
                break Err(SimulationError::WallTimeLimit {
                    t: t_previous,
                    steps: accepted,
                    seconds: limit.as_secs_f64(),
                });
            }
            if let Err(e) = solver.set_stop_time(self.next_stop(t_previous)) {
                break Err(integrator_error(t_previous, e));
            }
            let reason = match solver.step() {
                Ok(reason) => reason,
                Err(e) => break Err(self.failure(solver.t(), e)),
            };
            // A singular matrix met in a rejected trial step is not a failure.
            self.singular.borrow_mut().take();
            let (t_now, root) = match reason {
                StepOutcome::Root(t_root, index) => (t_root, Some(index)),
                _ => (solver.t(), None),
            };
            if let Err(e) = self.process_interval(&mut solver, t_previous, t_now, &mut interpolated)
            {
                break Err(e);
            }
            if root.is_some()
                && let Err(e) = solver.state_mut_back(t_now)
            {
                break Err(integrator_error(t_now, e));
            }
            let y = self
                .equations
                .cartesian(t_now, solver.y(), &mut self.mapped);
            self.current.copy_from_slice(y);
            let step = t_now - t_previous;
            if step > 0.0 {
                self.statistics.smallest_step = self.statistics.smallest_step.min(step);
                self.statistics.largest_step = self.statistics.largest_step.max(step);
            }
            {
                let (q, qd) = self.current.split_at(n);
                for element in self.elements.borrow_mut().iter_mut() {
                    element.on_accepted_step(t_previous, t_now, q, qd);
                }
            }
            let current = std::mem::take(&mut self.current);
            self.track_drift(t_now, &current);
            self.current = current;
            if let Some(index) = root {
                self.handle_event(&mut solver, t_now, index);
            }
            self.jacobian_cache.borrow_mut().valid = false;
            self.observer.progress(t_now, t_end);
            t_previous = t_now;
            accepted += 1;
            let at_end = t_now >= t_end - 1e-12 * t_end.abs().max(1.0);
            if matches!(reason, StepOutcome::StopTime) && at_end {
                break Ok(());
            }
        };
        solver.statistics(&mut self.statistics);
        let (q, qd) = self.current.split_at(n);
        self.final_state = Some(State {
            t: t_previous,
            q: q.to_vec(),
            qd: qd.to_vec(),
        });
        outcome
    }

    /// Lets the element owning root `index` react, then restarts the integrator from the
    /// (unchanged) state with a freshly evaluated derivative, since the force law may change.
    fn handle_event<S: Stepper>(&mut self, solver: &mut S, t: f64, index: usize) {
        let n = self.system.coordinate_count();
        let Some(&(element, local)) = self.event_owner.get(index) else {
            return;
        };
        {
            let (q, qd) = self.current.split_at(n);
            if let Some(e) = self.elements.borrow_mut().get_mut(element) {
                e.on_event(local, t, q, qd);
            }
        }
        self.events.push(EventRecord {
            t,
            element,
            index: local,
        });
        let (_, y, dy) = solver.derivative_mut();
        let elements = self.elements.borrow();
        // A singular system shows up as NaN here and fails the next step with a clear error.
        if let Err(error) = self.equations.rhs(&elements, t, y, dy) {
            self.singular.borrow_mut().get_or_insert((t, error));
        }
    }
}
