//! Forward dynamics on diffsol: options, the stepping loop (output by interpolation, hooks,
//! events, energy audit) and the run report.
//!
//! Jacobian strategy: diffsol's closure interface asks for Jacobian–vector products and
//! assembles the dense Jacobian from `2n` of them at one `(t, y)`. The jac-vec closure
//! therefore keeps the dense exact Jacobian of the last `(t, y)` it saw (interior mutability)
//! and answers each product from it: one Cholesky factorization of the Schur complement
//! `Φ_q M⁻¹ Φ_qᵀ` and `2n` triangular solves per Jacobian instead of `2n` right-hand sides, each
//! with its own factorization. Figures in docs/performance.md.

use std::cell::RefCell;
use std::time::{Duration, Instant};

use diffsol::{
    NalgebraContext, NalgebraMat, NalgebraVec, OdeBuilder, OdeEquationsImplicit, OdeSolverMethod,
    OdeSolverProblem, OdeSolverStopReason, Vector, VectorCommon,
};
use nalgebra::DMatrix;

use crate::constraints::ConstraintOwner;
use crate::error::{EvaluationError, SimulationError};
use crate::force::ForceElement;
use crate::formulation::{Equations, Formulation};
use crate::iteration::SecondOrderLu;
use crate::joint_coordinates::{JointEvaluator, Tree};
use crate::radau::{Radau5, RadauError, RadauLimits, RadauStop, VectorFunction};
use crate::sparse_iteration::SparseSecondOrderLu;
use crate::state::{AbsoluteTolerances, State};
use crate::system::{Baumgarte, Evaluator, System};
use crate::trajectory::Trajectory;

/// Time integrator (diffsol's, and Radau IIA of this crate); named in kebab case in scene
/// files (`tr-bdf2`, `radau`).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default, serde::Serialize, serde::Deserialize)]
#[serde(rename_all = "kebab-case")]
pub enum Integrator {
    /// Variable-order BDF (orders 1–5), the stiff default (the paper's `ode15s` is similar).
    #[default]
    Bdf,
    /// TR-BDF2, an L-stable SDIRK method of order 2.
    TrBdf2,
    /// ESDIRK3(4), an L-stable SDIRK method of order 3.
    Esdirk34,
    /// Tsitouras 5(4), explicit: cheapest per step, for non-stiff runs.
    Tsit45,
    /// Three-stage Radau IIA, an L-stable collocation method of order 5 (Hairer & Wanner's
    /// RADAU5; `crate::radau`). Dense linear algebra whatever the [`LinearSolverKind`].
    #[serde(rename = "radau")]
    Radau5,
}

/// How the implicit integrators get `∂f/∂y`.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub enum JacobianMethod {
    /// Exact, from the differentiated augmented system (default).
    #[default]
    Exact,
    /// Forward differences of the right-hand side: the reference for measuring the savings.
    FiniteDifference,
}

/// Which linear solver the implicit integrators' Newton iterations use. Both eliminate the
/// `q` block of the iteration matrix and factor the `n × n` remainder.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub enum LinearSolverKind {
    /// [`SecondOrderLu`]: dense LU (default; fastest for small mechanisms).
    #[default]
    Dense,
    /// [`crate::SparseSecondOrderLu`]: faer's sparse LU with its symbolic analysis reused, for
    /// long mechanisms cut into loosely coupled parts (docs/performance.md, scaling).
    SparseFaer,
}

/// When to report the state.
#[derive(Debug, Clone, PartialEq)]
pub enum OutputTimes {
    /// Every `dt` from the start time to the end time, both included.
    Every(f64),
    /// At these times (sorted, within the run).
    At(Vec<f64>),
}

impl OutputTimes {
    /// The times of [`OutputTimes::Every`]: `t0, t0 + dt, …` up to `t_end` (included when it
    /// falls on the grid up to round-off). Callers check `dt > 0` and the span first.
    pub fn uniform(t0: f64, t_end: f64, dt: f64) -> Vec<f64> {
        let count = ((t_end - t0) / dt * (1.0 + 1e-12)).floor() as usize;
        (0..=count)
            .map(|i| (t0 + i as f64 * dt).min(t_end))
            .collect()
    }
}

/// Options of a dynamic simulation: start from [`SimulationOptions::until`] and change what
/// differs, by field or with the `with_*` methods (new options can be added without breaking
/// callers, so the struct cannot be written as a literal outside this crate).
#[derive(Debug, Clone, PartialEq)]
#[non_exhaustive]
pub struct SimulationOptions {
    /// End time (s); the run starts at the assembled state's time. No default.
    pub t_end: f64,
    /// Time integrator, default [`Integrator::Bdf`].
    pub integrator: Integrator,
    /// Relative tolerance of the local error test, default 1e-6.
    pub rtol: f64,
    /// Absolute tolerances per kind of variable, default [`AbsoluteTolerances::default`]
    /// (1e-8 m, 1e-8 rad, 1e-6 m/s, 1e-6 rad/s).
    pub atol: AbsoluteTolerances,
    /// Constraint stabilisation, default α = β = 50 1/s ([`Baumgarte::default`]).
    pub baumgarte: Baumgarte,
    /// When frames are reported to the [`Observer`] and recorded, default every 1e-4 s.
    pub output: OutputTimes,
    /// How the implicit integrators get `∂f/∂y`, default [`JacobianMethod::Exact`].
    pub jacobian: JacobianMethod,
    /// Keep every output frame in [`SimulationResult::trajectory`]. Default true. A frame
    /// holds `4n + m` numbers: 100 s of the 15-coordinate LGRES at 1e-4 s is ~0.5 GB, so long
    /// runs should turn this off and record selectively with an [`Observer`].
    pub record_trajectory: bool,
    /// Integrate the work of drivers and non-conservative elements into
    /// [`SimulationResult::energy`]. Default true.
    pub energy_audit: bool,
    /// diffsol's limit on Newton failures, counted over the whole run (not per step). Default
    /// no cap (`usize::MAX`): any fixed cap ends a long contact-rich run at an arbitrary time,
    /// and a run that cannot make progress still stops, on `min_step`.
    pub max_nonlinear_solver_failures: usize,
    /// diffsol's limit on consecutive error-test failures, default 40.
    pub max_error_test_failures: usize,
    /// Smallest step diffsol may take before giving up, default 1e-14 s.
    pub min_step: f64,
    /// Largest step (s), default none. diffsol has no such option; it is enforced with moving
    /// stop times (the step is shortened, the method keeps its order). Events are found from
    /// sign changes between step ends, so an element whose event could begin and end within
    /// one step (a brief impact) needs a bound here.
    pub max_step: Option<f64>,
    /// Largest number of accepted steps before the run stops with
    /// [`SimulationError::StepLimit`], default none. A deterministic budget for sweeps that
    /// may meet an integrator unsuited to the problem (an explicit method on stiff contact).
    pub max_steps: Option<usize>,
    /// Wall-time budget: the run stops with [`SimulationError::WallTimeLimit`] before the first
    /// step that would start past it, default none. Where it stops depends on the machine, so
    /// it guards against runs that cannot finish; `max_steps` is the deterministic budget.
    pub max_wall_time: Option<Duration>,
    /// Coordinates to integrate in, default [`Formulation::Cartesian`].
    pub formulation: Formulation,
    /// Linear solver of the Newton iterations, default [`LinearSolverKind::Dense`].
    pub linear_solver: LinearSolverKind,
}

impl SimulationOptions {
    /// Defaults (BDF, rtol 1e-6, output every 1e-4 s) for a run ending at `t_end` (s).
    pub fn until(t_end: f64) -> Self {
        Self {
            t_end,
            integrator: Integrator::default(),
            rtol: 1e-6,
            atol: AbsoluteTolerances::default(),
            baumgarte: Baumgarte::default(),
            output: OutputTimes::Every(1e-4),
            jacobian: JacobianMethod::default(),
            record_trajectory: true,
            energy_audit: true,
            max_nonlinear_solver_failures: usize::MAX,
            max_error_test_failures: 40,
            min_step: 1e-14,
            max_step: None,
            max_steps: None,
            max_wall_time: None,
            formulation: Formulation::default(),
            linear_solver: LinearSolverKind::default(),
        }
    }

    /// The same options with `integrator`.
    pub fn with_integrator(mut self, integrator: Integrator) -> Self {
        self.integrator = integrator;
        self
    }

    /// The same options with relative tolerance `rtol`.
    pub fn with_rtol(mut self, rtol: f64) -> Self {
        self.rtol = rtol;
        self
    }

    /// The same options with absolute tolerances `atol`.
    pub fn with_atol(mut self, atol: AbsoluteTolerances) -> Self {
        self.atol = atol;
        self
    }

    /// The same options with Baumgarte stabilisation `baumgarte`.
    pub fn with_baumgarte(mut self, baumgarte: Baumgarte) -> Self {
        self.baumgarte = baumgarte;
        self
    }

    /// The same options with output at `output`.
    pub fn with_output(mut self, output: OutputTimes) -> Self {
        self.output = output;
        self
    }

    /// The same options with Jacobian method `jacobian`.
    pub fn with_jacobian(mut self, jacobian: JacobianMethod) -> Self {
        self.jacobian = jacobian;
        self
    }

    /// The same options keeping (or not) every frame in the result.
    pub fn with_record_trajectory(mut self, record: bool) -> Self {
        self.record_trajectory = record;
        self
    }

    /// The same options with (or without) the energy audit.
    pub fn with_energy_audit(mut self, audit: bool) -> Self {
        self.energy_audit = audit;
        self
    }

    /// The same options with steps no longer than `max_step` (s).
    pub fn with_max_step(mut self, max_step: f64) -> Self {
        self.max_step = Some(max_step);
        self
    }

    /// The same options stopping after `max_steps` accepted steps.
    pub fn with_max_steps(mut self, max_steps: usize) -> Self {
        self.max_steps = Some(max_steps);
        self
    }

    /// The same options stopping once `max_wall_time` of wall time has passed.
    pub fn with_max_wall_time(mut self, max_wall_time: Duration) -> Self {
        self.max_wall_time = Some(max_wall_time);
        self
    }

    fn output_times(&self, t0: f64) -> Result<Vec<f64>, SimulationError> {
        let invalid = |m: String| Err(SimulationError::InvalidOptions(m));
        if !self.t_end.is_finite() || self.t_end <= t0 {
            return invalid(format!(
                "end time {} must be finite and after the start {t0}",
                self.t_end
            ));
        }
        let positive = [
            ("rtol", self.rtol),
            ("position atol", self.atol.position),
            ("angle atol", self.atol.angle),
            ("velocity atol", self.atol.velocity),
            ("angular velocity atol", self.atol.angular_velocity),
            ("min_step", self.min_step),
            ("max_step", self.max_step.unwrap_or(1.0)),
        ];
        if let Some((name, value)) = positive.iter().find(|(_, v)| !(v.is_finite() && *v > 0.0)) {
            return invalid(format!("{name} must be positive and finite, got {value}"));
        }
        match &self.output {
            OutputTimes::Every(dt) => {
                if !(dt.is_finite() && *dt > 0.0) {
                    return invalid(format!("output interval must be positive, got {dt}"));
                }
                Ok(OutputTimes::uniform(t0, self.t_end, *dt))
            }
            OutputTimes::At(times) => {
                let sorted = times.windows(2).all(|w| w[0] <= w[1]);
                let inside = times.iter().all(|t| *t >= t0 && *t <= self.t_end);
                if !sorted || !inside {
                    return invalid("output times must be sorted and within the run".into());
                }
                Ok(times.clone())
            }
        }
    }
}

/// One output time, handed to the [`Observer`].
pub struct Frame<'a> {
    /// Time (s).
    pub t: f64,
    /// Coordinates (m, rad).
    pub q: &'a [f64],
    /// Velocities (m/s, rad/s).
    pub qd: &'a [f64],
    /// Accelerations (m/s², rad/s²).
    pub qdd: &'a [f64],
    /// Lagrange multipliers in the order of [`System::constraint_labels`].
    pub lambda: &'a [f64],
    /// The force elements, for custom outputs (e.g. a contact force).
    pub elements: &'a [Box<dyn ForceElement>],
}

impl Frame<'_> {
    /// Element `id` as its concrete type, e.g. to record a contact force at this frame.
    pub fn element<T: ForceElement>(&self, id: crate::force::ElementId) -> Option<&T> {
        crate::force::downcast(self.elements.get(id.0)?.as_ref())
    }
}

/// Receives every output frame and progress reports during a run. Both methods default to
/// doing nothing; `()` is the observer that ignores everything.
pub trait Observer {
    /// Called at every output time, in order; the frame is interpolated, not a step end.
    fn output(&mut self, _frame: &Frame<'_>) {}
    /// Called after every accepted step with its end time and the run's end time (s).
    fn progress(&mut self, _t: f64, _t_end: f64) {}
}

impl Observer for () {}

/// Integrator statistics of one run.
#[derive(Debug, Clone, Default, PartialEq)]
pub struct SolverStatistics {
    /// Accepted steps.
    pub steps: usize,
    /// Steps rejected by the local error test.
    pub rejected_steps: usize,
    /// Newton iterations that failed to converge (the step is then retried smaller).
    pub nonlinear_solver_failures: usize,
    /// Newton iterations over all steps.
    pub nonlinear_iterations: usize,
    /// Right-hand-side evaluations made by the integrator (including those of
    /// finite-difference Jacobians).
    pub rhs_evaluations: usize,
    /// Dense Jacobians computed (exact or by finite differences).
    pub jacobian_evaluations: usize,
    /// Jacobian-vector products requested by diffsol (answered from the cached Jacobian).
    pub jacobian_vector_products: usize,
    /// Factorizations of the iteration matrix (diffsol's linear-solver setups).
    pub factorizations: usize,
    /// Shortest accepted step (s).
    pub smallest_step: f64,
    /// Longest accepted step (s).
    pub largest_step: f64,
    /// Events located ([`SimulationResult::events`]).
    pub events: usize,
    /// Wall time of the run (machine-dependent).
    pub wall_time: Duration,
}

/// Largest constraint violation seen at output times and accepted steps.
#[derive(Debug, Clone, Copy, Default, PartialEq)]
pub struct ConstraintDrift {
    /// max |Φ| (m or rad)
    pub position: f64,
    /// max |Φ̇| (m/s or rad/s)
    pub velocity: f64,
}

/// Energy balance `ΔT = Σ W_elements + Σ W_drivers + residual`; ideal joints do no work, so
/// the residual measures integration error and constraint drift.
#[derive(Debug, Clone, Default, PartialEq)]
pub struct EnergyAudit {
    /// Kinetic energy at the start (J).
    pub initial_kinetic: f64,
    /// Kinetic energy at the end (J).
    pub final_kinetic: f64,
    /// Largest kinetic energy seen at output times and step ends.
    pub peak_kinetic: f64,
    /// Work of each force element (conservative ones as `−ΔV`), by name.
    pub element_work: Vec<(String, f64)>,
    /// Potential energy of conservative elements at start and end, by name.
    pub potential: Vec<(String, f64, f64)>,
    /// Work of each driver, from its multiplier: `∫ λ_d Φ_t,d dt`, by name.
    pub driver_work: Vec<(String, f64)>,
    /// `ΔT − Σ W` (J): zero for an exact solution.
    pub residual: f64,
}

impl EnergyAudit {
    /// Residual relative to the largest energy term, for tolerances.
    pub fn relative_residual(&self) -> f64 {
        let scale = self
            .element_work
            .iter()
            .chain(&self.driver_work)
            .map(|(_, w)| w.abs())
            .chain([self.initial_kinetic.abs(), self.final_kinetic.abs()])
            .chain(
                self.potential
                    .iter()
                    .flat_map(|(_, a, b)| [a.abs(), b.abs()]),
            )
            .fold(f64::MIN_POSITIVE, f64::max);
        self.residual.abs() / scale
    }
}

/// An event located during the run.
#[derive(Debug, Clone, PartialEq)]
pub struct EventRecord {
    /// Time of the root (s).
    pub t: f64,
    /// Index of the element whose event it was (as in [`crate::ElementId`]).
    pub element: usize,
    /// Which of that element's event functions changed sign.
    pub index: usize,
}

/// Everything a run reports. The force elements stay in the [`System`].
#[derive(Debug, Clone, PartialEq)]
pub struct SimulationResult {
    /// State at the end time, to continue from.
    pub final_state: State,
    /// The output frames; empty unless [`SimulationOptions::record_trajectory`].
    pub trajectory: Trajectory,
    /// Integrator counters and timings.
    pub statistics: SolverStatistics,
    /// Largest constraint violation seen.
    pub drift: ConstraintDrift,
    /// Energy balance; `None` unless [`SimulationOptions::energy_audit`].
    pub energy: Option<EnergyAudit>,
    /// Events in the order they were located.
    pub events: Vec<EventRecord>,
}

/// The dense Jacobian of the last `(t, y)` diffsol asked about.
struct JacobianCache<'s> {
    evaluator: Box<dyn Equations + 's>,
    method: JacobianMethod,
    t: f64,
    y: Vec<f64>,
    valid: bool,
    matrix: DMatrix<f64>,
    products: usize,
}

impl JacobianCache<'_> {
    /// Makes `matrix` the Jacobian at `(t, y)` unless it already is; a failed evaluation
    /// leaves NaNs (the step fails) and is recorded in `singular`.
    fn update(
        &mut self,
        elements: &[Box<dyn ForceElement>],
        t: f64,
        y: &[f64],
        singular: &RefCell<Option<(f64, EvaluationError)>>,
    ) {
        if self.valid && self.t == t && self.y == y {
            return;
        }
        let result = match self.method {
            JacobianMethod::Exact => self.evaluator.jacobian(elements, t, y, &mut self.matrix),
            JacobianMethod::FiniteDifference => {
                self.evaluator
                    .finite_difference_jacobian(elements, t, y, &mut self.matrix)
            }
        };
        if let Err(error) = result {
            self.matrix.fill(f64::NAN);
            singular.borrow_mut().get_or_insert((t, error));
        }
        self.t = t;
        self.y.copy_from_slice(y);
        self.valid = true;
    }
}

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
    equations: Box<dyn Equations + 's>,
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
    singular: &'s RefCell<Option<(f64, EvaluationError)>>,
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

    fn run(
        &self,
        initial: &State,
        options: &SimulationOptions,
        observer: &mut dyn Observer,
        elements: &RefCell<Vec<Box<dyn ForceElement>>>,
    ) -> Result<SimulationResult, SimulationError> {
        let started = Instant::now();
        let output_times = options.output_times(initial.t)?;
        let n = self.coordinate_count();
        let m = self.constraint_count();
        let event_owner: Vec<(usize, usize)> = elements
            .borrow()
            .iter()
            .enumerate()
            .flat_map(|(e, element)| (0..element.event_count()).map(move |i| (e, i)))
            .collect();
        let tree = (options.formulation == Formulation::JointCoordinates)
            .then(|| Tree::new(self.bodies().len(), self.joints(), self.constraints()));
        let equations = || -> Box<dyn Equations + '_> {
            match &tree {
                None => Box::new(self.evaluator(options.baumgarte)),
                Some(tree) => Box::new(JointEvaluator::new(self, tree, options.baumgarte)),
            }
        };
        let mut restart = equations();
        let size = restart.size();
        let x0 = restart.initial_state(initial);
        let atol = restart.tolerances(&options.atol);
        let mut mapped = vec![0.0; 2 * n];
        let y0: Vec<f64> = restart.cartesian(initial.t, &x0, &mut mapped).to_vec();

        let singular = RefCell::new(None);
        let rhs_evaluator = RefCell::new(equations());
        let cache = RefCell::new(JacobianCache {
            evaluator: equations(),
            method: options.jacobian,
            t: f64::NAN,
            y: vec![0.0; size],
            valid: false,
            matrix: DMatrix::zeros(size, size),
            products: 0,
        });
        let rhs = |y: &[f64], _p: &[f64], t: f64, dy: &mut [f64]| {
            let elements = elements.borrow();
            if let Err(error) = rhs_evaluator.borrow_mut().rhs(&elements, t, y, dy) {
                singular.borrow_mut().get_or_insert((t, error));
            }
        };
        let jacobian_vector = |y: &[f64], _p: &[f64], t: f64, v: &[f64], jv: &mut [f64]| {
            let mut cache = cache.borrow_mut();
            let cache = &mut *cache;
            cache.products += 1;
            cache.update(&elements.borrow(), t, y, &singular);
            // diffsol assembles its matrix from products with unit vectors: those are columns
            // (the same numbers as the sum below, whose other terms are zeros), copied in O(n)
            // instead of the O(n²) strided sum, which made assembly O(n³) (docs/performance.md).
            let mut nonzeros = v.iter().enumerate().filter(|(_, x)| **x != 0.0);
            match (nonzeros.next(), nonzeros.next()) {
                (Some((c, 1.0)), None) => jv.copy_from_slice(cache.matrix.column(c).as_slice()),
                _ => {
                    for (r, out) in jv.iter_mut().enumerate() {
                        *out = (0..v.len()).map(|c| cache.matrix[(r, c)] * v[c]).sum();
                    }
                }
            }
        };
        let init = |_p: &[f64], _t: f64, x: &mut [f64]| x.copy_from_slice(&x0);
        let builder = OdeBuilder::<NalgebraMat<f64>>::new()
            .t0(initial.t)
            .rtol(options.rtol)
            .atol(atol.clone())
            .rhs_implicit(&rhs, &jacobian_vector)
            .init(&init, size);

        let mut run = Run {
            system: self,
            options,
            elements,
            jacobian_cache: &cache,
            evaluator: self.evaluator(options.baumgarte),
            equations: restart,
            mapped,
            driver_power: vec![0.0; self.driver_names().len()],
            element_power: vec![0.0; elements.borrow().len()],
            observer,
            final_state: None,
            current: y0.clone(),
            output_times,
            next_output: 0,
            event_owner,
            trajectory: Trajectory {
                coordinates: n,
                constraints: m,
                ..Trajectory::default()
            },
            drift: ConstraintDrift::default(),
            peak_kinetic: 0.0,
            statistics: SolverStatistics {
                smallest_step: f64::INFINITY,
                ..SolverStatistics::default()
            },
            events: Vec::new(),
            element_work: vec![0.0; elements.borrow().len()],
            driver_work: vec![0.0; self.driver_names().len()],
            scratch: vec![0.0; n],
            frame_buffer: vec![0.0; 2 * n],
            singular: &singular,
        };
        let initial_potential = run.potentials(initial.t, &initial.q);
        while run.next_output < run.output_times.len()
            && run.output_times[run.next_output] <= initial.t
        {
            run.emit_frame(initial.t, &y0)?;
        }
        run.track_drift(initial.t, &y0);

        let event_count = run.event_owner.len();
        let root_map = RefCell::new((equations(), vec![0.0; 2 * n]));
        let roots = |x: &[f64], _p: &[f64], t: f64, g: &mut [f64]| {
            let mut map = root_map.borrow_mut();
            let (map, scratch) = &mut *map;
            let (q, qd) = map.cartesian(t, x, scratch).split_at(n);
            let mut offset = 0;
            for element in elements.borrow().iter() {
                let count = element.event_count();
                element.event_functions(t, q, qd, &mut g[offset..offset + count]);
                offset += count;
            }
        };
        if options.integrator == Integrator::Radau5 {
            let jacobian = |y: &[f64], t: f64, out: &mut DMatrix<f64>| {
                let mut cache = cache.borrow_mut();
                cache.update(&elements.borrow(), t, y, &singular);
                out.copy_from(&cache.matrix);
            };
            let limits = RadauLimits {
                min_step: options.min_step,
                max_error_test_failures: options.max_error_test_failures,
                max_nonlinear_failures: options.max_nonlinear_solver_failures,
            };
            let roots = (event_count > 0).then_some((&roots as VectorFunction, event_count));
            let stepper = Radau5::new(
                &rhs,
                &jacobian,
                roots,
                initial.t,
                &x0,
                options.rtol,
                &atol,
                limits,
            );
            run.step_loop(stepper)?;
        } else if event_count == 0 {
            let problem = builder
                .build()
                .map_err(|e| integrator_error(initial.t, e))?;
            let problem = configure(problem, options);
            run.integrate(&problem)?;
        } else {
            let problem = builder
                .root(&roots, event_count)
                .build()
                .map_err(|e| integrator_error(initial.t, e))?;
            let problem = configure(problem, options);
            run.integrate(&problem)?;
        }

        let mut statistics = run.statistics.clone();
        let events = std::mem::take(&mut run.events);
        let final_state = run.final_state.take().unwrap_or_else(|| initial.clone());
        let energy = options
            .energy_audit
            .then(|| run.energy_audit(initial, &final_state, &initial_potential));
        let trajectory = std::mem::take(&mut run.trajectory);
        let drift = run.drift;
        drop(run);
        let cache = cache.borrow();
        let rhs_evaluator = rhs_evaluator.borrow();
        statistics.rhs_evaluations =
            rhs_evaluator.evaluations().0 + cache.evaluator.evaluations().0;
        statistics.jacobian_evaluations = cache.evaluator.evaluations().1;
        statistics.jacobian_vector_products = cache.products;
        statistics.events = events.len();
        statistics.wall_time = started.elapsed();
        Ok(SimulationResult {
            final_state,
            trajectory,
            statistics,
            drift,
            energy,
            events,
        })
    }
}

fn integrator_error(t: f64, error: impl std::fmt::Display) -> SimulationError {
    SimulationError::Integrator {
        t,
        message: error.to_string(),
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

/// How an accepted step ended.
#[derive(Debug, Clone, Copy, PartialEq)]
enum StepOutcome {
    /// An ordinary step.
    Step,
    /// The step ended at the stop time.
    StopTime,
    /// Root `index` changed sign at the time given, within the step.
    Root(f64, usize),
}

/// What [`Run::step_loop`] needs of an integrator, so that one loop (outputs, hooks, events,
/// energy audit, limits) serves diffsol's methods ([`Diffsol`]) and [`Radau5`].
trait Stepper {
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
struct Diffsol<'a, Eqn, S> {
    solver: S,
    buffer: NalgebraVec<f64>,
    equations: std::marker::PhantomData<&'a Eqn>,
}

impl<'a, Eqn, S> Diffsol<'a, Eqn, S>
where
    Eqn: OdeEquationsImplicit<
            T = f64,
            V = NalgebraVec<f64>,
            M = NalgebraMat<f64>,
            C = NalgebraContext,
        > + 'a,
    S: OdeSolverMethod<'a, Eqn>,
{
    fn new(solver: S) -> Self {
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
    Eqn: OdeEquationsImplicit<
            T = f64,
            V = NalgebraVec<f64>,
            M = NalgebraMat<f64>,
            C = NalgebraContext,
        > + 'a,
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

/// Gauss–Legendre nodes and weights on [0, 1], exact for polynomials of degree 5.
const GAUSS_NODES: [(f64, f64); 3] = [
    (0.112_701_665_379_258_3, 5.0 / 18.0),
    (0.5, 8.0 / 18.0),
    (0.887_298_334_620_741_7, 5.0 / 18.0),
];

impl Run<'_, '_, '_> {
    fn integrate<Eqn>(&mut self, problem: &OdeSolverProblem<Eqn>) -> Result<(), SimulationError>
    where
        Eqn: OdeEquationsImplicit<
                T = f64,
                V = NalgebraVec<f64>,
                M = NalgebraMat<f64>,
                C = NalgebraContext,
            >,
    {
        let t0 = problem.t0;
        let error = |e| integrator_error(t0, e);
        match (self.options.integrator, self.options.linear_solver) {
            (Integrator::Bdf, LinearSolverKind::Dense) => {
                self.step_loop(Diffsol::new(problem.bdf::<SecondOrderLu>().map_err(error)?))
            }
            (Integrator::TrBdf2, LinearSolverKind::Dense) => self.step_loop(Diffsol::new(
                problem.tr_bdf2::<SecondOrderLu>().map_err(error)?,
            )),
            (Integrator::Esdirk34, LinearSolverKind::Dense) => self.step_loop(Diffsol::new(
                problem.esdirk34::<SecondOrderLu>().map_err(error)?,
            )),
            (Integrator::Bdf, LinearSolverKind::SparseFaer) => self.step_loop(Diffsol::new(
                problem.bdf::<SparseSecondOrderLu>().map_err(error)?,
            )),
            (Integrator::TrBdf2, LinearSolverKind::SparseFaer) => self.step_loop(Diffsol::new(
                problem.tr_bdf2::<SparseSecondOrderLu>().map_err(error)?,
            )),
            (Integrator::Esdirk34, LinearSolverKind::SparseFaer) => self.step_loop(Diffsol::new(
                problem.esdirk34::<SparseSecondOrderLu>().map_err(error)?,
            )),
            (Integrator::Tsit45, _) => {
                self.step_loop(Diffsol::new(problem.tsit45().map_err(error)?))
            }
            // `System::run` steps Radau IIA itself: it needs no diffsol problem.
            (Integrator::Radau5, _) => Err(SimulationError::InvalidOptions(
                "Radau IIA is not a diffsol method".into(),
            )),
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

    /// Output frames and energy quadrature over the accepted step `(t_start, t_end]`, from the
    /// integrator's interpolant.
    fn process_interval<S: Stepper>(
        &mut self,
        solver: &mut S,
        t_start: f64,
        t_end: f64,
        y: &mut [f64],
    ) -> Result<(), SimulationError> {
        while self.next_output < self.output_times.len()
            && self.output_times[self.next_output] <= t_end
        {
            let t = self.output_times[self.next_output];
            solver
                .interpolate(t, y)
                .map_err(|e| integrator_error(t, e))?;
            let mut values = std::mem::take(&mut self.frame_buffer);
            values.copy_from_slice(self.equations.cartesian(t, y, &mut self.mapped));
            let emitted = self.emit_frame(t, &values);
            self.frame_buffer = values;
            emitted?;
        }
        if self.options.energy_audit && t_end > t_start && self.needs_quadrature() {
            for (node, weight) in GAUSS_NODES {
                let t = t_start + node * (t_end - t_start);
                solver
                    .interpolate(t, y)
                    .map_err(|e| integrator_error(t, e))?;
                self.accumulate_power(t, y, weight * (t_end - t_start));
            }
        }
        Ok(())
    }

    fn needs_quadrature(&self) -> bool {
        !self.driver_work.is_empty()
            || self.elements.borrow().iter().any(|e| {
                e.potential_energy(0.0, &self.current[..self.system.coordinate_count()])
                    .is_none()
            })
    }

    /// Adds `weight ×` the power of the non-conservative elements and the drivers at the
    /// integrated state `x`: in one pass of the formulation when it offers one and there are
    /// drivers (whose power needs a solve anyway), else from the Cartesian state.
    fn accumulate_power(&mut self, t: f64, x: &[f64], weight: f64) {
        let elements = self.elements.borrow();
        if !self.driver_work.is_empty() {
            let mut element_powers = std::mem::take(&mut self.element_power);
            let mut driver_powers = std::mem::take(&mut self.driver_power);
            let result =
                self.equations
                    .powers(&elements, t, x, &mut element_powers, &mut driver_powers);
            if let Some(result) = &result
                && result.is_ok()
            {
                let works = self.element_work.iter_mut().chain(&mut self.driver_work);
                for (work, power) in works.zip(element_powers.iter().chain(&driver_powers)) {
                    *work += weight * power;
                }
            }
            self.element_power = element_powers;
            self.driver_power = driver_powers;
            if result.is_some() {
                return;
            }
        }
        let n = self.system.coordinate_count();
        let y = self.equations.cartesian(t, x, &mut self.mapped);
        let (q, qd) = y.split_at(n);
        for (work, element) in self.element_work.iter_mut().zip(elements.iter()) {
            if element.potential_energy(t, q).is_some() {
                continue;
            }
            self.scratch.fill(0.0);
            element.add_forces(t, q, qd, &mut self.scratch);
            *work += weight * self.scratch.iter().zip(qd).map(|(f, v)| f * v).sum::<f64>();
        }
        if self.driver_work.is_empty()
            || self
                .evaluator
                .solve_accelerations(&elements, t, q, qd)
                .is_err()
        {
            return;
        }
        let lambda = self.evaluator.multipliers();
        for (k, owner) in self.system.constraint_owners().iter().enumerate() {
            if let ConstraintOwner::Driver(driver) = owner {
                self.driver_work[driver.0] +=
                    weight * lambda[k] * self.evaluator.local(k).time_rate;
            }
        }
    }

    fn emit_frame(&mut self, t: f64, y: &[f64]) -> Result<(), SimulationError> {
        let n = self.system.coordinate_count();
        let (q, qd) = y.split_at(n);
        let elements = self.elements.borrow();
        self.evaluator
            .solve_accelerations(&elements, t, q, qd)
            .map_err(|error| SimulationError::Evaluation { t, error })?;
        let frame = Frame {
            t,
            q,
            qd,
            qdd: self.evaluator.accelerations(),
            lambda: self.evaluator.multipliers(),
            elements: &elements,
        };
        self.observer.output(&frame);
        if self.options.record_trajectory {
            let trajectory = &mut self.trajectory;
            trajectory.times.push(t);
            trajectory.q.extend_from_slice(q);
            trajectory.qd.extend_from_slice(qd);
            trajectory.qdd.extend_from_slice(frame.qdd);
            trajectory.lambda.extend_from_slice(frame.lambda);
        }
        self.next_output += 1;
        drop(elements);
        self.track_drift(t, y);
        Ok(())
    }

    fn track_drift(&mut self, t: f64, y: &[f64]) {
        let (q, qd) = y.split_at(self.system.coordinate_count());
        let (position, velocity) = match self.equations.drifting() {
            None => self.system.violation(t, q, qd),
            Some(equations) => self
                .system
                .violation_of(equations.iter().copied(), t, q, qd),
        };
        self.peak_kinetic = self.peak_kinetic.max(self.system.kinetic_energy(qd));
        self.drift.position = self.drift.position.max(position);
        self.drift.velocity = self.drift.velocity.max(velocity);
    }

    fn potentials(&self, t: f64, q: &[f64]) -> Vec<Option<f64>> {
        self.elements
            .borrow()
            .iter()
            .map(|e| e.potential_energy(t, q))
            .collect()
    }

    fn energy_audit(
        &self,
        initial: &State,
        last: &State,
        initial_potential: &[Option<f64>],
    ) -> EnergyAudit {
        let final_potential = self.potentials(last.t, &last.q);
        let elements = self.elements.borrow();
        let mut audit = EnergyAudit {
            initial_kinetic: self.system.kinetic_energy(&initial.qd),
            final_kinetic: self.system.kinetic_energy(&last.qd),
            peak_kinetic: self.peak_kinetic,
            ..EnergyAudit::default()
        };
        for (k, element) in elements.iter().enumerate() {
            let work = match (
                initial_potential.get(k).copied().flatten(),
                final_potential[k],
            ) {
                (Some(v0), Some(v1)) => {
                    audit.potential.push((element.name().to_string(), v0, v1));
                    v0 - v1
                }
                _ => self.element_work[k],
            };
            audit.element_work.push((element.name().to_string(), work));
        }
        audit.driver_work = self
            .system
            .driver_names()
            .iter()
            .cloned()
            .zip(self.driver_work.iter().copied())
            .collect();
        let total_work: f64 = audit
            .element_work
            .iter()
            .chain(&audit.driver_work)
            .map(|(_, w)| w)
            .sum();
        audit.residual = audit.final_kinetic - audit.initial_kinetic - total_work;
        audit
    }
}
