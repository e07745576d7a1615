//! The equations of motion in the tree's free coordinates `z` and their exact Jacobian.
//!
//! With `q = q(z, t)`, `q̇ = J ż + (prescribed rates)`, `q̈ = J z̈ + c` (`c`: everything but the
//! free accelerations, i.e. `J̇ż` and the prescribed accelerations), projecting
//! `M q̈ + Φ_qᵀλ = G` onto the tree's motions gives
//! `[JᵀMJ  (Φ_qJ)ᵀ; Φ_qJ  0] [z̈; λ] = [Jᵀ(G − Mc); γ* − Φ_q c]`,
//! with `Φ` only the loop-closure and unprescribed driver equations (none for a tree).
//! Differentiating it along a direction of `(z, ż)` (with `z̈, λ` held, `r = G − Mq̈ − Φ_qᵀλ`
//! the tree joints' reactions):
//! `top = dJᵀ r + Jᵀ(∂G/∂q dq + ∂G/∂q̇ dq̇ − Σλ_k H_k dq − M dq̈)`,
//! `bottom = ∂(γ* − Φ_q q̈)/∂q dq + ∂(…)/∂q̇ dq̇ − Φ_q dq̈`, and the same matrix gives
//! `[dz̈; dλ]`. The kinematic derivatives `dq, dq̇, dq̈, dJ` come from one forward-mode pass of
//! the tree kinematics per direction ([`super::scalar::Dual`]); the elements' partials are
//! their own exact ones.

use nalgebra::DMatrix;

use crate::constraints::LocalDerivatives;
use crate::error::{EvaluationError, check_len};
use crate::force::{ForceElement, element_partials};
use crate::formulation::{
    Equations, ForwardDifferences, Integrated, check_jacobian_call, finite_difference_jacobian,
    first_order, kinematic_rows,
};
use crate::linalg::{DenseCholesky, dependent_rows};
use crate::state::{AbsoluteTolerances, State};
use crate::system::{Baumgarte, System};

use super::scalar::{Dual, V2};
use super::tree::{Motion, Placement, Tree};

/// Relative pivot size below which `JᵀMJ` or the loop Schur complement counts as singular.
const SINGULAR_PIVOT: f64 = 1e-12;

/// Dual-number workspace of the Jacobian's forward-mode passes.
struct DualWork {
    z: Vec<Dual>,
    zd: Vec<Dual>,
    zdd: Vec<Dual>,
    q: Vec<Dual>,
    qd: Vec<Dual>,
    qdd: Vec<Dual>,
    axes: Vec<V2<Dual>>,
    trig: Vec<V2<Dual>>,
    column: Vec<Dual>,
}

/// Right-hand side `(ż, z̈)` of the free coordinates and its exact Jacobian, in preallocated
/// storage.
pub(crate) struct JointEvaluator<'s> {
    system: &'s System,
    tree: &'s Tree,
    baumgarte: Baumgarte,
    n: usize,
    nf: usize,
    ml: usize,
    /// All coordinates (free and prescribed), rates and accelerations.
    z: Vec<f64>,
    zd: Vec<f64>,
    zdd: Vec<f64>,
    q: Vec<f64>,
    qd: Vec<f64>,
    /// `c` after the kinematics, `q̈` after a solve.
    qdd: Vec<f64>,
    axes: Vec<V2<f64>>,
    trig: Vec<V2<f64>>,
    /// Time of the prescribed coordinates in `z, ż, z̈`.
    prescribed_at: f64,
    /// `J = ∂q/∂z_free`, `n × nf`, column-major.
    jac: Vec<f64>,
    forces: Vec<f64>,
    /// One element's forces, when its power is wanted apart.
    element_forces: Vec<f64>,
    /// `r = G − M q̈ − Φ_qᵀλ` after a solve.
    residual: Vec<f64>,
    reduced_mass: DMatrix<f64>,
    mass_factor: DenseCholesky,
    locals: Vec<LocalDerivatives>,
    /// `Φ_z = Φ_q J` (`ml × nf`) and `Y = (JᵀMJ)⁻¹ Φ_zᵀ` (`nf × ml`).
    phi_z: DMatrix<f64>,
    coupling: DMatrix<f64>,
    schur: DMatrix<f64>,
    schur_factor: DenseCholesky,
    /// `[z̈; λ]` after a solve.
    solution: Vec<f64>,
    d_dq: DMatrix<f64>,
    d_dqd: DMatrix<f64>,
    /// Per kept equation: `∂(γ* − Φ_q q̈)/∂q` and `/∂q̇` in local slots.
    partial_rows: Vec<([f64; 6], [f64; 6])>,
    work: Vec<f64>,
    dual: DualWork,
    /// Scratch `[a; b]` of one reduced solve, `nf + ml`.
    column: Vec<f64>,
    /// Scratch of the forward-difference Jacobian.
    forward_differences: ForwardDifferences,
    pub(crate) rhs_evaluations: usize,
    pub(crate) jacobian_evaluations: usize,
}

impl<'s> JointEvaluator<'s> {
    pub fn new(system: &'s System, tree: &'s Tree, baumgarte: Baumgarte) -> Self {
        let n = system.coordinate_count();
        let nf = tree.free.len();
        let ml = tree.kept.len();
        let nz = tree.coordinates;
        let dual = DualWork {
            z: vec![Dual::default(); nz],
            zd: vec![Dual::default(); nz],
            zdd: vec![Dual::default(); nz],
            q: vec![Dual::default(); n],
            qd: vec![Dual::default(); n],
            qdd: vec![Dual::default(); n],
            axes: vec![[Dual::default(); 2]; nz],
            trig: vec![[Dual::default(); 2]; n / 3],
            column: vec![Dual::default(); n],
        };
        Self {
            system,
            tree,
            baumgarte,
            n,
            nf,
            ml,
            z: vec![0.0; nz],
            zd: vec![0.0; nz],
            zdd: vec![0.0; nz],
            q: vec![0.0; n],
            qd: vec![0.0; n],
            qdd: vec![0.0; n],
            axes: vec![[0.0; 2]; nz],
            trig: vec![[0.0; 2]; n / 3],
            prescribed_at: f64::NAN,
            jac: vec![0.0; n * nf],
            forces: vec![0.0; n],
            element_forces: vec![0.0; n],
            residual: vec![0.0; n],
            reduced_mass: DMatrix::zeros(nf, nf),
            mass_factor: DenseCholesky::new(nf),
            locals: vec![LocalDerivatives::default(); ml],
            phi_z: DMatrix::zeros(ml, nf),
            coupling: DMatrix::zeros(nf, ml),
            schur: DMatrix::zeros(ml, ml),
            schur_factor: DenseCholesky::new(ml),
            solution: vec![0.0; nf + ml],
            d_dq: DMatrix::zeros(n, n),
            d_dqd: DMatrix::zeros(n, n),
            partial_rows: vec![([0.0; 6], [0.0; 6]); ml],
            work: vec![0.0; n],
            dual,
            column: vec![0.0; nf + ml],
            forward_differences: ForwardDifferences::new(2 * nf),
            rhs_evaluations: 0,
            jacobian_evaluations: 0,
        }
    }

    /// Fills all coordinates and rates at `t`, with zero free accelerations.
    fn coordinates(&mut self, t: f64, x: &[f64]) {
        let nf = self.nf;
        for (k, &c) in self.tree.free.iter().enumerate() {
            self.z[c] = x[k];
            self.zd[c] = x[nf + k];
            self.zdd[c] = 0.0;
        }
        // The integrator asks for the same time many times (Newton iterations, roots).
        if t == self.prescribed_at {
            return;
        }
        self.prescribed_at = t;
        let constraints = self.system.constraints();
        for p in &self.tree.prescribed {
            let f = constraints.drive(p.driver);
            self.z[p.coordinate] = (f.value(t) - p.offset) / p.scale;
            self.zd[p.coordinate] = f.velocity(t) / p.scale;
            self.zdd[p.coordinate] = f.acceleration(t) / p.scale;
        }
    }

    /// Places the tree at `z, ż, z̈` (set by [`Self::coordinates`]): `q, q̇` into `y` (length
    /// `2n`) when given, else into this evaluator's own; `c` (`q̈` but the free accelerations'
    /// part), the joint axes and the bodies' angles into its own either way.
    fn place(&mut self, y: Option<&mut [f64]>) {
        let (q, qd) = match y {
            Some(y) => y.split_at_mut(self.n),
            None => (self.q.as_mut_slice(), self.qd.as_mut_slice()),
        };
        self.tree.place(
            &self.z,
            &self.zd,
            &self.zdd,
            &mut Placement {
                q,
                qd,
                qdd: &mut self.qdd,
                axes: &mut self.axes,
                trig: &mut self.trig,
            },
        );
    }

    /// Kinematics, forces and the reduced solve at `(t, x)`: `z̈`, `λ`, `q̈` and the residual.
    fn solve(
        &mut self,
        elements: &[Box<dyn ForceElement>],
        t: f64,
        x: &[f64],
    ) -> Result<(), EvaluationError> {
        self.solve_with_powers(elements, t, x, None)
    }

    /// [`solve`](Self::solve), also writing each non-conservative element's power `F·q̇`
    /// into `element_powers` (0 for elements with a potential energy) when given.
    fn solve_with_powers(
        &mut self,
        elements: &[Box<dyn ForceElement>],
        t: f64,
        x: &[f64],
        element_powers: Option<&mut [f64]>,
    ) -> Result<(), EvaluationError> {
        let (n, nf, ml) = (self.n, self.nf, self.ml);
        self.coordinates(t, x);
        self.place(None);
        for (k, &c) in self.tree.free.iter().enumerate() {
            self.tree
                .column(c, &self.q, &self.axes, &mut self.jac[k * n..(k + 1) * n]);
        }
        self.forces.fill(0.0);
        match element_powers {
            None => {
                for element in elements {
                    element.add_forces(t, &self.q, &self.qd, &mut self.forces);
                }
            }
            Some(powers) => {
                for (element, power) in elements.iter().zip(powers) {
                    self.element_forces.fill(0.0);
                    element.add_forces(t, &self.q, &self.qd, &mut self.element_forces);
                    *power = if element.potential_energy(t, &self.q).is_some() {
                        0.0
                    } else {
                        self.element_forces
                            .iter()
                            .zip(&self.qd)
                            .map(|(f, v)| f * v)
                            .sum()
                    };
                    for (total, f) in self.forces.iter_mut().zip(&self.element_forces) {
                        *total += f;
                    }
                }
            }
        }
        let mass = self.system.mass_diagonal();
        // Reduced mass JᵀMJ (lower triangle) and forces Jᵀ(G − Mc).
        for (i, (w, (g, c))) in self
            .work
            .iter_mut()
            .zip(self.forces.iter().zip(&self.qdd))
            .enumerate()
        {
            *w = g - mass[i] * c;
        }
        for a in 0..nf {
            let column_a = &self.jac[a * n..(a + 1) * n];
            for b in a..nf {
                let column_b = &self.jac[b * n..(b + 1) * n];
                self.reduced_mass[(b, a)] =
                    (0..n).map(|i| column_a[i] * mass[i] * column_b[i]).sum();
            }
            self.solution[a] = column_a.iter().zip(&self.work).map(|(j, w)| j * w).sum();
        }
        let Baumgarte { alpha, beta } = self.baumgarte;
        let constraints = self.system.constraints();
        for (row, &k) in self.tree.kept.iter().enumerate() {
            let d = constraints.local(k, &self.q, &self.qd, t);
            let slots = constraints.slots(k);
            let mut rhs = d.stabilised_gamma(slots, &self.qd, alpha, beta);
            for b in 0..nf {
                self.phi_z[(row, b)] = 0.0;
            }
            for (slot, g) in slots.iter().zip(&d.grad) {
                let Some(i) = *slot else { continue };
                rhs -= g * self.qdd[i];
                for b in 0..nf {
                    self.phi_z[(row, b)] += g * self.jac[b * n + i];
                }
            }
            self.solution[nf + row] = rhs;
            self.locals[row] = d;
        }
        if self
            .mass_factor
            .factor(&self.reduced_mass, SINGULAR_PIVOT)
            .is_err()
        {
            return Err(EvaluationError::Singular {
                dependent: "none: the joint-coordinate mass matrix JᵀMJ is singular \
                            (degenerate tree coordinates)"
                    .into(),
            });
        }
        if ml > 0 {
            for row in 0..ml {
                let y = &mut self.column[..nf];
                for (b, y) in y.iter_mut().enumerate() {
                    *y = self.phi_z[(row, b)];
                }
                self.mass_factor.solve_in_place(y);
                for (b, y) in y.iter().enumerate() {
                    self.coupling[(b, row)] = *y;
                }
            }
            for r in 0..ml {
                for c in 0..=r {
                    self.schur[(r, c)] = (0..nf)
                        .map(|b| self.phi_z[(r, b)] * self.coupling[(b, c)])
                        .sum();
                }
            }
            if self
                .schur_factor
                .factor(&self.schur, SINGULAR_PIVOT)
                .is_err()
            {
                let labels = self.system.constraint_labels();
                let rows = dependent_rows(&self.phi_z, 1e-10);
                let dependent = if rows.is_empty() {
                    "none found (ill-conditioned)".to_string()
                } else {
                    rows.iter()
                        .map(|&r| labels[self.tree.kept[r]].clone())
                        .collect::<Vec<_>>()
                        .join(", ")
                };
                return Err(EvaluationError::Singular { dependent });
            }
        }
        let mut solution = std::mem::take(&mut self.solution);
        self.reduced_solve(&mut solution);
        self.solution = solution;
        // q̈ = c + J z̈ and r = G − M q̈ − Φ_qᵀλ.
        for b in 0..nf {
            let a = self.solution[b];
            for (qdd, j) in self.qdd.iter_mut().zip(&self.jac[b * n..(b + 1) * n]) {
                *qdd += j * a;
            }
        }
        for (i, r) in self.residual.iter_mut().enumerate() {
            *r = self.forces[i] - mass[i] * self.qdd[i];
        }
        for (row, &k) in self.tree.kept.iter().enumerate() {
            let lambda = self.solution[nf + row];
            for (slot, g) in constraints.slots(k).iter().zip(&self.locals[row].grad) {
                if let Some(i) = *slot {
                    self.residual[i] -= lambda * g;
                }
            }
        }
        Ok(())
    }

    /// Solves `[JᵀMJ Φ_zᵀ; Φ_z 0] [x; μ] = [a; b]` in place with the current factors:
    /// `t = (JᵀMJ)⁻¹a`, `S μ = Φ_z t − b`, `x = t − Y μ`.
    fn reduced_solve(&self, column: &mut [f64]) {
        let nf = self.nf;
        let (top, bottom) = column.split_at_mut(nf);
        self.mass_factor.solve_in_place(top);
        if self.ml == 0 {
            return;
        }
        for (row, b) in bottom.iter_mut().enumerate() {
            let product: f64 = (0..nf).map(|c| self.phi_z[(row, c)] * top[c]).sum();
            *b = product - *b;
        }
        self.schur_factor.solve_in_place(bottom);
        for (c, x) in top.iter_mut().enumerate() {
            *x -= (0..self.ml)
                .map(|row| self.coupling[(c, row)] * bottom[row])
                .sum::<f64>();
        }
    }

    /// The power of each driver (driver order) at `(t, x)`, for the energy audit: a driver
    /// that prescribes coordinate `z_p` exerts `Q = J_pᵀ(Mq̈ − G + Φ_qᵀλ) = −J_pᵀ r` along
    /// it (power `Q ż_p`); one that stays a constraint, `λ_k ∂Φ_k/∂t` as in the Cartesian
    /// formulation. One reduced solve instead of the Cartesian one of `q̈` and all `λ`; the
    /// same pass writes each element's power `F·q̇` into `element_powers` (0 for elements
    /// with a potential energy), so the audit evaluates the forces once per node.
    fn audit_powers(
        &mut self,
        elements: &[Box<dyn ForceElement>],
        t: f64,
        x: &[f64],
        element_powers: &mut [f64],
        powers: &mut [f64],
    ) -> Result<(), EvaluationError> {
        check_len("x", x, 2 * self.nf)?;
        check_len("element powers", element_powers, elements.len())?;
        self.solve_with_powers(elements, t, x, Some(element_powers))?;
        powers.fill(0.0);
        for p in &self.tree.prescribed {
            self.tree
                .column(p.coordinate, &self.q, &self.axes, &mut self.work);
            let force: f64 = -self
                .work
                .iter()
                .zip(&self.residual)
                .map(|(j, r)| j * r)
                .sum::<f64>();
            powers[p.driver] += force * self.zd[p.coordinate];
        }
        let owners = self.system.constraint_owners();
        for (row, &k) in self.tree.kept.iter().enumerate() {
            if let crate::constraints::ConstraintOwner::Driver(driver) = owners[k] {
                powers[driver.0] += self.solution[self.nf + row] * self.locals[row].time_rate;
            }
        }
        Ok(())
    }
}

/// The joint-coordinate formulation's equations: `x = (z_free, ż_free)`.
impl Equations for JointEvaluator<'_> {
    /// Length of the integrated state `(z_free, ż_free)`.
    fn size(&self) -> usize {
        2 * self.nf
    }

    /// `ẋ = (ż, z̈)`; NaN and an error on a singular system.
    fn rhs(
        &mut self,
        elements: &[Box<dyn ForceElement>],
        t: f64,
        x: &[f64],
        dx: &mut [f64],
    ) -> Result<(), EvaluationError> {
        self.rhs_evaluations += 1;
        let nf = self.nf;
        check_len("x", x, 2 * nf)?;
        check_len("ẋ", dx, 2 * nf)?;
        let result = self.solve(elements, t, x);
        first_order(dx, &x[nf..], &result, &self.solution[..nf]);
        result
    }

    /// Exact `∂ẋ/∂x` (`2nf × 2nf`): see the module docs.
    // Local slots index several arrays at once (Hessian, global map).
    #[allow(clippy::needless_range_loop)]
    fn jacobian(
        &mut self,
        elements: &[Box<dyn ForceElement>],
        t: f64,
        x: &[f64],
        jacobian: &mut DMatrix<f64>,
    ) -> Result<(), EvaluationError> {
        self.jacobian_evaluations += 1;
        let (n, nf, ml) = (self.n, self.nf, self.ml);
        check_jacobian_call(2 * nf, x, jacobian)?;
        kinematic_rows(jacobian, nf);
        if let Err(e) = self.solve(elements, t, x) {
            jacobian.fill(f64::NAN);
            return Err(e);
        }
        let state = (t, self.q.as_slice(), self.qd.as_slice());
        element_partials(elements, state, &mut self.d_dq, &mut self.d_dqd);
        let Baumgarte { alpha, beta } = self.baumgarte;
        let constraints = self.system.constraints();
        // A = ∂G/∂q − Σ λ_k H_k, and the kept equations' rows, with w = q̈ + 2αq̇.
        for (w, (a, v)) in self.work.iter_mut().zip(self.qdd.iter().zip(&self.qd)) {
            *w = a + 2.0 * alpha * v;
        }
        for (row, &k) in self.tree.kept.iter().enumerate() {
            let d = &self.locals[row];
            let slots = constraints.slots(k);
            let lambda = self.solution[nf + row];
            for a in 0..6 {
                let Some(ia) = slots[a] else { continue };
                for b in 0..6 {
                    if let Some(ib) = slots[b] {
                        self.d_dq[(ia, ib)] -= lambda * d.hess[a][b];
                    }
                }
            }
            self.partial_rows[row] =
                d.acceleration_partials(slots, &self.qd, &self.work, alpha, beta);
        }
        // Held in the forward-mode passes: z̈ (free: solved; prescribed: as set).
        for (k, &c) in self.tree.free.iter().enumerate() {
            self.zdd[c] = self.solution[k];
        }
        let mass = self.system.mass_diagonal();
        let mut column = std::mem::take(&mut self.column);
        for direction in 0..2 * nf {
            let velocity = direction >= nf;
            let seeded = self.tree.free[direction % nf];
            let dual = &mut self.dual;
            for c in 0..self.tree.coordinates {
                let seed = f64::from(u8::from(c == seeded));
                dual.z[c] = Dual {
                    v: self.z[c],
                    d: if velocity { 0.0 } else { seed },
                };
                dual.zd[c] = Dual {
                    v: self.zd[c],
                    d: if velocity { seed } else { 0.0 },
                };
                dual.zdd[c] = Dual {
                    v: self.zdd[c],
                    d: 0.0,
                };
            }
            self.tree.place(
                &dual.z,
                &dual.zd,
                &dual.zdd,
                &mut Placement {
                    q: &mut dual.q,
                    qd: &mut dual.qd,
                    qdd: &mut dual.qdd,
                    axes: &mut dual.axes,
                    trig: &mut dual.trig,
                },
            );
            // top = dJᵀ r + Jᵀ(A dq + ∂G/∂q̇ dq̇ − M dq̈)
            for (i, value) in self.work.iter_mut().enumerate() {
                let mut sum = -mass[i] * dual.qdd[i].d;
                for j in 0..n {
                    sum += self.d_dqd[(i, j)] * dual.qd[j].d;
                    if !velocity {
                        sum += self.d_dq[(i, j)] * dual.q[j].d;
                    }
                }
                *value = sum;
            }
            for (b, &c) in self.tree.free.iter().enumerate() {
                let j = &self.jac[b * n..(b + 1) * n];
                let mut sum: f64 = j.iter().zip(&self.work).map(|(j, w)| j * w).sum();
                if !velocity {
                    self.tree.column(c, &dual.q, &dual.axes, &mut dual.column);
                    sum += dual
                        .column
                        .iter()
                        .zip(&self.residual)
                        .map(|(dj, r)| dj.d * r)
                        .sum::<f64>();
                }
                column[b] = sum;
            }
            for (row, &k) in self.tree.kept.iter().enumerate() {
                let (by_q, by_qd) = &self.partial_rows[row];
                let grad = &self.locals[row].grad;
                let mut sum = 0.0;
                for (a, slot) in constraints.slots(k).iter().enumerate() {
                    let Some(i) = *slot else { continue };
                    sum +=
                        by_q[a] * dual.q[i].d + by_qd[a] * dual.qd[i].d - grad[a] * dual.qdd[i].d;
                }
                column[nf + row] = sum;
            }
            self.reduced_solve(&mut column);
            for r in 0..nf {
                jacobian[(nf + r, direction)] = column[r];
            }
        }
        self.column = column;
        debug_assert_eq!(self.column.len(), nf + ml);
        Ok(())
    }

    /// Forward-difference Jacobian, the reference for the exact one.
    fn finite_difference_jacobian(
        &mut self,
        elements: &[Box<dyn ForceElement>],
        t: f64,
        x: &[f64],
        jacobian: &mut DMatrix<f64>,
    ) -> Result<(), EvaluationError> {
        self.jacobian_evaluations += 1;
        finite_difference_jacobian(
            self,
            |evaluator| &mut evaluator.forward_differences,
            elements,
            t,
            x,
            jacobian,
        )
    }

    fn evaluations(&self) -> (usize, usize) {
        (self.rhs_evaluations, self.jacobian_evaluations)
    }
}

/// The integration loop's view: the map between the tree's free coordinates and Cartesian ones.
impl Integrated for JointEvaluator<'_> {
    /// The free coordinates and rates of an assembled Cartesian state.
    fn initial_state(&mut self, state: &State) -> Vec<f64> {
        self.tree
            .read(&state.q, &state.qd, &mut self.z, &mut self.zd);
        let free = &self.tree.free;
        free.iter()
            .map(|&c| self.z[c])
            .chain(free.iter().map(|&c| self.zd[c]))
            .collect()
    }

    /// Absolute tolerances of `(z, ż)`: angles for rotations, lengths for slides.
    fn tolerances(&self, atol: &AbsoluteTolerances) -> Vec<f64> {
        let pick = |c: &usize, velocity: bool| match (self.tree.motion(*c), velocity) {
            (Motion::Rotation { .. }, false) => atol.angle,
            (Motion::Rotation { .. }, true) => atol.angular_velocity,
            (Motion::Translation, false) => atol.position,
            (Motion::Translation, true) => atol.velocity,
        };
        let free = &self.tree.free;
        free.iter()
            .map(|c| pick(c, false))
            .chain(free.iter().map(|c| pick(c, true)))
            .collect()
    }

    /// The Cartesian `(q, q̇)` of the integrated state `x` at `t`, into `y` (length `2n`).
    fn cartesian<'a>(&mut self, t: f64, x: &'a [f64], y: &'a mut [f64]) -> &'a [f64] {
        self.coordinates(t, x);
        self.place(Some(&mut *y));
        y
    }

    /// The equations that can drift: loop closures and unprescribed drivers.
    fn drifting(&self) -> Option<&[usize]> {
        Some(&self.tree.kept)
    }

    fn powers(
        &mut self,
        elements: &[Box<dyn ForceElement>],
        t: f64,
        x: &[f64],
        element_powers: &mut [f64],
        driver_powers: &mut [f64],
    ) -> Option<Result<(), EvaluationError>> {
        Some(self.audit_powers(elements, t, x, element_powers, driver_powers))
    }
}
