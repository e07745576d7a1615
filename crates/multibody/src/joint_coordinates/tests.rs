//! A mechanism with every kind of tree joint (revolutes in both anchor orders, a free
//! prismatic with the slider as child, a locked one with the base as child, a floating body),
//! a loop closed by an ideal revolute, a prescribed joint angle, a prescribed body coordinate,
//! and nonlinear spring-dampers: the joint formulation's exact Jacobian against differences of
//! its right-hand side, and its motion against the Cartesian formulation's.

use nalgebra::DMatrix;

use super::{JointEvaluator, Tree};
use crate::drive::{Harmonic, Ramp};
use crate::force::{ForceElement, ForcePartials, Gravity};
use crate::formulation::{Equations, Integrated};
use crate::model::{Anchor, Body, Coordinate, DriveTarget, Model, RotationLock};
use crate::{Formulation, OutputTimes, SimulationOptions, System};

fn rotate(theta: f64, s: [f64; 2]) -> [f64; 2] {
    let (sin, cos) = theta.sin_cos();
    [cos * s[0] - sin * s[1], sin * s[0] + cos * s[1]]
}

fn add(a: [f64; 2], b: [f64; 2]) -> [f64; 2] {
    [a[0] + b[0], a[1] + b[1]]
}

fn sub(a: [f64; 2], b: [f64; 2]) -> [f64; 2] {
    [a[0] - b[0], a[1] - b[1]]
}

/// A spring-damper between two body points with a cubic stiffening term. Its partials are
/// central differences of its own forces (relative error ~1e-9), which is all this test needs:
/// it checks how the formulation chains them, not the element.
struct Spring {
    a: (usize, [f64; 2]),
    b: (usize, [f64; 2]),
    stiffness: f64,
    damping: f64,
}

impl Spring {
    fn point(
        &self,
        end: (usize, [f64; 2]),
        q: &[f64],
        qd: &[f64],
    ) -> ([f64; 2], [f64; 2], [f64; 2]) {
        let (b, s) = end;
        let arm = rotate(q[3 * b + 2], s);
        let w = qd[3 * b + 2];
        (
            add([q[3 * b], q[3 * b + 1]], arm),
            add([qd[3 * b], qd[3 * b + 1]], [-w * arm[1], w * arm[0]]),
            arm,
        )
    }
}

impl ForceElement for Spring {
    fn name(&self) -> &str {
        "spring"
    }
    fn add_forces(&self, _t: f64, q: &[f64], qd: &[f64], g: &mut [f64]) {
        let (pa, va, arm_a) = self.point(self.a, q, qd);
        let (pb, vb, arm_b) = self.point(self.b, q, qd);
        let d = sub(pb, pa);
        let v = sub(vb, va);
        let stretch = d[0] * d[0] + d[1] * d[1];
        let k = self.stiffness * (1.0 + stretch);
        let f = [
            -k * d[0] - self.damping * v[0],
            -k * d[1] - self.damping * v[1],
        ];
        for ((body, arm), sign) in [(self.b.0, arm_b), (self.a.0, arm_a)]
            .into_iter()
            .zip([1.0, -1.0])
        {
            g[3 * body] += sign * f[0];
            g[3 * body + 1] += sign * f[1];
            g[3 * body + 2] += sign * (arm[0] * f[1] - arm[1] * f[0]);
        }
    }
    fn add_partials(&self, t: f64, q: &[f64], qd: &[f64], partials: &mut ForcePartials<'_>) {
        let n = q.len();
        let h = 1e-6;
        for c in 0..2 * n {
            let shifted = |delta: f64| {
                let (mut q, mut qd) = (q.to_vec(), qd.to_vec());
                if c < n {
                    q[c] += delta;
                } else {
                    qd[c - n] += delta;
                }
                let mut g = vec![0.0; n];
                self.add_forces(t, &q, &qd, &mut g);
                g
            };
            let (plus, minus) = (shifted(h), shifted(-h));
            for r in 0..n {
                let value = (plus[r] - minus[r]) / (2.0 * h);
                if c < n {
                    partials.add_dq(r, c, value);
                } else {
                    partials.add_dqd(r, c - n, value);
                }
            }
        }
    }
}

fn mechanism() -> System {
    let mut model = Model::new();
    let mut body = |name: &str, pose: [f64; 3], velocity: [f64; 3]| {
        model
            .add_body(
                Body::new(name, 1.0 + pose[2].abs(), 0.1 + 0.05 * pose[0].abs(), pose)
                    .with_velocity(velocity),
            )
            .expect("valid body")
    };
    let t0 = 0.3;
    let r0 = rotate(t0, [0.5, 0.0]);
    let b0 = body("b0", [r0[0], r0[1], t0], [0.0; 3]);
    let tip = rotate(t0, [1.0, 0.0]);
    let t1 = -0.5;
    let r1 = sub(tip, rotate(t1, [-0.4, 0.05]));
    let b1 = body("b1", [r1[0], r1[1], t1], [0.1, -0.2, 0.3]);
    let t2 = 0.2;
    let axis = [1.0 / 1.04_f64.sqrt(), 0.2 / 1.04_f64.sqrt()];
    let base = add(r1, rotate(t1, [0.3, 0.0]));
    let ps = add(base, rotate(t1, [0.25 * axis[0], 0.25 * axis[1]]));
    let r2 = sub(ps, rotate(t2, [-0.1, 0.1]));
    let b2 = body("b2", [r2[0], r2[1], t2], [0.3, 0.1, -0.4]);
    let t3 = t2 - 0.4;
    let slider = add(r2, rotate(t2, [0.3, 0.0]));
    let pb = sub(slider, rotate(t3, [0.0, 0.1]));
    let r3 = sub(pb, rotate(t3, [0.2, -0.1]));
    let b3 = body("b3", [r3[0], r3[1], t3], [0.0, 0.2, 0.1]);
    let b4 = body("b4", [1.5, -0.5, 0.1], [0.2, 0.1, 0.5]);
    let hinge = add(r3, rotate(t3, [-0.3, 0.2]));
    let t5 = 1.0;
    let r5 = sub(hinge, rotate(t5, [-0.2, 0.0]));
    let b5 = body("b5", [r5[0], r5[1], t5], [0.0; 3]);
    let pin = add(r5, rotate(t5, [0.2, 0.0]));
    let on_b1 = rotate(-t1, sub(pin, r1));
    let g0 = model
        .add_revolute("g0", Anchor::ground(0.0, 0.0), Anchor::on(b0, -0.5, 0.0))
        .expect("valid");
    model
        .add_revolute("r1", Anchor::on(b1, -0.4, 0.05), Anchor::on(b0, 0.5, 0.0))
        .expect("valid");
    model
        .add_prismatic(
            "p2",
            Anchor::on(b1, 0.3, 0.0),
            [1.0, 0.2],
            Anchor::on(b2, -0.1, 0.1),
            RotationLock::Free,
        )
        .expect("valid");
    model
        .add_prismatic(
            "p3",
            Anchor::on(b3, 0.2, -0.1),
            [0.0, 1.0],
            Anchor::on(b2, 0.3, 0.0),
            RotationLock::At(0.4),
        )
        .expect("valid");
    // Body 5 hangs from body 3 and is pinned to body 1: the tree reaches it from body 1 (its
    // scan comes first), so the hinge on body 3 closes the loop and body 3 hangs from body 2
    // as the base of the locked prismatic.
    model
        .add_revolute(
            "hinge",
            Anchor::on(b3, -0.3, 0.2),
            Anchor::on(b5, -0.2, 0.0),
        )
        .expect("valid");
    model
        .add_revolute(
            "loop",
            Anchor::on(b5, 0.2, 0.0),
            Anchor::on(b1, on_b1[0], on_b1[1]),
        )
        .expect("valid");
    model
        .add_driver(
            "crank",
            DriveTarget::JointAngle(g0),
            Box::new(Harmonic {
                offset: t0,
                amplitude: 0.2,
                omega: 3.0,
            }),
        )
        .expect("valid");
    model
        .add_driver(
            "floating x",
            DriveTarget::Coordinate(b4, Coordinate::X),
            Box::new(Ramp {
                initial: 1.5,
                rate: 0.2,
            }),
        )
        .expect("valid");
    let gravity = Gravity::new(&model, [0.0, -9.81]);
    let mut system = System::new(model).expect("valid model");
    system.add_element(Box::new(gravity));
    for (a, b, stiffness) in [
        ((4, [0.1, 0.0]), (2, [0.2, -0.1]), 30.0),
        ((0, [0.3, 0.0]), (3, [-0.1, 0.1]), 50.0),
    ] {
        system.add_element(Box::new(Spring {
            a,
            b,
            stiffness,
            damping: 2.0,
        }));
    }
    system
}

#[test]
fn the_tree_keeps_only_the_loop_and_prescribes_both_drivers() {
    let system = mechanism();
    let tree = Tree::new(system.bodies().len(), system.joints(), system.constraints());
    // g0, r1: 1 each; p2 (free): 2; loop: 1; p3 (locked, base as child): 1; floating: 3.
    // The crank angle and the floating x are prescribed.
    assert_eq!(tree.coordinates, 9);
    assert_eq!(tree.free.len(), 7);
    assert_eq!(tree.prescribed.len(), 2);
    let labels: Vec<&str> = tree
        .kept
        .iter()
        .map(|&k| system.constraint_labels()[k].as_str())
        .collect();
    assert_eq!(labels, ["revolute 'hinge' x", "revolute 'hinge' y"]);
}

#[test]
fn exact_jacobian_matches_differences_of_the_right_hand_side() {
    let system = mechanism();
    let (q, qd) = system.initial_guess();
    let state = system.assemble(0.2, &q, &qd).expect("assembles");
    let tree = Tree::new(system.bodies().len(), system.joints(), system.constraints());
    let mut evaluator = JointEvaluator::new(&system, &tree, crate::Baumgarte::default());
    let x = evaluator.initial_state(&state);
    // The read-off coordinates reproduce the assembled state.
    let mut y = vec![0.0; 2 * system.coordinate_count()];
    evaluator.cartesian(0.2, &x, &mut y);
    let mapped: Vec<f64> = state.q.iter().chain(&state.qd).copied().collect();
    let mismatch = y
        .iter()
        .zip(&mapped)
        .map(|(a, b)| (a - b).abs())
        .fold(0.0, f64::max);
    assert!(mismatch < 1e-10, "{mismatch:e}");
    let size = x.len();
    let mut exact = DMatrix::zeros(size, size);
    evaluator
        .jacobian(system.elements(), 0.2, &x, &mut exact)
        .expect("nonsingular");
    // Central differences (forward differences would limit the check to ~1e-7).
    let mut numeric = DMatrix::zeros(size, size);
    let (mut plus, mut minus) = (vec![0.0; size], vec![0.0; size]);
    for c in 0..size {
        let h = 1e-6;
        let mut shifted = x.clone();
        shifted[c] = x[c] + h;
        evaluator
            .rhs(system.elements(), 0.2, &shifted, &mut plus)
            .expect("rhs");
        shifted[c] = x[c] - h;
        evaluator
            .rhs(system.elements(), 0.2, &shifted, &mut minus)
            .expect("rhs");
        for r in 0..size {
            numeric[(r, c)] = (plus[r] - minus[r]) / (2.0 * h);
        }
    }
    let scale = exact.amax();
    let error = (&exact - &numeric).amax() / scale;
    println!("joint-coordinate Jacobian vs central differences: {error:e} of {scale:e}");
    // Central differences at h = 1e-6 are good to ~1e-9 relative for these smooth forces.
    assert!(error < 1e-7, "relative error {error:e}");
}

#[test]
fn the_formulations_agree_on_the_motion() {
    let mut system = mechanism();
    let (q, qd) = system.initial_guess();
    let start = system.assemble(0.0, &q, &qd).expect("assembles");
    let mut options = SimulationOptions::until(2.0);
    options.rtol = 1e-10;
    options.atol = crate::AbsoluteTolerances::uniform(1e-11);
    options.output = OutputTimes::Every(0.1);
    let cartesian = system
        .simulate(&start, &options, &mut ())
        .expect("cartesian");
    options.formulation = Formulation::JointCoordinates;
    let joint = system.simulate(&start, &options, &mut ()).expect("joint");
    let (a, b) = (&cartesian.trajectory, &joint.trajectory);
    assert_eq!(a.len(), b.len());
    let mut worst: [f64; 4] = [0.0; 4];
    for frame in 0..a.len() {
        for (k, (x, y)) in [
            (a.q(frame), b.q(frame)),
            (a.qd(frame), b.qd(frame)),
            (a.qdd(frame), b.qdd(frame)),
            (a.lambda(frame), b.lambda(frame)),
        ]
        .into_iter()
        .enumerate()
        {
            let d = x
                .iter()
                .zip(y)
                .map(|(u, v)| (u - v).abs())
                .fold(0.0, f64::max);
            worst[k] = worst[k].max(d);
        }
    }
    println!(
        "cartesian {} steps, joint {} steps; largest differences q {:e}, q̇ {:e}, q̈ {:e}, λ {:e}; joint drift {:?}",
        cartesian.statistics.steps,
        joint.statistics.steps,
        worst[0],
        worst[1],
        worst[2],
        worst[3],
        joint.drift
    );
    // Both are converged to ~1e-9 over 2 s of a smooth, driven motion.
    assert!(worst[0] < 1e-7 && worst[1] < 1e-6, "{worst:?}");
    assert!(worst[2] < 1e-4 && worst[3] < 1e-4, "{worst:?}");
    let energy = joint.energy.expect("audited");
    assert!(energy.relative_residual() < 1e-6, "{energy:?}");
}
