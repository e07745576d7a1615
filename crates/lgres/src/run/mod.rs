//! One run of a scene: the response over `cycles` drive periods against the ideal mechanism,
//! then the wear stages, with every summary number kept in memory ([`RunOutcome`]).
//!
//! [`run_scene`] is what the CLI's `run` calls and what a study loop can call repeatedly; it
//! writes nothing (see [`crate::io::artifacts`]) and reports progress through [`Progress`].
//!
//! - **Response run**: assembled from the scene's initial poses (pins concentric), integrated
//!   over `run.cycles` periods on unworn surfaces, sampled every `solver.output_interval`.
//! - **Reference**: the all-ideal mechanism ([`Scene::idealized`]) by kinematic analysis at the
//!   same times, on its own thread while the response is integrated (after a check at the
//!   first output time, so that a mechanism that does not assemble is refused before any
//!   simulation). A scene without active clearance joints runs this kinematic path only.
//! - **Wear stages** ([`wear::run_stage`]): each sub-step rebuilds the system on the current
//!   (frozen) worn surfaces and integrates `run.transient_window + K` periods, gathering wear
//!   over the last `K` only: the concentric start-up impact (docs/model.md §8) is not amplified, and a
//!   periodic drive makes any `K` consecutive periods `K` full cycles. With
//!   `run.trajectories = M ≥ 2` the `K` periods are spread over `M` trajectories on threads
//!   that continue from sub-step to sub-step, so only the first sub-step integrates the
//!   start-up window ([`clearance::Ensemble`]). After the stages the response is simulated
//!   once more on the worn surfaces.
//! - **Peaks** are statistics over cycles, with and without the start-up window (docs/model.md §8:
//!   the clearance dynamics are chaotic, single peaks are not reproducible).
//!
//! Here: the options, errors and the driver; `outcome` holds the result types, `record` the
//! response run and its recording observer, `summary` the statistics and energy books,
//! `stages` the wear stages, `life` the joints' life curves over the stages' drive cycles
//! and [`validity`] the worn geometry's validity measures.

mod life;
mod outcome;
mod record;
mod stages;
mod summary;
pub mod validity;

use std::time::Instant;

use multibody::{
    AbsoluteTolerances, AssemblyError, Baumgarte, KinematicsError, OutputTimes, SimulationError,
    SimulationOptions,
};
use serde::Serialize;
use wear::WornJoint;

use crate::build::{BuildError, Surfaces, build, unworn_joints};
use crate::scene::{self, Scene};

pub use life::cycles_to_reach;
pub use outcome::{
    ClearanceLimitReport, ContactSeries, Deviation, JointSummary, JointWearHistory,
    JointWearSummary, LifePoint, MechanismFrames, Motion, Numerics, PeakStats, Response,
    ResponseSummary, RunOutcome, SubstepSummary, Summary, WearSummary,
};
use record::{Ideal, assemble, respond, simulate};
use stages::stages;
use summary::summarize;
pub use summary::{
    ENERGY_BOOKS_TOLERANCE_J, MIN_ELASTIC_SHARE, STAGE_HALVES_TOLERANCE, median_bootstrap_noise,
    peak_stats,
};

/// Most frames an animation shows: one drive cycle in at most this many poses
/// ([`MechanismFrames`], [`crate::io::animation`]).
pub const MAX_ANIMATION_FRAMES: usize = 72;

/// Receives progress; every method defaults to doing nothing (`()` ignores everything).
pub trait Progress {
    /// A new phase of `cycles` drive periods starts (e.g. `"response"`, `"stage 1.2"`).
    fn phase(&mut self, _label: &str, _cycles: f64) {}
    /// Position within the current phase, in periods.
    fn advance(&mut self, _cycles: f64) {}
    /// The current phase is done.
    fn finish(&mut self) {}
    /// A note or warning for the user (e.g. a single-jump extrapolation warning).
    fn note(&mut self, _text: &str) {}
}

impl Progress for () {}

/// Overrides of the scene's run settings.
#[derive(Debug, Clone, Default)]
pub struct RunOptions {
    /// Start from the worn surfaces of an earlier run: the folder holding its last-stage
    /// `wear_<joint>_stage<k>.csv` files (see [`crate::io::surfaces`]). The response run and the
    /// stages then begin from those surfaces.
    pub surfaces: Option<std::path::PathBuf>,
    /// Simulated cycles per wear stage `K` instead of `run.cycles_per_stage`; the
    /// amplification is rescaled so a stage still stands for `K_scene × amplification` cycles.
    pub cycles_per_stage: Option<u32>,
    /// Trajectories a wear sub-step's `K` cycles are spread over, instead of
    /// `run.trajectories`; they must divide `K`.
    pub trajectories: Option<u32>,
    /// Threads a wear sub-step's trajectories run on (`run.trajectories`; default: the
    /// machine's cores). The results do not depend on it.
    pub threads: Option<usize>,
    /// Skip the response run on the worn surfaces after the stages.
    pub skip_worn_response: bool,
}

/// Why a run failed.
#[derive(Debug, thiserror::Error)]
pub enum RunError {
    /// The scene does not make a valid system (field named).
    #[error(transparent)]
    Build(#[from] BuildError),
    /// The initial poses do not assemble.
    #[error(
        "{what}: the initial poses (bodies[*].x, y, theta_deg) do not assemble at t = 0: {source}"
    )]
    Assembly {
        /// Which system.
        what: String,
        /// Cause, naming the constraints.
        source: AssemblyError,
    },
    /// The worker threads of a wear sub-step's trajectories could not be started.
    #[error(
        "the {threads} worker thread(s) of the wear trajectories could not be started: {message}"
    )]
    Threads {
        /// How many were asked for.
        threads: usize,
        /// The system's reason.
        message: String,
    },
    /// The trajectories of a wear sub-step do not divide its simulated cycles.
    #[error(
        "run.trajectories = {trajectories} must divide the simulated cycles per wear stage \
         K = {cycles_per_stage} (--cycles-per-stage, run.cycles_per_stage): each trajectory \
         simulates whole drive cycles"
    )]
    Trajectories {
        /// `run.trajectories`.
        trajectories: u32,
        /// `K` after the overrides.
        cycles_per_stage: u32,
    },
    /// The ideal mechanism's kinematic analysis failed.
    #[error(
        "kinematic analysis of the ideal mechanism (clearance joints {joints} made ideal \
         revolute joints; drivers {drivers}): {source}; the drivers must fix every degree of \
         freedom the ideal mechanism has"
    )]
    Kinematics {
        /// The clearance joints, by name.
        joints: String,
        /// The drivers, by name.
        drivers: String,
        /// Cause.
        source: KinematicsError,
    },
    /// The integrator failed or ran out of its budget (the hint names the scene field).
    #[error("{what}: {source}{}", crate::scene::limits::budget_hint(source))]
    Simulation {
        /// Which run.
        what: String,
        /// Cause.
        source: SimulationError,
    },
    /// Wear staging failed (e.g. a pin worn through, too many sub-steps).
    #[error("wear staging: {0}")]
    Wear(#[from] wear::WearError),
    /// A wear stage's run ended without the wear record of a worn joint (an internal error:
    /// the element was built without one, or it was taken twice).
    #[error("{what}: clearance joint {joint} has no wear record after its run (internal error)")]
    LostWearBuffer {
        /// Which run.
        what: String,
        /// The joint.
        joint: String,
    },
    /// The worn surfaces to start from could not be loaded (file and joint named).
    #[error(transparent)]
    Surfaces(#[from] crate::io::surfaces::SurfacesError),
    /// The scene has no drive period (validation normally catches this).
    #[error("run.period: no drive period; give run.period")]
    NoPeriod,
    /// The scene has no body to record.
    #[error("run.response_body: no body to record")]
    NoResponseBody,
    /// The scene (with the run's overrides applied) is not valid.
    #[error(transparent)]
    Scene(#[from] scene::SceneError),
    /// A pin starts outside its bearing after assembly at t = 0.
    #[error(
        "{what}: clearance_joints[{index}] ({joint}): after assembly at t = 0 the pin centre is \
         {eccentricity:.6e} m from the bearing centre, beyond the clearance ({clearance:e} m): \
         the pin starts outside its bearing (check the bodies' initial poses and the joint's \
         pin_point, bearing_point)"
    )]
    PinOutsideBearing {
        /// Which system.
        what: String,
        /// Index into `clearance_joints`.
        index: usize,
        /// Joint name.
        joint: String,
        /// Initial eccentricity, m.
        eccentricity: f64,
        /// Nominal clearance, m.
        clearance: f64,
    },
    /// A contact penetrated beyond [`crate::scene::limits::MAX_PENETRATION_FRACTION`] of its
    /// clearance (or pin radius): the contact law is outside its validity.
    #[error(
        "{what}: clearance joint {joint}: peak penetration {penetration:.3e} m exceeds {limit:.3e} m \
         (half the smaller of clearance and pin radius): the contact law is outside its validity \
         (material too soft, load too high or tolerances too loose); forces are not trusted"
    )]
    PenetrationBeyondLimit {
        /// Which run.
        what: String,
        /// Clearance joint name.
        joint: String,
        /// Peak penetration, m.
        penetration: f64,
        /// The limit, m.
        limit: f64,
    },
    /// A run produced a non-finite value.
    #[error("{what}: the solution became non-finite (NaN or infinite) at t = {t}")]
    NonFinite {
        /// Which run.
        what: String,
        /// First bad output time.
        t: f64,
    },
}

impl RunError {
    /// Whether the scene itself is at fault (exit code 2) rather than the run (1).
    pub fn is_bad_input(&self) -> bool {
        matches!(
            self,
            RunError::Build(_)
                | RunError::Surfaces(_)
                | RunError::Scene(_)
                | RunError::Kinematics { .. }
                | RunError::Assembly { .. }
                | RunError::PinOutsideBearing { .. }
                | RunError::NoPeriod
                | RunError::NoResponseBody
                | RunError::Trajectories { .. }
        )
    }
}

/// What [`check_assembly`] found.
#[derive(Debug, Clone, Copy, Serialize)]
pub struct AssemblyCheck {
    /// Coordinates (3 per body).
    pub coordinates: usize,
    /// Constraint equations (clearance joints are force elements, not constraints).
    pub constraints: usize,
    /// `coordinates − constraints`.
    pub degrees_of_freedom: isize,
    /// Largest coordinate change assembly made to the file's initial poses (m or rad).
    pub largest_move: f64,
}

/// Everything `run` checks before it simulates, with the same `options`: the scene as run
/// ([`scene_as_run`]: validation after `K` and the trajectories are set), the drive period,
/// the recorded body, the ideal mechanism's kinematic analysis at the output times, and the
/// scene's system assembled at t = 0 from the file's initial poses. So `check` rejects what
/// `run` would. `name` names the scene in errors.
pub fn check_assembly(
    name: &str,
    scene: &Scene,
    options: &RunOptions,
) -> Result<AssemblyCheck, RunError> {
    let scene = &scene_as_run(name, scene, options)?;
    let (times, body) = run_plan(scene)?;
    ideal_motion(scene, &times, body, None)?;
    unworn_joints(scene)?;
    let built = build(scene, Surfaces::default())?;
    let state = assemble(&built, "assembly check")?;
    let (q0, _) = built.system.initial_guess();
    Ok(AssemblyCheck {
        coordinates: built.system.coordinate_count(),
        constraints: built.system.constraint_count(),
        degrees_of_freedom: built.system.degrees_of_freedom(),
        largest_move: q0
            .iter()
            .zip(&state.q)
            .map(|(a, b)| (a - b).abs())
            .fold(0.0, f64::max),
    })
}

/// Simulates `scene` (see the module docs); `name` labels the summary.
pub fn run_scene(
    name: &str,
    scene: &Scene,
    options: &RunOptions,
    progress: &mut dyn Progress,
) -> Result<RunOutcome, RunError> {
    let started = Instant::now();
    let scene_k = scene.run.cycles_per_stage;
    let scene = scene_as_run(name, scene, options)?;
    let (times, body) = run_plan(&scene)?;
    let period = scene.cycle_period().ok_or(RunError::NoPeriod)?;
    let cycles = scene.run.cycles.max(1);
    let t_end = period * f64::from(cycles);
    // The surfaces a run starts from are input: read (and refused) before any simulation.
    let active = scene.active_clearance_joints().count() > 0;
    let unworn = unworn_joints(&scene)?;
    let initial = match &options.surfaces {
        Some(dir) => crate::io::surfaces::load_last_stage(dir, &scene, &unworn)?,
        None => unworn,
    };
    let frames = scene.run.animation.then(|| {
        animation_frames(
            &times,
            scene.run.transient_window,
            period,
            MAX_ANIMATION_FRAMES,
        )
    });
    // The ideal reference is computed on its own thread while the response is simulated (it
    // is needed only to compare them): most of its cost leaves the run's wall time. A
    // mechanism that is not fully driven or does not assemble is still refused before any
    // simulation: the kinematic analysis at the first output time is done first, here.
    ideal_motion(&scene, &times[..times.len().min(1)], body, None)?;
    let start: &[Option<WornJoint>] = if options.surfaces.is_some() {
        &initial
    } else {
        &[]
    };
    let indices = frames.clone().unwrap_or_default();
    let (ideal, simulated) = std::thread::scope(|s| {
        let job = s.spawn(|| ideal_motion(&scene, &times, body, frames));
        // The unworn response samples round surfaces (no wear code); one from loaded
        // surfaces samples those.
        let simulated =
            active.then(|| simulate(&scene, start, &times, &indices, body, progress, "response"));
        let ideal = job
            .join()
            .unwrap_or_else(|panic| std::panic::resume_unwind(panic));
        (ideal, simulated)
    });
    // The ideal mechanism's failure first, as when it was computed before the response.
    let ideal = ideal?;

    let mut wear_history = Vec::new();
    let (response, response_summary, wear_summary, worn) = match simulated {
        None => {
            // Without clearance the mechanism is its ideal self.
            let frames = ideal.frames.map(|f| MechanismFrames {
                poses: f.ideal_poses.clone(),
                ..f
            });
            let response = Response {
                times: times.clone(),
                motion: ideal.motion.clone(),
                ideal: ideal.motion,
                contact: Vec::new(),
                frames,
            };
            let summary = summarize(&scene, &response, None, cycles, t_end);
            (response, summary, None, None)
        }
        Some(simulated) => {
            let (response, summary) = simulated?.compare(&scene, &ideal)?;
            // Worn surfaces may legitimately open the clearance past the limit: warn only there.
            match crate::scene::limits::check_penetration(&scene, "response", &response.contact) {
                Err(e) if options.surfaces.is_some() => progress.note(&format!("warning: {e}")),
                checked => checked?,
            }
            let mut wear_summary = None;
            let mut worn = None;
            if scene.run.wear_stages > 0 && initial.iter().any(Option::is_some) {
                let (history, mut ws, surfaces) =
                    stages(&scene, &initial, period, options.threads, progress)?;
                ws.scene_cycles_per_stage = scene_k;
                wear_history = history;
                wear_summary = Some(ws);
                if !options.skip_worn_response {
                    let run = respond(
                        &scene,
                        &surfaces,
                        &times,
                        &ideal,
                        body,
                        progress,
                        "worn response",
                    )?;
                    // Worn surfaces may legitimately open the clearance past the limit: warn only.
                    if let Err(e) = crate::scene::limits::check_penetration(
                        &scene,
                        "worn response",
                        &run.0.contact,
                    ) {
                        progress.note(&format!("warning: {e}"));
                    }
                    worn = Some(run);
                }
            }
            (response, summary, wear_summary, worn)
        }
    };
    let summary = Summary {
        scene: name.to_string(),
        description: scene.description.clone(),
        contacts: scene
            .clearance_joints
            .iter()
            .map(|j| format!("{}: {}", j.name, j.contact_description()))
            .collect(),
        response_body: scene.bodies[body].name.clone(),
        period_s: period,
        transient_window_s: scene.run.transient_window,
        reference: "kinematic analysis of the scene with every clearance joint ideal, at the \
                    output times"
            .into(),
        response: response_summary,
        wear: wear_summary,
        worn_response: worn.as_ref().map(|(_, s)| s.clone()),
        wall_time_s: started.elapsed().as_secs_f64(),
    };
    Ok(RunOutcome {
        scene,
        summary,
        response,
        worn_response: worn.map(|(r, _)| r),
        wear: wear_history,
    })
}

/// The scene a run simulates: `scene` with `options`' simulated cycles per wear stage `K`
/// (the amplification rescaled so a stage still stands for as many cycles) and trajectories,
/// validated again with them. [`check_assembly`] and [`run_scene`] both start here, so a scene
/// and options one accepts the other does not refuse as bad input. `name` names the scene in
/// errors.
pub fn scene_as_run(name: &str, scene: &Scene, options: &RunOptions) -> Result<Scene, RunError> {
    let mut scene = scene.clone();
    let scene_k = scene.run.cycles_per_stage;
    if let Some(k) = options.cycles_per_stage {
        // K = 0 is left to the validation below, which names it.
        if k > 0 {
            scene.run.amplification *= f64::from(scene_k) / f64::from(k);
        }
        scene.run.cycles_per_stage = k;
    }
    if let Some(m) = options.trajectories {
        scene.run.trajectories = m;
    }
    let (k, m) = (scene.run.cycles_per_stage, scene.run.trajectories);
    if scene.run.wear_stages > 0 && (m == 0 || !k.is_multiple_of(m)) {
        return Err(RunError::Trajectories {
            trajectories: m,
            cycles_per_stage: k,
        });
    }
    scene.validate(&format!(
        "{name} as run (K = {k} cycles per wear stage on {m} trajector{})",
        if m == 1 { "y" } else { "ies" }
    ))?;
    Ok(scene)
}

/// The response run's output times and recorded body of a validated scene.
fn run_plan(scene: &Scene) -> Result<(Vec<f64>, usize), RunError> {
    let period = scene.cycle_period().ok_or(RunError::NoPeriod)?;
    let body = scene.response_body().ok_or(RunError::NoResponseBody)?;
    let t_end = period * f64::from(scene.run.cycles.max(1));
    Ok((
        OutputTimes::uniform(0.0, t_end, scene.solver.output_interval),
        body,
    ))
}

/// Indices into the output `times` of the frames an animation shows (at most `max`): one
/// `period` from the first output time at or after `window`, evenly spaced, the time that
/// closes the cycle left out (the animation loops). A run shorter than the window plus one
/// period gives its last period; one shorter than a period all of it, end included.
pub(crate) fn animation_frames(times: &[f64], window: f64, period: f64, max: usize) -> Vec<usize> {
    let (Some(&first), Some(&last)) = (times.first(), times.last()) else {
        return Vec::new();
    };
    if max == 0 || !(period.is_finite() && period > 0.0) {
        return Vec::new();
    }
    let tol = 1e-9 * period;
    let at_or_after = |t: f64| times.partition_point(|&u| u < t - tol).min(times.len() - 1);
    let mut start = at_or_after(window.max(first));
    if times[start] + period > last + tol {
        start = at_or_after((last - period).max(first));
    }
    let t0 = times[start];
    let full = last - t0 >= period - tol;
    let step = if full {
        period / max as f64
    } else {
        (last - t0) / (max.max(2) - 1) as f64
    };
    let mut frames: Vec<usize> = Vec::with_capacity(max);
    for j in 0..max {
        let t = t0 + j as f64 * step;
        let i = times.partition_point(|&u| u < t).min(times.len() - 1);
        // The nearer of the output times either side of t.
        let k = if i > start && (t - times[i - 1]) <= (times[i] - t) {
            i - 1
        } else {
            i
        };
        let in_cycle = !full || times[k] - t0 <= period - 0.5 * step;
        if in_cycle && frames.last().is_none_or(|&p| k > p) {
            frames.push(k);
        }
    }
    frames
}

/// The all-ideal mechanism's motion of `body` at `times` (kinematic analysis), with the
/// poses of every body at `frames` (indices into `times`) when an animation is drawn.
fn ideal_motion(
    scene: &Scene,
    times: &[f64],
    body: usize,
    frames: Option<Vec<usize>>,
) -> Result<Ideal, RunError> {
    let ideal_built = build(&scene.idealized(), Surfaces::default())?;
    let (q0, _) = ideal_built.system.initial_guess();
    let names = |v: Vec<&str>| {
        if v.is_empty() {
            "(none)".to_string()
        } else {
            v.join(", ")
        }
    };
    let kin = ideal_built
        .system
        .kinematics(times, &q0)
        .map_err(|source| RunError::Kinematics {
            joints: names(
                scene
                    .clearance_joints
                    .iter()
                    .map(|c| c.name.as_str())
                    .collect(),
            ),
            drivers: names(scene.drivers.iter().map(|d| d.name.as_str()).collect()),
            source,
        })?;
    let mut motion = Motion::default();
    for f in 0..kin.times.len() {
        motion.push(body, kin.q(f), kin.qd(f), kin.qdd(f));
    }
    let frames = frames.map(|frames| MechanismFrames {
        ideal_poses: frames
            .iter()
            .map(|&f| MechanismFrames::poses_of(kin.q(f)))
            .collect(),
        frames,
        poses: Vec::new(),
    });
    Ok(Ideal { motion, frames })
}

/// Simulation options from the scene's solver settings (integrator, rtol, the clearance-scaled
/// absolute tolerances, Baumgarte gains) for a run to `t_end`.
pub fn simulation_options(
    scene: &Scene,
    t_end: f64,
    output: OutputTimes,
    record: bool,
) -> SimulationOptions {
    let tol = scene.tolerances();
    let mut o = SimulationOptions::until(t_end);
    o.integrator = scene.solver.integrator;
    o.formulation = scene.solver.formulation;
    o.rtol = scene.solver.rtol;
    o.atol = AbsoluteTolerances {
        position: tol.position,
        angle: tol.angle,
        velocity: tol.velocity,
        angular_velocity: tol.velocity,
    };
    o.baumgarte = Baumgarte {
        alpha: scene.solver.baumgarte_alpha,
        beta: scene.solver.baumgarte_beta,
    };
    o.output = output;
    o.record_trajectory = record;
    o.max_steps = Some(scene.solver.max_steps.unwrap_or(scene::DEFAULT_MAX_STEPS));
    let wall = scene
        .solver
        .max_wall_time
        .unwrap_or(scene::DEFAULT_MAX_WALL_TIME);
    o.max_wall_time = std::time::Duration::try_from_secs_f64(wall).ok();
    o
}

#[cfg(test)]
mod tests {
    use super::animation_frames;

    fn uniform(n: usize, dt: f64) -> Vec<f64> {
        (0..n).map(|k| k as f64 * dt).collect()
    }

    #[test]
    fn frames_span_one_period_from_the_window() {
        let times = uniform(301, 0.01);
        let expected: Vec<usize> = (0..10).map(|j| 11 + 10 * j).collect();
        assert_eq!(animation_frames(&times, 0.105, 1.0, 10), expected);
    }

    #[test]
    fn a_run_too_short_for_the_window_shows_its_last_period() {
        let times = uniform(301, 0.01);
        let expected: Vec<usize> = (0..10).map(|j| 200 + 10 * j).collect();
        assert_eq!(animation_frames(&times, 2.5, 1.0, 10), expected);
    }

    #[test]
    fn coarse_output_gives_every_sample_of_the_period_once() {
        let times = uniform(31, 0.1);
        let expected: Vec<usize> = (0..10).collect();
        assert_eq!(animation_frames(&times, 0.0, 1.0, 72), expected);
    }

    #[test]
    fn a_run_shorter_than_a_period_shows_all_of_it() {
        let times = uniform(6, 0.1);
        assert_eq!(
            animation_frames(&times, 0.3, 1.0, 6),
            vec![0, 1, 2, 3, 4, 5]
        );
        assert!(animation_frames(&[], 0.0, 1.0, 6).is_empty());
        assert!(animation_frames(&times, 0.0, 0.0, 6).is_empty());
        assert!(animation_frames(&times, 0.0, 1.0, 0).is_empty());
    }
}
