//! Constraint equations, one scalar equation at a time, with the derivatives the solvers need.
//!
//! Every ideal joint and driver compiles into scalar equations of three shapes, each depending
//! on at most two bodies (six *local* coordinates: slots 0–2 body i, 3–5 body j):
//! - a projected point difference `e·(P_j − P_i) − f(t)`, with `e` fixed globally or turning
//!   with body i (revolute rows, prismatic line, prismatic slide driver),
//! - a relative angle `θ_j − θ_i − f(t)`,
//! - a single coordinate `q_k − f(t)`.
//!
//! For each equation we evaluate, in local coordinates, the value, gradient (a row of `Φ_q`),
//! Hessian `H` and the third derivative contracted twice with `q̇`. Everything the dynamics
//! needs follows: `γ = −q̇ᵀHq̇ + f''`, `∂γ/∂q̇ = −2Hq̇`, `∂(Φ_q w)/∂q = (Hw)ᵀ`,
//! `∂(Φ_qᵀλ)/∂q = Σ λ_k H_k`, `∂γ/∂q = −T(q̇, q̇, ·)`. No constraint here has `Φ_qt ≠ 0`.

use crate::drive::DriveFunction;
use crate::model::{Anchor, DriveTarget, Joint, Model, RotationLock};

/// Global coordinate index of each local slot, `None` for ground or unused slots.
pub(crate) type Slots = [Option<usize>; 6];

#[derive(Debug, Clone, Copy)]
enum Direction {
    /// Fixed in the global frame.
    Global([f64; 2]),
    /// Fixed in body i's frame (body i must exist).
    OnBodyI([f64; 2]),
}

#[derive(Debug, Clone, Copy)]
enum Shape {
    Projected {
        /// Body-fixed point on i (global point if i is ground).
        s_i: [f64; 2],
        s_j: [f64; 2],
        direction: Direction,
    },
    RelativeAngle,
    Coordinate,
}

/// What a scalar equation subtracts: a constant or a driver's function of time.
#[derive(Debug, Clone, Copy)]
enum Target {
    Constant(f64),
    Driver(usize),
}

/// Which model item an equation belongs to.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum ConstraintOwner {
    Joint(crate::model::JointId),
    Driver(crate::model::DriverId),
}

#[derive(Debug, Clone)]
struct ScalarEquation {
    shape: Shape,
    target: Target,
    slots: Slots,
}

/// Derivatives of one scalar equation at a state, in local coordinates.
#[derive(Debug, Clone, Copy, Default)]
pub(crate) struct LocalDerivatives {
    pub value: f64,
    /// ∂Φ/∂t
    pub time_rate: f64,
    /// ∂²Φ/∂t²
    pub time_acceleration: f64,
    pub grad: [f64; 6],
    pub hess: [[f64; 6]; 6],
    /// `Σ_ab ∂_k H_ab q̇_a q̇_b`
    pub third_vv: [f64; 6],
}

impl LocalDerivatives {
    /// `γ − 2αΦ̇ − β²Φ` of this equation at `q̇`: the right-hand side of its stabilised
    /// acceleration equation `Φ_q q̈ = …` (same operations, in the same order, as the Cartesian
    /// right-hand side).
    // Local slots index several arrays at once (gradient, Hessian, global map).
    #[allow(clippy::needless_range_loop)]
    pub fn stabilised_gamma(&self, slots: &Slots, qd: &[f64], alpha: f64, beta: f64) -> f64 {
        let mut phi_dot = self.time_rate;
        let mut quadratic = 0.0;
        for a in 0..6 {
            let Some(ia) = slots[a] else { continue };
            phi_dot += self.grad[a] * qd[ia];
            for b in 0..6 {
                if let Some(ib) = slots[b] {
                    quadratic += self.hess[a][b] * qd[ia] * qd[ib];
                }
            }
        }
        let gamma = -quadratic - self.time_acceleration;
        gamma - 2.0 * alpha * phi_dot - beta * beta * self.value
    }

    /// Partials of `γ − 2αΦ̇ − β²Φ − Φ_q q̈` with respect to `q` and `q̇` (local slots), given
    /// `w = q̈ + 2αq̇`: `−T(q̇, q̇, ·) − Hw − β²∇Φ` and `−2Hq̇ − 2α∇Φ`.
    #[allow(clippy::needless_range_loop)]
    pub fn acceleration_partials(
        &self,
        slots: &Slots,
        qd: &[f64],
        w: &[f64],
        alpha: f64,
        beta: f64,
    ) -> ([f64; 6], [f64; 6]) {
        let (mut by_q, mut by_qd) = ([0.0; 6], [0.0; 6]);
        for a in 0..6 {
            if slots[a].is_none() {
                continue;
            }
            let (mut h_w, mut h_qd) = (0.0, 0.0);
            for b in 0..6 {
                let Some(ib) = slots[b] else { continue };
                h_w += self.hess[a][b] * w[ib];
                h_qd += self.hess[a][b] * qd[ib];
            }
            by_q[a] = -self.third_vv[a] - h_w - beta * beta * self.grad[a];
            by_qd[a] = -2.0 * h_qd - 2.0 * alpha * self.grad[a];
        }
        (by_q, by_qd)
    }
}

/// The compiled constraint set `Φ(q, t) = 0`.
pub(crate) struct Constraints {
    equations: Vec<ScalarEquation>,
    labels: Vec<String>,
    owners: Vec<ConstraintOwner>,
    drives: Vec<Box<dyn DriveFunction>>,
    /// What each driver prescribes, in driver order (the joint-coordinate formulation
    /// prescribes a tree coordinate instead of adding the equation where it can).
    drive_targets: Vec<DriveTarget>,
}

fn rotate(theta: f64, s: [f64; 2]) -> [f64; 2] {
    let (sin, cos) = theta.sin_cos();
    [cos * s[0] - sin * s[1], sin * s[0] + cos * s[1]]
}

/// The vector turned +90°.
fn perp(a: [f64; 2]) -> [f64; 2] {
    [-a[1], a[0]]
}

fn dot(a: [f64; 2], b: [f64; 2]) -> f64 {
    a[0] * b[0] + a[1] * b[1]
}

fn slots_of(i: Option<usize>, j: Option<usize>) -> Slots {
    let body = |b: Option<usize>, k: usize| b.map(|b| 3 * b + k);
    [
        body(i, 0),
        body(i, 1),
        body(i, 2),
        body(j, 0),
        body(j, 1),
        body(j, 2),
    ]
}

impl Constraints {
    /// Compiles the joints and drivers of `model`, taking ownership of its drive functions.
    pub fn compile(model: &mut Model) -> Self {
        let mut equations = Vec::new();
        let mut labels = Vec::new();
        let mut owners = Vec::new();
        let mut push = |shape, target, slots, label: String, owner| {
            equations.push(ScalarEquation {
                shape,
                target,
                slots,
            });
            labels.push(label);
            owners.push(owner);
        };
        let index = |a: &Anchor| a.body.map(|b| b.0);
        for (k, joint) in model.joints.iter().enumerate() {
            let owner = ConstraintOwner::Joint(crate::model::JointId(k));
            match joint {
                Joint::Revolute { name, i, j } => {
                    for (axis, component) in [([1.0, 0.0], "x"), ([0.0, 1.0], "y")] {
                        push(
                            Shape::Projected {
                                s_i: i.point,
                                s_j: j.point,
                                direction: Direction::Global(axis),
                            },
                            Target::Constant(0.0),
                            slots_of(index(i), index(j)),
                            format!("revolute '{name}' {component}"),
                            owner,
                        );
                    }
                }
                Joint::Prismatic {
                    name,
                    base,
                    axis,
                    slider,
                    rotation,
                } => {
                    let normal = perp(*axis);
                    let direction = match base.body {
                        Some(_) => Direction::OnBodyI(normal),
                        None => Direction::Global(normal),
                    };
                    push(
                        Shape::Projected {
                            s_i: base.point,
                            s_j: slider.point,
                            direction,
                        },
                        Target::Constant(0.0),
                        slots_of(index(base), index(slider)),
                        format!("prismatic '{name}' line"),
                        owner,
                    );
                    if let RotationLock::At(angle) = rotation {
                        push(
                            Shape::RelativeAngle,
                            Target::Constant(*angle),
                            slots_of(index(base), index(slider)),
                            format!("prismatic '{name}' rotation"),
                            owner,
                        );
                    }
                }
            }
        }
        let drive_targets = model.drivers.iter().map(|d| d.target).collect();
        let drives: Vec<Box<dyn DriveFunction>> = std::mem::take(&mut model.drivers)
            .into_iter()
            .enumerate()
            .map(|(k, driver)| {
                let owner = ConstraintOwner::Driver(crate::model::DriverId(k));
                let target = Target::Driver(k);
                let label = format!("driver '{}'", driver.name);
                match driver.target {
                    DriveTarget::Coordinate(body, coordinate) => {
                        let mut slots = [None; 6];
                        slots[0] = Some(body.coordinate(coordinate));
                        push(Shape::Coordinate, target, slots, label, owner);
                    }
                    DriveTarget::JointAngle(joint) => {
                        if let Some(Joint::Revolute { i, j, .. }) = model.joints.get(joint.0) {
                            push(
                                Shape::RelativeAngle,
                                target,
                                slots_of(index(i), index(j)),
                                label,
                                owner,
                            );
                        }
                    }
                    DriveTarget::JointSlide(joint) => {
                        if let Some(Joint::Prismatic {
                            base, axis, slider, ..
                        }) = model.joints.get(joint.0)
                        {
                            let direction = match base.body {
                                Some(_) => Direction::OnBodyI(*axis),
                                None => Direction::Global(*axis),
                            };
                            push(
                                Shape::Projected {
                                    s_i: base.point,
                                    s_j: slider.point,
                                    direction,
                                },
                                target,
                                slots_of(index(base), index(slider)),
                                label,
                                owner,
                            );
                        }
                    }
                }
                driver.function
            })
            .collect();
        Self {
            equations,
            labels,
            owners,
            drives,
            drive_targets,
        }
    }

    /// The function of driver `driver` (index in driver order).
    pub fn drive(&self, driver: usize) -> &dyn DriveFunction {
        self.drives[driver].as_ref()
    }

    /// What driver `driver` prescribes.
    pub fn drive_target(&self, driver: usize) -> DriveTarget {
        self.drive_targets[driver]
    }

    pub fn len(&self) -> usize {
        self.equations.len()
    }

    pub fn labels(&self) -> &[String] {
        &self.labels
    }

    pub fn owners(&self) -> &[ConstraintOwner] {
        &self.owners
    }

    pub fn slots(&self, k: usize) -> &Slots {
        &self.equations[k].slots
    }

    /// Derivatives of equation `k` at `(q, q̇, t)`.
    pub fn local(&self, k: usize, q: &[f64], qd: &[f64], t: f64) -> LocalDerivatives {
        let equation = &self.equations[k];
        let gather = |values: &[f64]| {
            let mut local = [0.0; 6];
            for (slot, index) in local.iter_mut().zip(equation.slots) {
                if let Some(index) = index {
                    *slot = values[index];
                }
            }
            local
        };
        let (x, v) = (gather(q), gather(qd));
        let mut d = LocalDerivatives::default();
        match equation.shape {
            Shape::Coordinate => {
                d.value = x[0];
                d.grad[0] = 1.0;
            }
            Shape::RelativeAngle => {
                d.value = x[5] - x[2];
                d.grad[2] = if equation.slots[2].is_some() {
                    -1.0
                } else {
                    0.0
                };
                d.grad[5] = if equation.slots[5].is_some() {
                    1.0
                } else {
                    0.0
                };
            }
            Shape::Projected {
                s_i,
                s_j,
                direction,
            } => projected(&mut d, &equation.slots, s_i, s_j, direction, &x, &v),
        }
        match equation.target {
            Target::Constant(c) => d.value -= c,
            Target::Driver(index) => {
                let f = &self.drives[index];
                d.value -= f.value(t);
                d.time_rate = -f.velocity(t);
                d.time_acceleration = -f.acceleration(t);
            }
        }
        d
    }
}

/// `Φ = e·(P_j − P_i)`; see the module docs for the local-slot convention.
fn projected(
    d: &mut LocalDerivatives,
    slots: &Slots,
    s_i: [f64; 2],
    s_j: [f64; 2],
    direction: Direction,
    x: &[f64; 6],
    v: &[f64; 6],
) {
    let body_i = slots[0].is_some();
    let body_j = slots[3].is_some();
    // Global attachment points relative to each centroid (or the ground point itself).
    let a_i = if body_i { rotate(x[2], s_i) } else { s_i };
    let a_j = if body_j { rotate(x[5], s_j) } else { s_j };
    let p_i = [x[0] + a_i[0], x[1] + a_i[1]];
    let p_j = [x[3] + a_j[0], x[4] + a_j[1]];
    let (wi, wj) = (v[2], v[5]);
    match direction {
        Direction::Global(e) => {
            d.value = dot(e, [p_j[0] - p_i[0], p_j[1] - p_i[1]]);
            if body_i {
                let h1 = dot(e, perp(a_i));
                let h0 = dot(e, a_i);
                d.grad[0] = -e[0];
                d.grad[1] = -e[1];
                d.grad[2] = -h1;
                d.hess[2][2] = h0;
                d.third_vv[2] = wi * wi * h1;
            }
            if body_j {
                let h1 = dot(e, perp(a_j));
                let h0 = dot(e, a_j);
                d.grad[3] = e[0];
                d.grad[4] = e[1];
                d.grad[5] = h1;
                d.hess[5][5] = -h0;
                d.third_vv[5] = -wj * wj * h1;
            }
        }
        Direction::OnBodyI(e0) => {
            // Φ = e(θ_i)·(R_j − r_i) + e·a_j − e0·s_i, with R_j the centroid of j (or the
            // ground point) and e·a_j = g(θ_j − θ_i).
            let e = rotate(x[2], e0);
            let ep = perp(e);
            let r_j = if body_j { [x[3], x[4]] } else { a_j };
            let delta = [r_j[0] - x[0], r_j[1] - x[1]];
            let (g0, g1) = if body_j {
                (dot(e, a_j), dot(e, perp(a_j)))
            } else {
                (0.0, 0.0)
            };
            d.value = dot(e, delta) + g0 - dot(e0, s_i);
            let g2 = -g0;
            d.grad[0] = -e[0];
            d.grad[1] = -e[1];
            d.grad[2] = dot(ep, delta) - g1;
            d.hess[2][0] = -ep[0];
            d.hess[2][1] = -ep[1];
            d.hess[2][2] = -dot(e, delta) + g2;
            if body_j {
                d.grad[3] = e[0];
                d.grad[4] = e[1];
                d.grad[5] = g1;
                d.hess[2][3] = ep[0];
                d.hess[2][4] = ep[1];
                d.hess[2][5] = -g2;
                d.hess[5][5] = g2;
            }
            for (a, b) in [(2, 0), (2, 1), (2, 3), (2, 4), (2, 5)] {
                d.hess[b][a] = d.hess[a][b];
            }
            let vi = [v[0], v[1]];
            let vj = [v[3], v[4]];
            d.third_vv[0] = wi * wi * e[0];
            d.third_vv[1] = wi * wi * e[1];
            d.third_vv[2] = 2.0 * wi * dot(e, vi) + wi * wi * (-dot(ep, delta) + g1);
            if body_j {
                d.third_vv[2] += -2.0 * wi * dot(e, vj) - 2.0 * wi * wj * g1 + wj * wj * g1;
                d.third_vv[3] = -wi * wi * e[0];
                d.third_vv[4] = -wi * wi * e[1];
                d.third_vv[5] = -wi * wi * g1 + 2.0 * wi * wj * g1 - wj * wj * g1;
            }
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::model::{Anchor, Body, BodyId};

    /// Finite-difference check of gradient, Hessian and contracted third derivative of every
    /// equation of a model that has each shape, with arbitrary (unassembled) coordinates.
    #[test]
    fn local_derivatives_match_finite_differences() {
        let mut model = Model::new();
        let a = model
            .add_body(Body::new("a", 1.0, 1.0, [0.3, -0.2, 0.7]))
            .expect("valid");
        let b = model
            .add_body(Body::new("b", 1.0, 1.0, [1.1, 0.4, -1.3]))
            .expect("valid");
        model
            .add_revolute("r", Anchor::on(a, 0.4, 0.1), Anchor::on(b, -0.3, 0.2))
            .expect("valid");
        model
            .add_revolute("g", Anchor::ground(0.1, 0.2), Anchor::on(a, -0.5, 0.05))
            .expect("valid");
        let p = model
            .add_prismatic(
                "p",
                Anchor::on(a, 0.2, -0.1),
                [0.6, 0.8],
                Anchor::on(b, 0.15, 0.3),
                RotationLock::At(0.3),
            )
            .expect("valid");
        model
            .add_prismatic(
                "pg",
                Anchor::ground(0.0, 1.0),
                [1.0, 0.2],
                Anchor::on(b, 0.1, -0.2),
                RotationLock::Free,
            )
            .expect("valid");
        model
            .add_prismatic(
                "pb",
                Anchor::on(b, 0.1, 0.1),
                [0.0, 1.0],
                Anchor::ground(0.3, -0.4),
                RotationLock::Free,
            )
            .expect("valid");
        model
            .add_driver(
                "slide",
                DriveTarget::JointSlide(p),
                Box::new(crate::drive::Ramp {
                    initial: 0.1,
                    rate: 0.2,
                }),
            )
            .expect("valid");
        model
            .add_driver(
                "x",
                DriveTarget::Coordinate(BodyId(1), crate::model::Coordinate::X),
                Box::new(crate::drive::Constant(1.0)),
            )
            .expect("valid");
        let (q, _) = model.initial_guess();
        let qd = vec![0.3, -0.7, 1.9, -0.4, 0.8, -2.3];
        let constraints = Constraints::compile(&mut model);
        let h = 1e-6;
        for k in 0..constraints.len() {
            let d0 = constraints.local(k, &q, &qd, 0.4);
            let slots = *constraints.slots(k);
            let quad = |q: &[f64]| {
                let d = constraints.local(k, q, &qd, 0.4);
                let mut s = 0.0;
                for a in 0..6 {
                    for b in 0..6 {
                        let (Some(ia), Some(ib)) = (slots[a], slots[b]) else {
                            continue;
                        };
                        s += d.hess[a][b] * qd[ia] * qd[ib];
                    }
                }
                s
            };
            for (a, slot) in slots.iter().enumerate() {
                let Some(index) = *slot else { continue };
                let mut plus = q.clone();
                let mut minus = q.clone();
                plus[index] += h;
                minus[index] -= h;
                let dp = constraints.local(k, &plus, &qd, 0.4);
                let dm = constraints.local(k, &minus, &qd, 0.4);
                let grad = (dp.value - dm.value) / (2.0 * h);
                assert!(
                    (grad - d0.grad[a]).abs() < 1e-8,
                    "{} grad {a}",
                    constraints.labels()[k]
                );
                for b in 0..6 {
                    let hess = (dp.grad[b] - dm.grad[b]) / (2.0 * h);
                    assert!(
                        (hess - d0.hess[a][b]).abs() < 1e-7,
                        "{} hess {a}{b}: {hess} vs {}",
                        constraints.labels()[k],
                        d0.hess[a][b]
                    );
                }
                let third = (quad(&plus) - quad(&minus)) / (2.0 * h);
                assert!(
                    (third - d0.third_vv[a]).abs() < 1e-6,
                    "{} third {a}: {third} vs {}",
                    constraints.labels()[k],
                    d0.third_vv[a]
                );
            }
        }
    }
}
