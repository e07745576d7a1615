//! The wear-stage driver: simulate K cycles on frozen surfaces, extrapolate their wear in
//! bounded sub-steps, re-simulate on the updated surfaces, for every stage of a plan.
//!
//! Extrapolation and its bounds are `wear`'s ([`wear::run_stage`]); this module owns the part
//! that needs a mechanism: building it on the current surfaces (the caller's
//! [`StageRuns::build`]), simulating it, and taking each wearing element's stage buffer out.

use std::sync::atomic::{AtomicU64, Ordering};
use std::time::Duration;

use contact::ImpactMemory;
use multibody::{
    ElementId, Observer, OutputTimes, SimulationError, SimulationOptions, SimulationResult, State,
    System,
};
use rayon::prelude::*;
use wear::{
    Extrapolation, JointNoise, JointResults, NOISE_GROUPS, NoiseBatches, Replicas, RunContext,
    StagePlan, StageReport, StageWear, StagingError, WearError, WearSample, WornJoint,
};

use crate::WornClearanceForce;

/// One K-cycle run on frozen surfaces, as the caller set it up.
pub struct StageSimulation {
    /// The mechanism, built on the surfaces the driver passed.
    pub system: System,
    /// Its assembled initial state.
    pub start: State,
    /// Integration settings; `t_end` ends the K cycles.
    pub options: SimulationOptions,
    /// The wearing elements, one [`WornClearanceForce`] with a stage-wear buffer
    /// ([`WornClearanceForce::with_stage_wear`]) per surface passed to the builder, same order.
    pub elements: Vec<ElementId>,
}

/// What the driver asks of the caller: a mechanism on given surfaces, and optionally how to
/// simulate it (to observe it). Any closure `FnMut(RunContext, &[WornJoint]) ->
/// Result<StageSimulation, E>` is one.
pub trait StageRuns {
    /// The caller's error when building fails.
    type Error;

    /// Builds the run `context` on `surfaces` (frozen during the run).
    fn build(
        &mut self,
        context: RunContext,
        surfaces: &[WornJoint],
    ) -> Result<StageSimulation, Self::Error>;

    /// Simulates a built run of a single trajectory ([`Ensemble::SINGLE`]); override to pass an
    /// observer (progress, recorders).
    fn simulate(
        &mut self,
        context: RunContext,
        run: &mut StageSimulation,
    ) -> Result<SimulationResult, SimulationError> {
        let _ = context;
        run.system.simulate(&run.start, &run.options, &mut ())
    }

    /// An ensemble's trajectories simulate on worker threads; the driver reports their
    /// progress here, on its own thread: `done` is the fraction of the sub-step's simulated
    /// time, exactly 0 once at the start, then values strictly between 0 and 1 about every
    /// tenth of a second, and exactly 1 once at the end.
    fn ensemble_progress(&mut self, context: RunContext, done: f64) {
        let _ = (context, done);
    }
}

/// How a sub-step's simulated cycles are spread over trajectories.
///
/// The wear of a sub-step estimates an average over the chaotic motion; `K` consecutive cycles
/// of one trajectory and `K/M` cycles of each of `M` trajectories estimate the same average.
/// With `M ≥ 2` the trajectories run on threads, and each continues, sub-step after sub-step,
/// from where it ended (its state and its contacts' impact memory) on the updated surfaces,
/// so only the first sub-step pays the start-up window. They are seeded deterministically:
/// in the first sub-step, trajectory `m` runs from the caller's assembled state and gathers
/// wear over the `m`-th of `M` equal parts of the caller's wear window (the run's cycles),
/// i.e. it is the same trajectory as the single run, cut at another place. Results do not
/// depend on the number of threads: each trajectory is computed alone and their wear is summed
/// in trajectory order.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Ensemble {
    trajectories: usize,
    threads: usize,
}

impl Ensemble {
    /// One trajectory: every run starts from the caller's assembled state and simulates its
    /// cycles after the start-up window one after the other (the paper's way).
    pub const SINGLE: Self = Self {
        trajectories: 1,
        threads: 1,
    };

    /// `trajectories` trajectories per sub-step on at most `threads` threads (both at least
    /// 1; a 0 counts as 1). Each trajectory covers `1/trajectories` of the caller's wear
    /// window: choose a divisor of the run's cycles so that each covers whole drive cycles.
    pub fn new(trajectories: usize, threads: usize) -> Self {
        Self {
            trajectories: trajectories.max(1),
            threads: threads.max(1),
        }
    }

    /// Trajectories per sub-step.
    pub fn trajectories(&self) -> usize {
        self.trajectories
    }

    /// Most threads they run on.
    pub fn threads(&self) -> usize {
        self.threads
    }
}

impl Default for Ensemble {
    fn default() -> Self {
        Self::SINGLE
    }
}

impl<E, F> StageRuns for F
where
    F: FnMut(RunContext, &[WornJoint]) -> Result<StageSimulation, E>,
{
    type Error = E;

    fn build(&mut self, context: RunContext, surfaces: &[WornJoint]) -> Result<StageSimulation, E> {
        self(context, surfaces)
    }
}

/// Why the stages stopped.
#[derive(Debug, thiserror::Error)]
pub enum WearStagesError<E> {
    /// Invalid plan, or wear that the surfaces cannot take.
    #[error(transparent)]
    Wear(#[from] WearError),
    /// The caller could not build a run.
    #[error("wear stage {} run {}: {source}", .context.stage + 1, .context.substep + 1)]
    Build {
        /// Which run.
        context: RunContext,
        /// The caller's error.
        source: E,
    },
    /// A run's simulation failed.
    #[error("wear stage {} run {}: {source}", .context.stage + 1, .context.substep + 1)]
    Simulation {
        /// Which run.
        context: RunContext,
        /// Cause.
        source: SimulationError,
    },
    /// The ensemble's worker threads could not be started.
    #[error("the wear stages' {threads} worker thread(s) could not be started: {source}")]
    Threads {
        /// How many were asked for.
        threads: usize,
        /// Cause.
        source: rayon::ThreadPoolBuildError,
    },
    /// An element listed in [`StageSimulation::elements`] is not a [`WornClearanceForce`] or
    /// carries no stage-wear buffer.
    #[error(
        "wear stage {} run {}: element {element} is not a worn clearance joint with a stage-wear \
         buffer",
        .context.stage + 1,
        .context.substep + 1
    )]
    NotWearing {
        /// Which run.
        context: RunContext,
        /// The element's index in the system.
        element: usize,
    },
}

/// Everything the stages produced.
#[derive(Debug, Clone, PartialEq)]
pub struct WearStages {
    /// One report per stage: its sub-steps, a single jump's warning, an early end at the
    /// plan's geometry limits.
    pub reports: Vec<StageReport>,
    /// The surfaces after each stage (the last are also left in the joints passed in).
    pub surfaces: Vec<Vec<WornJoint>>,
    /// Per run of the K cycles, in order over all stages (a stage's runs are its
    /// [`StageReport::run_weights`]: one per sub-step with fixed bounds, more with controlled
    /// extrapolation): the largest [`halves_difference`] over the joints whose elements kept
    /// the first half apart ([`WornClearanceForce::with_halves`]); `None` where none did.
    pub halves_differences: Vec<Option<f64>>,
    /// Per stage (with even K): the stage's wear extrapolated from each half of the simulated
    /// cycles alone, `Σ amplification × half`, compared: the larger relative difference of
    /// their peak depths and of their worn volumes over all joints ([`StageHalves`]).
    pub stage_halves: Vec<Option<StageHalves>>,
    /// Per wearing joint, per point of its life curve (the start, then every sub-step of every
    /// stage): the sampling noise of its results there ([`wear::NoiseBatches`], batches over
    /// all runs so far). `None` at the start; throughout when a run kept no halves (odd K on
    /// one trajectory, an odd number of trajectories); and from the first error-controlled
    /// stage on, whose corrector's correlated sub-steps the levelling cannot read.
    pub life_noise: Vec<Vec<Option<JointNoise>>>,
    /// Per stage, per wearing joint: the jackknife replicas of its surfaces at the stage's end,
    /// from which the noise of any measure of them follows ([`Replicas::noise`]); none (no
    /// replica) when a run kept no halves, and from the first error-controlled stage on.
    pub stage_replicas: Vec<Vec<Replicas>>,
}

/// How far a whole stage's wear depends on which half of its simulated cycles it came from:
/// each sub-step's first-half and second-half wear are amplified like the sub-step and summed
/// over the stage, giving two estimates of half the stage's wear. Their difference is the
/// sampling noise of the stage's result (the per-run [`halves_difference`] is that of a single
/// sub-step, which averaging over the sub-steps reduces).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct StageHalves {
    /// Largest `|peak₁ − peak₂| / mean` over joints and surfaces.
    pub peak_depth: f64,
    /// Largest `|V₁ − V₂| / mean` of the worn volumes over joints.
    pub worn_volume: f64,
}

/// Runs every stage of `plan` (or up to its clearance stop, [`wear::StagePlan::next_stage`])
/// on `joints` (all wearing joints of the mechanism, updated together so one sub-step bound
/// covers them all), one trajectory per run ([`Ensemble::SINGLE`]). On error the joints hold
/// the surfaces of the sub-steps completed so far.
pub fn run_wear_stages<R: StageRuns>(
    joints: &mut [WornJoint],
    plan: &StagePlan,
    runs: &mut R,
) -> Result<WearStages, WearStagesError<R::Error>> {
    run_ensemble_stages(joints, plan, Ensemble::SINGLE, runs)
}

/// [`run_wear_stages`] with each sub-step's cycles spread over the trajectories of `ensemble`.
pub fn run_ensemble_stages<R: StageRuns>(
    joints: &mut [WornJoint],
    plan: &StagePlan,
    ensemble: Ensemble,
    runs: &mut R,
) -> Result<WearStages, WearStagesError<R::Error>> {
    plan.validate()?;
    let mut members = if ensemble.trajectories > 1 {
        let pool = rayon::ThreadPoolBuilder::new()
            .num_threads(ensemble.threads)
            .thread_name(|i| format!("wear-trajectory-{i}"))
            .build()
            .map_err(|source| WearStagesError::Threads {
                threads: ensemble.threads,
                source,
            })?;
        Some(Members {
            pool,
            continuations: vec![None; ensemble.trajectories],
        })
    } else {
        None
    };
    let mut out = WearStages {
        reports: Vec::with_capacity(plan.stages),
        surfaces: Vec::with_capacity(plan.stages),
        halves_differences: Vec::new(),
        stage_halves: Vec::new(),
        life_noise: vec![vec![None]; joints.len()],
        stage_replicas: Vec::with_capacity(plan.stages),
    };
    let mut noise = Some(NoiseBatches::new(joints, NOISE_GROUPS));
    // Per joint, its results at every point of the life curve so far (the levelling's input).
    let mut history: Vec<Vec<JointResults>> =
        joints.iter().map(|j| vec![JointResults::of(j)]).collect();
    let mut lengths = Vec::new();
    // Runs of an error-controlled stage simulate predicted surfaces, not the life's points.
    let controlled = matches!(plan.extrapolation, Extrapolation::Controlled { .. });
    while let Some(stage_plan) = plan.next_stage(&out.reports) {
        let plan = &stage_plan;
        let stage = out.reports.len();
        let mut halves: Vec<Vec<[StageWear; 2]>> = Vec::new();
        // The surfaces each run started from: the life's points between sub-steps.
        let mut entries: Vec<Vec<WornJoint>> = Vec::new();
        let mut runner = |context: RunContext, surfaces: &[WornJoint]| {
            if !controlled {
                entries.push(surfaces.to_vec());
            }
            let (wear, difference, split) = match &mut members {
                None => run_once(runs, context, surfaces, plan.smoothing)?,
                Some(members) => members.run(runs, context, surfaces, plan.smoothing)?,
            };
            out.halves_differences.push(difference);
            let sample = WearSample {
                wear,
                halves: (!split.is_empty()).then(|| split.clone()),
            };
            halves.push(split);
            Ok(sample)
        };
        let report = wear::run_stage(joints, stage, plan, &mut runner).map_err(|e| match e {
            StagingError::Wear(e) => WearStagesError::Wear(e),
            StagingError::Runner(e) => e,
        })?;
        out.stage_halves
            .push(stage_halves(&halves, &report, joints));
        let replicas = stage_noise(
            &mut noise,
            &halves,
            &report,
            (!controlled).then_some(&entries[..]),
            joints,
            LifeCurves {
                noise: &mut out.life_noise,
                history: &mut history,
                lengths: &mut lengths,
            },
        );
        out.stage_replicas.push(replicas);
        out.reports.push(report);
        out.surfaces.push(joints.to_vec());
    }
    Ok(out)
}

/// Per wearing joint, its life curve's noise and results, point by point.
struct LifeCurves<'a> {
    noise: &'a mut [Vec<Option<JointNoise>>],
    history: &'a mut [Vec<JointResults>],
    /// The length (amplification) of every sub-step so far.
    lengths: &'a mut Vec<f64>,
}

impl LifeCurves<'_> {
    /// Appends the point whose surfaces are `surfaces`, reached by a sub-step of length
    /// `length`: their results, and the jackknife noise of `noise`'s batches levelled by the
    /// curves so far ([`JointNoise::levelled`]).
    fn push(&mut self, noise: &Option<NoiseBatches>, surfaces: &[WornJoint], length: f64) {
        self.lengths.push(length);
        let replicas = noise.as_ref().map(NoiseBatches::replicas);
        for (j, joint) in surfaces.iter().enumerate() {
            let (Some(curve), Some(history)) = (self.noise.get_mut(j), self.history.get_mut(j))
            else {
                continue;
            };
            history.push(JointResults::of(joint));
            let jackknife = replicas
                .as_ref()
                .and_then(|r| r.get(j))
                .and_then(|r| r.joint_noise(joint));
            curve.push(jackknife.map(|n| n.levelled(history, self.lengths)));
        }
    }

    /// Appends a point without noise (an error-controlled stage's, see [`stage_noise`]).
    fn push_none(&mut self) {
        for curve in self.noise.iter_mut() {
            curve.push(None);
        }
    }
}

/// Adds a stage's runs to the noise batches (`None` once a run kept no halves) and appends
/// each sub-step's point to the life curves, measured on the surfaces the next run started
/// from (`entries`; the stage's end on `joints`). Without entries (an error-controlled stage)
/// the points carry no noise and the batches are dropped. Returns the stage end's replicas.
fn stage_noise(
    noise: &mut Option<NoiseBatches>,
    halves: &[Vec<[StageWear; 2]>],
    report: &StageReport,
    entries: Option<&[Vec<WornJoint>]>,
    joints: &[WornJoint],
    mut curves: LifeCurves<'_>,
) -> Vec<Replicas> {
    let Some(entries) = entries else {
        // An error-controlled stage's noise cannot be levelled: its corrector gives each run's
        // wear to two sub-steps, which correlates consecutive increments of the life curve by
        // construction and hides the negative correlation the levelling reads. The jackknife
        // alone was measured at 0.5× (A) to 14× (B) the scatter of eight repeats of the
        // LGRES stage (docs/convergence.md), so none is given, here or after.
        for _ in &report.substeps {
            curves.push_none();
        }
        *noise = None;
        return vec![Replicas::default(); joints.len()];
    };
    for (run, &weight) in report.run_weights.iter().enumerate() {
        if let Some(batches) = noise.as_mut() {
            match halves.get(run) {
                Some(h) if !h.is_empty() => batches.add(h, weight),
                _ if weight > 0.0 => *noise = None,
                _ => {}
            }
        }
        if run < report.substeps.len() {
            let surfaces = entries.get(run + 1).map_or(joints, |e| &e[..]);
            curves.push(noise, surfaces, report.substeps[run].amplification);
        }
    }
    match noise {
        Some(batches) => batches.replicas(),
        None => vec![Replicas::default(); joints.len()],
    }
}

/// One run's stage wear per joint and its largest halves difference.
/// Each joint's wear, the largest halves difference, and each joint's (first half, second
/// half) when the halves were kept.
type RunWear = (Vec<StageWear>, Option<f64>, Vec<[StageWear; 2]>);

/// The [`StageHalves`] of one stage from its runs' halves (one entry per run, in order), each
/// run weighted with the amplification its wear received ([`StageReport::run_weights`]).
fn stage_halves(
    halves: &[Vec<[StageWear; 2]>],
    report: &StageReport,
    joints: &[WornJoint],
) -> Option<StageHalves> {
    let weighted = || {
        halves
            .iter()
            .zip(&report.run_weights)
            .filter(|(_, w)| **w > 0.0)
    };
    if report.substeps.is_empty() || weighted().any(|(run, _)| run.is_empty()) {
        return None;
    }
    let mut result = StageHalves {
        peak_depth: 0.0,
        worn_volume: 0.0,
    };
    let relative = |a: f64, b: f64| {
        let mean = 0.5 * (a + b);
        if mean > 0.0 {
            (a - b).abs() / mean
        } else {
            0.0
        }
    };
    for (j, joint) in joints.iter().enumerate() {
        let cells = (joint.bearing().cells(), joint.pin().cells());
        let mut sums = [
            (vec![0.0; cells.0], vec![0.0; cells.1]),
            (vec![0.0; cells.0], vec![0.0; cells.1]),
        ];
        for (run, weight) in weighted() {
            let [first, second] = &run[j];
            for (sum, half) in sums.iter_mut().zip([first, second]) {
                for (s, h) in sum.0.iter_mut().zip(half.bearing()) {
                    *s += weight * h;
                }
                for (s, h) in sum.1.iter_mut().zip(half.pin()) {
                    *s += weight * h;
                }
            }
        }
        let peak = |v: &[f64]| v.iter().copied().fold(0.0, f64::max);
        let volume = |(b, p): &(Vec<f64>, Vec<f64>)| {
            StageWear::from_depths(joint, b.clone(), p.clone()).map_or(0.0, |w| w.worn_volume())
        };
        result.peak_depth = result
            .peak_depth
            .max(relative(peak(&sums[0].0), peak(&sums[1].0)))
            .max(relative(peak(&sums[0].1), peak(&sums[1].1)));
        result.worn_volume = result
            .worn_volume
            .max(relative(volume(&sums[0]), volume(&sums[1])));
    }
    Some(result)
}

/// Builds, simulates and collects one run: each joint's stage wear and the largest halves
/// difference.
fn run_once<R: StageRuns>(
    runs: &mut R,
    context: RunContext,
    surfaces: &[WornJoint],
    smoothing: f64,
) -> Result<RunWear, WearStagesError<R::Error>> {
    let mut run = runs
        .build(context, surfaces)
        .map_err(|source| WearStagesError::Build { context, source })?;
    runs.simulate(context, &mut run)
        .map_err(|source| WearStagesError::Simulation { context, source })?;
    let mut gathered = Vec::with_capacity(run.elements.len());
    for &id in &run.elements {
        let element = worn_element(&mut run.system, id, context)?;
        let first = element.take_first_half();
        let total = take_stage_wear(element, id, context)?;
        gathered.push((total, first));
    }
    Ok(smoothed(gathered, smoothing))
}

/// The wearing element `id` of `system`, or the error naming it.
fn worn_element<E>(
    system: &mut System,
    id: ElementId,
    context: RunContext,
) -> Result<&mut WornClearanceForce, WearStagesError<E>> {
    system
        .element_mut::<WornClearanceForce>(id)
        .ok_or(WearStagesError::NotWearing {
            context,
            element: id.0,
        })
}

/// The stage wear element `id` gathered (its buffer taken out), or the error naming it.
fn take_stage_wear<E>(
    element: &mut WornClearanceForce,
    id: ElementId,
    context: RunContext,
) -> Result<StageWear, WearStagesError<E>> {
    element
        .take_stage_wear()
        .ok_or(WearStagesError::NotWearing {
            context,
            element: id.0,
        })
}

/// Each joint's (total, first half if kept) wear, smoothed, with the largest halves
/// difference and the halves themselves (all joints' or none).
fn smoothed(gathered: Vec<(StageWear, Option<StageWear>)>, smoothing: f64) -> RunWear {
    let mut wear = Vec::with_capacity(gathered.len());
    let mut difference: Option<f64> = None;
    let mut split = Vec::new();
    for (mut total, first) in gathered {
        total.smooth(smoothing);
        if let Some(mut first) = first {
            first.smooth(smoothing);
            let d = halves_difference(&first, &total);
            difference = Some(difference.map_or(d, |x| x.max(d)));
            let mut second = total.clone();
            second.subtract(&first);
            split.push([first, second]);
        }
        wear.push(total);
    }
    if split.len() != wear.len() {
        split.clear();
    }
    (wear, difference, split)
}

/// Where a trajectory of an ensemble ended: its state and each wearing element's impact memory.
#[derive(Clone, Debug)]
struct Continuation {
    state: State,
    memories: Vec<ImpactMemory>,
}

/// The trajectories of an ensemble ([`Ensemble`]) and the threads they run on.
struct Members {
    pool: rayon::ThreadPool,
    /// Per trajectory, where it ended (`None` before its first run).
    continuations: Vec<Option<Continuation>>,
}

/// Writes a trajectory's simulated fraction of its span for the driver's progress reports.
struct Fraction<'a> {
    done: &'a AtomicU64,
    t0: f64,
}

impl Observer for Fraction<'_> {
    fn progress(&mut self, t: f64, t_end: f64) {
        let fraction = ((t - self.t0) / (t_end - self.t0)).clamp(0.0, 1.0);
        self.done.store(fraction.to_bits(), Ordering::Relaxed);
    }
}

impl Members {
    /// One sub-step: every trajectory simulated on the pool, their wear summed in order; with
    /// an even number of trajectories the first half of them is the halves check's first half.
    fn run<R: StageRuns>(
        &mut self,
        runs: &mut R,
        context: RunContext,
        surfaces: &[WornJoint],
        smoothing: f64,
    ) -> Result<RunWear, WearStagesError<R::Error>> {
        let count = self.continuations.len();
        let mut simulations = Vec::with_capacity(count);
        for (member, continuation) in self.continuations.iter().enumerate() {
            let mut run = runs
                .build(context, surfaces)
                .map_err(|source| WearStagesError::Build { context, source })?;
            let mut window_start = run.start.t;
            for &id in &run.elements {
                window_start =
                    window_start.max(worn_element(&mut run.system, id, context)?.wear_start());
            }
            let span = (run.options.t_end - window_start) / count as f64;
            let wear_from = match continuation {
                None => window_start + member as f64 * span,
                Some(c) => {
                    run.start = c.state.clone();
                    c.state.t
                }
            };
            for (k, &id) in run.elements.iter().enumerate() {
                let element = worn_element(&mut run.system, id, context)?;
                element.set_wear_window(wear_from);
                if let Some(memory) = continuation.as_ref().and_then(|c| c.memories.get(k)) {
                    element.set_impact_memory(*memory);
                }
            }
            run.options.t_end = wear_from + span;
            run.options.output = OutputTimes::At(vec![run.options.t_end]);
            simulations.push(run);
        }

        let fractions: Vec<AtomicU64> = (0..count).map(|_| AtomicU64::new(0)).collect();
        let pool = &self.pool;
        runs.ensemble_progress(context, 0.0);
        let results: Vec<Result<SimulationResult, SimulationError>> = std::thread::scope(|scope| {
            let (finished, finishing) = std::sync::mpsc::channel::<()>();
            let simulations = &mut simulations;
            let fractions = &fractions;
            let worker = scope.spawn(move || {
                let results = pool.install(|| {
                    simulations
                        .par_iter_mut()
                        .zip(fractions)
                        .map(|(run, done)| {
                            let mut observer = Fraction {
                                done,
                                t0: run.start.t,
                            };
                            run.system.simulate(&run.start, &run.options, &mut observer)
                        })
                        .collect()
                });
                // The receiver may be gone only if the driver's thread panicked.
                let _ = finished.send(());
                results
            });
            // Until the worker reports or dies (its sender dropped), report progress.
            while let Err(std::sync::mpsc::RecvTimeoutError::Timeout) =
                finishing.recv_timeout(Duration::from_millis(100))
            {
                let done: f64 = fractions
                    .iter()
                    .map(|f| f64::from_bits(f.load(Ordering::Relaxed)))
                    .sum();
                // Strictly between the start (0) and the end (1), which are reported once each.
                let done = done / count as f64;
                if done > 0.0 && done < 1.0 {
                    runs.ensemble_progress(context, done);
                }
            }
            worker
                .join()
                .unwrap_or_else(|panic| std::panic::resume_unwind(panic))
        });
        runs.ensemble_progress(context, 1.0);

        let mut gathered: Vec<(StageWear, Option<StageWear>)> = Vec::new();
        let mut continuations = Vec::with_capacity(count);
        for (member, (run, result)) in simulations.iter_mut().zip(results).enumerate() {
            let result =
                result.map_err(|source| WearStagesError::Simulation { context, source })?;
            if member > 0 && run.elements.len() != gathered.len() {
                return Err(WearError::JointCount {
                    expected: gathered.len(),
                    found: run.elements.len(),
                }
                .into());
            }
            let mut memories = Vec::with_capacity(run.elements.len());
            for (k, &id) in run.elements.iter().enumerate() {
                let element = worn_element(&mut run.system, id, context)?;
                memories.push(element.impact_memory());
                let wear = take_stage_wear(element, id, context)?;
                let in_first_half = count.is_multiple_of(2) && member < count / 2;
                match gathered.get_mut(k) {
                    None => gathered.push((wear.clone(), in_first_half.then_some(wear))),
                    Some((total, first)) => {
                        total.add(&wear);
                        if let (true, Some(first)) = (in_first_half, first) {
                            first.add(&wear);
                        }
                    }
                }
            }
            continuations.push(Some(Continuation {
                state: result.final_state,
                memories,
            }));
        }
        self.continuations = continuations;
        Ok(smoothed(gathered, smoothing))
    }
}

/// How far the two halves of a run's cycles wear apart: the largest per-cell difference
/// between the first half's depth and the rest, over the largest per-cell mean of the two
/// halves. Near 0 when the cycles wear alike (the run's wear is a converged estimate); near 2
/// when one half wears where the other does not.
pub fn halves_difference(first: &StageWear, total: &StageWear) -> f64 {
    let mut largest_difference: f64 = 0.0;
    let mut largest_mean: f64 = 0.0;
    for (a, t) in [
        (first.bearing(), total.bearing()),
        (first.pin(), total.pin()),
    ] {
        for (h1, ht) in a.iter().zip(t) {
            let h2 = ht - h1;
            largest_difference = largest_difference.max((h1 - h2).abs());
            largest_mean = largest_mean.max(0.5 * ht);
        }
    }
    if largest_mean > 0.0 {
        largest_difference / largest_mean
    } else {
        0.0
    }
}
