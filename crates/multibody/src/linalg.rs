//! Dense LU (partial pivoting) and Cholesky factorizations that work in preallocated storage.
//!
//! nalgebra's `LU` allocates its permutation on every factorization. The right-hand side of the
//! equations of motion factors the Schur complement `Φ_q M⁻¹ Φ_qᵀ` (Cholesky) once per call;
//! position analysis factors `Φ_q Φ_qᵀ` (LU).

use nalgebra::DMatrix;

/// Copies `matrix` into the square `factors` of the same order, to be factored in place:
/// the order and the copy.
fn load<'a>(factors: &'a mut DMatrix<f64>, matrix: &DMatrix<f64>) -> (usize, &'a mut [f64]) {
    let size = factors.nrows();
    assert_eq!(matrix.shape(), (size, size), "matrix size");
    let a = factors.as_mut_slice();
    a.copy_from_slice(matrix.as_slice());
    (size, a)
}

/// What a solve with the square `factors` works on: their order, their entries and the first
/// `order` entries of the right-hand side `b`.
fn view<'a>(factors: &'a DMatrix<f64>, b: &'a mut [f64]) -> (usize, &'a [f64], &'a mut [f64]) {
    let size = factors.nrows();
    (size, factors.as_slice(), &mut b[..size])
}

/// LU factors of a square matrix, kept in place together with the row permutation.
#[derive(Debug, Clone)]
pub(crate) struct DenseLu {
    factors: DMatrix<f64>,
    pivots: Vec<usize>,
}

/// The pivot that was too small, i.e. the elimination step where the matrix proved singular.
#[derive(Debug, Clone, Copy, PartialEq)]
pub(crate) struct SingularPivot {
    pub column: usize,
}

impl DenseLu {
    pub fn new(size: usize) -> Self {
        Self {
            factors: DMatrix::zeros(size, size),
            pivots: vec![0; size],
        }
    }

    /// Order of the matrices this factors.
    pub fn size(&self) -> usize {
        self.factors.nrows()
    }

    /// Factors `matrix` (copied, so the caller keeps it). A pivot below `relative_tolerance`
    /// times the largest entry of the matrix counts as singular.
    ///
    /// Works on the column-major storage as plain slices (no per-element bounds checks or
    /// strided iterators); the floating-point operations and their order are those of the
    /// textbook loop, so the factors are bitwise the same.
    pub fn factor(
        &mut self,
        matrix: &DMatrix<f64>,
        relative_tolerance: f64,
    ) -> Result<(), SingularPivot> {
        let scale = matrix
            .iter()
            .fold(0.0f64, |m, v| m.max(v.abs()))
            .max(f64::MIN_POSITIVE);
        let (size, a) = load(&mut self.factors, matrix);
        for k in 0..size {
            let column_k = &a[k * size..(k + 1) * size];
            let mut pivot_row = k;
            let mut pivot_abs = column_k[k].abs();
            for (r, value) in column_k.iter().enumerate().skip(k + 1) {
                let value = value.abs();
                if value > pivot_abs {
                    pivot_abs = value;
                    pivot_row = r;
                }
            }
            // A NaN pivot fails this test too, which is what we want.
            if pivot_abs.is_nan() || pivot_abs <= relative_tolerance * scale {
                return Err(SingularPivot { column: k });
            }
            self.pivots[k] = pivot_row;
            if pivot_row != k {
                for column in a.chunks_exact_mut(size) {
                    column.swap(k, pivot_row);
                }
            }
            let (left, right) = a.split_at_mut((k + 1) * size);
            let column_k = &mut left[k * size..];
            let inverse_pivot = 1.0 / column_k[k];
            for value in &mut column_k[k + 1..] {
                *value *= inverse_pivot;
            }
            let lower = &column_k[k + 1..];
            for column in right.chunks_exact_mut(size) {
                let upper = column[k];
                if upper != 0.0 {
                    for (value, l) in column[k + 1..].iter_mut().zip(lower) {
                        *value -= l * upper;
                    }
                }
            }
        }
        Ok(())
    }

    /// Solves `A x = b` in place, with `A` the last matrix factored successfully.
    pub fn solve_in_place(&self, b: &mut [f64]) {
        let (size, a, b) = view(&self.factors, b);
        for (k, &pivot) in self.pivots.iter().enumerate() {
            b.swap(k, pivot);
        }
        for c in 0..size {
            let value = b[c];
            if value != 0.0 {
                let column = &a[c * size..(c + 1) * size];
                for (target, l) in b[c + 1..].iter_mut().zip(&column[c + 1..]) {
                    *target -= l * value;
                }
            }
        }
        for c in (0..size).rev() {
            let column = &a[c * size..(c + 1) * size];
            b[c] /= column[c];
            let value = b[c];
            if value != 0.0 {
                for (target, u) in b[..c].iter_mut().zip(&column[..c]) {
                    *target -= u * value;
                }
            }
        }
    }
}

/// Cholesky factors `S = L Lᵀ` of a symmetric positive (semi)definite matrix, kept in
/// preallocated storage (the lower triangle of `factors`, column-major).
///
/// The solves skip the zeros below each column's last nonzero (its envelope): the Schur
/// complement of a mechanism cut into parts by force elements is block diagonal and so is `L`,
/// which makes a solve linear instead of quadratic in the number of constraints, the dominant
/// cost of a long mechanism's Jacobian (docs/performance.md, scaling). Only zero terms are
/// skipped, so results are unchanged.
#[derive(Debug, Clone)]
pub(crate) struct DenseCholesky {
    factors: DMatrix<f64>,
    /// Per column `c`, one past the last row with a nonzero `L[r, c]` (at least `c + 1`).
    envelope: Vec<usize>,
}

impl DenseCholesky {
    pub fn new(size: usize) -> Self {
        Self {
            factors: DMatrix::zeros(size, size),
            envelope: (1..=size).collect(),
        }
    }

    /// Factors the symmetric `matrix` (only its lower triangle is read; copied, so the caller
    /// keeps it). A pivot `d_k = S_kk − Σ_j L_kj²` at or below `relative_tolerance` times the
    /// largest diagonal entry counts as singular (rank deficient), as does a NaN pivot.
    pub fn factor(
        &mut self,
        matrix: &DMatrix<f64>,
        relative_tolerance: f64,
    ) -> Result<(), SingularPivot> {
        let (size, a) = load(&mut self.factors, matrix);
        let scale = (0..size)
            .fold(0.0f64, |m, k| m.max(a[k * size + k].abs()))
            .max(f64::MIN_POSITIVE);
        let threshold = relative_tolerance * scale;
        // Left-looking column Cholesky: column k of L from columns 0..k.
        for k in 0..size {
            let (done, rest) = a.split_at_mut(k * size);
            let column_k = &mut rest[..size];
            for j in 0..k {
                let column_j = &done[j * size..(j + 1) * size];
                let l_kj = column_j[k];
                if l_kj != 0.0 {
                    for (value, l) in column_k[k..].iter_mut().zip(&column_j[k..]) {
                        *value -= l * l_kj;
                    }
                }
            }
            let pivot = column_k[k];
            if pivot.is_nan() || pivot <= threshold {
                return Err(SingularPivot { column: k });
            }
            let root = pivot.sqrt();
            column_k[k] = root;
            let inverse = 1.0 / root;
            for value in &mut column_k[k + 1..] {
                *value *= inverse;
            }
            self.envelope[k] = k
                + 1
                + column_k[k + 1..]
                    .iter()
                    .rposition(|v| *v != 0.0)
                    .map_or(0, |r| r + 1);
        }
        Ok(())
    }

    /// Solves `S x = b` in place, with `S` the last matrix factored successfully.
    pub fn solve_in_place(&self, b: &mut [f64]) {
        let (size, a, b) = view(&self.factors, b);
        // L y = b (column oriented).
        for c in 0..size {
            let end = self.envelope[c];
            let column = &a[c * size..c * size + end];
            b[c] /= column[c];
            let value = b[c];
            if value != 0.0 {
                for (target, l) in b[c + 1..end].iter_mut().zip(&column[c + 1..]) {
                    *target -= l * value;
                }
            }
        }
        // Lᵀ x = y (row k of Lᵀ is column k of L).
        for c in (0..size).rev() {
            let end = self.envelope[c];
            let column = &a[c * size..c * size + end];
            let dot: f64 = b[c + 1..end]
                .iter()
                .zip(&column[c + 1..])
                .map(|(x, l)| x * l)
                .sum();
            b[c] = (b[c] - dot) / column[c];
        }
    }
}

/// Indices of rows of `matrix` (m×n) that are linear combinations of earlier rows, found by
/// Gaussian elimination with column pivoting over the rows in order. Used to name the constraints
/// that make a constraint Jacobian rank deficient.
pub(crate) fn dependent_rows(matrix: &DMatrix<f64>, relative_tolerance: f64) -> Vec<usize> {
    row_pivots(matrix, relative_tolerance)
        .iter()
        .enumerate()
        .filter_map(|(r, p)| p.is_none().then_some(r))
        .collect()
}

/// The row with the smallest elimination pivot relative to the matrix: the most nearly
/// dependent one, to name when a factorization fails but no row is dependent within tolerance.
pub(crate) fn weakest_row(matrix: &DMatrix<f64>) -> Option<usize> {
    row_pivots(matrix, 0.0)
        .iter()
        .enumerate()
        .min_by(|a, b| a.1.unwrap_or(0.0).total_cmp(&b.1.unwrap_or(0.0)))
        .map(|(r, _)| r)
}

/// Per row, the pivot magnitude Gaussian elimination with column pivoting over the rows in
/// order finds for it, or `None` if none exceeds `relative_tolerance` × the largest entry.
fn row_pivots(matrix: &DMatrix<f64>, relative_tolerance: f64) -> Vec<Option<f64>> {
    let mut work = matrix.clone();
    let (rows, cols) = work.shape();
    let scale = matrix.amax().max(f64::MIN_POSITIVE);
    let mut used_columns = vec![false; cols];
    let mut pivots = Vec::with_capacity(rows);
    for r in 0..rows {
        let mut best = None;
        let mut best_abs = relative_tolerance * scale;
        for c in 0..cols {
            if !used_columns[c] && work[(r, c)].abs() > best_abs {
                best_abs = work[(r, c)].abs();
                best = Some(c);
            }
        }
        let Some(c) = best else {
            pivots.push(None);
            continue;
        };
        pivots.push(Some(best_abs / scale));
        used_columns[c] = true;
        let pivot = work[(r, c)];
        for below in (r + 1)..rows {
            let factor = work[(below, c)] / pivot;
            if factor != 0.0 {
                for k in 0..cols {
                    let value = work[(r, k)];
                    work[(below, k)] -= factor * value;
                }
            }
        }
    }
    pivots
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Asserts that `solve` turns `matrix · x` back into `x = (1, −2, 0.5)` within `tolerance`.
    fn check_solves(matrix: &DMatrix<f64>, solve: impl FnOnce(&mut [f64]), tolerance: f64) {
        let x = [1.0, -2.0, 0.5];
        let mut b: Vec<f64> = (0..3)
            .map(|r| (0..3).map(|c| matrix[(r, c)] * x[c]).sum())
            .collect();
        solve(&mut b);
        for (got, want) in b.iter().zip(x) {
            assert!((got - want).abs() < tolerance, "{got} vs {want}");
        }
    }

    #[test]
    fn solves_a_permuted_system() {
        let a = DMatrix::from_row_slice(3, 3, &[0.0, 2.0, 1.0, 1.0, 1.0, 0.0, 3.0, 0.0, 4.0]);
        let mut lu = DenseLu::new(3);
        lu.factor(&a, 1e-14).expect("nonsingular");
        check_solves(&a, |b| lu.solve_in_place(b), 1e-14);
    }

    #[test]
    fn reports_singular_and_dependent_rows() {
        let a = DMatrix::from_row_slice(3, 3, &[1.0, 2.0, 3.0, 2.0, 4.0, 6.0, 0.0, 1.0, 1.0]);
        let mut lu = DenseLu::new(3);
        assert!(lu.factor(&a, 1e-12).is_err());
        assert_eq!(dependent_rows(&a, 1e-12), vec![1]);
        assert_eq!(weakest_row(&a), Some(1));
    }

    #[test]
    fn cholesky_solves_and_reports_rank_deficiency() {
        let b = DMatrix::from_row_slice(3, 3, &[2.0, 1.0, 0.0, 0.0, 1.0, 3.0, 1.0, 0.0, 1.0]);
        let s = &b * b.transpose();
        let mut cholesky = DenseCholesky::new(3);
        cholesky.factor(&s, 1e-12).expect("positive definite");
        check_solves(&s, |rhs| cholesky.solve_in_place(rhs), 1e-13);
        let deficient = DMatrix::from_row_slice(2, 3, &[1.0, 2.0, 3.0, 2.0, 4.0, 6.0]);
        let s = &deficient * deficient.transpose();
        let mut cholesky = DenseCholesky::new(2);
        assert_eq!(cholesky.factor(&s, 1e-12), Err(SingularPivot { column: 1 }));
    }
}
