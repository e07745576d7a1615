//! What a simulation is asked to do: the integrator, linear solver and Jacobian method, the
//! output times, tolerances and budgets ([`SimulationOptions`]), and their validation before a
//! run starts.

use std::time::Duration;

use crate::error::SimulationError;
use crate::formulation::Formulation;
use crate::state::AbsoluteTolerances;
use crate::system::Baumgarte;

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
    /// [`crate::SecondOrderLu`]: dense LU (default; fastest for small mechanisms).
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
    /// When frames are reported to the [`crate::Observer`] and recorded, default every 1e-4 s.
    pub output: OutputTimes,
    /// How the implicit integrators get `∂f/∂y`, default [`JacobianMethod::Exact`].
    pub jacobian: JacobianMethod,
    /// Keep every output frame in [`crate::SimulationResult::trajectory`]. Default true. A frame
    /// holds `4n + m` numbers: 100 s of the 15-coordinate LGRES at 1e-4 s is ~0.5 GB, so long
    /// runs should turn this off and record selectively with an [`crate::Observer`].
    pub record_trajectory: bool,
    /// Integrate the work of drivers and non-conservative elements into
    /// [`crate::SimulationResult::energy`]. Default true.
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

    /// The output times of a run starting at `t0`, after checking every option that has a
    /// valid range (a bad one is [`SimulationError::InvalidOptions`]).
    pub(super) fn output_times(&self, t0: f64) -> Result<Vec<f64>, SimulationError> {
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
