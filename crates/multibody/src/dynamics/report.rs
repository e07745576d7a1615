//! What a run hands out: the frames an [`Observer`] sees while it runs, and the
//! [`SimulationResult`] (statistics, drift, energy audit, events) at its end.

use std::time::Duration;

use crate::force::ForceElement;
use crate::state::State;
use crate::trajectory::Trajectory;

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
    /// Lagrange multipliers in the order of [`crate::System::constraint_labels`].
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

/// Everything a run reports. The force elements stay in the [`crate::System`].
#[derive(Debug, Clone, PartialEq)]
pub struct SimulationResult {
    /// State at the end time, to continue from.
    pub final_state: State,
    /// The output frames; empty unless [`crate::SimulationOptions::record_trajectory`].
    pub trajectory: Trajectory,
    /// Integrator counters and timings.
    pub statistics: SolverStatistics,
    /// Largest constraint violation seen.
    pub drift: ConstraintDrift,
    /// Energy balance; `None` unless [`crate::SimulationOptions::energy_audit`].
    pub energy: Option<EnergyAudit>,
    /// Events in the order they were located.
    pub events: Vec<EventRecord>,
}
