//! The wear stages of a run: each sub-step simulates `K` cycles on the frozen worn surfaces,
//! on one trajectory or spread over `run.trajectories` trajectories on threads
//! ([`clearance::Ensemble`]), then extrapolates their wear within the plan's limits (see
//! [`wear::run_stage`]).

use std::time::Instant;

use clearance::{Ensemble, StageRuns, StageSimulation, WearStagesError, run_ensemble_stages};
use multibody::{OutputTimes, SimulationError, SimulationResult};
use wear::{ClearanceStop, Extrapolation, GeometryLimits, RunContext, StagePlan, WornJoint};

use super::life::life_curves;
use super::record::{Recorder, assemble};
use super::{JointWearHistory, Motion, Progress, RunError, WearSummary, simulation_options};
use crate::build::{BuildError, Surfaces, build};
use contact::{ContactModel, ShapeLimits};
use scene::{RunSettings, Scene, ValidScene};

mod wear_summary;

use wear_summary::StagesRan;

/// What the wear stages give the run.
pub(super) struct StagesOutcome {
    /// Per wearing joint: its surfaces after each stage and its life curve.
    pub(super) history: Vec<JointWearHistory>,
    /// How the stages were run, for `summary.json` and the report.
    pub(super) summary: WearSummary,
    /// The final surfaces, one slot per active clearance joint (`None`: it does not wear).
    pub(super) surfaces: Vec<Option<WornJoint>>,
}

/// A scene's K-cycle runs for the stage driver: the scene built on the current surfaces,
/// wearing after the start-up window, observed for progress only.
struct SceneRuns<'a> {
    scene: &'a ValidScene,
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
    /// With `run.until_limit`: the limit (m) and the wearing joints' names; the progress then
    /// says how far the surfaces of the current run are toward it.
    limit: Option<(f64, Vec<String>)>,
    /// How far toward the limit, in words, for the current run's label.
    toward_limit: Option<String>,
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
        if let Some(words) = &self.toward_limit {
            return format!("{name}: {words}");
        }
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

/// How far `joints` (named `names`) are toward the clearance `limit`, for a progress line:
/// the least advanced joint's share of the way from its nominal clearance, and each joint's
/// largest local clearance, e.g. "62 % of the way to the 0.800 mm limit (A 0.871, B 0.687 mm)".
fn toward_limit(limit: f64, names: &[String], joints: &[WornJoint]) -> String {
    let share = joints
        .iter()
        .map(|j| {
            let c0 = j.nominal_clearance();
            ((j.max_local_clearance() - c0) / (limit - c0)).clamp(0.0, 1.0)
        })
        .fold(1.0, f64::min);
    let each: Vec<String> = names
        .iter()
        .zip(joints)
        .map(|(n, j)| format!("{n} {:.3}", 1e3 * j.max_local_clearance()))
        .collect();
    format!(
        "{:.0} % of the way to the {:.3} mm clearance limit ({} mm)",
        100.0 * share,
        1e3 * limit,
        each.join(", ")
    )
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
        if let Some((limit, names)) = &self.limit {
            self.toward_limit = Some(toward_limit(*limit, names, current));
        }
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

/// Runs the wear stages (plan, runs, history, summary). `scene_cycles_per_stage` is the
/// scene's own K before any override, which the summary reports beside the K run.
pub(super) fn stages(
    scene: &ValidScene,
    initial: &[Option<WornJoint>],
    period: f64,
    scene_cycles_per_stage: u32,
    threads: Option<usize>,
    progress: &mut dyn Progress,
) -> Result<StagesOutcome, RunError> {
    let started = Instant::now();
    let r = &scene.run;
    let k = r.cycles_per_stage.max(1);
    let shape_limits = shape_limits(scene)?;
    let plan = stage_plan(r, shape_limits, k);
    // Gather wear after the start-up window only (see the module docs).
    let wear_start = r.transient_window;
    let wearing = || {
        scene
            .active_clearance_joints()
            .zip(initial)
            .filter(|(_, w)| w.is_some())
            .map(|(c, _)| c)
    };
    let slots = wearing_slots(initial);
    let mut joints: Vec<WornJoint> = initial.iter().flatten().cloned().collect();
    let start = joints.clone();
    let mut runs = SceneRuns {
        scene,
        slots: &slots,
        wear_start,
        t_end: wear_start + f64::from(k) * period,
        period,
        k,
        progress: &mut *progress,
        clock: None,
        limit: until_limit(r, k)
            .map(|stop| (stop.limit, wearing().map(|c| c.name.clone()).collect())),
        toward_limit: None,
    };
    let staged = run_ensemble_stages(&mut joints, &plan, ensemble(r, threads), &mut runs)
        .map_err(run_error)?;
    let (curves, cycles_applied) = life_curves(&start, &staged.reports, k);
    let names = wearing().map(|c| c.name.clone());
    let k_d_scatters = wearing()
        .map(|c| c.wear.as_ref().map_or(0.0, |w| w.k_d_scatter))
        .collect();
    let history: Vec<JointWearHistory> = joints
        .iter()
        .enumerate()
        .zip(names)
        .zip(curves)
        .map(|(((i, j), name), life)| JointWearHistory {
            name,
            bearing_radius: j.bearing().nominal_radius(),
            pin_radius: j.pin().nominal_radius(),
            stages: staged.surfaces.iter().map(|s| s[i].clone()).collect(),
            life,
            life_noise: staged.life_noise.get(i).cloned().unwrap_or_default(),
            stage_replicas: staged
                .stage_replicas
                .iter()
                .map(|s| s.get(i).cloned().unwrap_or_default())
                .collect(),
        })
        .collect();
    let ran = StagesRan {
        settings: r,
        plan: &plan,
        k,
        scene_cycles_per_stage,
        staged: &staged,
        shape_limited: shape_limits.is_some(),
        k_d_scatters,
    };
    let summary = ran.summary(&history, cycles_applied, wear_start, started, progress);
    let surfaces = slots
        .iter()
        .map(|index| index.and_then(|i| joints.get(i).cloned()))
        .collect();
    Ok(StagesOutcome {
        history,
        summary,
        surfaces,
    })
}

/// The stage plan of the run settings `r`: how each stage is extrapolated, smoothed and
/// stepped, and where it stops. `shape_limits` are the contact models' tightest.
fn stage_plan(r: &RunSettings, shape_limits: Option<ShapeLimits>, k: u32) -> StagePlan {
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
    StagePlan::new(r.wear_stages as usize, r.amplification, extrapolation)
        .with_smoothing(r.wear_smoothing_deg.to_radians())
        .with_stepping(r.wear_stepping)
        // Error-controlled stages size their own sub-steps (validation refuses both).
        .with_noise_target(r.wear_noise.filter(|_| r.wear_tolerance.is_none()))
        .with_geometry_limits(
            // The stop is the models' own: a model that follows any shape names none.
            shape_limits
                .filter(|_| r.adaptive_extrapolation && r.stop_at_validity_limits)
                .map(|l| GeometryLimits::new(l.slope, l.curvature)),
        )
        .with_clearance_stop(until_limit(r, k))
        .with_forming_bound(r.forming_bound())
}

/// With `run.until_limit`: the stop at `run.clearance_limit`, `run.max_cycles` spread over
/// runs of `k` cycles (validation requires both with it).
fn until_limit(r: &RunSettings, k: u32) -> Option<ClearanceStop> {
    match (r.until_limit, r.clearance_limit, r.max_cycles) {
        (true, Some(limit), Some(max_cycles)) => {
            Some(ClearanceStop::new(limit, max_cycles / f64::from(k)))
        }
        _ => None,
    }
}

/// Per active clearance joint: its index among the wearing joints, if it wears.
fn wearing_slots(initial: &[Option<WornJoint>]) -> Vec<Option<usize>> {
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
}

/// The trajectories of a sub-step (`run.trajectories`) on at most `threads` threads (default:
/// the machine's cores).
fn ensemble(r: &RunSettings, threads: Option<usize>) -> Ensemble {
    let threads = threads.unwrap_or_else(|| {
        std::thread::available_parallelism().map_or(1, std::num::NonZeroUsize::get)
    });
    let trajectories = r.trajectories.max(1) as usize;
    Ensemble::new(trajectories, threads.min(trajectories))
}

/// The stage driver's failure as the run's, named after the run it happened in.
fn run_error(e: WearStagesError<RunError>) -> RunError {
    match e {
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
    }
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
