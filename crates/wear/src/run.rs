//! Running a plan's stages ([`run_stages`], [`run_stage`]): the adaptive and single-jump
//! sub-steps here, the error-controlled ones in `controlled`; the plan, the runner's context
//! and sample, the reports and the sub-step update both share are in `staging`.

use crate::accumulate::StageWear;
use crate::controlled::{self, Control};
use crate::error::WearError;
use crate::joint::WornJoint;
use crate::noise::{NOISE_GROUPS, NoiseBatches, noise_fraction};
use crate::staging::{
    Extrapolation, ExtrapolationWarning, RunContext, StagePlan, StageReport, StagingError,
    WearSample, WearStepping, apply_all, clearance_bounded_amplification,
    clearance_changes_per_amplification, limited_amplification, sample,
};

/// Runs all stages of `plan` on `joints` (all joints of the mechanism that wear, updated
/// together so one sub-step bound covers them all).
///
/// `runner(context, joints)` must simulate the K cycles on the joints as given (frozen) and
/// return one [`StageWear`] per joint, same order, as a `Vec` or a [`WearSample`] with the
/// halves. On error the joints hold the surfaces of the sub-steps completed so far. With a
/// [`ClearanceStop`](crate::ClearanceStop) the stages go on until it ends them
/// ([`StagePlan::next_stage`]).
pub fn run_stages<E, W, F>(
    joints: &mut [WornJoint],
    plan: &StagePlan,
    mut runner: F,
) -> Result<Vec<StageReport>, StagingError<E>>
where
    W: Into<WearSample>,
    F: FnMut(RunContext, &[WornJoint]) -> Result<W, E>,
{
    plan.validate()?;
    let mut reports = Vec::new();
    while let Some(stage_plan) = plan.next_stage(&reports) {
        let report = run_stage(joints, reports.len(), &stage_plan, &mut runner)?;
        reports.push(report);
    }
    Ok(reports)
}

/// Runs stage `stage` of `plan` (see [`run_stages`]).
pub fn run_stage<E, W, F>(
    joints: &mut [WornJoint],
    stage: usize,
    plan: &StagePlan,
    runner: &mut F,
) -> Result<StageReport, StagingError<E>>
where
    W: Into<WearSample>,
    F: FnMut(RunContext, &[WornJoint]) -> Result<W, E>,
{
    plan.validate()?;
    let mut report = StageReport::start(stage);
    if let Extrapolation::Controlled {
        tolerance,
        min_fraction,
        max_fraction,
        max_runs,
    } = plan.extrapolation
    {
        let control = Control {
            tolerance,
            min_fraction,
            max_fraction,
            max_runs,
        };
        return controlled::run_stage(joints, plan, control, runner, report);
    }
    let mut used = 0.0;
    // With a noise target: this stage's samples, and its surfaces' peaks at its start.
    let mut noise = plan
        .noise_target
        .map(|target| (target, NoiseBatches::new(joints, NOISE_GROUPS)));
    let start: Vec<[f64; 2]> = joints
        .iter()
        .map(|j| [j.bearing().peak().depth, j.pin().peak().depth])
        .collect();
    loop {
        let context = RunContext {
            stage,
            substep: report.substeps.len(),
            applied: used / plan.amplification,
        };
        let WearSample { wear, halves } = sample(runner, context, joints)?;
        let (mut slope_per_unit, mut curvature_per_unit): (f64, f64) = (0.0, 0.0);
        for (joint, w) in joints.iter().zip(&wear) {
            let (slope, curvature) = joint.shape_change_per_amplification(w)?;
            slope_per_unit = slope_per_unit.max(slope);
            curvature_per_unit = curvature_per_unit.max(curvature);
        }
        let remaining = plan.amplification - used;
        let mut at_limits = false;
        let amplification = match plan.extrapolation {
            Extrapolation::Adaptive {
                max_fraction,
                max_slope_change,
                max_curvature_change,
                ..
            } => {
                let max_fraction = match &noise {
                    Some((target, batches)) => noise_fraction(
                        *target,
                        batches,
                        joints,
                        &start,
                        &report.substeps,
                        [used, remaining],
                        max_fraction,
                    ),
                    None => max_fraction,
                };
                // The largest amplification every bound allows; the small slack avoids a
                // needless re-run for a rounding-sized remainder.
                let clearance = clearance_bounded_amplification(
                    joints,
                    &clearance_changes_per_amplification(joints, &wear)?,
                    max_fraction,
                    plan.forming.as_ref(),
                );
                let allowed = [
                    (slope_per_unit, max_slope_change),
                    (curvature_per_unit, max_curvature_change),
                ]
                .iter()
                .filter(|(rate, _)| *rate > 0.0)
                .map(|(rate, bound)| bound / rate)
                .fold(clearance, f64::min);
                let limited = limited_amplification(plan, joints, &wear)?;
                if limited < allowed.min(remaining) {
                    at_limits = true;
                    limited
                } else if allowed * (1.0 + 1e-9) < remaining {
                    allowed
                } else {
                    remaining
                }
            }
            // Controlled stages return above, before this loop.
            Extrapolation::SingleJump { .. } | Extrapolation::Controlled { .. } => remaining,
        };
        if at_limits && amplification <= 0.0 {
            report.run_weights.push(0.0);
            report.ended_at_limits = Some(used);
            return Ok(report);
        }
        let substep = match plan.stepping {
            WearStepping::Explicit => apply_all(joints, &wear, amplification, context)?,
            WearStepping::LinearlyImplicit => {
                let implicit: Vec<StageWear> =
                    wear.iter().map(|w| w.implicit(amplification).0).collect();
                apply_all(joints, &implicit, amplification, context)?
            }
        };
        report.run_weights.push(amplification);
        used += amplification;
        match (&mut noise, &halves) {
            (Some((_, batches)), Some(halves)) => batches.add(halves, amplification),
            // No halves to measure the noise from: the plan's own bound.
            (Some(_), None) => noise = None,
            _ => {}
        }
        if let Extrapolation::SingleJump { warn_fraction } = plan.extrapolation
            && substep.max_change_fraction > warn_fraction
        {
            report.warning = Some(ExtrapolationWarning {
                stage,
                amplification,
                change_fraction: substep.max_change_fraction,
                limit: warn_fraction,
            });
        }
        let reached = report.push_substep(substep, plan, joints);
        if at_limits {
            report.ended_at_limits = Some(used);
            return Ok(report);
        }
        if reached || amplification == remaining {
            return Ok(report);
        }
        if let Extrapolation::Adaptive { max_substeps, .. } = plan.extrapolation
            && report.substeps.len() >= max_substeps
        {
            return Err(WearError::SubstepLimit {
                stage,
                limit: max_substeps,
                remaining: plan.amplification - used,
            }
            .into());
        }
    }
}
