//! Building and running a scene, between the scene format (the `scene` crate) and what is made
//! of a run (crate `output`'s files, figures and reports; crate `analysis`'s studies): a
//! validated scene → a
//! `multibody` system ([`build`]), one run of it ([`run_scene`]), the validity of its worn
//! geometry ([`validity`]), the run settings given outside the scene file ([`overrides`]) and
//! the worn surfaces a run starts from, handed over in memory ([`surfaces`]). No file is read
//! or written here.
//!
//! One run of a scene: the response over `cycles` drive periods against the ideal mechanism,
//! then the wear stages, with every summary number kept in memory ([`RunOutcome`]).
//!
//! [`run_scene`] is what the CLI's `run` calls and what a study loop can call repeatedly; it
//! writes nothing (`output::artifacts` does) and reports progress through [`Progress`].
//!
//! ```
//! const CRANK: &str = r#"
//! description = "A driven crank"
//! inertia_convention = "centroidal"
//! gravity = [0.0, -9.81]
//!
//! [[bodies]]
//! name = "crank"
//! mass = 0.3
//! inertia = 1e-4
//! x = 0.025
//! y = 0.0
//! theta_deg = 0.0
//!
//! [[revolute_joints]]
//! name = "O"
//! body = "crank"
//! point = [-0.025, 0.0]
//! other = "ground"
//! other_point = [0.0, 0.0]
//!
//! [[drivers]]
//! name = "speed"
//! target = { kind = "body-coordinate", body = "crank", coordinate = "theta" }
//! law = { kind = "ramp", value = 0.0, rate = 6.283 }
//! "#;
//! let crank = scene::load_str(CRANK, "crank", &[])?;
//! let options = sim::RunOptions::default();
//! let outcome = sim::run_scene("crank", &crank, &options, &mut ())?;
//! // No clearance joint: the response is the ideal mechanism's, nothing wears.
//! assert!(!outcome.response.times.is_empty());
//! assert!(outcome.response.contact.is_empty());
//! # Ok::<(), sim::RunError>(())
//! ```
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

#![warn(missing_docs)]

pub mod build;
mod error;
mod ideal;
mod life;
mod options;
mod outcome;
pub mod overrides;
mod progress;
mod record;
mod stages;
mod summary;
pub mod surfaces;
pub mod validity;

use std::time::Instant;

use multibody::OutputTimes;
use serde::Serialize;
use wear::WornJoint;

use crate::build::{Surfaces, build, unworn_joints};
use ideal::IdealMechanism;
use scene::{Scene, ValidScene};

pub use error::RunError;
pub use life::cycles_to_reach;
pub use options::{RunOptions, simulation_options};
pub use outcome::{
    ClearanceLimitReport, ContactSeries, Deviation, JointSummary, JointWearHistory,
    JointWearSummary, LifePoint, MechanismFrames, Motion, Numerics, PeakStats, Response,
    ResponseSummary, RunOutcome, SubstepSummary, Summary, WearSummary,
};
pub use progress::Progress;
use record::{assemble, respond, simulate};
use stages::stages;
use summary::summarize;
pub use summary::{
    ENERGY_BOOKS_TOLERANCE_J, STAGE_HALVES_TOLERANCE, median_bootstrap_noise, peak_stats,
};
pub use validity::MIN_ELASTIC_SHARE;

/// Most frames an animation shows: one drive cycle in at most this many poses
/// ([`MechanismFrames`], `output::animation`).
pub const MAX_ANIMATION_FRAMES: usize = 72;

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
    scene: &ValidScene,
    options: &RunOptions,
) -> Result<AssemblyCheck, RunError> {
    let scene = &scene_as_run(name, scene, options)?;
    let (times, body) = run_plan(scene)?;
    IdealMechanism::build(scene)?.motion(&times, body, None)?;
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
    scene: &ValidScene,
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
        Some(source) => source.load(&scene, &unworn)?,
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
    let ideal_mechanism = IdealMechanism::build(&scene)?;
    ideal_mechanism.motion(&times[..times.len().min(1)], body, None)?;
    let start: &[Option<WornJoint>] = if options.surfaces.is_some() {
        &initial
    } else {
        &[]
    };
    let indices = frames.clone().unwrap_or_default();
    let (ideal, simulated) = std::thread::scope(|s| {
        let times = &times;
        let job = s.spawn(move || ideal_mechanism.motion(times, body, frames));
        // The unworn response samples round surfaces (no wear code); one from loaded
        // surfaces samples those.
        let simulated =
            active.then(|| simulate(&scene, start, times, &indices, body, progress, "response"));
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
            match validity::check_penetration(&scene, "response", &response.contact) {
                Err(e) if options.surfaces.is_some() => progress.note(&format!("warning: {e}")),
                checked => checked?,
            }
            let mut wear_summary = None;
            let mut worn = None;
            if scene.run.wear_stages > 0 && initial.iter().any(Option::is_some) {
                let staged = stages(&scene, &initial, period, scene_k, options.threads, progress)?;
                wear_history = staged.history;
                wear_summary = Some(staged.summary);
                if !options.skip_worn_response {
                    let (worn_response, worn_summary) = respond(
                        &scene,
                        &staged.surfaces,
                        &times,
                        &ideal,
                        body,
                        progress,
                        "worn response",
                    )?;
                    // Worn surfaces may legitimately open the clearance past the limit: warn only.
                    if let Err(e) =
                        validity::check_penetration(&scene, "worn response", &worn_response.contact)
                    {
                        progress.note(&format!("warning: {e}"));
                    }
                    worn = Some((worn_response, worn_summary));
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
/// checked again only if they change it ([`ValidScene::edit`]). [`check_assembly`] and
/// [`run_scene`] both start here, so a scene and options one accepts the other does not refuse
/// as bad input. `name` names the scene in errors.
pub fn scene_as_run(
    name: &str,
    scene: &ValidScene,
    options: &RunOptions,
) -> Result<ValidScene, RunError> {
    let scene_k = scene.run.cycles_per_stage;
    let k = options.cycles_per_stage.unwrap_or(scene_k);
    let m = options.trajectories.unwrap_or(scene.run.trajectories);
    if scene.run.wear_stages > 0 && (m == 0 || !k.is_multiple_of(m)) {
        return Err(RunError::Trajectories {
            trajectories: m,
            cycles_per_stage: k,
        });
    }
    if (k, m) == (scene_k, scene.run.trajectories) {
        return Ok(scene.clone());
    }
    let origin = format!(
        "{name} as run (K = {k} cycles per wear stage on {m} trajector{})",
        if m == 1 { "y" } else { "ies" }
    );
    Ok(scene.clone().edit(&origin, |scene| {
        // K = 0 is left to the validation, which names it.
        if k > 0 {
            scene.run.amplification *= f64::from(scene_k) / f64::from(k);
        }
        scene.run.cycles_per_stage = k;
        scene.run.trajectories = m;
    })?)
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
