//! The wear-stage driver: simulate K cycles on frozen surfaces, extrapolate their wear in
//! bounded sub-steps, re-simulate on the updated surfaces, for every stage of a plan.
//!
//! Extrapolation and its bounds are `wear`'s ([`wear::run_stage`]); this module owns the part
//! that needs a mechanism: building it on the current surfaces (the caller's
//! [`StageRuns::build`]), simulating it, and taking each wearing element's stage buffer out.

use multibody::{ElementId, SimulationError, SimulationOptions, SimulationResult, State, System};
use wear::{RunContext, StagePlan, StageReport, StageWear, StagingError, WearError, WornJoint};

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

    /// Simulates a built run; override to pass an observer (progress, recorders).
    fn simulate(
        &mut self,
        context: RunContext,
        run: &mut StageSimulation,
    ) -> Result<SimulationResult, SimulationError> {
        let _ = context;
        run.system.simulate(&run.start, &run.options, &mut ())
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
    /// Per run (sub-step), in order over all stages: the largest [`halves_difference`] over
    /// the joints whose elements kept the first half apart
    /// ([`WornClearanceForce::with_halves`]); `None` where none did.
    pub halves_differences: Vec<Option<f64>>,
    /// Per stage (with even K): the stage's wear extrapolated from each half of the simulated
    /// cycles alone, `Σ amplification × half`, compared: the larger relative difference of
    /// their peak depths and of their worn volumes over all joints ([`StageHalves`]).
    pub stage_halves: Vec<Option<StageHalves>>,
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

/// Runs every stage of `plan` on `joints` (all wearing joints of the mechanism, updated
/// together so one sub-step bound covers them all). On error the joints hold the surfaces of
/// the sub-steps completed so far.
pub fn run_wear_stages<R: StageRuns>(
    joints: &mut [WornJoint],
    plan: &StagePlan,
    runs: &mut R,
) -> Result<WearStages, WearStagesError<R::Error>> {
    plan.validate()?;
    let mut out = WearStages {
        reports: Vec::with_capacity(plan.stages),
        surfaces: Vec::with_capacity(plan.stages),
        halves_differences: Vec::new(),
        stage_halves: Vec::new(),
    };
    for stage in 0..plan.stages {
        let mut halves: Vec<Vec<(StageWear, StageWear)>> = Vec::new();
        let mut runner = |context: RunContext, surfaces: &[WornJoint]| {
            let (wear, difference, split) = run_once(runs, context, surfaces, plan.smoothing)?;
            out.halves_differences.push(difference);
            halves.push(split);
            Ok(wear)
        };
        let report = wear::run_stage(joints, stage, plan, &mut runner).map_err(|e| match e {
            StagingError::Wear(e) => WearStagesError::Wear(e),
            StagingError::Runner(e) => e,
        })?;
        out.stage_halves
            .push(stage_halves(&halves, &report, joints));
        out.reports.push(report);
        out.surfaces.push(joints.to_vec());
    }
    Ok(out)
}

/// One run's stage wear per joint and its largest halves difference.
/// Each joint's wear, the largest halves difference, and each joint's (first half, second
/// half) when the halves were kept.
type RunWear = (Vec<StageWear>, Option<f64>, Vec<(StageWear, StageWear)>);

/// The [`StageHalves`] of one stage from its runs' halves (one entry per run, in order; the
/// runs whose wear was applied are the report's sub-steps).
fn stage_halves(
    halves: &[Vec<(StageWear, StageWear)>],
    report: &StageReport,
    joints: &[WornJoint],
) -> Option<StageHalves> {
    if report.substeps.is_empty() || halves.iter().take(report.substeps.len()).any(Vec::is_empty) {
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
        for (run, substep) in halves.iter().zip(&report.substeps) {
            let (first, second) = &run[j];
            for (sum, half) in sums.iter_mut().zip([first, second]) {
                for (s, h) in sum.0.iter_mut().zip(half.bearing()) {
                    *s += substep.amplification * h;
                }
                for (s, h) in sum.1.iter_mut().zip(half.pin()) {
                    *s += substep.amplification * h;
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
    let mut wear = Vec::with_capacity(run.elements.len());
    let mut difference: Option<f64> = None;
    let mut split = Vec::new();
    for &id in &run.elements {
        let not_wearing = || WearStagesError::NotWearing {
            context,
            element: id.0,
        };
        let element = run
            .system
            .element_mut::<WornClearanceForce>(id)
            .ok_or_else(not_wearing)?;
        let mut first = element.take_first_half();
        let mut total = element.take_stage_wear().ok_or_else(not_wearing)?;
        total.smooth(smoothing);
        if let Some(first) = &mut first {
            first.smooth(smoothing);
        }
        if let Some(first) = first {
            let d = halves_difference(&first, &total);
            difference = Some(difference.map_or(d, |x| x.max(d)));
            let mut second = total.clone();
            second.subtract(&first);
            split.push((first, second));
        }
        wear.push(total);
    }
    if split.len() != wear.len() {
        split.clear();
    }
    Ok((wear, difference, split))
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
