//! The right-hand side and its exact Jacobian do not allocate.

mod common;

use alloc_count::{CountingAllocator, allocations_of};
use common::{SliderCrank, SpringDamper, with_gravity_and_spring};
use multibody::{Baumgarte, Equations};
use nalgebra::DMatrix;

#[global_allocator]
static GLOBAL: CountingAllocator = CountingAllocator;

#[test]
fn rhs_and_jacobian_do_not_allocate() {
    let (model, _) = SliderCrank::STANDARD.model(0.9);
    let system = with_gravity_and_spring(model, SpringDamper::SOFT);
    let (q, qd) = system.initial_guess();
    let y: Vec<f64> = q.iter().chain(&qd).copied().collect();
    let mut dy = vec![0.0; y.len()];
    let mut jacobian = DMatrix::zeros(y.len(), y.len());
    let mut evaluator = system.evaluator(Baumgarte::default());
    let elements = system.elements();
    let allocations = allocations_of(|| {
        for k in 0..10 {
            let t = 0.1 * k as f64;
            evaluator.rhs(elements, t, &y, &mut dy).expect("regular");
            evaluator
                .jacobian(elements, t, &y, &mut jacobian)
                .expect("regular");
        }
    });
    assert_eq!(allocations, 0);
}
