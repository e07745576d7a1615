//! The error-controlled extrapolation of a stage
//! ([`Extrapolation::Controlled`](crate::Extrapolation::Controlled)): the predictor–corrector
//! sub-steps, their error estimate and the sampling noise it discounts.

use crate::accumulate::StageWear;
use crate::error::WearError;
use crate::joint::WornJoint;
use crate::staging::{
    RunContext, StagePlan, StageReport, StagingError, WearSample, apply_all,
    clearance_bounded_amplification, clearance_changes_per_amplification, limited_amplification,
    sample,
};

/// The settings of [`Extrapolation::Controlled`](crate::Extrapolation::Controlled).
#[derive(Clone, Copy)]
pub(crate) struct Control {
    pub(crate) tolerance: f64,
    pub(crate) min_fraction: f64,
    pub(crate) max_fraction: f64,
    pub(crate) max_runs: usize,
}

impl Control {
    /// Bounds on how fast the step may change from one sub-step to the next.
    const GROWTH: (f64, f64) = (0.5, 2.0);
    /// Safety factor of the step choice.
    const SAFETY: f64 = 0.9;

    /// The factor on the step after a sub-step with error estimate `estimate` of `order`.
    fn factor(&self, estimate: f64, order: i32) -> f64 {
        let (shrink, grow) = Self::GROWTH;
        if estimate > 0.0 {
            (Self::SAFETY * (self.tolerance / estimate).powf(1.0 / f64::from(order)))
                .clamp(shrink, grow)
        } else {
            grow
        }
    }
}

/// A stage of [`Extrapolation::Controlled`](crate::Extrapolation::Controlled) sub-steps (see
/// there).
pub(crate) fn run_stage<E, W, F>(
    joints: &mut [WornJoint],
    plan: &StagePlan,
    control: Control,
    runner: &mut F,
    mut report: StageReport,
) -> Result<StageReport, StagingError<E>>
where
    W: Into<WearSample>,
    F: FnMut(RunContext, &[WornJoint]) -> Result<W, E>,
{
    let stage = report.stage;
    let context = |run: usize, used: f64| RunContext {
        stage,
        substep: run,
        applied: used / plan.amplification,
    };
    // The rate at the sub-step's start and the run it came from.
    let mut start = sample(runner, context(0, 0.0), joints)?;
    let mut noise = NoiseLevel::new(joints.len());
    noise.add(&start);
    let mut start_run = 0;
    // The rate and amplification of the sub-step before (for the second-order estimate).
    let mut previous: Option<(WearSample, f64)> = None;
    report.run_weights.push(0.0);
    let mut used = 0.0;
    let mut proposed: Option<f64> = None;
    loop {
        let remaining = plan.amplification - used;
        // The first step, and the floor: sampling noise that the halves do not remove keeps
        // the estimate from falling with the step, so no step is cut below the fixed bound's.
        // A forming joint lowers both (infinite: no clearance changes).
        let per_unit = clearance_changes_per_amplification(joints, &start.wear)?;
        let bounded = |fraction| {
            clearance_bounded_amplification(joints, &per_unit, fraction, plan.forming.as_ref())
        };
        let (floor, cap) = (bounded(control.min_fraction), bounded(control.max_fraction));
        let limit = noise_limited_amplification(
            joints.len(),
            &noise,
            control.tolerance,
            plan.amplification,
        );
        // The noise bound holds the floor too: below it the steps would not end (the noise of
        // a tight tolerance asks for ρ/(2·tolerance²) sub-steps, 1e4 at 1e-3), and at the
        // floor the sub-steps are the fixed bound's, whose noise the stage then carries.
        let mut step = proposed
            .unwrap_or(floor)
            .max(floor)
            .min(cap)
            .min(limit.max(floor));
        if step * (1.0 + 1e-9) >= remaining {
            step = remaining;
        }
        if report.run_weights.len() >= control.max_runs {
            return Err(WearError::SubstepLimit {
                stage,
                limit: control.max_runs,
                remaining,
            }
            .into());
        }
        let run = report.run_weights.len();
        let mut predicted = joints.to_vec();
        apply_all(&mut predicted, &start.wear, step, context(run, used))?;
        let end = sample(runner, context(run, used), &predicted)?;
        noise.add(&end);
        report.run_weights.push(0.0);
        let (estimate, order) = error_estimate(
            previous.as_ref().map(|(w, a)| (w, *a)),
            &start,
            &end,
            step,
            &noise,
        );
        proposed = Some(step * control.factor(estimate, order));
        if estimate > control.tolerance && step > floor * (1.0 + 1e-9) {
            continue;
        }
        let mean: Vec<StageWear> = start
            .wear
            .iter()
            .zip(&end.wear)
            .map(|(a, b)| {
                let mut m = a.clone();
                m.add(b);
                m.scale(0.5);
                m
            })
            .collect();
        let limited = limited_amplification(plan, joints, &mean)?;
        let at_limits = limited < step;
        let step = if at_limits { limited } else { step };
        if step > 0.0 {
            let mut substep = apply_all(joints, &mean, step, context(run, used))?;
            substep.error_estimate = Some(estimate);
            report.run_weights[start_run] += 0.5 * step;
            report.run_weights[run] += 0.5 * step;
            used += step;
            if report.push_substep(substep, plan, joints) && !at_limits {
                return Ok(report);
            }
        }
        if at_limits {
            report.ended_at_limits = Some(used);
            return Ok(report);
        }
        if step == remaining {
            return Ok(report);
        }
        previous = Some((std::mem::replace(&mut start, end), step));
        start_run = run;
    }
}

/// The sampling noise of the runs' wear, pooled over a stage: per joint, the mean over the
/// runs so far of the halves' relative noise power `Σ (u − v)² / Σ w²` (for a sum of two
/// independent halves `E[(u − v)²] = Var(u + v)`). One run's pair of halves is a poor estimate
/// of its own noise (the wear of a few cycles is dominated by a few impacts), the mean over
/// the stage's runs a steadier one.
struct NoiseLevel {
    sums: Vec<f64>,
    runs: usize,
}

impl NoiseLevel {
    fn new(joints: usize) -> Self {
        Self {
            sums: vec![0.0; joints],
            runs: 0,
        }
    }

    /// Adds a run's halves (nothing without them).
    fn add(&mut self, sample: &WearSample) {
        let Some(halves) = &sample.halves else {
            return;
        };
        for ((sum, w), [u, v]) in self.sums.iter_mut().zip(&sample.wear).zip(halves) {
            let size = squared_norm(w);
            if size > 0.0 {
                *sum += squared_difference(u, v) / size;
            }
        }
        self.runs += 1;
    }

    /// Joint `j`'s pooled relative noise power of one run (0 before any halves).
    fn ratio(&self, j: usize) -> f64 {
        if self.runs == 0 {
            0.0
        } else {
            self.sums.get(j).copied().unwrap_or(0.0) / self.runs as f64
        }
    }
}

/// The largest amplification of a sub-step such that the sampling noise the stage's wear
/// gathers stays near `tolerance` of it: with a run's relative noise power `ρ` per joint
/// ([`NoiseLevel`]), a sub-step of amplification `a` applies the mean of two rates, with
/// noise power about `a²ρ‖w‖²/2`; keeping `a·ρ/2 ≤ tolerance²·A` for every sub-step of a stage
/// of amplification `A` keeps the sum within `tolerance²·(A·‖w‖)²`, i.e. the stage's wear
/// within `tolerance` of its expectation (root mean square over the cells). Infinite without
/// halves or noise.
fn noise_limited_amplification(
    joints: usize,
    noise: &NoiseLevel,
    tolerance: f64,
    stage: f64,
) -> f64 {
    (0..joints)
        .map(|j| noise.ratio(j))
        .filter(|ratio| *ratio > 0.0)
        .map(|ratio| 2.0 * tolerance * tolerance * stage / ratio)
        .fold(f64::INFINITY, f64::min)
}

/// `Σ w²` over both surfaces' cells of a record.
fn squared_norm(w: &StageWear) -> f64 {
    w.bearing().iter().chain(w.pin()).map(|x| x * x).sum()
}

/// `Σ (a − b)²` over both surfaces' cells of two records of the same joint.
fn squared_difference(a: &StageWear, b: &StageWear) -> f64 {
    a.bearing()
        .iter()
        .zip(b.bearing())
        .chain(a.pin().iter().zip(b.pin()))
        .map(|(x, y)| (x - y).powi(2))
        .sum()
}

/// The controlled extrapolation's error estimate of a sub-step of amplification `step` from
/// the rate `start` to the rate `end`, per unit of its wear, with the order of the step size
/// it grows with (see [`Extrapolation::Controlled`](crate::Extrapolation::Controlled)).
///
/// With the sub-step before it (`previous`: its starting rate and amplification), the
/// trapezoid's own local error `(a³/12)·w''`, `w''` from the second divided difference of the
/// three rates (order 2). For the stage's first sub-step, the explicit predictor's local error
/// `(a/2)·(w* − w)` (order 1), which bounds it. Either way, per joint,
/// `scale·sqrt(max(D − N, 0) / S)` with `D` the squared norm of the rates' combination over the
/// cells, `N` its expected value from sampling noise alone (the combination's squared
/// coefficients times each rate's `Σ (first half − second half)²`: for a sum of two independent
/// halves `E[(u − v)²] = Var(u + v)`) and `S` the squared norm of the sub-step's mean rate;
/// the largest over the joints.
fn error_estimate(
    previous: Option<(&WearSample, f64)>,
    start: &WearSample,
    end: &WearSample,
    step: f64,
    noise: &NoiseLevel,
) -> (f64, i32) {
    let (terms, scale, order) = match previous {
        Some((before, a_before)) => (
            vec![
                (before, 1.0 / a_before),
                (start, -(1.0 / step + 1.0 / a_before)),
                (end, 1.0 / step),
            ],
            step * step / (6.0 * (step + a_before)),
            2,
        ),
        None => (vec![(start, -1.0), (end, 1.0)], 0.5, 1),
    };
    let mut largest: f64 = 0.0;
    for (j, (a, b)) in start.wear.iter().zip(&end.wear).enumerate() {
        let size: f64 = a
            .bearing()
            .iter()
            .zip(b.bearing())
            .chain(a.pin().iter().zip(b.pin()))
            .map(|(x, y)| (0.5 * (x + y)).powi(2))
            .sum();
        let cells = a.bearing().len() + a.pin().len();
        let mut combination = vec![0.0; cells];
        let mut expected_noise = 0.0;
        for (sample, coefficient) in &terms {
            let w = &sample.wear[j];
            for (c, x) in combination
                .iter_mut()
                .zip(w.bearing().iter().chain(w.pin()))
            {
                *c += coefficient * x;
            }
            expected_noise += coefficient * coefficient * noise.ratio(j) * squared_norm(w);
        }
        let difference: f64 = combination.iter().map(|c| c * c).sum();
        if size > 0.0 {
            largest = largest.max(scale * ((difference - expected_noise).max(0.0) / size).sqrt());
        }
    }
    (largest, order)
}
