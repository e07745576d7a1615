//! Summary numbers of a run: peak statistics over cycles, deviations from the ideal
//! mechanism, numerics and energy books.

use multibody::SimulationResult;

use super::{Deviation, JointSummary, Numerics, PeakStats, Response, ResponseSummary};
use crate::build::{BuiltScene, JointHandle};
use scene::Scene;

/// What a dynamic run leaves for its energy books.
pub(super) struct Audit<'a> {
    pub(super) built: &'a BuiltScene,
    pub(super) result: &'a SimulationResult,
    pub(super) joints: &'a [JointHandle],
    /// Elastic energy stored in each joint at the start (joint order).
    pub(super) initial_energy: &'a [f64],
}

/// Energy books of one joint over a run (J, totals).
#[derive(Default)]
struct JointBooks {
    friction: f64,
    damping: f64,
    stored_start: f64,
    stored_end: f64,
    audited: f64,
}

impl Audit<'_> {
    fn books(&self, k: usize, name: &str) -> JointBooks {
        let probe = self
            .joints
            .get(k)
            .and_then(|h| h.probe(self.built.system.elements()));
        let work = self
            .result
            .energy
            .as_ref()
            .and_then(|e| e.element_work.iter().find(|(n, _)| n == name))
            .map_or(0.0, |(_, w)| *w);
        let stored_start = self.initial_energy.get(k).copied().unwrap_or(0.0);
        let stored_end = probe
            .and_then(|p| p.last_diagnostics())
            .map_or(0.0, |d| d.elastic_energy);
        JointBooks {
            friction: probe.map_or(0.0, |p| p.friction_dissipation()),
            damping: probe.map_or(0.0, |p| p.damping_dissipation()),
            stored_start,
            stored_end,
            audited: -work - (stored_end - stored_start),
        }
    }
}

/// Energy per cycle (J) below which the books count as closed: a dissipation this small counts
/// as round-off, not as energy put in, and a difference between the audited dissipation and
/// damping + friction this small as integration error (the report's verdict).
pub const ENERGY_BOOKS_TOLERANCE_J: f64 = 0.05;

pub(super) fn summarize(
    scene: &Scene,
    response: &Response,
    audit: Option<Audit<'_>>,
    cycles: u32,
    t_end: f64,
) -> ResponseSummary {
    let period = scene.cycle_period().unwrap_or(t_end);
    let window = scene.run.transient_window;
    let per_cycle = 1.0 / f64::from(cycles);
    let mut joint_summaries = Vec::new();
    let (mut dissipated, mut friction, mut damping) = (0.0, 0.0, 0.0);
    let mut energy_warnings = Vec::new();
    for (k, series) in response.contact.iter().enumerate() {
        let books = audit
            .as_ref()
            .map_or_else(JointBooks::default, |a| a.books(k, &series.name));
        dissipated += books.audited;
        friction += books.friction;
        damping += books.damping;
        for (what, value) in [
            ("its contact force", books.audited),
            ("its normal force's damping", books.damping),
            ("its friction", books.friction),
        ] {
            if value * per_cycle < -ENERGY_BOOKS_TOLERANCE_J {
                energy_warnings.push(format!(
                    "joint {}: {what} put {:.3} J per cycle INTO the mechanism (negative \
                     dissipation): the contact is not dissipative on these surfaces, so its \
                     forces are not physical results",
                    series.name,
                    -value * per_cycle
                ));
            }
        }
        let after_transient = Some(peak_stats(
            &response.times,
            &series.normal_force,
            &series.elastic_force,
            period,
            window,
        ))
        .filter(|p| p.cycles > 0);
        let validity = series.validity.clone().map(|mut v| {
            if let Some(p) = &after_transient {
                v.judge_elastic_share(p.elastic_share_median);
            }
            v
        });
        joint_summaries.push(JointSummary {
            name: series.name.clone(),
            clearance_m: series.clearance,
            normal_force_all: peak_stats(
                &response.times,
                &series.normal_force,
                &series.elastic_force,
                period,
                0.0,
            ),
            normal_force_after_transient: after_transient,
            max_penetration_m: series.penetration.iter().copied().fold(f64::MIN, f64::max),
            max_eccentricity_m: series.eccentricity.iter().copied().fold(0.0, f64::max),
            validity,
            friction_dissipation_per_cycle_j: books.friction * per_cycle,
            damping_dissipation_per_cycle_j: books.damping * per_cycle,
            elastic_energy_start_j: books.stored_start,
            elastic_energy_end_j: books.stored_end,
            contact_dissipation_per_cycle_j: books.audited * per_cycle,
            energy_books_residual_per_cycle_j: (books.audited - books.damping - books.friction)
                * per_cycle,
        });
    }
    ResponseSummary {
        cycles,
        duration_s: t_end,
        joints: joint_summaries,
        deviation: deviation(response, 0.0),
        deviation_after_transient: response
            .times
            .iter()
            .any(|t| *t >= window)
            .then(|| deviation(response, window)),
        dissipated_per_cycle_j: dissipated * per_cycle,
        friction_per_cycle_j: friction * per_cycle,
        damping_per_cycle_j: damping * per_cycle,
        energy_warnings,
        numerics: audit.map(|a| numerics(a.result)),
    }
}

pub(super) fn numerics(r: &SimulationResult) -> Numerics {
    let s = &r.statistics;
    Numerics {
        steps: s.steps,
        rejected_steps: s.rejected_steps,
        rhs_evaluations: s.rhs_evaluations,
        jacobian_evaluations: s.jacobian_evaluations,
        factorizations: s.factorizations,
        smallest_step_s: s.smallest_step,
        largest_step_s: s.largest_step,
        events: s.events,
        drift_position: r.drift.position,
        drift_velocity: r.drift.velocity,
        energy_residual_j: r.energy.as_ref().map_or(f64::NAN, |e| e.residual),
        energy_relative_residual: r
            .energy
            .as_ref()
            .map_or(f64::NAN, |e| e.relative_residual()),
        wall_time_s: s.wall_time.as_secs_f64(),
    }
}

/// Per-cycle peaks of `values` for samples at `t ≥ from`, with the elastic share
/// `elastic/value` at each cycle's peak sample (`elastic` may be empty: no shares).
pub fn peak_stats(
    times: &[f64],
    values: &[f64],
    elastic: &[f64],
    period: f64,
    from: f64,
) -> PeakStats {
    // Per cycle: (peak, elastic share at the peak).
    let mut peaks: Vec<(f64, f64)> = Vec::new();
    let mut current: Option<(usize, f64, f64)> = None;
    for (k, (t, v)) in times.iter().zip(values).enumerate() {
        if *t < from {
            continue;
        }
        let share = match elastic.get(k) {
            Some(e) if *v > 0.0 => e / v,
            _ => f64::NAN,
        };
        // A sample exactly at the end of the run belongs to the last cycle.
        let cycle = ((t / period) * (1.0 - 1e-12)).floor().max(0.0) as usize;
        match current {
            Some((c, peak, _)) if c == cycle && peak >= *v => {}
            Some((c, _, _)) if c == cycle => current = Some((c, *v, share)),
            Some((_, peak, peak_share)) => {
                peaks.push((peak, peak_share));
                current = Some((cycle, *v, share));
            }
            None => current = Some((cycle, *v, share)),
        }
    }
    peaks.extend(current.map(|(_, p, s)| (p, s)));
    if peaks.is_empty() {
        return PeakStats::default();
    }
    let mut shares: Vec<f64> = peaks
        .iter()
        .map(|p| p.1)
        .filter(|s| s.is_finite())
        .collect();
    let mut peaks: Vec<f64> = peaks.into_iter().map(|p| p.0).collect();
    peaks.sort_by(f64::total_cmp);
    shares.sort_by(f64::total_cmp);
    PeakStats {
        max: peaks[peaks.len() - 1],
        cycles: peaks.len(),
        cycle_median: quantile(&peaks, 0.5),
        cycle_min: peaks[0],
        cycle_max: peaks[peaks.len() - 1],
        cycle_iqr: quantile(&peaks, 0.75) - quantile(&peaks, 0.25),
        cycle_median_noise: median_bootstrap_noise(&peaks),
        elastic_share_median: if shares.is_empty() {
            f64::NAN
        } else {
            quantile(&shares, 0.5)
        },
        elastic_share_min: shares.first().copied().unwrap_or(f64::NAN),
    }
}

/// The `q`-quantile of sorted, non-empty `values`, interpolated linearly.
fn quantile(values: &[f64], q: f64) -> f64 {
    let x = q * (values.len() - 1) as f64;
    let (lo, hi) = (x.floor() as usize, x.ceil() as usize);
    values[lo] + (x - lo as f64) * (values[hi] - values[lo])
}

/// Bootstrap resamples behind [`median_bootstrap_noise`].
const BOOTSTRAP_RESAMPLES: usize = 2000;

/// The standard deviation of the median of `sorted` over [`BOOTSTRAP_RESAMPLES`] resamples drawn
/// with replacement: the sampling noise of a median of per-cycle peaks. Deterministic (a fixed
/// SplitMix64 stream), so a run's summary is reproducible; 0 for fewer than two values.
pub fn median_bootstrap_noise(sorted: &[f64]) -> f64 {
    let n = sorted.len();
    if n < 2 {
        return 0.0;
    }
    let mut state: u64 = 0x9E37_79B9_7F4A_7C15;
    let mut next = move || {
        state = state.wrapping_add(0x9E37_79B9_7F4A_7C15);
        let mut z = state;
        z = (z ^ (z >> 30)).wrapping_mul(0xBF58_476D_1CE4_E5B9);
        z = (z ^ (z >> 27)).wrapping_mul(0x94D0_49BB_1331_11EB);
        z ^ (z >> 31)
    };
    let mut sample = vec![0.0; n];
    let (mut sum, mut sum_sq) = (0.0, 0.0);
    for _ in 0..BOOTSTRAP_RESAMPLES {
        for slot in sample.iter_mut() {
            // Multiply-shift: an index in 0..n without modulo bias worth the name (n ≪ 2³²).
            *slot = sorted[(((next() >> 32) * n as u64) >> 32) as usize];
        }
        sample.sort_by(f64::total_cmp);
        let m = quantile(&sample, 0.5);
        sum += m;
        sum_sq += m * m;
    }
    let mean = sum / BOOTSTRAP_RESAMPLES as f64;
    (sum_sq / BOOTSTRAP_RESAMPLES as f64 - mean * mean)
        .max(0.0)
        .sqrt()
}

pub(super) fn deviation(r: &Response, from: f64) -> Deviation {
    let mut d = [0.0f64; 6];
    let (a, b) = (r.motion.series(), r.ideal.series());
    for (k, t) in r.times.iter().enumerate() {
        if *t < from {
            continue;
        }
        for c in 0..6 {
            if let (Some(x), Some(y)) = (a[c].get(k), b[c].get(k)) {
                d[c] = d[c].max((x - y).abs());
            }
        }
    }
    Deviation {
        x_m: d[0],
        y_m: d[1],
        vx_m_s: d[2],
        vy_m_s: d[3],
        ax_m_s2: d[4],
        ay_m_s2: d[5],
    }
}

/// Largest disagreement of the two halves of a stage's simulated cycles, each extrapolated
/// alone (their peak depths and worn volumes, relative to the mean), for which the stage's
/// wear counts as converged in K. The stage's result averages both halves, so its own sampling
/// noise is about `1/√2` of this.
pub const STAGE_HALVES_TOLERANCE: f64 = 0.1;

#[cfg(test)]
mod tests {
    use super::*;

    /// For a large sample from a normal distribution the median's standard error is
    /// `√(π/2) σ/√n` (asymptotic); the bootstrap must find it within 15 % (its own resampling
    /// noise at 2000 resamples is ~2 %, the rest is the finite sample).
    #[test]
    fn bootstrap_noise_of_the_median_matches_the_normal_closed_form() {
        let n = 201;
        // Evenly spaced normal quantiles (σ = 1) by bisection on the error function's series.
        let cdf = |x: f64| 0.5 * (1.0 + erf(x / std::f64::consts::SQRT_2));
        let sample: Vec<f64> = (0..n)
            .map(|k| {
                let p = (k as f64 + 0.5) / n as f64;
                let (mut lo, mut hi) = (-10.0, 10.0);
                for _ in 0..80 {
                    let mid = 0.5 * (lo + hi);
                    if cdf(mid) < p { lo = mid } else { hi = mid }
                }
                0.5 * (lo + hi)
            })
            .collect();
        let expected = (std::f64::consts::PI / 2.0).sqrt() / (n as f64).sqrt();
        let noise = median_bootstrap_noise(&sample);
        assert!(
            (noise / expected - 1.0).abs() < 0.15,
            "{noise} vs {expected}"
        );
        assert_eq!(median_bootstrap_noise(&sample[..1]), 0.0);
        // Constant peaks have no noise.
        assert_eq!(median_bootstrap_noise(&[3.0; 7]), 0.0);
    }

    /// Abramowitz & Stegun 7.1.26 (|error| < 1.5e-7), enough for the quantiles above.
    fn erf(x: f64) -> f64 {
        let t = 1.0 / (1.0 + 0.327_591_1 * x.abs());
        let poly = t
            * (0.254_829_592
                + t * (-0.284_496_736
                    + t * (1.421_413_741 + t * (-1.453_152_027 + t * 1.061_405_429))));
        (1.0 - poly * (-x * x).exp()).copysign(x)
    }

    /// The elastic share is read at each cycle's peak sample, not elsewhere in the cycle.
    #[test]
    fn the_elastic_share_is_taken_at_each_cycles_peak() {
        // Two cycles of four samples; the peaks (10 and 20) carry elastic parts 4 and 18.
        let times = [0.0, 0.25, 0.5, 0.75, 1.0, 1.25, 1.5, 1.75];
        let force = [1.0, 10.0, 2.0, 0.0, 5.0, 6.0, 20.0, 1.0];
        let elastic = [1.0, 4.0, 2.0, 0.0, 5.0, 6.0, 18.0, 1.0];
        let p = peak_stats(&times, &force, &elastic, 1.0, 0.0);
        assert_eq!(p.cycles, 2);
        assert_eq!(p.cycle_median, 15.0);
        assert_eq!(p.elastic_share_min, 0.4);
        assert!((p.elastic_share_median - 0.65).abs() < 1e-12);
        // Without an elastic series the share is unknown, not zero.
        assert!(
            peak_stats(&times, &force, &[], 1.0, 0.0)
                .elastic_share_median
                .is_nan()
        );
    }
}
