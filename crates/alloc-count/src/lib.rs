//! Test support: a global allocator that counts the allocations of each thread, so that a test
//! can prove a hot kernel (a right-hand side, a Jacobian, a contact force) allocates nothing.
//!
//! A test binary installs it once and measures a closure:
//!
//! ```ignore
//! #[global_allocator]
//! static GLOBAL: alloc_count::CountingAllocator = alloc_count::CountingAllocator;
//!
//! let count = alloc_count::allocations_of(|| kernel(&mut scratch));
//! assert_eq!(count, 0);
//! ```
//!
//! The count is per thread, so tests running in parallel in the same binary do not disturb
//! each other's counts. Without the allocator installed, [`allocations_of`] returns 0 for
//! everything: install it in every test file that uses it.

use std::alloc::{GlobalAlloc, Layout, System};
use std::cell::Cell;

thread_local! {
    /// Allocations made on this thread since it started.
    static ALLOCATIONS: Cell<usize> = const { Cell::new(0) };
}

/// The system allocator, counting every allocation (and reallocation) of the thread that
/// makes it.
pub struct CountingAllocator;

// SAFETY: every call is forwarded to the system allocator unchanged; counting touches only a
// const-initialised thread-local `Cell` without a destructor, which does not allocate.
unsafe impl GlobalAlloc for CountingAllocator {
    unsafe fn alloc(&self, layout: Layout) -> *mut u8 {
        ALLOCATIONS.with(|a| a.set(a.get() + 1));
        // SAFETY: the caller's contract for `alloc` is passed on.
        unsafe { System.alloc(layout) }
    }

    unsafe fn dealloc(&self, ptr: *mut u8, layout: Layout) {
        // SAFETY: the caller's contract for `dealloc` is passed on.
        unsafe { System.dealloc(ptr, layout) }
    }

    unsafe fn realloc(&self, ptr: *mut u8, layout: Layout, new_size: usize) -> *mut u8 {
        ALLOCATIONS.with(|a| a.set(a.get() + 1));
        // SAFETY: the caller's contract for `realloc` is passed on.
        unsafe { System.realloc(ptr, layout, new_size) }
    }
}

/// The allocations `f` made on this thread (0 unless [`CountingAllocator`] is the global
/// allocator of the test binary).
pub fn allocations_of(f: impl FnOnce()) -> usize {
    let before = ALLOCATIONS.with(Cell::get);
    f();
    ALLOCATIONS.with(Cell::get) - before
}
