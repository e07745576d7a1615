//! The Cartesian formulation's equations of motion: `ẏ = f(t, y)` for `y = (q, q̇)` from the
//! augmented system solved through the Schur complement of the diagonal mass matrix, and its
//! exact Jacobian from the differentiated system with the same factorization.

use nalgebra::DMatrix;

use crate::constraints::{Constraints, LocalDerivatives};
use crate::error::{EvaluationError, check_len};
use crate::force::{ForceElement, element_partials};
use crate::formulation::{
    Equations, ForwardDifferences, Integrated, check_jacobian_call, finite_difference_jacobian,
    first_order, kinematic_rows,
};
use crate::linalg::DenseCholesky;
use crate::state::{AbsoluteTolerances, State};

use super::{Baumgarte, SINGULAR_PIVOT, System};

impl System {
    /// An evaluator of the right-hand side and its exact Jacobian, with its own workspace.
    pub fn evaluator(&self, baumgarte: Baumgarte) -> Evaluator<'_> {
        Evaluator::new(self, baumgarte)
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
}

/// The Cartesian formulation's equations: `y = (q, q̇)`.
impl Equations for Evaluator<'_> {
    fn size(&self) -> usize {
        2 * self.accelerations().len()
    }

    /// `ẏ = (q̇, q̈)`. A singular augmented matrix yields NaN (so the integrator rejects the
    /// step) and an `Err` naming the dependent constraints.
    fn rhs(
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
    fn jacobian(
        &mut self,
        elements: &[Box<dyn ForceElement>],
        t: f64,
        y: &[f64],
        jacobian: &mut DMatrix<f64>,
    ) -> Result<(), EvaluationError> {
        self.jacobian_evaluations += 1;
        let n = self.n;
        check_jacobian_call(2 * n, y, jacobian)?;
        let (q, qd) = y.split_at(n);
        kinematic_rows(jacobian, n);
        if let Err(e) = self.solve_accelerations(elements, t, q, qd) {
            jacobian.fill(f64::NAN);
            return Err(e);
        }
        element_partials(elements, (t, q, qd), &mut self.d_dq, &mut self.d_dqd);
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
    fn finite_difference_jacobian(
        &mut self,
        elements: &[Box<dyn ForceElement>],
        t: f64,
        y: &[f64],
        jacobian: &mut DMatrix<f64>,
    ) -> Result<(), EvaluationError> {
        self.jacobian_evaluations += 1;
        finite_difference_jacobian(
            self,
            |evaluator| &mut evaluator.forward_differences,
            elements,
            t,
            y,
            jacobian,
        )
    }

    fn evaluations(&self) -> (usize, usize) {
        (self.rhs_evaluations, self.jacobian_evaluations)
    }
}

/// The integration loop's view: the integrated state is the Cartesian one.
impl Integrated for Evaluator<'_> {
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
}
