//! The Newton iterations' linear solver on faer's sparse LU, for mechanisms whose iteration
//! matrix is mostly zeros.
//!
//! Same block elimination as [`crate::SecondOrderLu`] (module `iteration`): the `2n × 2n`
//! iteration matrix `[[a I, b I], [P, Q]]` reduces to the `n × n` matrix `S = Q − (b/a) P`. In
//! Cartesian coordinates `∂q̈/∂q` is dense only within a set of bodies that ideal joints connect
//! (the multipliers couple them through `(Φ_q M⁻¹ Φ_qᵀ)⁻¹`); force elements such as clearance
//! joints couple neighbouring sets locally. So a long mechanism cut by clearance joints has a
//! block-banded `S`, which faer factors in time linear in the number of blocks, where the dense
//! LU needs `n³`. The symbolic analysis (fill-reducing ordering, elimination structure) is
//! computed once and reused by every numeric factorization whose nonzeros lie in the stored
//! pattern; a matrix with a nonzero outside it widens the pattern (union) and is analysed again.
//! diffsol hands over the dense matrix, so each factorization still scans `4n²` entries.
//!
//! This module is the sparse [`ReducedLu`]; the block form's check, the full LU without it and
//! diffsol's plumbing are `iteration`'s [`BlockLu`], shared with the dense solver.

use diffsol::LaError;
use faer::dyn_stack::{MemBuffer, MemStack};
use faer::sparse::linalg::lu::{LuRef, NumericLu, SymbolicLu, factorize_symbolic_lu};
use faer::sparse::{SparseColMatRef, SymbolicSparseColMat};
use faer::{Conj, MatMut, Par};
use nalgebra::DMatrix;

use crate::iteration::{BlockLu, ReducedLu};

/// A column-compressed sparsity pattern (rows sorted within each column).
#[derive(Debug, Clone, Default, PartialEq)]
struct Pattern {
    col_ptr: Vec<usize>,
    row_idx: Vec<usize>,
}

impl Pattern {
    /// The nonzeros of the `size × size` column-major `dense`, its diagonal, and `other`'s
    /// entries.
    fn union(dense: &[f64], size: usize, other: Option<&Pattern>) -> Self {
        let mut pattern = Pattern {
            col_ptr: Vec::with_capacity(size + 1),
            row_idx: Vec::new(),
        };
        pattern.col_ptr.push(0);
        for (j, column) in dense.chunks_exact(size).enumerate() {
            let old = other.map_or(&[][..], |p| &p.row_idx[p.col_ptr[j]..p.col_ptr[j + 1]]);
            let mut old = old.iter().peekable();
            for (i, &value) in column.iter().enumerate() {
                let listed = old.next_if_eq(&&i).is_some();
                if listed || value != 0.0 || i == j {
                    pattern.row_idx.push(i);
                }
            }
            pattern.col_ptr.push(pattern.row_idx.len());
        }
        pattern
    }

    /// Gathers `dense`'s entries at the pattern into `values`; `false` (values unusable) if
    /// `dense` has a nonzero outside the pattern.
    fn gather(&self, dense: &[f64], size: usize, values: &mut Vec<f64>) -> bool {
        values.clear();
        for (j, column) in dense.chunks_exact(size).enumerate() {
            let rows = &self.row_idx[self.col_ptr[j]..self.col_ptr[j + 1]];
            let mut next = 0;
            for &r in rows {
                if column[next..r].iter().any(|&v| v != 0.0) {
                    return false;
                }
                values.push(column[r]);
                next = r + 1;
            }
            if column[next..].iter().any(|&v| v != 0.0) {
                return false;
            }
        }
        true
    }

    fn symbolic(&self, size: usize) -> SymbolicSparseColMat<usize> {
        // Built here from sorted, in-range indices, so the checks cannot fail.
        SymbolicSparseColMat::new_checked(
            size,
            size,
            self.col_ptr.clone(),
            None,
            self.row_idx.clone(),
        )
    }
}

/// The reduced matrix's sparse factors, kept across factorizations.
struct SparseFactors {
    size: usize,
    pattern: Pattern,
    structure: SymbolicSparseColMat<usize>,
    symbolic: SymbolicLu<usize>,
    numeric: NumericLu<usize, f64>,
    values: Vec<f64>,
    factor_scratch: MemBuffer,
    solve_scratch: std::cell::RefCell<MemBuffer>,
}

impl std::fmt::Debug for SparseFactors {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.debug_struct("SparseFactors")
            .field("size", &self.size)
            .field("nonzeros", &self.pattern.row_idx.len())
            .finish_non_exhaustive()
    }
}

impl SparseFactors {
    fn analyse(pattern: Pattern, size: usize) -> Option<Self> {
        let structure = pattern.symbolic(size);
        let symbolic = factorize_symbolic_lu(structure.as_ref(), Default::default()).ok()?;
        let factor_scratch = MemBuffer::new(
            symbolic.factorize_numeric_lu_scratch::<f64>(Par::Seq, Default::default()),
        );
        let solve_scratch = MemBuffer::new(symbolic.solve_in_place_scratch::<f64>(1, Par::Seq));
        Some(Self {
            size,
            values: Vec::with_capacity(pattern.row_idx.len()),
            pattern,
            structure,
            symbolic,
            numeric: NumericLu::new(),
            factor_scratch,
            solve_scratch: std::cell::RefCell::new(solve_scratch),
        })
    }

    /// Numeric factorization of the values already gathered.
    fn factor(&mut self) -> bool {
        let matrix = SparseColMatRef::new(self.structure.as_ref(), &self.values);
        self.symbolic
            .factorize_numeric_lu(
                &mut self.numeric,
                matrix,
                Par::Seq,
                MemStack::new(&mut self.factor_scratch),
                Default::default(),
            )
            .is_ok()
    }

    fn solve_in_place(&self, rhs: &mut [f64]) {
        let lu = LuRef::new_unchecked(&self.symbolic, &self.numeric);
        let mut scratch = self.solve_scratch.borrow_mut();
        let rhs = MatMut::from_column_major_slice_mut(rhs, self.size, 1);
        lu.solve_in_place_with_conj(Conj::No, rhs, Par::Seq, MemStack::new(&mut scratch));
    }
}

/// The sparse reduced matrix: `P` in compressed columns, `S` factored by faer with its
/// symbolic analysis kept.
#[derive(Debug, Default)]
pub struct SparseReduced {
    /// `P` in compressed columns: its pattern and values.
    lower_left: Pattern,
    lower_values: Vec<f64>,
    /// `S` before factoring (dense scratch, column-major).
    schur: Vec<f64>,
    sparse: Option<SparseFactors>,
    /// Symbolic analyses done so far (one unless the pattern grew).
    analyses: usize,
}

impl SparseReduced {
    /// Factors `S` (in `self.schur`), reusing the symbolic analysis when the pattern holds.
    fn factor_reduced(&mut self, n: usize) -> bool {
        let reusable = match &mut self.sparse {
            Some(factors) if factors.size == n => {
                let mut values = std::mem::take(&mut factors.values);
                let fits = factors.pattern.gather(&self.schur, n, &mut values);
                factors.values = values;
                fits
            }
            _ => false,
        };
        if !reusable {
            let previous = self
                .sparse
                .as_ref()
                .filter(|f| f.size == n)
                .map(|f| &f.pattern);
            let pattern = Pattern::union(&self.schur, n, previous);
            let Some(mut factors) = SparseFactors::analyse(pattern, n) else {
                self.sparse = None;
                return false;
            };
            self.analyses += 1;
            let mut values = std::mem::take(&mut factors.values);
            factors.pattern.gather(&self.schur, n, &mut values);
            factors.values = values;
            self.sparse = Some(factors);
        }
        self.sparse.as_mut().is_some_and(SparseFactors::factor)
    }
}

impl ReducedLu for SparseReduced {
    fn factor(&mut self, matrix: &DMatrix<f64>, ratio: f64) -> bool {
        let size = matrix.nrows();
        let n = size / 2;
        let data = matrix.as_slice();
        self.schur.clear();
        self.lower_left.col_ptr.clear();
        self.lower_left.row_idx.clear();
        self.lower_values.clear();
        self.lower_left.col_ptr.push(0);
        for j in 0..n {
            let p = &data[j * size + n..(j + 1) * size];
            let q = &data[(n + j) * size + n..(n + j + 1) * size];
            for (i, (&p, &q)) in p.iter().zip(q).enumerate() {
                self.schur.push(q - ratio * p);
                if p != 0.0 {
                    self.lower_left.row_idx.push(i);
                    self.lower_values.push(p);
                }
            }
            self.lower_left.col_ptr.push(self.lower_left.row_idx.len());
        }
        self.factor_reduced(n)
    }

    fn eliminate(&self, rhs: &mut [f64], a: f64) -> Result<usize, LaError> {
        let factors = self
            .sparse
            .as_ref()
            .ok_or_else(|| LaError::Other("iteration matrix not factored, or singular".into()))?;
        let n = factors.size;
        let (top, bottom) = rhs.split_at_mut(n);
        // x₂ from S x₂ = r₂ − P r₁ / a.
        for (j, &r) in top.iter().enumerate() {
            if r != 0.0 {
                let range = self.lower_left.col_ptr[j]..self.lower_left.col_ptr[j + 1];
                for (&i, &p) in self.lower_left.row_idx[range.clone()]
                    .iter()
                    .zip(&self.lower_values[range])
                {
                    bottom[i] -= p * r / a;
                }
            }
        }
        factors.solve_in_place(bottom);
        Ok(n)
    }

    /// faer does not stop at a zero pivot: a singular `S` shows up in the solution.
    fn check(&self, solution: &[f64]) -> Result<(), LaError> {
        if solution.iter().all(|v| v.is_finite()) {
            Ok(())
        } else {
            Err(LaError::Other("singular iteration matrix".into()))
        }
    }
}

/// diffsol linear solver like [`crate::SecondOrderLu`], with the reduced `n × n` matrix
/// factored by faer's sparse LU (sequential) and its symbolic analysis reused; see the module
/// docs. Selected by [`crate::LinearSolverKind::SparseFaer`]. A matrix without the block form
/// gets the dense LU.
pub type SparseSecondOrderLu = BlockLu<SparseReduced>;

impl SparseSecondOrderLu {
    /// Symbolic analyses so far: 1 when every factorization reused the first one.
    pub fn symbolic_analyses(&self) -> usize {
        self.reduced().analyses
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::iteration::Factored;
    use crate::iteration::tests::{entry, factor_singular};
    use crate::linalg::DenseLu;

    /// `[[I, −c I], [−c A, I − c B]]` with `A`, `B` block-tridiagonal (blocks of 3).
    fn banded_iteration_matrix(n: usize, c: f64) -> DMatrix<f64> {
        let near = |i: usize, j: usize| (i / 3).abs_diff(j / 3) <= 1;
        DMatrix::from_fn(2 * n, 2 * n, |i, j| match (i < n, j < n) {
            (true, true) => f64::from(u8::from(i == j)),
            (true, false) if j == i + n => -c,
            (false, true) if near(i - n, j) => -c * 1e6 * entry(i, j, 0.37),
            (false, false) if near(i - n, j - n) => {
                f64::from(u8::from(i == j)) - c * 50.0 * entry(i, j, 1.91)
            }
            _ => 0.0,
        })
    }

    #[test]
    fn sparse_reduced_solve_matches_the_dense_lu_and_reuses_its_analysis() {
        let n = 30;
        let mut solver = SparseSecondOrderLu::default();
        for c in [1e-6, 1e-4, 1e-2] {
            let matrix = banded_iteration_matrix(n, c);
            solver.factor(&matrix);
            assert_eq!(solver.factored(), Factored::Reduced { a: 1.0, b: -c });
            let rhs: Vec<f64> = (0..2 * n).map(|i| entry(i, 3, 0.83)).collect();
            let mut x = rhs.clone();
            solver.solve_slice(&mut x).expect("factored");
            let mut dense = DenseLu::new(2 * n);
            dense.factor(&matrix, 0.0).expect("nonsingular");
            let mut reference = rhs.clone();
            dense.solve_in_place(&mut reference);
            // Two pivoting orders on a matrix with entries up to 1e4 and an O(1) solution:
            // agreement at round-off.
            let scale = reference.iter().fold(0.0f64, |m, v| m.max(v.abs()));
            for (got, want) in x.iter().zip(&reference) {
                assert!(
                    (got - want).abs() <= 1e-10 * scale,
                    "c = {c}: {got} vs {want}"
                );
            }
        }
        // Same pattern at every c: one analysis.
        assert_eq!(solver.symbolic_analyses(), 1);
        // A nonzero outside the pattern widens it, and the result is still right.
        let mut matrix = banded_iteration_matrix(n, 1e-3);
        matrix[(n, 2 * n - 1)] = 0.5;
        solver.factor(&matrix);
        assert_eq!(solver.symbolic_analyses(), 2);
        let rhs: Vec<f64> = (0..2 * n).map(|i| entry(i, 1, 0.5)).collect();
        let mut x = rhs.clone();
        solver.solve_slice(&mut x).expect("factored");
        let residual = &matrix * nalgebra::DVector::from_column_slice(&x)
            - nalgebra::DVector::from_column_slice(&rhs);
        assert!(residual.amax() < 1e-9, "residual {}", residual.amax());
    }

    #[test]
    fn a_singular_reduced_matrix_is_an_error_at_the_solve() {
        let n = 6;
        let (factored, solve_failed) =
            factor_singular::<SparseReduced>(banded_iteration_matrix(n, 1e-3), n);
        assert!(factored == Factored::No || solve_failed);
    }
}
