//! The counter counts: what a kernel test's "0 allocations" rests on.

use alloc_count::{CountingAllocator, allocations_of};

#[global_allocator]
static GLOBAL: CountingAllocator = CountingAllocator;

#[test]
fn counts_each_allocation_and_reallocation_of_its_thread_and_nothing_else() {
    let mut sum = 0u64;
    assert_eq!(allocations_of(|| sum = (1..=10u64).sum()), 0);
    assert_eq!(sum, 55);
    let mut kept = Vec::new();
    assert_eq!(
        allocations_of(|| {
            kept = Vec::<u64>::with_capacity(4);
            kept.extend([1, 2, 3, 4]);
        }),
        1
    );
    // Growing past the capacity reallocates: counted too.
    assert_eq!(allocations_of(|| kept.extend([5, 6, 7, 8, 9])), 1);
    // Another thread's allocations are its own.
    let other = std::thread::spawn(|| allocations_of(|| drop(vec![0u8; 64])));
    assert_eq!(allocations_of(|| {}), 0);
    assert_eq!(other.join().expect("the thread ran"), 1);
}
