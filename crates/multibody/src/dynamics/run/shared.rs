//! What the integrator's closures share with the step loop: the elements, the equations
//! instances they evaluate, the cache of the last dense Jacobian and the first evaluation
//! failure since the last accepted step.
//!
//! Jacobian strategy: diffsol's closure interface asks for Jacobian–vector products and
//! assembles the dense Jacobian from `2n` of them at one `(t, y)`. The jac-vec closure
//! therefore keeps the dense exact Jacobian of the last `(t, y)` it saw (interior mutability)
//! and answers each product from it: one Cholesky factorization of the Schur complement
//! `Φ_q M⁻¹ Φ_qᵀ` and `2n` triangular solves per Jacobian instead of `2n` right-hand sides, each
//! with its own factorization. Figures in docs/performance.md.

use std::cell::RefCell;

use nalgebra::DMatrix;

use crate::error::EvaluationError;
use crate::force::ForceElement;
use crate::formulation::Integrated;

use super::super::options::JacobianMethod;
use super::super::report::SolverStatistics;

/// The dense Jacobian of the last `(t, y)` diffsol asked about.
pub(super) struct JacobianCache<'s> {
    evaluator: Box<dyn Integrated + 's>,
    method: JacobianMethod,
    t: f64,
    y: Vec<f64>,
    pub(super) valid: bool,
    matrix: DMatrix<f64>,
    products: usize,
}

impl<'s> JacobianCache<'s> {
    /// An empty cache of `evaluator`'s Jacobians of `size × size`.
    fn new(evaluator: Box<dyn Integrated + 's>, method: JacobianMethod, size: usize) -> Self {
        Self {
            evaluator,
            method,
            t: f64::NAN,
            y: vec![0.0; size],
            valid: false,
            matrix: DMatrix::zeros(size, size),
            products: 0,
        }
    }

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

    /// `J v` for diffsol, from the Jacobian at `(t, y)`.
    fn product(
        &mut self,
        elements: &[Box<dyn ForceElement>],
        t: f64,
        y: &[f64],
        v: &[f64],
        jv: &mut [f64],
        singular: &RefCell<Option<(f64, EvaluationError)>>,
    ) {
        self.products += 1;
        self.update(elements, t, y, singular);
        // diffsol assembles its matrix from products with unit vectors: those are columns
        // (the same numbers as the sum below, whose other terms are zeros), copied in O(n)
        // instead of the O(n²) strided sum, which made assembly O(n³) (docs/performance.md).
        let mut nonzeros = v.iter().enumerate().filter(|(_, x)| **x != 0.0);
        match (nonzeros.next(), nonzeros.next()) {
            (Some((c, 1.0)), None) => jv.copy_from_slice(self.matrix.column(c).as_slice()),
            _ => {
                for (r, out) in jv.iter_mut().enumerate() {
                    *out = (0..v.len()).map(|c| self.matrix[(r, c)] * v[c]).sum();
                }
            }
        }
    }
}

/// What the integrator's closures share with the step loop, each behind its own `RefCell`:
/// the elements (read by the right-hand side, changed by hooks between steps), the equations
/// instances that the right-hand side, the Jacobian and the event functions evaluate, and the
/// first evaluation failure since the last accepted step (the integrator only sees NaN).
pub(super) struct Shared<'s> {
    pub(super) elements: &'s RefCell<Vec<Box<dyn ForceElement>>>,
    rhs: RefCell<Box<dyn Integrated + 's>>,
    pub(super) jacobian: RefCell<JacobianCache<'s>>,
    /// The event functions' map to Cartesian coordinates, with its scratch (length `2n`).
    roots: RefCell<(Box<dyn Integrated + 's>, Vec<f64>)>,
    pub(super) singular: RefCell<Option<(f64, EvaluationError)>>,
}

impl<'s> Shared<'s> {
    /// Three instances from `equations`: the right-hand side's, the Jacobian's, the roots'.
    pub(super) fn new(
        elements: &'s RefCell<Vec<Box<dyn ForceElement>>>,
        equations: impl Fn() -> Box<dyn Integrated + 's>,
        method: JacobianMethod,
        size: usize,
        coordinates: usize,
    ) -> Self {
        Self {
            elements,
            rhs: RefCell::new(equations()),
            jacobian: RefCell::new(JacobianCache::new(equations(), method, size)),
            roots: RefCell::new((equations(), vec![0.0; 2 * coordinates])),
            singular: RefCell::new(None),
        }
    }

    /// The right-hand side, in diffsol's closure signature but for the parameters.
    pub(super) fn rhs(&self, y: &[f64], t: f64, dy: &mut [f64]) {
        let elements = self.elements.borrow();
        if let Err(error) = self.rhs.borrow_mut().rhs(&elements, t, y, dy) {
            self.singular.borrow_mut().get_or_insert((t, error));
        }
    }

    /// A Jacobian–vector product for diffsol.
    pub(super) fn jacobian_vector(&self, y: &[f64], t: f64, v: &[f64], jv: &mut [f64]) {
        let mut cache = self.jacobian.borrow_mut();
        cache.product(&self.elements.borrow(), t, y, v, jv, &self.singular);
    }

    /// The dense Jacobian for Radau IIA.
    pub(super) fn jacobian(&self, y: &[f64], t: f64, out: &mut DMatrix<f64>) {
        let mut cache = self.jacobian.borrow_mut();
        cache.update(&self.elements.borrow(), t, y, &self.singular);
        out.copy_from(&cache.matrix);
    }

    /// Every element's event functions, concatenated, at the integrated state `x`.
    pub(super) fn event_functions(&self, x: &[f64], t: f64, g: &mut [f64]) {
        let mut map = self.roots.borrow_mut();
        let (map, scratch) = &mut *map;
        let n = scratch.len() / 2;
        let (q, qd) = map.cartesian(t, x, scratch).split_at(n);
        let mut offset = 0;
        for element in self.elements.borrow().iter() {
            let count = element.event_count();
            element.event_functions(t, q, qd, &mut g[offset..offset + count]);
            offset += count;
        }
    }

    /// The evaluation counters of the run into `statistics`.
    pub(super) fn count(&self, statistics: &mut SolverStatistics) {
        let cache = self.jacobian.borrow();
        statistics.rhs_evaluations =
            self.rhs.borrow().evaluations().0 + cache.evaluator.evaluations().0;
        statistics.jacobian_evaluations = cache.evaluator.evaluations().1;
        statistics.jacobian_vector_products = cache.products;
    }
}
