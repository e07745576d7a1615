//! The wear stages of a run: each sub-step simulates `K` cycles on the frozen worn surfaces,
//! on one trajectory or spread over `run.trajectories` trajectories on threads
//! ([`clearance::Ensemble`]), then extrapolates their wear within the plan's limits (see
//! [`wear::run_stage`]).

use std::time::Instant;

use clearance::{Ensemble, StageRuns, StageSimulation, WearStagesError, run_ensemble_stages};
use multibody::{OutputTimes, SimulationError, SimulationResult};
use wear::{Extrapolation, GeometryLimits, RunContext, StagePlan, WearStepping, WornJoint};

use super::life::{clearance_limit, life_curves};
use super::outcome::StageHalvesSummary;
use super::record::{Recorder, assemble};
use super::summary::STAGE_HALVES_TOLERANCE;
use super::{
    JointWearHistory, JointWearSummary, Motion, Progress, RunError, SubstepSummary, WearSummary,
    simulation_options,
};
use crate::build::{BuildError, Surfaces, build};
use contact::{ContactModel, ShapeLimits};
use scene::Scene;

/// Per-stage history, summary and final surfaces (one slot per active clearance joint).
type Staged = (Vec<JointWearHistory>, WearSummary, Vec<Option<WornJoint>>);

/// A scene's K-cycle runs for the stage driver: the scene built on the current surfaces,
/// wearing after the start-up window, observed for progress only.
struct SceneRuns<'a> {
    scene: &'a Scene,
    /// Per active clearance joint: its index among the wearing joints, if it wears.
    slots: &'a [Option<usize>],
    wear_start: f64,
    t_end: f64,
    period: f64,
    /// Cycles per run.
    k: u32,
    progress: &'a mut dyn Progress,
    /// When the current stage's first run started: the time estimate's clock.
    clock: Option<(usize, Instant)>,
}

fn run_name(context: RunContext) -> String {
    format!(
        "wear stage {} run {}",
        context.stage + 1,
        context.substep + 1
    )
}

impl SceneRuns<'_> {
    /// The progress label of a run: its name, and once part of the stage is applied, about
    /// how many runs the stage takes and how long it has left (from the amplification applied
    /// so far per run and per second; sub-steps grow as the clearance opens, so both are
    /// upper estimates early on).
    fn label(&mut self, context: RunContext) -> String {
        let started = match self.clock {
            Some((stage, at)) if stage == context.stage => at,
            _ => {
                let now = Instant::now();
                self.clock = Some((context.stage, now));
                now
            }
        };
        let name = run_name(context);
        let applied = context.applied;
        if !(applied > 0.0 && applied < 1.0) || context.substep == 0 {
            return name;
        }
        let runs = (context.substep as f64 / applied).round();
        let left = started.elapsed().as_secs_f64() * (1.0 - applied) / applied;
        format!(
            "{name} of about {runs:.0} ({:.0} % of the stage applied, about {} left)",
            100.0 * applied,
            duration_words(left)
        )
    }
}

/// A duration in words a progress line can carry: "40 s", "7 min", "1 h 05 min".
fn duration_words(seconds: f64) -> String {
    let s = seconds.max(0.0).round() as u64;
    match s {
        0..=89 => format!("{s} s"),
        90..=3569 => format!("{} min", (s + 30) / 60),
        _ => {
            let minutes = (s + 30) / 60;
            format!("{} h {:02} min", minutes / 60, minutes % 60)
        }
    }
}

impl StageRuns for SceneRuns<'_> {
    type Error = RunError;

    fn build(
        &mut self,
        context: RunContext,
        current: &[WornJoint],
    ) -> Result<StageSimulation, RunError> {
        let worn: Vec<Option<WornJoint>> = self
            .slots
            .iter()
            .map(|s| s.map(|i| current[i].clone()))
            .collect();
        let built = build(
            self.scene,
            Surfaces {
                worn: &worn,
                accumulate_from: Some(self.wear_start),
                // Whole cycles in each half: only for an even K.
                split_halves_at: self
                    .k
                    .is_multiple_of(2)
                    .then(|| self.wear_start + f64::from(self.k / 2) * self.period),
            },
        )?;
        let start = assemble(&built, &run_name(context))?;
        let mut options = simulation_options(
            self.scene,
            self.t_end,
            OutputTimes::At(vec![self.t_end]),
            false,
        );
        // Only the wear matters here; skipping the energy quadrature saves time per step.
        options.energy_audit = false;
        let elements = built
            .joints
            .iter()
            .filter(|h| h.worn)
            .map(|h| h.element)
            .collect();
        Ok(StageSimulation {
            system: built.system,
            start,
            options,
            elements,
        })
    }

    fn simulate(
        &mut self,
        context: RunContext,
        run: &mut StageSimulation,
    ) -> Result<SimulationResult, SimulationError> {
        let label = self.label(context);
        self.progress.phase(&label, self.t_end / self.period);
        let mut recorder = Recorder {
            body: 0,
            joints: &[],
            period: self.period,
            times: Vec::new(),
            motion: Motion::default(),
            contact: Vec::new(),
            validity: Vec::new(),
            progress: &mut *self.progress,
            record: false,
            frames: &[],
            poses: Vec::new(),
        };
        let result = run.system.simulate(&run.start, &run.options, &mut recorder);
        self.progress.finish();
        result
    }

    fn ensemble_progress(&mut self, context: RunContext, done: f64) {
        let cycles = f64::from(self.k);
        if done <= 0.0 {
            let label = self.label(context);
            self.progress.phase(&label, cycles);
        } else if done >= 1.0 {
            self.progress.finish();
        } else {
            self.progress.advance(done * cycles);
        }
    }
}

/// Runs the wear stages; returns the per-stage history, the summary and the final surfaces
/// (one slot per active clearance joint). `scene_cycles_per_stage` is the scene's own K
/// before any override, which the summary reports beside the K run.
pub(super) fn stages(
    scene: &Scene,
    initial: &[Option<WornJoint>],
    period: f64,
    scene_cycles_per_stage: u32,
    threads: Option<usize>,
    progress: &mut dyn Progress,
) -> Result<Staged, RunError> {
    let started = Instant::now();
    let r = &scene.run;
    let k = r.cycles_per_stage.max(1);
    let shape_limits = shape_limits(scene)?;
    let (max_slope_change, max_curvature_change) = r.shape_change_bounds(shape_limits.is_some());
    let extrapolation =
        if let (true, Some(tolerance)) = (r.adaptive_extrapolation, r.wear_tolerance) {
            Extrapolation::Controlled {
                tolerance,
                min_fraction: r.max_clearance_change,
                max_fraction: Extrapolation::DEFAULT_CONTROLLED_MAX_FRACTION
                    .max(r.max_clearance_change),
                max_runs: r.max_substeps as usize,
            }
        } else if r.adaptive_extrapolation {
            Extrapolation::Adaptive {
                max_fraction: r.max_clearance_change,
                max_substeps: r.max_substeps as usize,
                max_slope_change,
                max_curvature_change,
            }
        } else {
            Extrapolation::SingleJump {
                warn_fraction: r.max_clearance_change,
            }
        };
    let plan = StagePlan::new(r.wear_stages as usize, r.amplification, extrapolation)
        .with_smoothing(r.wear_smoothing_deg.to_radians())
        .with_stepping(r.wear_stepping)
        .with_geometry_limits(
            // The stop is the models' own: a model that follows any shape names none.
            shape_limits
                .filter(|_| r.adaptive_extrapolation && r.stop_at_validity_limits)
                .map(|l| GeometryLimits::new(l.slope, l.curvature)),
        );
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
    let start = joints.clone();
    let mut runs = SceneRuns {
        scene,
        slots: &slots,
        wear_start,
        t_end,
        period,
        k,
        progress: &mut *progress,
        clock: None,
    };
    let threads = threads.unwrap_or_else(|| {
        std::thread::available_parallelism().map_or(1, std::num::NonZeroUsize::get)
    });
    let trajectories = r.trajectories.max(1) as usize;
    let ensemble = Ensemble::new(trajectories, threads.min(trajectories));
    let staged =
        run_ensemble_stages(&mut joints, &plan, ensemble, &mut runs).map_err(|e| match e {
            WearStagesError::Wear(e) => RunError::Wear(e),
            WearStagesError::Build { source, .. } => source,
            WearStagesError::Simulation { context, source } => RunError::Simulation {
                what: run_name(context),
                source,
            },
            WearStagesError::NotWearing { context, element } => RunError::LostWearBuffer {
                what: run_name(context),
                joint: format!("element {element}"),
            },
            WearStagesError::Threads { threads, source } => RunError::Threads {
                threads,
                message: source.to_string(),
            },
        })?;
    let (curves, cycles_applied) = life_curves(&start, &staged.reports, k);
    let history: Vec<JointWearHistory> = joints
        .iter()
        .enumerate()
        .zip(&names)
        .zip(curves)
        .map(|(((i, j), name), life)| JointWearHistory {
            name: name.clone(),
            bearing_radius: j.bearing().nominal_radius(),
            pin_radius: j.pin().nominal_radius(),
            stages: staged.surfaces.iter().map(|s| s[i].clone()).collect(),
            life,
        })
        .collect();
    let mut substeps = Vec::new();
    let mut runs_per_stage = Vec::new();
    let mut rejected_runs = Vec::new();
    let mut details = Vec::new();
    let mut warnings = Vec::new();
    let mut ended_at_limits = Vec::new();
    for (stage, report) in staged.reports.iter().enumerate() {
        substeps.push(report.substeps.len());
        // The stage's first run among all runs (the halves differences are per run).
        let first: usize = runs_per_stage.iter().sum();
        runs_per_stage.push(report.run_weights.len());
        rejected_runs.push(report.rejected_runs());
        details.extend(report.substeps.iter().map(|r| {
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
                halves_difference: staged
                    .halves_differences
                    .get(first + r.context.substep)
                    .copied()
                    .flatten(),
                error_estimate: r.error_estimate,
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
    }
    let max_halves_difference = details
        .iter()
        .filter_map(|d| d.halves_difference)
        .reduce(f64::max);
    let stage_halves: Vec<Option<StageHalvesSummary>> = staged
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
            "warning: {} trajectories per sub-step: with an odd number the convergence of the \
             stage's wear in K cannot be checked (its halves are half of the trajectories \
             each); give an even run.trajectories",
            r.trajectories
        )),
        None => warnings.push(format!(
            "warning: K = {k} simulated cycle(s) per sub-step: with odd K the convergence of \
             the stage's wear in K cannot be checked; give an even K (--cycles-per-stage 2 or \
             more)"
        )),
        Some(d) if d > STAGE_HALVES_TOLERANCE => warnings.push(format!(
            "warning: the stage's wear extrapolated from each half of its K = {k} cycles alone \
             differs by up to {:.0} % in peak depth or worn volume (tolerance {:.0} %): the \
             stage's wear is not converged in K",
            100.0 * d,
            100.0 * STAGE_HALVES_TOLERANCE
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
            let (b, p) = (j.bearing().peak(), j.pin().peak());
            let (bd, ba, pd, pa) = (b.depth, b.angle, p.depth, p.angle);
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
                max_local_clearance_m: j.max_local_clearance(),
                clearance_limit: r
                    .clearance_limit
                    .map(|limit| clearance_limit(&h.life, limit)),
            }
        })
        .collect();
    let mut surfaces = vec![None; initial.len()];
    for (slot, index) in slots.iter().enumerate() {
        if let Some(i) = index {
            surfaces[slot] = joints.get(*i).cloned();
        }
    }
    let mut summary = WearSummary {
        stages: r.wear_stages,
        cycles_per_stage: k,
        scene_cycles_per_stage,
        trajectories: r.trajectories,
        amplification: r.amplification,
        cycles_represented_per_stage: f64::from(k) * r.amplification,
        cycles_applied,
        wear_start_s: wear_start,
        extrapolation: if let Extrapolation::Controlled {
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
            if shape_limits.is_some()
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
        },
        substeps_per_stage: substeps,
        runs_per_stage,
        rejected_runs_per_stage: rejected_runs,
        substeps: details,
        max_halves_difference,
        stage_halves,
        converged,
        cycles_applied_at_limits: ended_at_limits,
        warnings,
        joints: joints_summary,
        wall_time_s: started.elapsed().as_secs_f64(),
    };
    // Which stepping ran (error-controlled stages are explicit whatever the scene says).
    if plan.stepping == WearStepping::LinearlyImplicit
        && !matches!(plan.extrapolation, Extrapolation::Controlled { .. })
    {
        summary.extrapolation.push_str(
            ", linearly implicit (the wear's stiffness taken from the cycles' contact zones)",
        );
    }
    Ok((history, summary, surfaces))
}

/// `fraction` as a percentage for a sentence: 2.5 for 0.025, 5 for 0.05 (no binary residue).
fn percent(fraction: f64) -> f64 {
    (fraction * 1e8).round() / 1e6
}

/// The tightest shape limits the active joints' contact models name (`None`: none of them
/// limits the worn outlines' shape).
fn shape_limits(scene: &Scene) -> Result<Option<ShapeLimits>, RunError> {
    let mut tightest: Option<ShapeLimits> = None;
    for c in scene.active_clearance_joints() {
        let model = c.contact_model().map_err(|source| BuildError::Contact {
            field: format!("clearance_joints.{}.contact", c.name),
            source,
        })?;
        if let Some(l) = model.shape_limits() {
            tightest = Some(tightest.map_or(l, |t| ShapeLimits {
                slope: t.slope.min(l.slope),
                curvature: t.curvature.min(l.curvature),
            }));
        }
    }
    Ok(tightest)
}
