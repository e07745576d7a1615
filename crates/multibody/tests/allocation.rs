//! The right-hand side and its exact Jacobian do not allocate.

mod common;

use std::alloc::{GlobalAlloc, Layout, System as SystemAllocator};
use std::cell::Cell;

use common::{SliderCrank, SpringDamper, with_gravity_and_spring};
use multibody::{Baumgarte, Equations};
use nalgebra::DMatrix;

thread_local! {
    static ALLOCATIONS: Cell<usize> = const { Cell::new(0) };
}

struct Counting;

unsafe impl GlobalAlloc for Counting {
    unsafe fn alloc(&self, layout: Layout) -> *mut u8 {
        ALLOCATIONS.with(|a| a.set(a.get() + 1));
        unsafe { SystemAllocator.alloc(layout) }
    }
    unsafe fn dealloc(&self, ptr: *mut u8, layout: Layout) {
        unsafe { SystemAllocator.dealloc(ptr, layout) }
    }
}

#[global_allocator]
static GLOBAL: Counting = Counting;

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
    let before = ALLOCATIONS.with(Cell::get);
    for k in 0..10 {
        let t = 0.1 * k as f64;
        evaluator.rhs(elements, t, &y, &mut dy).expect("regular");
        evaluator
            .jacobian(elements, t, &y, &mut jacobian)
            .expect("regular");
    }
    assert_eq!(ALLOCATIONS.with(Cell::get) - before, 0);
}
