//! What the wear stages report: per stage its sub-steps and runs, its warnings, the check of
//! its wear's convergence in K (the halves), each joint's final wear, and the stepping in words.

use std::time::Instant;

use clearance::WearStages;
use wear::{Extrapolation, StagePlan, WearStepping};

use crate::life::{clearance_limit, life_summary};
use crate::outcome::StageHalvesSummary;
use crate::summary::STAGE_HALVES_TOLERANCE;
use crate::{JointWearHistory, JointWearSummary, Progress, SubstepSummary, WearSummary};
use scene::RunSettings;

/// The wear stages as they ran: what the summary is made from.
pub(super) struct StagesRan<'a> {
    pub(super) settings: &'a RunSettings,
    pub(super) plan: &'a StagePlan,
    /// Simulated cycles per sub-step run.
    pub(super) k: u32,
    /// The scene's own K before any override.
    pub(super) scene_cycles_per_stage: u32,
    pub(super) staged: &'a WearStages,
    /// Whether a contact model limits the worn outlines' shape.
    pub(super) shape_limited: bool,
    /// Per wearing joint, the scatter of its `ln k_d` (`wear.k_d_scatter`).
    pub(super) k_d_scatters: Vec<f64>,
}

/// Per stage: its sub-steps, runs, rejected runs and where it ended early; every sub-step's
/// details; the stages' warnings and notes, in stage order.
#[derive(Default)]
struct StageRecords {
    substeps: Vec<usize>,
    runs: Vec<usize>,
    rejected_runs: Vec<usize>,
    details: Vec<SubstepSummary>,
    ended_at_limits: Vec<Option<f64>>,
    warnings: Vec<String>,
}

impl StagesRan<'_> {
    /// The stages' summary; its warnings are also noted to `progress`.
    pub(super) fn summary(
        &self,
        history: &[JointWearHistory],
        cycles_applied: f64,
        wear_start: f64,
        started: Instant,
        progress: &mut dyn Progress,
    ) -> WearSummary {
        let r = self.settings;
        let k = self.k;
        let mut records = self.stage_records();
        let max_halves_difference = records
            .details
            .iter()
            .filter_map(|d| d.halves_difference)
            .reduce(f64::max);
        let (stage_halves, converged) = self.halves(&mut records.warnings);
        if matches!(self.plan.extrapolation, Extrapolation::Controlled { .. }) {
            records.warnings.push(
                "note: error-controlled sub-steps (run.wear_tolerance) give no sampling noise: \
                 their corrector shares each run's wear between two sub-steps, so the life \
                 curve does not show how much of the noise the worn geometry levels out; run \
                 without run.wear_tolerance for the wear results with their noise"
                    .into(),
            );
        }
        if self.plan.forming.is_some()
            && matches!(self.plan.extrapolation, Extrapolation::Adaptive { .. })
        {
            records.warnings.push(
                "note: with run.forming_clearance_change the printed noise is not calibrated: on \
                 the built-in lgres it was 0.8-2.6 times the scatter of repeated stages, joint \
                 B's volume and peaks overstated (the forming phase's falling wear rate hides \
                 from the life curve how much of the noise the worn geometry levels out; \
                 docs/convergence.md, \"Four reference runs\"), so read it as a rough guide, \
                 mostly an overestimate"
                    .into(),
            );
        }
        for w in &records.warnings {
            progress.note(w);
        }
        let joints = joint_summaries(history, r, &self.k_d_scatters);
        let life = life_summary(r, &joints, &self.staged.reports, cycles_applied);
        WearSummary {
            stages: u32::try_from(self.staged.reports.len()).unwrap_or(u32::MAX),
            cycles_per_stage: k,
            scene_cycles_per_stage: self.scene_cycles_per_stage,
            trajectories: r.trajectories,
            amplification: r.amplification,
            cycles_represented_per_stage: f64::from(k) * r.amplification,
            cycles_applied,
            wear_start_s: wear_start,
            extrapolation: self.extrapolation_words(),
            substeps_per_stage: records.substeps,
            runs_per_stage: records.runs,
            rejected_runs_per_stage: records.rejected_runs,
            substeps: records.details,
            max_halves_difference,
            stage_halves,
            converged,
            cycles_applied_at_limits: records.ended_at_limits,
            warnings: records.warnings,
            joints,
            life,
            wall_time_s: started.elapsed().as_secs_f64(),
        }
    }

    fn stage_records(&self) -> StageRecords {
        let (k, plan) = (self.k, self.plan);
        let mut records = StageRecords::default();
        for (stage, report) in self.staged.reports.iter().enumerate() {
            records.substeps.push(report.substeps.len());
            // The stage's first run among all runs (the halves differences are per run).
            let first: usize = records.runs.iter().sum();
            records.runs.push(report.run_weights.len());
            records.rejected_runs.push(report.rejected_runs());
            records.details.extend(report.substeps.iter().map(|r| {
                SubstepSummary {
                    stage: stage + 1,
                    amplification: r.amplification,
                    max_depth_m: r.max_depth,
                    change_fraction: r.max_change_fraction,
                    slope_change: r.joints.iter().map(|j| j.slope_change).fold(0.0, f64::max),
                    curvature_change: r
                        .joints
                        .iter()
                        .map(|j| j.curvature_change)
                        .fold(0.0, f64::max),
                    halves_difference: self
                        .staged
                        .halves_differences
                        .get(first + r.context.substep)
                        .copied()
                        .flatten(),
                    error_estimate: r.error_estimate,
                }
            }));
            if let Some(w) = report.warning {
                records.warnings.push(format!("warning: {w}"));
            }
            let applied = report
                .ended_at_limits
                .map(|amplification| amplification * f64::from(k));
            if let (Some(cycles), Some(limits)) = (applied, plan.geometry_limits) {
                records.warnings.push(format!(
                    "note: stage {} ended after {cycles:.3e} of its {:.3e} cycles ({:.2} %): the \
                     worn geometry reached the contact model's slope limit {} \
                     (run.stop_at_validity_limits)",
                    stage + 1,
                    plan.amplification * f64::from(k),
                    100.0 * cycles / (plan.amplification * f64::from(k)),
                    limits.slope
                ));
            }
            records.ended_at_limits.push(applied);
        }
        records
    }

    /// Per stage, its wear extrapolated from each half of the K cycles compared, and whether
    /// every stage is converged in K; the warning when it cannot be told or is not.
    fn halves(&self, warnings: &mut Vec<String>) -> (Vec<Option<StageHalvesSummary>>, bool) {
        let (r, k) = (self.settings, self.k);
        let stage_halves: Vec<Option<StageHalvesSummary>> = self
            .staged
            .stage_halves
            .iter()
            .map(|h| {
                h.map(|h| StageHalvesSummary {
                    peak_depth: h.peak_depth,
                    worn_volume: h.worn_volume,
                })
            })
            .collect();
        let worst = stage_halves
            .iter()
            .map(|h| h.map(|h| h.peak_depth.max(h.worn_volume)))
            .collect::<Option<Vec<f64>>>()
            .and_then(|all| all.into_iter().reduce(f64::max));
        let converged = worst.is_some_and(|d| d <= STAGE_HALVES_TOLERANCE);
        match worst {
            None if r.trajectories > 1 => warnings.push(format!(
                "warning: {} trajectories per sub-step: with an odd number the convergence of \
                 the stage's wear in K cannot be checked (its halves are half of the \
                 trajectories each); give an even run.trajectories",
                r.trajectories
            )),
            None => warnings.push(format!(
                "warning: K = {k} simulated cycle(s) per sub-step: with odd K the convergence \
                 of the stage's wear in K cannot be checked; give an even K (--cycles-per-stage \
                 2 or more)"
            )),
            Some(d) if d > STAGE_HALVES_TOLERANCE => warnings.push(format!(
                "warning: the stage's wear extrapolated from each half of its K = {k} cycles \
                 alone differs by up to {:.0} % in peak depth or worn volume (tolerance {:.0} \
                 %): the stage's wear is not converged in K",
                100.0 * d,
                100.0 * STAGE_HALVES_TOLERANCE
            )),
            Some(_) => {}
        }
        (stage_halves, converged)
    }

    /// How the stages were stepped, in words.
    fn extrapolation_words(&self) -> String {
        let (r, plan) = (self.settings, self.plan);
        let (max_slope_change, max_curvature_change) = r.shape_change_bounds(self.shape_limited);
        let mut words = if let Extrapolation::Controlled {
            tolerance,
            min_fraction,
            max_fraction,
            ..
        } = plan.extrapolation
        {
            format!(
                "controlled (tolerance {} %; the first sub-step's predictor changes a local \
                 clearance by at most {} %, none by more than {} %)",
                percent(tolerance),
                percent(min_fraction),
                percent(max_fraction)
            )
        } else if r.adaptive_extrapolation {
            if self.shape_limited
                || max_slope_change.is_finite()
                || max_curvature_change.is_finite()
            {
                format!(
                    "adaptive (each sub-step changes a local clearance by at most {} %, its \
                     slope by at most {} c0/rad and its curvature by at most {} c0/rad²)",
                    percent(r.max_clearance_change),
                    max_slope_change,
                    max_curvature_change
                )
            } else {
                format!(
                    "adaptive (each sub-step changes a local clearance by at most {} %)",
                    percent(r.max_clearance_change)
                )
            }
        } else {
            "single-jump (the paper's)".into()
        };
        // A single jump has no sub-steps to bound.
        if let Some(forming) = plan
            .forming
            .filter(|_| !matches!(plan.extrapolation, Extrapolation::SingleJump { .. }))
        {
            words.push_str(&format!(
                ", at most {} % while a joint's deeper peak is under {} % of its clearance \
                 (run.forming_clearance_change)",
                percent(forming.max_fraction),
                percent(forming.depth)
            ));
        }
        if let (Some(target), Extrapolation::Adaptive { .. }) =
            (plan.noise_target, plan.extrapolation)
        {
            words.push_str(&format!(
                ", sub-steps lengthened to up to {} % for a relative noise of {} % of the peak \
                 depths at the stage's end (run.wear_noise)",
                percent(wear::NOISE_MAX_FRACTION.max(r.max_clearance_change)),
                percent(target)
            ));
        }
        // Which stepping ran (error-controlled stages are explicit whatever the scene says).
        if plan.stepping == WearStepping::LinearlyImplicit
            && !matches!(plan.extrapolation, Extrapolation::Controlled { .. })
        {
            words.push_str(
                ", linearly implicit (the wear's stiffness taken from the cycles' contact zones)",
            );
        }
        words
    }
}

/// Each wearing joint's final wear: peaks, the ranges it is concentrated in, the largest local
/// clearance and, when the scene sets one, when the clearance limit is reached.
fn joint_summaries(
    history: &[JointWearHistory],
    r: &RunSettings,
    k_d_scatters: &[f64],
) -> Vec<JointWearSummary> {
    history
        .iter()
        .zip(k_d_scatters)
        .filter_map(|(h, s)| h.stages.last().map(|j| (h, j, *s)))
        .map(|(h, j, scatter)| {
            let (b, p) = (j.bearing().peak(), j.pin().peak());
            let noise = h.life_noise.last().copied().flatten();
            let ranges = |p: &wear::WornProfile| {
                p.concentrated_ranges(0.5)
                    .iter()
                    .map(|r| r.degrees())
                    .collect()
            };
            JointWearSummary {
                name: h.name.clone(),
                bearing_peak_depth_m: b.depth,
                bearing_peak_depth_noise_m: noise.map(|n| n.bearing_peak_depth),
                bearing_peak_angle_deg: b.angle.to_degrees(),
                pin_peak_depth_m: p.depth,
                pin_peak_depth_noise_m: noise.map(|n| n.pin_peak_depth),
                pin_peak_angle_deg: p.angle.to_degrees(),
                worn_volume_m3: j.worn_volume(),
                worn_volume_noise_m3: noise.map(|n| n.worn_volume),
                bearing_ranges_deg: ranges(j.bearing()),
                pin_ranges_deg: ranges(j.pin()),
                max_local_clearance_m: j.max_local_clearance(),
                max_local_clearance_noise_m: noise.map(|n| n.max_local_clearance),
                noise_batches: if noise.is_some() {
                    h.stage_replicas.last().map_or(0, wear::Replicas::count)
                } else {
                    0
                },
                clearance_limit: r
                    .clearance_limit
                    .map(|limit| clearance_limit(&h.life, &h.life_noise, limit, scatter)),
            }
        })
        .collect()
}

/// `fraction` as a percentage for a sentence: 2.5 for 0.025, 5 for 0.05 (no binary residue).
fn percent(fraction: f64) -> f64 {
    (fraction * 1e8).round() / 1e6
}
