//! Checking a force element's exact partials against central differences of its forces.

use nalgebra::DMatrix;

use crate::error::{EvaluationError, check_len};
use crate::force::ForcePartials;

use super::System;

impl System {
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
