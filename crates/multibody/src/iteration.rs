//! The linear solver of the implicit integrators' Newton iterations, reduced to the size of
//! the mechanism's coordinates.
//!
//! The integrated state is `y = (q, q̇)` with `ẏ = (q̇, q̈(q, q̇, t))`, so the right-hand side's
//! Jacobian is `[[0, I], [A, B]]` with `A = ∂q̈/∂q`, `B = ∂q̈/∂q̇`, and the iteration matrix
//! that diffsol's BDF and SDIRK methods factor, `I − c J`, has the block form
//! `[[a I, b I], [P, Q]]` (here `a = 1`, `b = −c`, `P = −c A`, `Q = I − c B`). Eliminating the
//! first block row leaves the `n × n` Schur complement `S = Q − (b/a) P` (= `I − c B − c² A`):
//!
//! ```text
//! S x₂ = r₂ − P r₁ / a,    x₁ = (r₁ − b x₂) / a,
//! ```
//!
//! an LU of `n × n` instead of `2n × 2n` (an eighth of the work) and solves of a quarter of the
//! work, with the same solution up to round-off (`det = aⁿ det S`, so both are singular
//! together). The block structure is checked on every factorization, entry by entry; a matrix
//! without it (another equation set, a mass matrix) gets the full `2n × 2n` LU.
//!
//! Both solvers, [`SecondOrderLu`] (dense) and [`crate::SparseSecondOrderLu`] (module
//! `sparse_iteration`), are this module's [`BlockLu`]: the check of the block form, the full
//! LU of a matrix without it, the back substitution `x₁` and diffsol's `LinearSolver` plumbing
//! are written once here; they differ only in how `S` is stored, factored and multiplied
//! ([`ReducedLu`]).

use diffsol::{
    LaError, LaLinearOp, Matrix, MatrixCommon, NalgebraContext, NalgebraMat, NalgebraVec, Vector,
};
use nalgebra::DMatrix;

use crate::linalg::DenseLu;

/// Only exact zero (or NaN) pivots count as singular, as in diffsol's own dense LU.
const PIVOT_TOLERANCE: f64 = 0.0;

/// How the last matrix was factored.
#[derive(Debug, Clone, Copy, PartialEq)]
pub(crate) enum Factored {
    /// Nothing factored yet, or the last factorization met a zero (or NaN) pivot.
    No,
    /// `[[a I, b I], [P, Q]]`: `S = Q − (b/a) P` is factored and `P` kept for the solves.
    Reduced { a: f64, b: f64 },
    /// The whole matrix.
    Full,
}

/// The reduced matrix's side of a block-eliminating solver: how `S = Q − (b/a) P` is formed
/// and factored, and how a solve eliminates `P`.
pub trait ReducedLu {
    /// Keeps `P` and factors `S = Q − ratio·P` of the block matrix `matrix` (`2n × 2n`, with
    /// the block form); `false` when `S` is singular or cannot be analysed.
    fn factor(&mut self, matrix: &DMatrix<f64>, ratio: f64) -> bool;
    /// `x₂` from `S x₂ = r₂ − P r₁ / a`, in place of `r₂` in `rhs = [r₁; r₂]`; returns `n`.
    fn eliminate(&self, rhs: &mut [f64], a: f64) -> Result<usize, LaError>;
    /// Checks the whole solution `[x₁; x₂]` (default: nothing to check).
    fn check(&self, _solution: &[f64]) -> Result<(), LaError> {
        Ok(())
    }
}

/// Both diffsol linear solvers ([`SecondOrderLu`], [`crate::SparseSecondOrderLu`]): the
/// iteration matrix as diffsol last gave it, its factors (`R` for the reduced form, a dense LU
/// for the full one) and which of them hold.
#[derive(Debug, Clone)]
pub struct BlockLu<R> {
    matrix: Option<NalgebraMat<f64>>,
    reduced: R,
    full: DenseLu,
    factored: Factored,
}

impl<R: Default> Default for BlockLu<R> {
    fn default() -> Self {
        Self {
            matrix: None,
            reduced: R::default(),
            full: DenseLu::new(0),
            factored: Factored::No,
        }
    }
}

/// `b`'s entries, checked to fit a `size × size` iteration matrix.
fn right_hand_side(b: &mut NalgebraVec<f64>, size: usize) -> Result<&mut [f64], LaError> {
    let data = b.inner_mut().as_mut_slice();
    if data.len() != size {
        return Err(LaError::Other(format!(
            "right-hand side of length {} for a {size}×{size} iteration matrix",
            data.len()
        )));
    }
    Ok(data)
}

/// `(a, b)` when `matrix` (`2n × 2n`, column-major) is `[[a I, b I], [·, ·]]` exactly, with
/// `a` finite and nonzero.
pub(crate) fn block_identity_top(matrix: &DMatrix<f64>) -> Option<(f64, f64)> {
    let size = matrix.nrows();
    if size == 0 || !size.is_multiple_of(2) || matrix.ncols() != size {
        return None;
    }
    let n = size / 2;
    let a = matrix[(0, 0)];
    let b = matrix[(0, n)];
    if !a.is_finite() || a == 0.0 || !b.is_finite() {
        return None;
    }
    for (j, column) in matrix.as_slice().chunks_exact(size).enumerate() {
        for (i, &value) in column[..n].iter().enumerate() {
            let expected = if j == i {
                a
            } else if j == i + n {
                b
            } else {
                0.0
            };
            if value != expected {
                return None;
            }
        }
    }
    Some((a, b))
}

impl<R: ReducedLu> BlockLu<R> {
    /// The reduced matrix's side.
    pub(crate) fn reduced(&self) -> &R {
        &self.reduced
    }

    /// How the last matrix was factored.
    #[cfg(test)]
    pub(crate) fn factored(&self) -> Factored {
        self.factored
    }

    /// Factors `matrix`, reduced when it has the block form.
    pub(crate) fn factor(&mut self, matrix: &DMatrix<f64>) {
        let size = matrix.nrows();
        self.factored = match block_identity_top(matrix) {
            Some((a, b)) => {
                if self.reduced.factor(matrix, b / a) {
                    Factored::Reduced { a, b }
                } else {
                    Factored::No
                }
            }
            None => {
                if self.full.size() != size {
                    self.full = DenseLu::new(size);
                }
                match self.full.factor(matrix, PIVOT_TOLERANCE) {
                    Ok(()) => Factored::Full,
                    Err(_) => Factored::No,
                }
            }
        };
    }

    /// Solves with the last factorization, in place on `rhs` (length `2n`).
    pub(crate) fn solve_slice(&self, rhs: &mut [f64]) -> Result<(), LaError> {
        match self.factored {
            Factored::No => Err(LaError::Other(
                "iteration matrix not factored, or singular".into(),
            )),
            Factored::Full => {
                self.full.solve_in_place(rhs);
                Ok(())
            }
            Factored::Reduced { a, b } => {
                let n = self.reduced.eliminate(rhs, a)?;
                let (top, bottom) = rhs.split_at_mut(n);
                // x₁ = (r₁ − b x₂) / a.
                for (x, &x2) in top.iter_mut().zip(bottom.iter()) {
                    *x = (*x - b * x2) / a;
                }
                self.reduced.check(rhs)
            }
        }
    }
}

/// The dense reduced matrix: `S` factored by LU, `P` kept dense.
#[derive(Debug, Clone)]
pub struct DenseReduced {
    /// `P`, the lower-left block.
    lower_left: DMatrix<f64>,
    /// `S`, before factoring.
    schur: DMatrix<f64>,
    lu: DenseLu,
    /// Scratch for `P r₁` (length `n`).
    product: std::cell::RefCell<Vec<f64>>,
}

impl Default for DenseReduced {
    fn default() -> Self {
        Self {
            lower_left: DMatrix::zeros(0, 0),
            schur: DMatrix::zeros(0, 0),
            lu: DenseLu::new(0),
            product: std::cell::RefCell::new(Vec::new()),
        }
    }
}

impl ReducedLu for DenseReduced {
    fn factor(&mut self, matrix: &DMatrix<f64>, ratio: f64) -> bool {
        let n = matrix.nrows() / 2;
        if self.schur.nrows() != n {
            self.schur = DMatrix::zeros(n, n);
            self.lower_left = DMatrix::zeros(n, n);
            self.lu = DenseLu::new(n);
            self.product.replace(vec![0.0; n]);
        }
        self.lower_left.copy_from(&matrix.view((n, 0), (n, n)));
        self.schur.copy_from(&matrix.view((n, n), (n, n)));
        for (s, p) in self
            .schur
            .as_mut_slice()
            .iter_mut()
            .zip(self.lower_left.as_slice())
        {
            *s -= ratio * p;
        }
        self.lu.factor(&self.schur, PIVOT_TOLERANCE).is_ok()
    }

    fn eliminate(&self, rhs: &mut [f64], a: f64) -> Result<usize, LaError> {
        let n = self.schur.nrows();
        let (top, bottom) = rhs.split_at_mut(n);
        let mut product = self.product.borrow_mut();
        // x₂ from S x₂ = r₂ − P r₁ / a.
        product.fill(0.0);
        for (column, &r) in self.lower_left.as_slice().chunks_exact(n).zip(top.iter()) {
            if r != 0.0 {
                for (p, &entry) in product.iter_mut().zip(column) {
                    *p += entry * r;
                }
            }
        }
        for (x, p) in bottom.iter_mut().zip(product.iter()) {
            *x -= p / a;
        }
        self.lu.solve_in_place(bottom);
        Ok(n)
    }
}

/// diffsol linear solver (dense, `nalgebra` storage) for iteration matrices of `(q, q̇)`
/// systems: see the module docs. Only unbatched matrices (`nbatch = 1`) are supported, which
/// is what this crate's integrators build.
pub type SecondOrderLu = BlockLu<DenseReduced>;

/// diffsol's linear-solver interface, once for both reduced factorizations: the matrix is
/// taken in at its sparsity, refactored at each linearisation, and solved with
/// [`BlockLu::solve_slice`].
impl<R: ReducedLu + Default> diffsol_la::LinearSolver<NalgebraMat<f64>> for BlockLu<R> {
    fn set_linearisation<C>(&mut self, op: &C)
    where
        C: LaLinearOp<T = f64, V = NalgebraVec<f64>, M = NalgebraMat<f64>, C = NalgebraContext>,
    {
        let Some(mut matrix) = self.matrix.take() else {
            self.factored = Factored::No;
            return;
        };
        op.matrix_inplace(&mut matrix);
        self.factor(matrix.inner());
        self.matrix = Some(matrix);
    }

    fn set_sparsity<C>(&mut self, op: &C)
    where
        C: LaLinearOp<T = f64, V = NalgebraVec<f64>, M = NalgebraMat<f64>, C = NalgebraContext>,
    {
        self.matrix = Some(NalgebraMat::new_from_sparsity(
            op.nrows(),
            op.ncols(),
            op.sparsity(),
            *op.context(),
        ));
        self.factored = Factored::No;
    }

    fn solve_in_place(&self, b: &mut NalgebraVec<f64>) -> Result<(), LaError> {
        let size = self.matrix.as_ref().map_or(0, |m| m.nrows());
        self.solve_slice(right_hand_side(b, size)?)
    }

    fn solve_transpose_in_place(&self, _b: &mut NalgebraVec<f64>) -> Result<(), LaError> {
        // Only adjoint sensitivities need it, and this crate does not use them.
        Err(LaError::Other(
            "the second-order LU solvers do not solve with the transpose".into(),
        ))
    }
}

#[cfg(test)]
pub(crate) mod tests {
    use super::*;

    /// A deterministic, well-conditioned pseudo-random matrix entry.
    pub(crate) fn entry(i: usize, j: usize, seed: f64) -> f64 {
        ((i as f64 + 1.3) * (j as f64 + 0.7) * seed).sin()
    }

    /// Zeroes row `n` (the first of the lower blocks) of the `2n × 2n` block `matrix`, so that
    /// its `S = Q − (b/a) P` gets a zero row (a singular iteration matrix), factors it with
    /// `BlockLu<R>` and tries a solve: how it was factored, and whether the solve failed.
    pub(crate) fn factor_singular<R: ReducedLu + Default>(
        mut matrix: DMatrix<f64>,
        n: usize,
    ) -> (Factored, bool) {
        for j in 0..2 * n {
            matrix[(n, j)] = 0.0;
        }
        let mut solver = BlockLu::<R>::default();
        solver.factor(&matrix);
        let mut rhs = vec![1.0; 2 * n];
        (solver.factored(), solver.solve_slice(&mut rhs).is_err())
    }

    /// `[[I, −c I], [−c A, I − c B]]` for a pseudo-random `A`, `B` (n = 15 as in the LGRES).
    fn iteration_matrix(n: usize, c: f64) -> DMatrix<f64> {
        DMatrix::from_fn(2 * n, 2 * n, |i, j| match (i < n, j < n) {
            (true, true) => f64::from(u8::from(i == j)),
            (true, false) => {
                if j == i + n {
                    -c
                } else {
                    0.0
                }
            }
            (false, true) => -c * 1e6 * entry(i, j, 0.37),
            (false, false) => f64::from(u8::from(i == j)) - c * 50.0 * entry(i, j, 1.91),
        })
    }

    fn solve_both(matrix: &DMatrix<f64>, rhs: &[f64]) -> (Vec<f64>, Vec<f64>, Factored) {
        let mut solver = SecondOrderLu::default();
        solver.factor(matrix);
        let mut reduced = rhs.to_vec();
        solver.solve_slice(&mut reduced).expect("factored");
        let mut full = DenseLu::new(matrix.nrows());
        full.factor(matrix, 0.0).expect("nonsingular");
        let mut reference = rhs.to_vec();
        full.solve_in_place(&mut reference);
        (reduced, reference, solver.factored())
    }

    #[test]
    fn reduced_solve_matches_the_full_lu() {
        let n = 15;
        for c in [1e-6, 1e-4, 1e-2] {
            let matrix = iteration_matrix(n, c);
            let rhs: Vec<f64> = (0..2 * n).map(|i| entry(i, 3, 0.83)).collect();
            let (x, reference, factored) = solve_both(&matrix, &rhs);
            assert_eq!(factored, Factored::Reduced { a: 1.0, b: -c });
            // Residual of the reduced solution against the full matrix, and agreement with
            // the full LU, both at round-off (the matrix entries reach 1e4, the solution O(1)).
            let residual = &matrix * nalgebra::DVector::from_column_slice(&x)
                - nalgebra::DVector::from_column_slice(&rhs);
            assert!(
                residual.amax() < 1e-9,
                "c = {c}: residual {}",
                residual.amax()
            );
            let difference = x
                .iter()
                .zip(&reference)
                .map(|(a, b)| (a - b).abs())
                .fold(0.0, f64::max);
            let scale = reference.iter().fold(0.0f64, |m, v| m.max(v.abs()));
            assert!(
                difference <= 1e-10 * scale,
                "c = {c}: {difference} vs {scale}"
            );
        }
    }

    #[test]
    fn matrices_without_the_block_form_get_the_full_lu() {
        let n = 4;
        let mut matrix = iteration_matrix(n, 1e-3);
        // One stray entry in the top blocks breaks the form.
        matrix[(1, 2)] = 1e-9;
        let rhs: Vec<f64> = (0..2 * n).map(|i| entry(i, 1, 0.5)).collect();
        let (x, reference, factored) = solve_both(&matrix, &rhs);
        assert_eq!(factored, Factored::Full);
        assert_eq!(x, reference);
        // An odd size cannot have it either.
        assert_eq!(block_identity_top(&DMatrix::identity(3, 3)), None);
    }

    #[test]
    fn a_singular_matrix_is_an_error_at_the_solve() {
        let n = 3;
        let (factored, solve_failed) =
            factor_singular::<DenseReduced>(iteration_matrix(n, 1e-3), n);
        assert_eq!(factored, Factored::No);
        assert!(solve_failed);
    }
}
