//! A compiled mechanism with its force elements: the model's bodies, joints and constraint
//! equations, the mass matrix, and what can be read off a state (energy, drift, reactions).
//!
//! The analyses are in submodules: `assembly` (position and velocity analysis, kinematics),
//! `evaluator` ([`crate::Evaluator`], the Cartesian formulation's [`crate::Equations`]; the
//! joint-coordinate one is in [`crate::joint_coordinates`]) and `partials` (checking an
//! element's partials). [`crate::State`] and the tolerances are in `state`, below all of them.
//! The submodules build on this one, so it re-exports none of them (the crate root does).

use nalgebra::DMatrix;

use crate::constraints::{ConstraintOwner, Constraints, LocalDerivatives};
use crate::error::{EvaluationError, ModelError, check_len};
use crate::force::{ElementId, ForceElement, Gravity};
use crate::linalg::{dependent_rows, weakest_row};
use crate::model::{Body, BodyId, Joint, Model};

mod assembly;
pub(crate) mod evaluator;
pub(crate) mod partials;

/// Relative pivot size below which a matrix counts as singular.
const SINGULAR_PIVOT: f64 = 1e-12;

/// Baumgarte stabilisation of the acceleration constraint:
/// `Φ_q q̈ = γ − 2αΦ̇ − β²Φ`.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Baumgarte {
    /// Velocity feedback α (1/s): damps the drift of `Φ̇`.
    pub alpha: f64,
    /// Position feedback β (1/s): pulls `Φ` back to zero.
    pub beta: f64,
}

impl Default for Baumgarte {
    /// `α = β = 50`, as in the paper.
    fn default() -> Self {
        Self {
            alpha: 50.0,
            beta: 50.0,
        }
    }
}

impl Baumgarte {
    /// No stabilisation: the plain acceleration equation (kinematic analysis).
    pub const NONE: Self = Self {
        alpha: 0.0,
        beta: 0.0,
    };
}

/// A validated mechanism, ready for analysis.
pub struct System {
    bodies: Vec<Body>,
    joints: Vec<Joint>,
    driver_names: Vec<String>,
    constraints: Constraints,
    /// Diagonal of the (constant) mass matrix: `(m, m, J)` per body.
    mass: Vec<f64>,
    pub(crate) elements: Vec<Box<dyn ForceElement>>,
    initial_guess: (Vec<f64>, Vec<f64>),
}

impl std::fmt::Debug for System {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.debug_struct("System")
            .field("bodies", &self.bodies.len())
            .field("constraints", &self.constraints.labels())
            .field(
                "elements",
                &self.elements.iter().map(|e| e.name()).collect::<Vec<_>>(),
            )
            .finish()
    }
}

impl System {
    /// Compiles `model` into constraint equations.
    pub fn new(mut model: Model) -> Result<Self, ModelError> {
        if model.bodies.is_empty() {
            return Err(ModelError::Empty);
        }
        let driver_names = model.drivers.iter().map(|d| d.name.clone()).collect();
        let initial_guess = model.initial_guess();
        let constraints = Constraints::compile(&mut model);
        let mass = model
            .bodies
            .iter()
            .flat_map(|b| [b.mass, b.mass, b.inertia])
            .collect();
        Ok(Self {
            bodies: model.bodies,
            joints: model.joints,
            driver_names,
            constraints,
            mass,
            elements: Vec::new(),
            initial_guess,
        })
    }

    /// Adds a force element; the returned id gives it back with [`System::element`].
    pub fn add_element(&mut self, element: Box<dyn ForceElement>) -> ElementId {
        self.elements.push(element);
        ElementId(self.elements.len() - 1)
    }

    /// The element `id` as its concrete type, e.g. to read wear accumulated during a run.
    pub fn element<T: ForceElement>(&self, id: ElementId) -> Option<&T> {
        crate::force::downcast(self.elements.get(id.0)?.as_ref())
    }

    /// Mutable access to element `id` as its concrete type (e.g. to update a worn surface
    /// between runs).
    pub fn element_mut<T: ForceElement>(&mut self, id: ElementId) -> Option<&mut T> {
        let element: &mut dyn std::any::Any = self.elements.get_mut(id.0)?.as_mut();
        element.downcast_mut()
    }

    /// The force elements in the order they were added (an [`ElementId`] indexes them).
    pub fn elements(&self) -> &[Box<dyn ForceElement>] {
        &self.elements
    }

    /// The bodies as given to the model (initial guesses, not the assembled state).
    pub fn bodies(&self) -> &[Body] {
        &self.bodies
    }

    /// The ideal joints, in the order of their [`crate::JointId`]s.
    pub fn joints(&self) -> &[Joint] {
        &self.joints
    }

    /// The drivers' names, in the order of their [`crate::DriverId`]s.
    pub fn driver_names(&self) -> &[String] {
        &self.driver_names
    }

    /// `n`: three per body.
    pub fn coordinate_count(&self) -> usize {
        self.mass.len()
    }

    /// `m`: scalar constraint equations (joints and drivers).
    pub fn constraint_count(&self) -> usize {
        self.constraints.len()
    }

    /// Name of each scalar constraint equation, in the order of `Φ` and `λ`.
    pub fn constraint_labels(&self) -> &[String] {
        self.constraints.labels()
    }

    /// The joint or driver each scalar constraint equation belongs to.
    pub fn constraint_owners(&self) -> &[ConstraintOwner] {
        self.constraints.owners()
    }

    /// Degrees of freedom, `n − m` (assuming independent constraints).
    pub fn degrees_of_freedom(&self) -> isize {
        self.coordinate_count() as isize - self.constraint_count() as isize
    }

    /// The mass-matrix diagonal `(m, m, J)` per body.
    pub fn mass_diagonal(&self) -> &[f64] {
        &self.mass
    }

    /// Positions and velocities of the bodies as given in the model (not yet assembled).
    pub fn initial_guess(&self) -> (Vec<f64>, Vec<f64>) {
        self.initial_guess.clone()
    }

    pub(crate) fn constraints(&self) -> &Constraints {
        &self.constraints
    }

    /// Kinetic energy `½ q̇ᵀ M q̇`.
    pub fn kinetic_energy(&self, qd: &[f64]) -> f64 {
        0.5 * self
            .mass
            .iter()
            .zip(qd)
            .map(|(m, v)| m * v * v)
            .sum::<f64>()
    }

    /// Largest `|Φ_k|` and `|Φ̇_k|` at a state: how far it has drifted off the constraints.
    pub fn constraint_violation(
        &self,
        t: f64,
        q: &[f64],
        qd: &[f64],
    ) -> Result<(f64, f64), EvaluationError> {
        let n = self.coordinate_count();
        check_len("q", q, n)?;
        check_len("q̇", qd, n)?;
        Ok(self.violation(t, q, qd))
    }

    pub(crate) fn violation(&self, t: f64, q: &[f64], qd: &[f64]) -> (f64, f64) {
        self.violation_of(0..self.constraints.len(), t, q, qd)
    }

    /// [`System::violation`] over the given equations only.
    pub(crate) fn violation_of(
        &self,
        equations: impl Iterator<Item = usize>,
        t: f64,
        q: &[f64],
        qd: &[f64],
    ) -> (f64, f64) {
        let mut max_phi: f64 = 0.0;
        let mut max_phi_dot: f64 = 0.0;
        for k in equations {
            let d = self.constraints.local(k, q, qd, t);
            max_phi = max_phi.max(d.value.abs());
            let rate = local_dot(&d, self.constraints.slots(k), qd) + d.time_rate;
            max_phi_dot = max_phi_dot.max(rate.abs());
        }
        (max_phi, max_phi_dot)
    }

    /// Generalized constraint force `−Φ_qᵀλ` that the equations of `owner` exert on `body`:
    /// `(F_x, F_y, M)`, the moment about the body's centroid. For a revolute joint this is the
    /// joint reaction on that body.
    pub fn reaction(
        &self,
        owner: ConstraintOwner,
        body: BodyId,
        t: f64,
        q: &[f64],
        lambda: &[f64],
    ) -> Result<[f64; 3], EvaluationError> {
        check_len("q", q, self.coordinate_count())?;
        check_len("λ", lambda, self.constraint_count())?;
        let zero = vec![0.0; q.len()];
        let mut force = [0.0; 3];
        for (k, _) in self
            .constraints
            .owners()
            .iter()
            .enumerate()
            .filter(|(_, o)| **o == owner)
        {
            let d = self.constraints.local(k, q, &zero, t);
            for (slot, index) in self.constraints.slots(k).iter().enumerate() {
                if let Some(index) = *index
                    && index / 3 == body.0
                {
                    force[index % 3] -= lambda[k] * d.grad[slot];
                }
            }
        }
        Ok(force)
    }

    /// Labels of the dependent constraints; when none is dependent within tolerance (an
    /// ill-conditioned rather than singular Jacobian), the most nearly dependent one.
    pub(crate) fn dependent_constraints(&self, phi_q: &DMatrix<f64>) -> String {
        let labels = self.constraints.labels();
        let rows = dependent_rows(phi_q, 1e-10);
        if rows.is_empty() {
            return weakest_row(phi_q).map_or_else(
                || "none found".to_string(),
                |k| format!("{} (nearly; ill-conditioned)", labels[k]),
            );
        }
        rows.into_iter()
            .map(|k| labels[k].clone())
            .collect::<Vec<_>>()
            .join(", ")
    }
}

impl Gravity {
    /// The same, for the bodies of a compiled system.
    pub fn for_system(system: &System, acceleration: [f64; 2]) -> Self {
        Self::of_bodies(system.bodies(), acceleration)
    }
}

/// `Φ_q q̇` of one equation, from its local gradient.
pub(crate) fn local_dot(
    d: &LocalDerivatives,
    slots: &crate::constraints::Slots,
    values: &[f64],
) -> f64 {
    slots
        .iter()
        .zip(d.grad)
        .filter_map(|(slot, g)| slot.map(|index| g * values[index]))
        .sum()
}

/// Systems move to worker threads (a wear stage simulates its ensemble of trajectories in
/// parallel): this fails to compile if a field stops being `Send`.
const _: fn() = || {
    fn send<T: Send>() {}
    send::<System>();
};
