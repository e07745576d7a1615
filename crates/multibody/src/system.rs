//! A compiled mechanism with its force elements: the equations of motion, their exact
//! Jacobian, assembly and kinematic analysis.
//!
//! [`Evaluator`] implements the Cartesian formulation's [`Equations`] (the joint-coordinate one
//! is in [`crate::joint_coordinates`]); [`State`] and the tolerances are in `state`, below both.

use nalgebra::DMatrix;

use crate::constraints::{ConstraintOwner, Constraints, LocalDerivatives};
use crate::error::{AssemblyError, EvaluationError, KinematicsError, ModelError, check_len};
use crate::force::{ElementId, ForceElement, ForcePartials, Gravity};
use crate::formulation::{Equations, ForwardDifferences, first_order};
use crate::linalg::{DenseCholesky, DenseLu, dependent_rows, weakest_row};
use crate::model::{Body, BodyId, Joint, Model};
use crate::state::{AbsoluteTolerances, State};
use crate::trajectory::Trajectory;

/// Relative pivot size below which a matrix counts as singular.
const SINGULAR_PIVOT: f64 = 1e-12;
/// Newton iterations of position analysis stop when every `|Φ_k|` is below this (m or rad).
const POSITION_TOLERANCE: f64 = 1e-12;
/// Position analysis fails if after its iterations some `|Φ_k|` is still above this.
const POSITION_ACCEPTANCE: f64 = 1e-9;
const MAX_NEWTON_ITERATIONS: usize = 50;

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

    /// Compares every element's exact partials ([`ForceElement::add_partials`]) with central
    /// differences of its forces at `(t, q, q̇)`, with steps `h_q` in the coordinates and `h_v`
    /// in the velocities. For each element: the largest difference relative to the largest
    /// partial of that element (or to 1 when all are zero), and where it is. An element that
    /// forgot a partial shows a relative error of order 1; a correct one the truncation and
    /// round-off of the differences (~1e-6 for smooth forces and sensible steps).
    pub fn check_partials(
        &self,
        t: f64,
        q: &[f64],
        qd: &[f64],
        h_q: f64,
        h_v: f64,
    ) -> Result<Vec<PartialsCheck>, EvaluationError> {
        let n = self.coordinate_count();
        check_len("q", q, n)?;
        check_len("q̇", qd, n)?;
        let mut report = Vec::with_capacity(self.elements.len());
        for element in &self.elements {
            let mut d_dq = DMatrix::zeros(n, n);
            let mut d_dqd = DMatrix::zeros(n, n);
            element.add_partials(
                t,
                q,
                qd,
                &mut ForcePartials {
                    d_dq: &mut d_dq,
                    d_dqd: &mut d_dqd,
                },
            );
            let forces = |q: &[f64], qd: &[f64]| {
                let mut g = vec![0.0; n];
                element.add_forces(t, q, qd, &mut g);
                g
            };
            let scale = d_dq.amax().max(d_dqd.amax()).max(1.0);
            let mut check = PartialsCheck {
                element: element.name().to_string(),
                max_relative_error: 0.0,
                worst: None,
            };
            for column in 0..2 * n {
                let (velocity, c) = (column >= n, column % n);
                let h = if velocity { h_v } else { h_q };
                let shifted = |delta: f64| {
                    let (mut q, mut qd) = (q.to_vec(), qd.to_vec());
                    if velocity {
                        qd[c] += delta;
                    } else {
                        q[c] += delta;
                    }
                    forces(&q, &qd)
                };
                let (plus, minus) = (shifted(h), shifted(-h));
                for r in 0..n {
                    let numeric = (plus[r] - minus[r]) / (2.0 * h);
                    let exact = if velocity {
                        d_dqd[(r, c)]
                    } else {
                        d_dq[(r, c)]
                    };
                    let error = (numeric - exact).abs() / scale;
                    if error > check.max_relative_error {
                        check.max_relative_error = error;
                        check.worst = Some(PartialEntry {
                            row: r,
                            column: c,
                            velocity,
                            exact,
                            numeric,
                        });
                    }
                }
            }
            report.push(check);
        }
        Ok(report)
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

    fn check_length(&self, values: &[f64], what: &'static str) -> Result<(), AssemblyError> {
        if values.len() != self.coordinate_count() {
            return Err(AssemblyError::WrongLength {
                expected: self.coordinate_count(),
                actual: values.len(),
            });
        }
        if !values.iter().all(|v| v.is_finite()) {
            return Err(AssemblyError::NonFinite { what });
        }
        Ok(())
    }

    /// Assembly: Newton–Raphson (least-norm steps) from `q_guess` onto `Φ(q, t) = 0`, then the
    /// velocities closest to `qd_guess` that satisfy `Φ_q q̇ = −Φ_t`.
    pub fn assemble(
        &self,
        t: f64,
        q_guess: &[f64],
        qd_guess: &[f64],
    ) -> Result<State, AssemblyError> {
        self.check_length(q_guess, "position guess")?;
        self.check_length(qd_guess, "velocity guess")?;
        let (n, m) = (self.coordinate_count(), self.constraint_count());
        if m > n {
            return Err(AssemblyError::Overconstrained {
                equations: m,
                coordinates: n,
            });
        }
        self.assemble_in(&mut Projector::new(n, m), t, q_guess, qd_guess)
    }

    /// [`System::assemble`] in `projector`'s storage (sized for this system), so that a
    /// series of assemblies ([`System::kinematics`]) allocates it once.
    fn assemble_in(
        &self,
        projector: &mut Projector,
        t: f64,
        q_guess: &[f64],
        qd_guess: &[f64],
    ) -> Result<State, AssemblyError> {
        let m = self.constraint_count();
        let mut q = q_guess.to_vec();
        let mut converged = false;
        for _ in 0..MAX_NEWTON_ITERATIONS {
            projector.evaluate(self, t, &q)?;
            if projector
                .residual
                .iter()
                .all(|r| r.abs() <= POSITION_TOLERANCE)
            {
                converged = true;
                break;
            }
            let step = projector.least_norm(&projector.residual);
            for (qi, dqi) in q.iter_mut().zip(step) {
                *qi -= dqi;
            }
            if !q.iter().all(|v| v.is_finite()) {
                break;
            }
        }
        if !converged {
            projector.evaluate_residual(self, t, &q);
            let residual = projector
                .residual
                .iter()
                .fold(0.0_f64, |a, r| a.max(r.abs()));
            if residual.is_nan() || residual > POSITION_ACCEPTANCE {
                return Err(self.not_converged(t, &projector.residual, residual));
            }
            projector.evaluate(self, t, &q)?;
        }
        // Velocities: q̇ = q̇₀ − Φ_qᵀ (Φ_q Φ_qᵀ)⁻¹ (Φ_q q̇₀ + Φ_t).
        let mut velocity_error = vec![0.0; m];
        for (k, error) in velocity_error.iter_mut().enumerate() {
            let d = self.constraints.local(k, &q, qd_guess, t);
            *error = local_dot(&d, self.constraints.slots(k), qd_guess) + d.time_rate;
        }
        let correction = projector.least_norm(&velocity_error);
        let qd = qd_guess
            .iter()
            .zip(correction)
            .map(|(v, c)| v - c)
            .collect();
        Ok(State { t, q, qd })
    }

    fn not_converged(&self, t: f64, residual: &[f64], max: f64) -> AssemblyError {
        let mut order: Vec<usize> = (0..residual.len()).collect();
        order.sort_by(|a, b| residual[*b].abs().total_cmp(&residual[*a].abs()));
        let worst = order
            .iter()
            .take(4)
            .map(|&k| format!("{} = {:.3e}", self.constraints.labels()[k], residual[k]))
            .collect::<Vec<_>>()
            .join(", ");
        AssemblyError::NotConverged {
            t,
            iterations: MAX_NEWTON_ITERATIONS,
            residual: max,
            worst,
        }
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

    /// Kinematic analysis of a mechanism driven in every degree of freedom: positions,
    /// velocities, accelerations and multipliers at each of `times`, from the constraints
    /// alone. Each time starts Newton from the previous solution (the first from `q_guess`),
    /// so closely spaced times follow one assembly branch. Force elements enter the
    /// multipliers through `M q̈ + Φ_qᵀλ = G`.
    pub fn kinematics(
        &self,
        times: &[f64],
        q_guess: &[f64],
    ) -> Result<Trajectory, KinematicsError> {
        let (n, m) = (self.coordinate_count(), self.constraint_count());
        if n != m {
            return Err(KinematicsError::NotFullyDriven {
                coordinates: n,
                equations: m,
            });
        }
        let zero = vec![0.0; n];
        let mut solution = Trajectory {
            coordinates: n,
            constraints: m,
            ..Trajectory::default()
        };
        self.check_length(q_guess, "position guess")?;
        let mut evaluator = self.evaluator(Baumgarte::NONE);
        let mut projector = Projector::new(n, m);
        let mut guess = q_guess.to_vec();
        for &t in times {
            // Newton starts from the previous time's solution carried forward to second
            // order, `q + q̇ Δt + q̈ Δt²/2`: closer than the previous `q` by a factor of about
            // `Δt`, it saves an iteration (a Jacobian and its factorization) at most times.
            if let Some(&previous) = solution.times.last() {
                let dt = t - previous;
                let k = solution.times.len() - 1;
                let frame = k * n..(k + 1) * n;
                let (q, qd, qdd) = (
                    &solution.q[frame.clone()],
                    &solution.qd[frame.clone()],
                    &solution.qdd[frame],
                );
                for (i, g) in guess.iter_mut().enumerate() {
                    let predicted = q[i] + dt * (qd[i] + 0.5 * dt * qdd[i]);
                    *g = if predicted.is_finite() {
                        predicted
                    } else {
                        q[i]
                    };
                }
            }
            let state = self.assemble_in(&mut projector, t, &guess, &zero)?;
            evaluator
                .solve_accelerations(&self.elements, t, &state.q, &state.qd)
                .map_err(|error| KinematicsError::Evaluation { t, error })?;
            solution.times.push(t);
            solution.q.extend_from_slice(&state.q);
            solution.qd.extend_from_slice(&state.qd);
            solution.qdd.extend_from_slice(evaluator.accelerations());
            solution.lambda.extend_from_slice(evaluator.multipliers());
        }
        Ok(solution)
    }

    /// An evaluator of the right-hand side and its exact Jacobian, with its own workspace.
    pub fn evaluator(&self, baumgarte: Baumgarte) -> Evaluator<'_> {
        Evaluator::new(self, baumgarte)
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

/// Position-level workspace: `Φ`, `Φ_q` and the factors of `Φ_q Φ_qᵀ`.
struct Projector {
    residual: Vec<f64>,
    phi_q: DMatrix<f64>,
    normal: DMatrix<f64>,
    lu: DenseLu,
}

impl Projector {
    fn new(n: usize, m: usize) -> Self {
        Self {
            residual: vec![0.0; m],
            phi_q: DMatrix::zeros(m, n),
            normal: DMatrix::zeros(m, m),
            lu: DenseLu::new(m),
        }
    }

    fn evaluate_residual(&mut self, system: &System, t: f64, q: &[f64]) {
        let zero = vec![0.0; q.len()];
        for (k, r) in self.residual.iter_mut().enumerate() {
            *r = system.constraints.local(k, q, &zero, t).value;
        }
    }

    /// `Φ`, `Φ_q` and the LU of `Φ_q Φ_qᵀ`; a rank-deficient `Φ_q` is an error naming the
    /// dependent constraints.
    fn evaluate(&mut self, system: &System, t: f64, q: &[f64]) -> Result<(), AssemblyError> {
        let zero = vec![0.0; q.len()];
        self.phi_q.fill(0.0);
        for k in 0..self.residual.len() {
            let d = system.constraints.local(k, q, &zero, t);
            self.residual[k] = d.value;
            for (slot, index) in system.constraints.slots(k).iter().enumerate() {
                if let Some(index) = *index {
                    self.phi_q[(k, index)] += d.grad[slot];
                }
            }
        }
        self.normal = &self.phi_q * self.phi_q.transpose();
        if self.lu.factor(&self.normal, SINGULAR_PIVOT).is_err() {
            return Err(AssemblyError::RankDeficient {
                t,
                dependent: system.dependent_constraints(&self.phi_q),
            });
        }
        Ok(())
    }

    /// `Φ_qᵀ (Φ_q Φ_qᵀ)⁻¹ r`: the smallest change of `q` (or `q̇`) that removes `r` to first order.
    fn least_norm(&self, r: &[f64]) -> Vec<f64> {
        let mut mu = r.to_vec();
        self.lu.solve_in_place(&mut mu);
        let mu = nalgebra::DVector::from_vec(mu);
        (self.phi_q.transpose() * mu).as_slice().to_vec()
    }
}

/// Evaluates `ẏ = f(t, y)` for `y = (q, q̇)` and its exact Jacobian, in preallocated storage
/// (no allocation per call).
pub struct Evaluator<'s> {
    system: &'s System,
    baumgarte: Baumgarte,
    n: usize,
    m: usize,
    locals: Vec<LocalDerivatives>,
    phi_q: DMatrix<f64>,
    /// `M⁻¹` (diagonal).
    inverse_mass: Vec<f64>,
    /// Schur complement `S = Φ_q M⁻¹ Φ_qᵀ` (`m × m`, lower triangle filled) and its Cholesky
    /// factors.
    schur: DMatrix<f64>,
    cholesky: DenseCholesky,
    /// Scratch: rows of one column of `Φ_q` with a nonzero entry (capacity `m`).
    column_rows: Vec<usize>,
    /// `[q̈; λ]` after a solve.
    solution: Vec<f64>,
    d_dq: DMatrix<f64>,
    d_dqd: DMatrix<f64>,
    /// Right-hand sides of the differentiated augmented system, `(n+m) × 2n`.
    derivative_rhs: DMatrix<f64>,
    /// Scratch vector of length `n`.
    work: Vec<f64>,
    /// Scratch of the forward-difference Jacobian.
    forward_differences: ForwardDifferences,
    /// RHS evaluations (including those of finite differences).
    pub(crate) rhs_evaluations: usize,
    /// Jacobian evaluations.
    pub(crate) jacobian_evaluations: usize,
}

impl<'s> Evaluator<'s> {
    fn new(system: &'s System, baumgarte: Baumgarte) -> Self {
        let (n, m) = (system.coordinate_count(), system.constraint_count());
        Self {
            system,
            baumgarte,
            n,
            m,
            locals: vec![LocalDerivatives::default(); m],
            phi_q: DMatrix::zeros(m, n),
            inverse_mass: system.mass.iter().map(|mass| 1.0 / mass).collect(),
            schur: DMatrix::zeros(m, m),
            cholesky: DenseCholesky::new(m),
            column_rows: Vec::with_capacity(m),
            solution: vec![0.0; n + m],
            d_dq: DMatrix::zeros(n, n),
            d_dqd: DMatrix::zeros(n, n),
            derivative_rhs: DMatrix::zeros(n + m, 2 * n),
            work: vec![0.0; n],
            forward_differences: ForwardDifferences::new(2 * n),
            rhs_evaluations: 0,
            jacobian_evaluations: 0,
        }
    }

    pub(crate) fn local(&self, k: usize) -> &LocalDerivatives {
        &self.locals[k]
    }

    /// `q̈` of the last successful solve.
    pub fn accelerations(&self) -> &[f64] {
        &self.solution[..self.n]
    }

    /// `λ` of the last successful solve.
    pub fn multipliers(&self) -> &[f64] {
        &self.solution[self.n..]
    }

    /// Solves `[M Φ_qᵀ; Φ_q 0] [q̈; λ] = [G; γ*]` through the Schur complement of the
    /// diagonal `M`: `(Φ_q M⁻¹ Φ_qᵀ) λ = Φ_q M⁻¹ G − γ*`, `q̈ = M⁻¹(G − Φ_qᵀλ)` (an `m × m`
    /// Cholesky factorization). On a rank-deficient `Φ_q` returns the names of the dependent
    /// constraints.
    // Local slots index several arrays at once (gradient, Hessian, global map).
    #[allow(clippy::needless_range_loop)]
    pub fn solve_accelerations(
        &mut self,
        elements: &[Box<dyn ForceElement>],
        t: f64,
        q: &[f64],
        qd: &[f64],
    ) -> Result<(), EvaluationError> {
        let (n, m) = (self.n, self.m);
        check_len("q", q, n)?;
        check_len("q̇", qd, n)?;
        let constraints = self.system.constraints();
        let Baumgarte { alpha, beta } = self.baumgarte;
        self.phi_q.as_mut_slice().fill(0.0);
        self.solution[..n].fill(0.0);
        for element in elements {
            element.add_forces(t, q, qd, &mut self.solution[..n]);
        }
        for k in 0..m {
            let d = constraints.local(k, q, qd, t);
            let slots = constraints.slots(k);
            let mut phi_dot = d.time_rate;
            let mut quadratic = 0.0;
            for a in 0..6 {
                let Some(ia) = slots[a] else { continue };
                self.phi_q[(k, ia)] += d.grad[a];
                phi_dot += d.grad[a] * qd[ia];
                for b in 0..6 {
                    if let Some(ib) = slots[b] {
                        quadratic += d.hess[a][b] * qd[ia] * qd[ib];
                    }
                }
            }
            let gamma = -quadratic - d.time_acceleration;
            self.solution[n + k] = gamma - 2.0 * alpha * phi_dot - beta * beta * d.value;
            self.locals[k] = d;
        }
        // S = Σ_i φ_i φ_iᵀ / M_ii over the columns φ_i of Φ_q (each has few nonzeros);
        // only the lower triangle is filled (all the Cholesky factorization reads).
        self.schur.as_mut_slice().fill(0.0);
        let phi_q = self.phi_q.as_slice();
        let schur = self.schur.as_mut_slice();
        // (`max(1)`: `chunks_exact` needs a nonzero size; with `m = 0` both slices are empty.)
        for (column, inverse_mass) in phi_q.chunks_exact(m.max(1)).zip(&self.inverse_mass) {
            self.column_rows.clear();
            self.column_rows
                .extend((0..m).filter(|&k| column[k] != 0.0));
            for (index, &l) in self.column_rows.iter().enumerate() {
                let scaled = column[l] * inverse_mass;
                let target = &mut schur[l * m..(l + 1) * m];
                for &k in &self.column_rows[index..] {
                    target[k] += column[k] * scaled;
                }
            }
        }
        if self.cholesky.factor(&self.schur, SINGULAR_PIVOT).is_err() {
            return Err(EvaluationError::Singular {
                dependent: self.system.dependent_constraints(&self.phi_q),
            });
        }
        Self::reduced_solve(
            &self.cholesky,
            &self.locals,
            constraints,
            &self.inverse_mass,
            &mut self.solution,
        );
        Ok(())
    }

    /// Solves `[M Φ_qᵀ; Φ_q 0] [x; μ] = [a; b]` in place (`column = [a; b]`, length `n + m`)
    /// with the factored Schur complement: `S μ = Φ_q M⁻¹ a − b`, `x = M⁻¹(a − Φ_qᵀ μ)`.
    /// `Φ_q` is applied row by row from the local gradients (at most six entries a row).
    fn reduced_solve(
        cholesky: &DenseCholesky,
        locals: &[LocalDerivatives],
        constraints: &Constraints,
        inverse_mass: &[f64],
        column: &mut [f64],
    ) {
        let n = inverse_mass.len();
        let (top, bottom) = column.split_at_mut(n);
        for (k, (b, d)) in bottom.iter_mut().zip(locals).enumerate() {
            let mut product = 0.0;
            for (slot, g) in constraints.slots(k).iter().zip(&d.grad) {
                if let Some(index) = *slot {
                    product += g * top[index] * inverse_mass[index];
                }
            }
            *b = product - *b;
        }
        cholesky.solve_in_place(bottom);
        for (k, (mu, d)) in bottom.iter().zip(locals).enumerate() {
            for (slot, g) in constraints.slots(k).iter().zip(&d.grad) {
                if let Some(index) = *slot {
                    top[index] -= g * mu;
                }
            }
        }
        for (x, inverse_mass) in top.iter_mut().zip(inverse_mass) {
            *x *= inverse_mass;
        }
    }

    /// `ẏ = (q̇, q̈)`. A singular augmented matrix yields NaN (so the integrator rejects the
    /// step) and an `Err` naming the dependent constraints.
    pub fn rhs(
        &mut self,
        elements: &[Box<dyn ForceElement>],
        t: f64,
        y: &[f64],
        dy: &mut [f64],
    ) -> Result<(), EvaluationError> {
        self.rhs_evaluations += 1;
        let n = self.n;
        check_len("y", y, 2 * n)?;
        check_len("ẏ", dy, 2 * n)?;
        let (q, qd) = y.split_at(n);
        let result = self.solve_accelerations(elements, t, q, qd);
        first_order(dy, qd, &result, &self.solution[..n]);
        result
    }

    /// Exact Jacobian `∂f/∂y` (`2n × 2n`) from the differentiated augmented system, reusing
    /// the single Cholesky factorization of the Schur complement `Φ_q M⁻¹ Φ_qᵀ` for all `2n`
    /// columns.
    #[allow(clippy::needless_range_loop)]
    pub fn jacobian(
        &mut self,
        elements: &[Box<dyn ForceElement>],
        t: f64,
        y: &[f64],
        jacobian: &mut DMatrix<f64>,
    ) -> Result<(), EvaluationError> {
        self.jacobian_evaluations += 1;
        let n = self.n;
        check_len("y", y, 2 * n)?;
        check_len("Jacobian rows", jacobian.as_slice(), 4 * n * n)?;
        let (q, qd) = y.split_at(n);
        jacobian.as_mut_slice().fill(0.0);
        for i in 0..n {
            jacobian[(i, n + i)] = 1.0;
        }
        if let Err(e) = self.solve_accelerations(elements, t, q, qd) {
            jacobian.fill(f64::NAN);
            return Err(e);
        }
        self.d_dq.as_mut_slice().fill(0.0);
        self.d_dqd.as_mut_slice().fill(0.0);
        let mut partials = ForcePartials {
            d_dq: &mut self.d_dq,
            d_dqd: &mut self.d_dqd,
        };
        for element in elements {
            element.add_partials(t, q, qd, &mut partials);
        }
        let Baumgarte { alpha, beta } = self.baumgarte;
        let constraints = self.system.constraints();
        let rhs = &mut self.derivative_rhs;
        // Top block: ∂G/∂q − ∂(Φ_qᵀλ)/∂q | ∂G/∂q̇.
        for r in 0..n {
            for c in 0..n {
                rhs[(r, c)] = self.d_dq[(r, c)];
                rhs[(r, n + c)] = self.d_dqd[(r, c)];
            }
        }
        // w = q̈ + 2αq̇, so that −∂(Φ_q q̈)/∂q − 2α∂(Φ_q q̇)/∂q = −∂(Φ_q w)/∂q.
        for (w, (a, v)) in self.work.iter_mut().zip(self.solution[..n].iter().zip(qd)) {
            *w = a + 2.0 * alpha * v;
        }
        for (k, d) in self.locals.iter().enumerate() {
            let lambda = self.solution[n + k];
            let slots = constraints.slots(k);
            let row = n + k;
            for c in 0..2 * n {
                rhs[(row, c)] = 0.0;
            }
            for a in 0..6 {
                let Some(ia) = slots[a] else { continue };
                let mut h_w = 0.0;
                let mut h_qd = 0.0;
                for b in 0..6 {
                    let Some(ib) = slots[b] else { continue };
                    h_w += d.hess[a][b] * self.work[ib];
                    h_qd += d.hess[a][b] * qd[ib];
                    rhs[(ia, ib)] -= lambda * d.hess[a][b];
                }
                // Bottom block, q columns: ∂γ/∂q − ∂(Φ_q w)/∂q − β²Φ_q.
                rhs[(row, ia)] += -d.third_vv[a] - h_w - beta * beta * d.grad[a];
                // q̇ columns: ∂γ/∂q̇ − 2αΦ_q.
                rhs[(row, n + ia)] += -2.0 * h_qd - 2.0 * alpha * d.grad[a];
            }
        }
        for column in rhs.as_mut_slice().chunks_exact_mut(n + self.m) {
            Self::reduced_solve(
                &self.cholesky,
                &self.locals,
                constraints,
                &self.inverse_mass,
                column,
            );
        }
        for c in 0..2 * n {
            for r in 0..n {
                jacobian[(n + r, c)] = rhs[(r, c)];
            }
        }
        Ok(())
    }

    /// Forward-difference Jacobian (`2n + 1` right-hand sides), the reference the exact one
    /// is measured against.
    pub fn finite_difference_jacobian(
        &mut self,
        elements: &[Box<dyn ForceElement>],
        t: f64,
        y: &[f64],
        jacobian: &mut DMatrix<f64>,
    ) -> Result<(), EvaluationError> {
        self.jacobian_evaluations += 1;
        check_len("y", y, 2 * self.n)?;
        check_len("Jacobian rows", jacobian.as_slice(), 4 * self.n * self.n)?;
        let mut differences = std::mem::take(&mut self.forward_differences);
        let result = differences.jacobian(|v, dv| self.rhs(elements, t, v, dv), y, jacobian);
        self.forward_differences = differences;
        result
    }
}

/// The Cartesian formulation's equations, as the integration loop drives them. `rhs` and the
/// Jacobians are [`Evaluator`]'s public methods, which callers outside the crate use directly.
impl Equations for Evaluator<'_> {
    fn size(&self) -> usize {
        2 * self.accelerations().len()
    }
    fn initial_state(&mut self, state: &State) -> Vec<f64> {
        state.q.iter().chain(&state.qd).copied().collect()
    }
    fn tolerances(&self, atol: &AbsoluteTolerances) -> Vec<f64> {
        let n = self.accelerations().len();
        (0..2 * n)
            .map(|i| match (i >= n, i % 3 == 2) {
                (false, false) => atol.position,
                (false, true) => atol.angle,
                (true, false) => atol.velocity,
                (true, true) => atol.angular_velocity,
            })
            .collect()
    }
    fn cartesian<'a>(&mut self, _t: f64, x: &'a [f64], _scratch: &'a mut [f64]) -> &'a [f64] {
        x
    }
    fn rhs(
        &mut self,
        elements: &[Box<dyn ForceElement>],
        t: f64,
        x: &[f64],
        dx: &mut [f64],
    ) -> Result<(), EvaluationError> {
        Evaluator::rhs(self, elements, t, x, dx)
    }
    fn jacobian(
        &mut self,
        elements: &[Box<dyn ForceElement>],
        t: f64,
        x: &[f64],
        jacobian: &mut DMatrix<f64>,
    ) -> Result<(), EvaluationError> {
        Evaluator::jacobian(self, elements, t, x, jacobian)
    }
    fn finite_difference_jacobian(
        &mut self,
        elements: &[Box<dyn ForceElement>],
        t: f64,
        x: &[f64],
        jacobian: &mut DMatrix<f64>,
    ) -> Result<(), EvaluationError> {
        Evaluator::finite_difference_jacobian(self, elements, t, x, jacobian)
    }
    fn evaluations(&self) -> (usize, usize) {
        (self.rhs_evaluations, self.jacobian_evaluations)
    }
}

/// How well one element's exact partials agree with finite differences
/// ([`System::check_partials`]).
#[derive(Debug, Clone, PartialEq)]
pub struct PartialsCheck {
    /// The element's name.
    pub element: String,
    /// Largest `|exact − numeric|` over all partials, relative to the element's largest
    /// partial (or to 1).
    pub max_relative_error: f64,
    /// Where it is (`None` when every partial agrees exactly).
    pub worst: Option<PartialEntry>,
}

/// One partial derivative `∂G_row/∂q_column` (or `∂q̇_column`) and its finite difference.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct PartialEntry {
    /// Force row (coordinate index).
    pub row: usize,
    /// Coordinate index of the derivative.
    pub column: usize,
    /// Whether the derivative is with respect to `q̇` (else `q`).
    pub velocity: bool,
    /// The element's exact value.
    pub exact: f64,
    /// The central difference.
    pub numeric: f64,
}

/// Systems move to worker threads (a wear stage simulates its ensemble of trajectories in
/// parallel): this fails to compile if a field stops being `Send`.
const _: fn() = || {
    fn send<T: Send>() {}
    send::<System>();
};
