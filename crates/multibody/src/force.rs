//! Force elements: everything that is not an ideal constraint enters the equations of motion
//! through [`ForceElement`] — gravity, springs, and (in other crates) clearance joints.

use std::any::Any;

use nalgebra::DMatrix;

use crate::model::{Body, BodyId, Model};

/// Index of a force element in the order it was added to a [`crate::System`].
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub struct ElementId(pub usize);

/// A source of generalized forces `G_e(t, q, q̇)` with exact partial derivatives.
///
/// The integrator reads elements (`&self`) inside the right-hand side and its Jacobian, and
/// mutates them (`&mut self`) only between steps, through the hooks. Everything but
/// [`ForceElement::add_forces`] has a default, so a simple element is a few lines; see the
/// crate docs for an example. `Any` is a supertrait so a caller can get its concrete element
/// back after a run ([`crate::System::element`]) to read what it accumulated; `Send` so a system
/// can be simulated on a worker thread (a wear stage runs its trajectories in parallel).
pub trait ForceElement: Any + Send {
    /// Shown in reports and energy audits.
    fn name(&self) -> &str;

    /// Adds this element's generalized forces to `forces` (length `n`; per body `(F_x, F_y,
    /// M)` with the moment about the centroid).
    fn add_forces(&self, t: f64, q: &[f64], qd: &[f64], forces: &mut [f64]);

    /// Adds `∂G_e/∂q` and `∂G_e/∂q̇`. Required, so that an element cannot forget it and
    /// silently make the "exact" Jacobian wrong: an element whose forces depend on time alone
    /// (like gravity) implements it as an empty body and says so. [`crate::System::check_partials`]
    /// compares it with finite differences of [`ForceElement::add_forces`].
    fn add_partials(&self, t: f64, q: &[f64], qd: &[f64], partials: &mut ForcePartials<'_>);

    /// Potential energy, for conservative elements. When `Some`, the energy audit books this
    /// element's work as `−ΔV` (exact); otherwise it integrates the power `G_e·q̇` over each
    /// accepted step.
    fn potential_energy(&self, _t: f64, _q: &[f64]) -> Option<f64> {
        None
    }

    /// Called once per accepted step, at its end, in step order (record contact onset
    /// velocities, accumulate wear, ...). `t_previous` is the start of the step.
    fn on_accepted_step(&mut self, _t_previous: f64, _t: f64, _q: &[f64], _qd: &[f64]) {}

    /// Number of event (root) functions this element has.
    fn event_count(&self) -> usize {
        0
    }

    /// Writes the `event_count()` event functions; the integrator lands a step where one
    /// changes sign and then calls [`ForceElement::on_event`]. The count must not change
    /// during a run.
    fn event_functions(&self, _t: f64, _q: &[f64], _qd: &[f64], _values: &mut [f64]) {}

    /// Called at the located event `index` (local to this element). The integrator restarts
    /// from this state afterwards, so the element may switch its force law here. The event
    /// function is ~0 at the restart and may report the same crossing again: decide the new
    /// regime from the state (e.g. the sign of the approach velocity), do not just toggle.
    fn on_event(&mut self, _index: usize, _t: f64, _q: &[f64], _qd: &[f64]) {}
}

pub(crate) fn downcast<T: ForceElement>(element: &dyn ForceElement) -> Option<&T> {
    let element: &dyn Any = element;
    element.downcast_ref()
}

/// Where a force element adds its partial derivatives `∂G/∂q` and `∂G/∂q̇` (both `n × n`).
pub struct ForcePartials<'a> {
    pub(crate) d_dq: &'a mut DMatrix<f64>,
    pub(crate) d_dqd: &'a mut DMatrix<f64>,
}

/// Every element's partials at `(t, q, q̇)` into `d_dq` and `d_dqd`, zeroed first: the
/// `∂G/∂q`, `∂G/∂q̇` that both formulations' exact Jacobians chain.
pub(crate) fn element_partials(
    elements: &[Box<dyn ForceElement>],
    (t, q, qd): (f64, &[f64], &[f64]),
    d_dq: &mut DMatrix<f64>,
    d_dqd: &mut DMatrix<f64>,
) {
    d_dq.as_mut_slice().fill(0.0);
    d_dqd.as_mut_slice().fill(0.0);
    let mut partials = ForcePartials { d_dq, d_dqd };
    for element in elements {
        element.add_partials(t, q, qd, &mut partials);
    }
}

impl ForcePartials<'_> {
    /// Adds `value` to `∂G_row/∂q_column`. Indices are coordinate indices (`3 × body +
    /// coordinate`, see [`BodyId::coordinate`]); out-of-range indices are a bug in the element
    /// and panic.
    pub fn add_dq(&mut self, row: usize, column: usize, value: f64) {
        self.d_dq[(row, column)] += value;
    }

    /// Adds `value` to `∂G_row/∂q̇_column`.
    pub fn add_dqd(&mut self, row: usize, column: usize, value: f64) {
        self.d_dqd[(row, column)] += value;
    }

    /// Adds the partials of a force acting on two bodies (`None` = ground, skipped), given as
    /// the 6×12 Jacobian of `(F_x, F_y, M)` of body `a` then body `b` with respect to
    /// `(q_a, q_b, q̇_a, q̇_b)` — the layout of a two-body contact Jacobian.
    pub fn add_pair(&mut self, bodies: [Option<BodyId>; 2], jacobian: &[[f64; 12]; 6]) {
        for (row_body, rows) in bodies.iter().zip([0, 3]) {
            let Some(row_body) = row_body else { continue };
            for (column_body, columns) in bodies.iter().zip([0, 3]) {
                let Some(column_body) = column_body else {
                    continue;
                };
                for r in 0..3 {
                    for c in 0..3 {
                        let row = 3 * row_body.0 + r;
                        let column = 3 * column_body.0 + c;
                        self.d_dq[(row, column)] += jacobian[rows + r][columns + c];
                        self.d_dqd[(row, column)] += jacobian[rows + r][6 + columns + c];
                    }
                }
            }
        }
    }
}

/// Uniform gravity `g` acting at every centroid. Conservative, so it reports its potential.
#[derive(Debug, Clone, PartialEq)]
pub struct Gravity {
    acceleration: [f64; 2],
    masses: Vec<f64>,
}

impl Gravity {
    /// Gravity of acceleration `g = (g_x, g_y)` on every body of `model` (e.g. `[0.0, -9.81]`).
    /// Build it after the last body is added.
    pub fn new(model: &Model, acceleration: [f64; 2]) -> Self {
        Self::of_bodies(model.bodies(), acceleration)
    }

    /// Gravity on `bodies` ([`Gravity::new`], and [`Gravity::for_system`] with a system's).
    pub(crate) fn of_bodies(bodies: &[Body], acceleration: [f64; 2]) -> Self {
        Self {
            acceleration,
            masses: bodies.iter().map(|b| b.mass).collect(),
        }
    }
}

impl ForceElement for Gravity {
    fn name(&self) -> &str {
        "gravity"
    }

    fn add_forces(&self, _t: f64, _q: &[f64], _qd: &[f64], forces: &mut [f64]) {
        for (body, mass) in forces.chunks_exact_mut(3).zip(&self.masses) {
            body[0] += mass * self.acceleration[0];
            body[1] += mass * self.acceleration[1];
        }
    }

    /// Constant forces: no partials.
    fn add_partials(&self, _t: f64, _q: &[f64], _qd: &[f64], _partials: &mut ForcePartials<'_>) {}

    fn potential_energy(&self, _t: f64, q: &[f64]) -> Option<f64> {
        Some(
            -q.chunks_exact(3)
                .zip(&self.masses)
                .map(|(body, mass)| {
                    mass * (self.acceleration[0] * body[0] + self.acceleration[1] * body[1])
                })
                .sum::<f64>(),
        )
    }
}
