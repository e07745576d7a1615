//! The wear stages of a run: each sub-step simulates `K` cycles on the frozen worn surfaces,
//! then extrapolates their wear within the plan's limits (see [`wear::run_stage`]).

use std::time::Instant;

use multibody::OutputTimes;
use wear::{Extrapolation, GeometryLimits, StagePlan, StageWear, StagingError, WornJoint};

use super::record::{Recorder, assemble};
use super::summary::{HALVES_TOLERANCE, halves_difference};
use super::{
    JointWearHistory, JointWearSummary, Motion, Progress, RunError, SubstepSummary, WearSummary,
    simulation_options,
};
use crate::build::{Surfaces, build};
use crate::clearance::WornClearanceForce;
use crate::scene::Scene;

/// Per-stage history, summary and final surfaces (one slot per active clearance joint).
type Staged = (Vec<JointWearHistory>, WearSummary, Vec<Option<WornJoint>>);

/// Runs the wear stages; returns the per-stage history, the summary and the final surfaces
/// (one slot per active clearance joint).
pub(super) fn stages(
    scene: &Scene,
    initial: &[Option<WornJoint>],
    period: f64,
    progress: &mut dyn Progress,
) -> Result<Staged, RunError> {
    let started = Instant::now();
    let r = &scene.run;
    let k = r.cycles_per_stage.max(1);
    let plan = StagePlan {
        stages: r.wear_stages as usize,
        amplification: r.amplification,
        geometry_limits: (r.adaptive_extrapolation && r.stop_at_validity_limits)
            .then_some(GeometryLimits::CONTACT_MODEL),
        extrapolation: if r.adaptive_extrapolation {
            Extrapolation::Adaptive {
                max_fraction: r.max_clearance_change,
                max_substeps: r.max_substeps as usize,
                max_slope_change: r.max_slope_change,
                max_curvature_change: r.max_curvature_change,
            }
        } else {
            Extrapolation::SingleJump {
                warn_fraction: r.max_clearance_change,
            }
        },
    };
    // Gather wear after the start-up window only (see the module docs).
    let wear_start = r.transient_window;
    let t_end = wear_start + f64::from(k) * period;
    let slots: Vec<Option<usize>> = {
        let mut next = 0;
        initial
            .iter()
            .map(|w| {
                w.as_ref().map(|_| {
                    next += 1;
                    next - 1
                })
            })
            .collect()
    };
    let mut joints: Vec<WornJoint> = initial.iter().flatten().cloned().collect();
    let names: Vec<String> = scene
        .active_clearance_joints()
        .zip(initial)
        .filter(|(_, w)| w.is_some())
        .map(|(c, _)| c.name.clone())
        .collect();
    let mut history: Vec<JointWearHistory> = joints
        .iter()
        .zip(&names)
        .map(|(j, name)| JointWearHistory {
            name: name.clone(),
            bearing_radius: j.bearing().nominal_radius(),
            pin_radius: j.pin().nominal_radius(),
            stages: Vec::new(),
        })
        .collect();
    let mut substeps = Vec::new();
    let mut details = Vec::new();
    let mut warnings = Vec::new();
    let mut ended_at_limits = Vec::new();
    // Per sub-step: how far the two halves of its K cycles disagree (even K only).
    let halves: std::cell::RefCell<Vec<Option<f64>>> = std::cell::RefCell::default();
    let mut runner = |ctx: wear::RunContext, current: &[WornJoint]| {
        let worn: Vec<Option<WornJoint>> = slots
            .iter()
            .map(|s| s.map(|i| current[i].clone()))
            .collect();
        let what = format!("wear stage {} run {}", ctx.stage + 1, ctx.substep + 1);
        let mut built = build(
            scene,
            Surfaces {
                worn: &worn,
                accumulate_from: Some(wear_start),
                // Whole cycles in each half: only for an even K.
                split_halves_at: k
                    .is_multiple_of(2)
                    .then(|| wear_start + f64::from(k / 2) * period),
            },
        )?;
        let state = assemble(&built, &what)?;
        let mut opts = simulation_options(scene, t_end, OutputTimes::At(vec![t_end]), false);
        // Only the wear matters here; skipping the energy quadrature saves time per step.
        opts.energy_audit = false;
        progress.phase(&what, t_end / period);
        let mut recorder = Recorder {
            body: 0,
            joints: &[],
            period,
            times: Vec::new(),
            motion: Motion::default(),
            contact: Vec::new(),
            validity: Vec::new(),
            progress: &mut *progress,
            record: false,
        };
        built
            .system
            .simulate(&state, &opts, &mut recorder)
            .map_err(|source| RunError::Simulation {
                what: what.clone(),
                source,
            })?;
        progress.finish();
        let mut out: Vec<StageWear> = Vec::with_capacity(names.len());
        let mut difference: Option<f64> = None;
        for h in built.joints.iter().filter(|h| h.worn) {
            let element = built.system.element_mut::<WornClearanceForce>(h.element);
            let lost = || RunError::LostWearBuffer {
                what: what.clone(),
                joint: h.name.clone(),
            };
            let element = element.ok_or_else(lost)?;
            let first = element.take_first_half();
            let wear = element.take_stage_wear().ok_or_else(lost)?;
            if let Some(first) = first {
                let d = halves_difference(&first, &wear);
                difference = Some(difference.map_or(d, |x: f64| x.max(d)));
            }
            out.push(wear);
        }
        halves.borrow_mut().push(difference);
        Ok::<_, RunError>(out)
    };
    for stage in 0..plan.stages {
        let report = match wear::run_stage(&mut joints, stage, &plan, &mut runner) {
            Ok(report) => report,
            Err(StagingError::Wear(e)) => return Err(RunError::Wear(e)),
            Err(StagingError::Runner(e)) => return Err(e),
        };
        substeps.push(report.substeps.len());
        let first = details.len();
        details.extend(report.substeps.iter().enumerate().map(|(i, r)| {
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
                halves_difference: halves.borrow().get(first + i).copied().flatten(),
            }
        }));
        if let Some(w) = report.warning {
            let text = format!("warning: {w}");
            warnings.push(text);
        }
        let applied = report
            .ended_at_limits
            .map(|amplification| amplification * f64::from(k));
        if let (Some(cycles), Some(limits)) = (applied, plan.geometry_limits) {
            warnings.push(format!(
                "note: stage {} ended after {cycles:.3e} of its {:.3e} cycles ({:.2} %): the worn \
                 geometry reached the contact model's slope limit {} (run.stop_at_validity_limits)",
                stage + 1,
                plan.amplification * f64::from(k),
                100.0 * cycles / (plan.amplification * f64::from(k)),
                limits.slope
            ));
        }
        ended_at_limits.push(applied);
        for (h, j) in history.iter_mut().zip(&joints) {
            h.stages.push(j.clone());
        }
    }
    let max_halves_difference = details
        .iter()
        .filter_map(|d| d.halves_difference)
        .reduce(f64::max);
    let converged = max_halves_difference.is_some_and(|d| d <= HALVES_TOLERANCE);
    match max_halves_difference {
        None => warnings.push(format!(
            "warning: K = {k} simulated cycle(s) per sub-step: the wear of one chaotic cycle is \
             not a converged estimate, and with odd K it cannot be checked; give an even K \
             (--cycles-per-stage 2 or more)"
        )),
        Some(d) if d > HALVES_TOLERANCE => warnings.push(format!(
            "warning: the two halves of a sub-step's K = {k} cycles wear differently by up to \
             {:.0} % of the peak (tolerance {:.0} %): the stage's wear is not converged in K",
            100.0 * d,
            100.0 * HALVES_TOLERANCE
        )),
        Some(_) => {}
    }
    for w in &warnings {
        progress.note(w);
    }
    let joints_summary = history
        .iter()
        .filter_map(|h| h.stages.last().map(|j| (h, j)))
        .map(|(h, j)| {
            let (bd, _, ba) = j.bearing().peak();
            let (pd, _, pa) = j.pin().peak();
            let ranges = |p: &wear::WornProfile| {
                p.concentrated_ranges(0.5)
                    .iter()
                    .map(|r| r.degrees())
                    .collect()
            };
            JointWearSummary {
                name: h.name.clone(),
                bearing_peak_depth_m: bd,
                bearing_peak_angle_deg: ba.to_degrees(),
                pin_peak_depth_m: pd,
                pin_peak_angle_deg: pa.to_degrees(),
                bearing_ranges_deg: ranges(j.bearing()),
                pin_ranges_deg: ranges(j.pin()),
            }
        })
        .collect();
    let mut surfaces = vec![None; initial.len()];
    for (slot, index) in slots.iter().enumerate() {
        if let Some(i) = index {
            surfaces[slot] = joints.get(*i).cloned();
        }
    }
    let summary = WearSummary {
        stages: r.wear_stages,
        cycles_per_stage: k,
        scene_cycles_per_stage: 0,
        amplification: r.amplification,
        cycles_represented_per_stage: f64::from(k) * r.amplification,
        wear_start_s: wear_start,
        extrapolation: if r.adaptive_extrapolation {
            format!(
                "adaptive (each sub-step changes a local clearance by at most {:.0} %, its slope \
                 by at most {} c0/rad and its curvature by at most {} c0/rad²)",
                100.0 * r.max_clearance_change,
                r.max_slope_change,
                r.max_curvature_change
            )
        } else {
            "single-jump (the paper's)".into()
        },
        substeps_per_stage: substeps,
        substeps: details,
        max_halves_difference,
        converged,
        cycles_applied_at_limits: ended_at_limits,
        warnings,
        joints: joints_summary,
        wall_time_s: started.elapsed().as_secs_f64(),
    };
    Ok((history, summary, surfaces))
}
