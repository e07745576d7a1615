//! Cost of one right-hand side and one Jacobian (exact vs forward differences) on a four-bar
//! under gravity: `cargo bench -p multibody --bench evaluation`.

use std::hint::black_box;

use criterion::{Criterion, criterion_group, criterion_main};
use multibody::{Anchor, Baumgarte, Body, Gravity, Model, System};
use nalgebra::DMatrix;

fn four_bar() -> System {
    let mut model = Model::new();
    let guess = [
        ("crank", 0.2, [0.07, 0.07, 0.785]),
        ("coupler", 0.5, [0.35, 0.25, 0.1]),
        ("rocker", 0.4, [0.5, 0.15, 1.8]),
    ];
    let ids: Vec<_> = guess
        .iter()
        .map(|(name, length, pose)| {
            model
                .add_body(Body::new(*name, 1.0, length * length / 12.0, *pose))
                .expect("valid body")
        })
        .collect();
    let joints = [
        (Anchor::ground(0.0, 0.0), Anchor::on(ids[0], -0.1, 0.0)),
        (Anchor::on(ids[0], 0.1, 0.0), Anchor::on(ids[1], -0.25, 0.0)),
        (Anchor::on(ids[1], 0.25, 0.0), Anchor::on(ids[2], 0.2, 0.0)),
        (Anchor::ground(0.45, 0.0), Anchor::on(ids[2], -0.2, 0.0)),
    ];
    for (k, (i, j)) in joints.into_iter().enumerate() {
        model
            .add_revolute(format!("J{k}"), i, j)
            .expect("valid joint");
    }
    let gravity = Gravity::new(&model, [0.0, -9.81]);
    let mut system = System::new(model).expect("valid model");
    system.add_element(Box::new(gravity));
    system
}

fn evaluation(c: &mut Criterion) {
    let system = four_bar();
    let (q, qd) = system.initial_guess();
    let state = system.assemble(0.0, &q, &qd).expect("assembles");
    let mut y: Vec<f64> = state.q.iter().chain(&state.qd).copied().collect();
    let size = y.len();
    y[size - 1] = 1.0;
    let mut dy = vec![0.0; size];
    let mut jacobian = DMatrix::zeros(size, size);
    let mut evaluator = system.evaluator(Baumgarte::default());
    let elements = system.elements();
    c.bench_function("four-bar rhs", |b| {
        b.iter(|| evaluator.rhs(elements, 0.0, black_box(&y), &mut dy))
    });
    c.bench_function("four-bar exact jacobian", |b| {
        b.iter(|| evaluator.jacobian(elements, 0.0, black_box(&y), &mut jacobian))
    });
    c.bench_function("four-bar finite-difference jacobian", |b| {
        b.iter(|| evaluator.finite_difference_jacobian(elements, 0.0, black_box(&y), &mut jacobian))
    });
}

criterion_group!(benches, evaluation);
criterion_main!(benches);
