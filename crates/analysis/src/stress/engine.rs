//! Running the battery: each case validated, built and integrated in isolation (a panic is a
//! result, not a crash), with its numbers gathered.

use std::panic::{AssertUnwindSafe, catch_unwind};
use std::time::Instant;

use multibody::{Frame, Observer, OutputTimes};
use wear::{Side, WornJoint, WornProfile};

use super::{
    CaseResult, Expect, Outcome, StressCase, StressError, StressOptions, SurfaceSetup, cases,
};
use lgres::scenes;
use scene::Scene;
use sim::build::{Surfaces, build, unworn_joints};
use sim::simulation_options;

/// Tracks the first non-finite sampled state.
struct Watch {
    non_finite_at: Option<f64>,
}

impl Observer for Watch {
    fn output(&mut self, frame: &Frame<'_>) {
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

/// Surfaces whose uniform depth `h = (factor − 1) c0` on both sides makes the clearance
/// `factor × c0`.
fn uniformly_worn(scene: &Scene, factor: f64) -> Result<Vec<Option<WornJoint>>, String> {
    let unworn = unworn_joints(scene).map_err(|e| e.to_string())?;
    unworn
        .into_iter()
        .map(|j| {
            j.map(|j| {
                let c0 = j.nominal_clearance();
                let h = (factor - 1.0) * c0;
                let (b, p) = (j.bearing(), j.pin());
                let bearing = WornProfile::from_depths(
                    Side::Bearing,
                    b.nominal_radius(),
                    vec![h; b.cells()],
                )?;
                let pin =
                    WornProfile::from_depths(Side::Pin, p.nominal_radius(), vec![h; p.cells()])?;
                WornJoint::from_profiles(j.wear_coefficient(), j.hinge_width(), bearing, pin)
            })
            .transpose()
            .map_err(|e| e.to_string())
        })
        .collect()
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

fn run_case_inner(case: &StressCase) -> CaseResult {
    let scene = &case.scene;
    match (
        scene.validate(&format!("stress case {:?}", case.name)),
        &case.expect,
    ) {
        (Err(e), Expect::Rejected(field)) => {
            let named = matches!(&e, scene::SceneError::Invalid { issues, .. }
                if issues.iter().any(|i| i.path.ends_with(field.as_str())));
            let outcome = if named {
                Outcome::ExpectedError {
                    error: "SceneError::Invalid".into(),
                    message: e.to_string(),
                }
            } else {
                failed("SceneError (not the expected field)", e)
            };
            return blank(case, outcome);
        }
        (Err(e), Expect::Completes) => return blank(case, failed("SceneError::Invalid", e)),
        (Ok(()), Expect::Rejected(field)) => {
            return blank(
                case,
                failed(
                    "UnexpectedSuccess",
                    format!("validation accepted the scene; expected an error on {field}"),
                ),
            );
        }
        (Ok(()), Expect::Completes) => {}
    }
    let worn = match case.surfaces {
        SurfaceSetup::Round => Ok(Vec::new()),
        SurfaceSetup::WearOn => unworn_joints(scene).map_err(|e| e.to_string()),
        SurfaceSetup::UniformlyWorn(f) => uniformly_worn(scene, f),
    };
    let worn = match worn {
        Ok(w) => w,
        Err(e) => return blank(case, failed("BuildError", e)),
    };
    let surfaces = Surfaces {
        worn: &worn,
        accumulate_from: (case.surfaces == SurfaceSetup::WearOn).then_some(0.0),
        split_halves_at: None,
    };
    let mut built = match build(scene, surfaces) {
        Ok(b) => b,
        Err(e) => return blank(case, failed("BuildError", e)),
    };
    let (q0, qd0) = built.system.initial_guess();
    let state = match built.system.assemble(0.0, &q0, &qd0) {
        Ok(s) => s,
        Err(e) => return blank(case, failed("AssemblyError", e)),
    };
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
    let mut opts = simulation_options(scene, case.duration, output, false);
    opts.energy_audit = case.energy_audit;
    let mut watch = Watch {
        non_finite_at: None,
    };
    let mut r = blank(case, Outcome::Completed);
    r.atol_position_m = opts.atol.position;
    let sim = match built.system.simulate(&state, &opts, &mut watch) {
        Ok(sim) => sim,
        Err(e) => {
            let name = match &e {
                multibody::SimulationError::Assembly(_) => "SimulationError::Assembly",
                multibody::SimulationError::InvalidOptions(_) => "SimulationError::InvalidOptions",
                multibody::SimulationError::Evaluation { .. } => "SimulationError::Evaluation",
                multibody::SimulationError::Integrator { .. } => "SimulationError::Integrator",
                multibody::SimulationError::StepLimit { .. } => "SimulationError::StepLimit",
                multibody::SimulationError::WallTimeLimit { .. } => {
                    "SimulationError::WallTimeLimit"
                }
            };
            r.outcome = failed(name, e);
            return r;
        }
    };
    let s = &sim.statistics;
    r.steps = s.steps;
    r.rejected_steps = s.rejected_steps;
    r.newton_failures = s.nonlinear_solver_failures;
    r.smallest_step_s = s.smallest_step;
    r.events = s.events;
    r.drift_position = sim.drift.position;
    if let Some(e) = &sim.energy {
        r.energy_residual_j = e.residual;
        r.energy_relative_residual = e.relative_residual();
    }
    r.peak_normal_force_n = built
        .joints
        .iter()
        .map(|h| {
            let peak = h
                .probe(built.system.elements())
                .map_or(f64::NAN, |p| p.peak_normal_force());
            (h.name.clone(), peak)
        })
        .collect();
    for h in built.joints.iter().filter(|h| h.worn) {
        if let Some(w) = built
            .system
            .element_mut::<clearance::WornClearanceForce>(h.element)
            .and_then(|e| e.stage_wear())
        {
            r.wear_depth_m.push((h.name.clone(), w.max_depth()));
            r.wear_volume_ratio
                .push((h.name.clone(), w.worn_volume() / w.archard_volume()));
        }
    }
    let final_ok = sim
        .final_state
        .q
        .iter()
        .chain(&sim.final_state.qd)
        .all(|x| x.is_finite());
    let end_reached = sim.final_state.t >= case.duration * (1.0 - 1e-9);
    r.outcome = if let Some(t) = watch.non_finite_at {
        failed("NonFinite", format!("non-finite state at t = {t} s"))
    } else if !final_ok {
        failed("NonFinite", "the final state is not finite")
    } else if !end_reached {
        failed(
            "Incomplete",
            format!(
                "the run stopped at t = {} s of {} s",
                sim.final_state.t, case.duration
            ),
        )
    } else if let Some((name, value)) = first_non_finite(&r, case.energy_audit) {
        failed("NonFinite", format!("{name} = {value} is not finite"))
    } else {
        Outcome::Completed
    };
    r
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
