//! One run in memory, in named steps: the scene as run, its plan, the start surfaces, the
//! response beside the ideal mechanism, the wear stages and the worn response, the outcome.

use std::time::Instant;

use multibody::OutputTimes;
use serde::Serialize;
use wear::WornJoint;

use crate::build::{Surfaces, build, unworn_joints};
use crate::ideal::IdealMechanism;
use crate::outcome::{
    MechanismFrames, Response, ResponseSummary, RunOutcome, Summary, WearSummary,
};
use crate::record::{Ideal, Simulated, assemble, respond, simulate};
use crate::stages::stages;
use crate::summary::summarize;
use crate::{JointWearHistory, Progress, RunError, RunOptions, validity};
use scene::{Scene, ValidScene};

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
    let plan = RunPlan::of(scene)?;
    IdealMechanism::build(scene)?.motion(&plan.times, plan.body, None)?;
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
    let plan = RunPlan::of(&scene)?;
    // The surfaces a run starts from are input: read (and refused) before any simulation.
    let unworn = unworn_joints(&scene)?;
    let initial = match &options.surfaces {
        Some(source) => source.load(&scene, &unworn)?,
        None => unworn,
    };
    // The unworn response samples round surfaces (no wear code); one from loaded surfaces
    // samples those.
    let start = if options.surfaces.is_some() {
        &initial[..]
    } else {
        &[]
    };
    let (ideal, simulated) = response_beside_ideal(&scene, &plan, start, progress)?;
    let (response, response_summary, wear) = match simulated {
        None => {
            let (response, summary) = kinematic_response(&scene, &plan, ideal);
            (response, summary, None)
        }
        Some(simulated) => {
            let (response, summary) = simulated?.compare(&scene, &ideal)?;
            // Worn surfaces may legitimately open the clearance past the limit: warn only there.
            match validity::check_penetration(&scene, "response", &response.contact) {
                Err(e) if options.surfaces.is_some() => progress.note(&format!("warning: {e}")),
                checked => checked?,
            }
            let wear = if scene.run.wear_stages > 0 && initial.iter().any(Option::is_some) {
                let wear = Wear {
                    scene: &scene,
                    plan: &plan,
                    ideal: &ideal,
                    options,
                    scene_k,
                };
                Some(wear.run(&initial, progress)?)
            } else {
                None
            };
            (response, summary, wear)
        }
    };
    let (history, wear_summary, worn) = match wear {
        Some(w) => (w.history, Some(w.summary), w.worn),
        None => (Vec::new(), None, None),
    };
    let summary = Summary {
        scene: name.to_string(),
        description: scene.description.clone(),
        contacts: scene
            .clearance_joints
            .iter()
            .map(|j| format!("{}: {}", j.name, j.contact_description()))
            .collect(),
        response_body: scene.bodies[plan.body].name.clone(),
        period_s: plan.period,
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
        wear: history,
    })
}

/// What a run records, settled before any simulation.
struct RunPlan {
    /// The output times, over the run's cycles.
    times: Vec<f64>,
    /// The recorded body.
    body: usize,
    /// The drive period (s).
    period: f64,
    /// Drive cycles of the response run.
    cycles: u32,
    /// The response run's end (s).
    t_end: f64,
}

impl RunPlan {
    /// The plan of a validated scene.
    fn of(scene: &Scene) -> Result<Self, RunError> {
        let period = scene.cycle_period().ok_or(RunError::NoPeriod)?;
        let body = scene.response_body().ok_or(RunError::NoResponseBody)?;
        let cycles = scene.run.cycles.max(1);
        let t_end = period * f64::from(cycles);
        Ok(Self {
            times: OutputTimes::uniform(0.0, t_end, scene.solver.output_interval),
            body,
            period,
            cycles,
            t_end,
        })
    }
}

/// The response simulated from `start` surfaces (empty: round) while the ideal mechanism's
/// motion is computed on its own thread (it is needed only to compare them: most of its cost
/// leaves the run's wall time). A mechanism that is not fully driven or does not assemble is
/// still refused before any simulation: its kinematic analysis at the first output time comes
/// first. `None` for the response when no clearance joint is active; the ideal mechanism's
/// failure is returned before the response's.
fn response_beside_ideal(
    scene: &ValidScene,
    plan: &RunPlan,
    start: &[Option<WornJoint>],
    progress: &mut dyn Progress,
) -> Result<(Ideal, Option<Result<Simulated, RunError>>), RunError> {
    let (times, body) = (&plan.times, plan.body);
    let frames = scene.run.animation.then(|| {
        animation_frames(
            times,
            scene.run.transient_window,
            plan.period,
            MAX_ANIMATION_FRAMES,
        )
    });
    let ideal_mechanism = IdealMechanism::build(scene)?;
    ideal_mechanism.motion(&times[..times.len().min(1)], body, None)?;
    let indices = frames.clone().unwrap_or_default();
    let active = scene.active_clearance_joints().count() > 0;
    let (ideal, simulated) = std::thread::scope(|s| {
        let job = s.spawn(move || ideal_mechanism.motion(times, body, frames));
        let simulated =
            active.then(|| simulate(scene, start, times, &indices, body, progress, "response"));
        let ideal = job
            .join()
            .unwrap_or_else(|panic| std::panic::resume_unwind(panic));
        (ideal, simulated)
    });
    Ok((ideal?, simulated))
}

/// Without clearance the mechanism is its ideal self: the response is the kinematic analysis.
fn kinematic_response(scene: &Scene, plan: &RunPlan, ideal: Ideal) -> (Response, ResponseSummary) {
    let frames = ideal.frames.map(|f| MechanismFrames {
        poses: f.ideal_poses.clone(),
        ..f
    });
    let response = Response {
        times: plan.times.clone(),
        motion: ideal.motion.clone(),
        ideal: ideal.motion,
        contact: Vec::new(),
        frames,
    };
    let summary = summarize(scene, &response, None, plan.cycles, plan.t_end);
    (response, summary)
}

/// The wear stages of a run and, unless skipped, the response on the surfaces they leave.
struct Wear<'a> {
    scene: &'a ValidScene,
    plan: &'a RunPlan,
    ideal: &'a Ideal,
    options: &'a RunOptions,
    /// The scene's own K before any override.
    scene_k: u32,
}

/// What the wear stages and the worn response gave.
struct Worn {
    history: Vec<JointWearHistory>,
    summary: WearSummary,
    worn: Option<(Response, ResponseSummary)>,
}

impl Wear<'_> {
    fn run(
        &self,
        initial: &[Option<WornJoint>],
        progress: &mut dyn Progress,
    ) -> Result<Worn, RunError> {
        let (scene, plan) = (self.scene, self.plan);
        let staged = stages(
            scene,
            initial,
            plan.period,
            self.scene_k,
            self.options.threads,
            progress,
        )?;
        let worn = if self.options.skip_worn_response {
            None
        } else {
            let (response, summary) = respond(
                scene,
                &staged.surfaces,
                &plan.times,
                self.ideal,
                plan.body,
                progress,
                "worn response",
            )?;
            // Worn surfaces may legitimately open the clearance past the limit: warn only.
            if let Err(e) = validity::check_penetration(scene, "worn response", &response.contact) {
                progress.note(&format!("warning: {e}"));
            }
            Some((response, summary))
        };
        Ok(Worn {
            history: staged.history,
            summary: staged.summary,
            worn,
        })
    }
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
