//! Running the battery: each case validated, then built and integrated in isolation through
//! [`sim::integrate`] (a panic is a result, not a crash), with its numbers gathered.

use std::panic::{AssertUnwindSafe, catch_unwind};
use std::time::Instant;

use multibody::{Frame, OutputTimes};

use super::{
    CaseResult, Expect, Outcome, StressCase, StressError, StressOptions, SurfaceSetup, cases,
};
use lgres::scenes;
use scene::ValidScene;
use sim::build::JointHandle;
use sim::integrate::{FrameObserver, StartSurfaces, StepBudget};
use sim::{Integrated, Integration, IntegrationError, IntegrationErrorKind};

/// Tracks the first non-finite sampled state.
#[derive(Default)]
struct Watch {
    non_finite_at: Option<f64>,
}

impl FrameObserver for Watch {
    fn frame(&mut self, frame: &Frame<'_>, _joints: &[JointHandle]) {
        if self.non_finite_at.is_none()
            && frame
                .q
                .iter()
                .chain(frame.qd)
                .chain(frame.qdd)
                .any(|x| !x.is_finite())
        {
            self.non_finite_at = Some(frame.t);
        }
    }
}

fn blank(case: &StressCase, outcome: Outcome) -> CaseResult {
    CaseResult {
        name: case.name.clone(),
        description: case.description.clone(),
        duration_s: case.duration,
        outcome,
        steps: 0,
        rejected_steps: 0,
        newton_failures: 0,
        smallest_step_s: f64::NAN,
        events: 0,
        drift_position: f64::NAN,
        energy_residual_j: f64::NAN,
        energy_relative_residual: f64::NAN,
        peak_normal_force_n: Vec::new(),
        wear_depth_m: Vec::new(),
        wear_volume_ratio: Vec::new(),
        atol_position_m: f64::NAN,
        wall_time_s: 0.0,
    }
}

fn failed(error: &str, message: impl ToString) -> Outcome {
    Outcome::Failed {
        error: error.into(),
        message: message.to_string(),
    }
}

/// Runs one case; never panics (a panic inside is caught and reported as `Failed`).
pub fn run_case(case: &StressCase) -> CaseResult {
    let started = Instant::now();
    let mut result = match catch_unwind(AssertUnwindSafe(|| run_case_inner(case))) {
        Ok(r) => r,
        Err(payload) => {
            let message = payload
                .downcast_ref::<String>()
                .cloned()
                .or_else(|| payload.downcast_ref::<&str>().map(|s| s.to_string()))
                .unwrap_or_else(|| "unknown panic".into());
            blank(case, failed("Panic", message))
        }
    };
    result.wall_time_s = started.elapsed().as_secs_f64();
    result
}

/// One case as named steps: its scene validated as expected, its integration, its numbers and
/// their verdict.
fn run_case_inner(case: &StressCase) -> CaseResult {
    let scene = match validated(case) {
        Ok(scene) => scene,
        Err(outcome) => return blank(case, outcome),
    };
    let integration = integration_of(case, &scene);
    let mut watch = Watch::default();
    match sim::integrate(&scene, &integration, &mut watch) {
        Err(e) => failed_integration(case, &scene, &integration, &e),
        Ok(run) => {
            let mut r = measured(case, &run);
            r.atol_position_m = integration.simulation_options(&scene).atol.position;
            r.outcome = verdict(case, &r, &run, &watch);
            r
        }
    }
}

/// The case's scene once validated; `Err`: the outcome of its validation when the case ends
/// there (the expected rejection, or a rejection or acceptance that was not expected).
fn validated(case: &StressCase) -> Result<ValidScene, Outcome> {
    let origin = format!("stress case {:?}", case.name);
    match (ValidScene::new(case.scene.clone(), &origin), &case.expect) {
        (Err(e), Expect::Rejected(field)) => {
            let named = matches!(&e, scene::SceneError::Invalid { issues, .. }
                if issues.iter().any(|i| i.path.ends_with(field.as_str())));
            Err(if named {
                Outcome::ExpectedError {
                    error: "SceneError::Invalid".into(),
                    message: e.to_string(),
                }
            } else {
                failed("SceneError (not the expected field)", e)
            })
        }
        (Err(e), Expect::Completes) => Err(failed("SceneError::Invalid", e)),
        (Ok(_), Expect::Rejected(field)) => Err(failed(
            "UnexpectedSuccess",
            format!("validation accepted the scene; expected an error on {field}"),
        )),
        (Ok(scene), Expect::Completes) => Ok(scene),
    }
}

/// The case's integration: its surfaces, its duration sampled densely or once per drive
/// cycle, its energy audit; the scene's solver settings.
fn integration_of(case: &StressCase, scene: &ValidScene) -> Integration {
    let output = if case.dense_output {
        OutputTimes::Every(scene.solver.output_interval)
    } else {
        let period = scene.cycle_period().unwrap_or(case.duration);
        let n = (case.duration / period).round().max(1.0) as usize;
        OutputTimes::At(
            (0..=n)
                .map(|k| (k as f64 * period).min(case.duration))
                .collect(),
        )
    };
    let surfaces = match case.surfaces {
        SurfaceSetup::Round => StartSurfaces::Round,
        SurfaceSetup::WearOn => StartSurfaces::Wearing {
            accumulate_from: 0.0,
        },
        SurfaceSetup::UniformlyWorn(factor) => StartSurfaces::UniformlyWorn { factor },
    };
    Integration {
        t_end: case.duration,
        output,
        energy_audit: case.energy_audit,
        max_steps: StepBudget::Scene,
        tolerances: None,
        surfaces,
    }
}

/// A case whose integration failed, named by the error's kind; the tolerance is reported when
/// the integrator ran.
fn failed_integration(
    case: &StressCase,
    scene: &ValidScene,
    integration: &Integration,
    e: &IntegrationError,
) -> CaseResult {
    let kind = e.kind();
    let mut r = blank(case, failed(kind.name(), e));
    if let IntegrationErrorKind::Simulation(_) = kind {
        r.atol_position_m = integration.simulation_options(scene).atol.position;
    }
    r
}

/// The numbers of a finished integration: solver counts, drift, energy books, peak forces,
/// wear.
fn measured(case: &StressCase, run: &Integrated) -> CaseResult {
    let mut r = blank(case, Outcome::Completed);
    let s = &run.result.statistics;
    r.steps = s.steps;
    r.rejected_steps = s.rejected_steps;
    r.newton_failures = s.nonlinear_solver_failures;
    r.smallest_step_s = s.smallest_step;
    r.events = s.events;
    r.drift_position = run.result.drift.position;
    if let Some(e) = &run.result.energy {
        r.energy_residual_j = e.residual;
        r.energy_relative_residual = e.relative_residual();
    }
    r.peak_normal_force_n = run
        .joints
        .iter()
        .map(|j| (j.name.clone(), j.peak_normal_force.unwrap_or(f64::NAN)))
        .collect();
    for (name, w) in run
        .joints
        .iter()
        .filter_map(|j| Some((&j.name, j.stage_wear.as_ref()?)))
    {
        r.wear_depth_m.push((name.clone(), w.max_depth()));
        r.wear_volume_ratio
            .push((name.clone(), w.worn_volume() / w.archard_volume()));
    }
    r
}

/// Completed only if the run reached its end with every sampled state and every measured
/// number finite.
fn verdict(case: &StressCase, r: &CaseResult, run: &Integrated, watch: &Watch) -> Outcome {
    let end = &run.result.final_state;
    let final_ok = end.q.iter().chain(&end.qd).all(|x| x.is_finite());
    let end_reached = end.t >= case.duration * (1.0 - 1e-9);
    if let Some(t) = watch.non_finite_at {
        failed("NonFinite", format!("non-finite state at t = {t} s"))
    } else if !final_ok {
        failed("NonFinite", "the final state is not finite")
    } else if !end_reached {
        failed(
            "Incomplete",
            format!("the run stopped at t = {} s of {} s", end.t, case.duration),
        )
    } else if let Some((name, value)) = first_non_finite(r, case.energy_audit) {
        failed("NonFinite", format!("{name} = {value} is not finite"))
    } else {
        Outcome::Completed
    }
}

/// The first measured number of `r` that is NaN or infinite, named as in the CSV. Finite states
/// do not make a case `ok` by themselves: a NaN residual, peak or wear ratio means the books or
/// the grid went wrong (a report must never print `ok` next to `NaN`). The energy books count
/// only when the case ran the audit: without it they are NaN for "not measured".
fn first_non_finite(r: &CaseResult, energy_audit: bool) -> Option<(String, f64)> {
    let mut measured = vec![
        ("smallest_step_s".to_string(), r.smallest_step_s),
        ("drift_position".to_string(), r.drift_position),
        ("atol_position_m".to_string(), r.atol_position_m),
    ];
    if energy_audit {
        measured.push(("energy_residual_j".into(), r.energy_residual_j));
        measured.push((
            "energy_relative_residual".into(),
            r.energy_relative_residual,
        ));
    }
    let per_joint = [
        ("peak_normal_force_n", &r.peak_normal_force_n),
        ("wear_depth_m", &r.wear_depth_m),
        ("wear_volume_ratio", &r.wear_volume_ratio),
    ];
    for (what, values) in per_joint {
        measured.extend(values.iter().map(|(j, v)| (format!("{what} of {j}"), *v)));
    }
    measured.into_iter().find(|(_, v)| !v.is_finite())
}

/// Runs every case of [`cases`] on the shipped `lgres` scene (the long one unless `quick`);
/// `on_case` is called before (`None`) and after (`Some`) each case, e.g. for progress.
pub fn run_battery(
    options: &StressOptions,
    on_case: &mut dyn FnMut(&StressCase, Option<&CaseResult>),
) -> Result<Vec<CaseResult>, StressError> {
    let base = scenes::builtin(scenes::DEFAULT)?;
    Ok(run_cases(
        &cases(&base, options.duration),
        options.quick,
        on_case,
    ))
}

/// Runs `cases` (skipping long ones when `quick`).
pub fn run_cases(
    cases: &[StressCase],
    quick: bool,
    on_case: &mut dyn FnMut(&StressCase, Option<&CaseResult>),
) -> Vec<CaseResult> {
    cases
        .iter()
        .map(|c| {
            on_case(c, None);
            let r = if quick && c.long {
                blank(
                    c,
                    Outcome::Skipped {
                        reason: format!("--quick: the {:.0} s run is left out", c.duration),
                    },
                )
            } else {
                run_case(c)
            };
            on_case(c, Some(&r));
            r
        })
        .collect()
}
