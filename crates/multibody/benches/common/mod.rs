//! Medians for the benches. Criterion's console line is a mean-based estimate; the project
//! quotes medians, which are robust to the noise of a shared machine. This module is also
//! included by `crates/sim/benches/lgres_cycle.rs` (`#[path]`), so there is one copy.

use std::hint::black_box;
use std::time::{Duration, Instant};

use criterion::BenchmarkGroup;
use criterion::measurement::WallTime;

/// Benchmarks `routine` as `name` in `group` (called `group_name`, for the printed line) with `sample_size` samples and prints the median
/// of criterion's samples (time per iteration). `setup` makes each iteration's input outside
/// the timed region (all inputs of a sample are made before its clock starts, all outputs
/// dropped after it stops). Returns the
/// median, or `None` if criterion did not run the bench (filtered out).
pub fn bench_median<I, O>(
    group: &mut BenchmarkGroup<'_, WallTime>,
    group_name: &str,
    name: &str,
    sample_size: usize,
    mut setup: impl FnMut() -> I,
    mut routine: impl FnMut(I) -> O,
) -> Option<Duration> {
    let mut per_iteration = Vec::new();
    group.sample_size(sample_size);
    group.bench_function(name, |b| {
        b.iter_custom(|iterations| {
            let inputs: Vec<I> = (0..iterations).map(|_| setup()).collect();
            let mut outputs = Vec::with_capacity(inputs.len());
            let start = Instant::now();
            for input in inputs {
                outputs.push(black_box(routine(black_box(input))));
            }
            let elapsed = start.elapsed();
            drop(outputs);
            per_iteration.push(elapsed.as_secs_f64() / iterations as f64);
            elapsed
        })
    });
    // Warm-up calls come first; the last `sample_size` calls are the measured samples.
    let skip = per_iteration.len().saturating_sub(sample_size);
    let mut samples = per_iteration.split_off(skip);
    if samples.is_empty() {
        return None;
    }
    samples.sort_by(f64::total_cmp);
    let median = Duration::from_secs_f64(samples[samples.len() / 2]);
    println!(
        "median {group_name}/{name}: {median:.3?} per iteration ({} samples)",
        samples.len()
    );
    Some(median)
}
