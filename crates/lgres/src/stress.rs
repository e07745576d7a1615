//! The stress battery: the default LGRES scene under stiff and extreme overrides, each run
//! briefly, to check that the integration stays finite and the step size does not collapse.
//!
//! Every case is one override of the shipped `lgres` scene (applied to both clearance joints),
//! validated like a scene file, built and integrated from the concentric start for
//! [`DEFAULT_DURATION`] (the start-up impacts plus some contact) unless the case says
//! otherwise. A case never panics the battery: validation, build, assembly and integrator
//! errors, non-finite states and even panics are caught and reported as that case's
//! [`Outcome`].
//!
//! Decisions, so the outcomes are read the same way everywhere:
//! - **Zero clearance** is rejected by scene validation (`clearance_joints[k].clearance: must be
//!   positive`), not treated as an ideal joint: an ideal joint is asked for explicitly with
//!   `ideal = true`. The case expects that named error.
//! - **`v0 = v1`** in Ambrósio friction is rejected by validation (`v1: must exceed v0`), not
//!   turned into plain Coulomb friction (which the scene format rejects: the integrator cannot
//!   step over its jump). The case expects that error.
//! - **Long run** (1000 cycles) is skipped with `--quick`; when run, it samples once per cycle
//!   and turns the energy audit off (its quadrature costs about a third of a run), so it reports
//!   no energy residual.
//! - **Doubled clearance by wear**: both surfaces carry a uniform Archard depth `h = c0`, so the
//!   local clearance `c0 + (h_bearing + h_pin)/2 = 2 c0` everywhere; the tolerances stay those
//!   of the nominal clearance (the scene's default `2e-4 × c0`).

use std::fmt::Write as _;
use std::panic::{AssertUnwindSafe, catch_unwind};
use std::path::{Path, PathBuf};
use std::time::Instant;

use multibody::{Frame, Observer, OutputTimes};
use serde::Serialize;
use wear::{Side, WornJoint, WornProfile};

use crate::build::{Surfaces, build, unworn_joints};
use crate::output::{OutputError, sci, write_atomic};
use crate::run::simulation_options;
use contact::{FrictionLawParams, NormalLawParams};

use crate::scene::{Scene, TimeLaw};
use crate::scenes;

/// Simulated time of a short case, s: the start-up impacts (first 0.02 s) plus contact.
pub const DEFAULT_DURATION: f64 = 0.3;
/// Drive cycles of the long case (skipped with `quick`).
pub const LONG_CYCLES: u32 = 1000;

/// What a case is expected to do.
#[derive(Debug, Clone, PartialEq, Eq, Serialize)]
pub enum Expect {
    /// Integrate to the end, finite.
    Completes,
    /// Be rejected by scene validation with an issue on a field whose path ends with this.
    Rejected(String),
}

/// How the surfaces of the clearance joints are set up.
#[derive(Debug, Clone, Copy, PartialEq, Serialize)]
pub enum SurfaceSetup {
    /// Round surfaces, no wear code (the response run's set-up).
    Round,
    /// Wear grids on, accumulating Archard wear on every accepted step from t = 0.
    WearOn,
    /// Frozen worn surfaces with a uniform depth making the clearance this many times `c0`.
    UniformlyWorn(f64),
}

/// One case of the battery.
#[derive(Debug, Clone)]
pub struct StressCase {
    /// Short name (table key).
    pub name: String,
    /// What was changed.
    pub description: String,
    /// The scene with the override applied (not yet validated).
    pub scene: Scene,
    /// Simulated time, s.
    pub duration: f64,
    /// Surfaces.
    pub surfaces: SurfaceSetup,
    /// Expected outcome.
    pub expect: Expect,
    /// Output every `solver.output_interval` (true) or once per drive cycle (false).
    pub dense_output: bool,
    /// Run the energy audit.
    pub energy_audit: bool,
    /// Skipped in a quick battery.
    pub long: bool,
}

/// How a case ended.
#[derive(Debug, Clone, PartialEq, Serialize)]
#[serde(tag = "kind", rename_all = "kebab-case")]
pub enum Outcome {
    /// Integrated to the end; every sampled state finite.
    Completed,
    /// Rejected with the expected named error.
    ExpectedError {
        /// Error name, e.g. `SceneError::Invalid`.
        error: String,
        /// Its message.
        message: String,
    },
    /// Did not do what was expected: the diagnostic says why.
    Failed {
        /// Error name (e.g. `SimulationError::Integrator`, `NonFinite`, `Panic`,
        /// `UnexpectedSuccess`).
        error: String,
        /// Its message.
        message: String,
    },
    /// Not run (the long case in a quick battery).
    Skipped {
        /// Why.
        reason: String,
    },
}

impl Outcome {
    /// `ok`, `expected error`, `FAILED` or `skipped`.
    pub fn label(&self) -> &'static str {
        match self {
            Outcome::Completed => "ok",
            Outcome::ExpectedError { .. } => "expected error",
            Outcome::Failed { .. } => "FAILED",
            Outcome::Skipped { .. } => "skipped",
        }
    }

    /// The error name and message on one line, if any.
    pub fn detail(&self) -> String {
        let text = match self {
            Outcome::Completed => String::new(),
            Outcome::ExpectedError { error, message } | Outcome::Failed { error, message } => {
                format!("{error}: {message}")
            }
            Outcome::Skipped { reason } => reason.clone(),
        };
        text.split_whitespace().collect::<Vec<_>>().join(" ")
    }
}

/// Numbers of one case (NaN where not measured).
#[derive(Debug, Clone, Serialize)]
pub struct CaseResult {
    /// Case name.
    pub name: String,
    /// What was changed.
    pub description: String,
    /// Simulated time asked for, s.
    pub duration_s: f64,
    /// How it ended.
    pub outcome: Outcome,
    /// Accepted steps.
    pub steps: usize,
    /// Rejected steps (local error test).
    pub rejected_steps: usize,
    /// Newton (nonlinear solver) failures.
    pub newton_failures: usize,
    /// Smallest accepted step, s.
    pub smallest_step_s: f64,
    /// Located contact events.
    pub events: usize,
    /// Largest |Φ| over the run, m or rad.
    pub drift_position: f64,
    /// Energy-balance residual, J (NaN: audit off).
    pub energy_residual_j: f64,
    /// Residual relative to the largest energy term.
    pub energy_relative_residual: f64,
    /// Largest normal force at an accepted step end, per clearance joint `(name, N)`.
    pub peak_normal_force_n: Vec<(String, f64)>,
    /// Wear cases: deepest accumulated cell per joint `(name, m)`, before any amplification.
    pub wear_depth_m: Vec<(String, f64)>,
    /// Wear cases: grid volume over Archard volume, per joint (1 + the arc-to-chord excess).
    pub wear_volume_ratio: Vec<(String, f64)>,
    /// Position absolute tolerance used, m.
    pub atol_position_m: f64,
    /// Wall time of the case (build, assembly, integration), s.
    pub wall_time_s: f64,
}

/// Battery settings.
#[derive(Debug, Clone, Copy)]
pub struct StressOptions {
    /// Skip the long case.
    pub quick: bool,
    /// Simulated time of the short cases, s.
    pub duration: f64,
}

impl Default for StressOptions {
    fn default() -> Self {
        Self {
            quick: false,
            duration: DEFAULT_DURATION,
        }
    }
}

/// Why the battery could not start or write its report (a failing case is not an error).
#[derive(Debug, thiserror::Error)]
pub enum StressError {
    /// The base scene did not load.
    #[error(transparent)]
    Scene(#[from] crate::scene::SceneError),
    /// A report file could not be written.
    #[error(transparent)]
    Output(#[from] OutputError),
}

fn each_joint(scene: &mut Scene, f: impl Fn(&mut crate::scene::ClearanceJoint)) {
    scene.clearance_joints.iter_mut().for_each(f);
}

fn set_restitution(scene: &mut Scene, e: f64) {
    each_joint(scene, |c| match &mut c.normal_law {
        NormalLawParams::LankaraniNikravesh(d)
        | NormalLawParams::HuntCrossley(d)
        | NormalLawParams::Flores(d) => d.restitution = e,
        NormalLawParams::Hertz(_) => {}
    });
}

fn set_friction(scene: &mut Scene, cf: f64) {
    each_joint(scene, |c| match &mut c.friction {
        FrictionLawParams::Ambrosio(a) => a.coefficient = cf,
        FrictionLawParams::Coulomb(k) => k.coefficient = cf,
        FrictionLawParams::None => {}
    });
}

/// The battery's cases on `base` (normally the shipped `lgres`), short ones lasting
/// `duration` s.
pub fn cases(base: &Scene, duration: f64) -> Vec<StressCase> {
    let case = |name: &str, description: &str, edit: &dyn Fn(&mut Scene)| {
        let mut scene = base.clone();
        edit(&mut scene);
        StressCase {
            name: name.into(),
            description: description.into(),
            scene,
            duration,
            surfaces: SurfaceSetup::Round,
            expect: Expect::Completes,
            dense_output: true,
            energy_audit: true,
            long: false,
        }
    };
    let mut v = vec![
        case("baseline", "the shipped lgres scene", &|_| {}),
        case("clearance 1 µm", "clearance 1e-6 m", &|s| {
            each_joint(s, |c| c.clearance = 1e-6)
        }),
        case(
            "clearance 1 µm, rtol 1e-9",
            "clearance 1e-6 m and rtol 1e-9, so rtol·|q| (q ~ 1 m) is 1e-3 of the clearance \
             (shipped scene: 2e-3), not all of it",
            &|s| {
                each_joint(s, |c| c.clearance = 1e-6);
                s.solver.rtol = 1e-9;
            },
        ),
        case("clearance 5 mm", "clearance 5e-3 m", &|s| {
            each_joint(s, |c| c.clearance = 5e-3)
        }),
        StressCase {
            expect: Expect::Rejected("clearance".into()),
            ..case(
                "clearance 0",
                "clearance 0 (rejected by validation, not made ideal)",
                &|s| each_joint(s, |c| c.clearance = 0.0),
            )
        },
        case("300 rpm", "drive at 300 rpm", &|s| {
            for d in &mut s.drivers {
                if let TimeLaw::Harmonic { rpm, omega, .. } = &mut d.law {
                    *rpm = Some(300.0);
                    *omega = None;
                }
            }
        }),
        case("c_e 0.1", "restitution 0.1", &|s| set_restitution(s, 0.1)),
        case("c_e 1.0", "restitution 1.0 (no damping)", &|s| {
            set_restitution(s, 1.0)
        }),
        case("c_f 0", "friction coefficient 0", &|s| set_friction(s, 0.0)),
        case("c_f 0.5", "friction coefficient 0.5", &|s| {
            set_friction(s, 0.5)
        }),
        StressCase {
            expect: Expect::Rejected("friction.slip_velocity".into()),
            ..case(
                "v0 = v1",
                "Ambrosio v0 = v1 = 1e-4 m/s (rejected by validation, not made Coulomb)",
                &|s| {
                    each_joint(s, |c| {
                        if let FrictionLawParams::Ambrosio(a) = &mut c.friction {
                            a.slip_velocity = a.stick_velocity;
                        }
                    })
                },
            )
        },
        case("E 1e12 Pa", "both surfaces E = 1e12 Pa", &|s| {
            each_joint(s, |c| {
                c.bearing_material.youngs_modulus = 1e12;
                c.pin_material.youngs_modulus = 1e12;
            })
        }),
        case(
            "liner E 3 GPa",
            "bearing (liner) E = 3e9 Pa, nu 0.3 kept; pin steel",
            &|s| each_joint(s, |c| c.bearing_material.youngs_modulus = 3e9),
        ),
        StressCase {
            surfaces: SurfaceSetup::WearOn,
            ..case(
                "wear, 1000 cells",
                "wear on, the scene's 1000 cells",
                &|_| {},
            )
        },
        StressCase {
            surfaces: SurfaceSetup::WearOn,
            ..case("wear, 10 cells", "wear on, 10 grid cells", &|s| {
                each_joint(s, |c| {
                    if let Some(w) = &mut c.wear {
                        w.cells = 10;
                    }
                })
            })
        },
        StressCase {
            surfaces: SurfaceSetup::WearOn,
            ..case("wear, 100000 cells", "wear on, 100,000 grid cells", &|s| {
                each_joint(s, |c| {
                    if let Some(w) = &mut c.wear {
                        w.cells = 100_000;
                    }
                })
            })
        },
        StressCase {
            surfaces: SurfaceSetup::UniformlyWorn(2.0),
            ..case(
                "worn to 2x clearance",
                "both surfaces worn by a uniform depth h = c0 (clearance 2 c0), frozen",
                &|_| {},
            )
        },
    ];
    let period = base.cycle_period().unwrap_or(1.0);
    v.push(StressCase {
        duration: period * f64::from(LONG_CYCLES),
        dense_output: false,
        energy_audit: false,
        long: true,
        ..case(
            "1000 cycles",
            "1000 drive cycles, sampled once per cycle, energy audit off",
            &|_| {},
        )
    });
    v
}

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
            let named = matches!(&e, crate::scene::SceneError::Invalid { issues, .. }
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
            .element_mut::<crate::clearance::WornClearanceForce>(h.element)
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
    } else if r.peak_normal_force_n.iter().any(|(_, f)| !f.is_finite()) {
        failed("NonFinite", "a peak normal force is not finite")
    } else {
        Outcome::Completed
    };
    r
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

fn peaks(r: &CaseResult, sep: &str) -> String {
    if r.peak_normal_force_n.is_empty() {
        return "-".into();
    }
    r.peak_normal_force_n
        .iter()
        .map(|(n, f)| {
            if f.is_finite() {
                format!("{n} {:.1}", f * 1e-3)
            } else {
                format!("{n} -")
            }
        })
        .collect::<Vec<_>>()
        .join(sep)
}

/// The results as CSV (one row a case; peaks in N, one column per joint name seen).
pub fn csv(results: &[CaseResult]) -> String {
    let mut joints: Vec<String> = Vec::new();
    for r in results {
        for (n, _) in &r.peak_normal_force_n {
            if !joints.contains(n) {
                joints.push(n.clone());
            }
        }
    }
    let quote = |s: &str| format!("\"{}\"", s.replace('"', "\"\""));
    let mut out = String::from(
        "case,outcome,duration_s,steps,rejected_steps,newton_failures,smallest_step_s,events,\
         drift_position,energy_residual_j,energy_relative_residual,atol_position_m",
    );
    for j in &joints {
        let _ = write!(out, ",peak_normal_force_{j}_n");
    }
    out.push_str(",wall_time_s,detail\n");
    for r in results {
        let _ = write!(
            out,
            "{},{},{},{},{},{},{},{},{},{},{},{}",
            quote(&r.name),
            r.outcome.label(),
            r.duration_s,
            r.steps,
            r.rejected_steps,
            r.newton_failures,
            r.smallest_step_s,
            r.events,
            r.drift_position,
            r.energy_residual_j,
            r.energy_relative_residual,
            r.atol_position_m
        );
        for j in &joints {
            let f = r
                .peak_normal_force_n
                .iter()
                .find(|(n, _)| n == j)
                .map_or(f64::NAN, |(_, f)| *f);
            let _ = write!(out, ",{f}");
        }
        let _ = writeln!(out, ",{:.3},{}", r.wall_time_s, quote(&r.outcome.detail()));
    }
    out
}

/// The results as a markdown table plus the failure/error details below it.
pub fn markdown(results: &[CaseResult]) -> String {
    let mut out = String::from(
        "| case | outcome | sim. time (s) | steps | rejected | smallest step (s) | drift \\|Φ\\| | \
         energy residual (J) | rel. residual | peak F_n (kN) | wall (s) |\n\
         |---|---|---:|---:|---:|---:|---:|---:|---:|---|---:|\n",
    );
    for r in results {
        let ran = !matches!(
            r.outcome,
            Outcome::Skipped { .. } | Outcome::ExpectedError { .. }
        ) && r.steps > 0;
        let count = |n: usize| if ran { n.to_string() } else { "-".into() };
        let _ = writeln!(
            out,
            "| {} | {} | {:.1} | {} | {} | {} | {} | {} | {} | {} | {:.2} |",
            r.name,
            r.outcome.label(),
            r.duration_s,
            count(r.steps),
            count(r.rejected_steps),
            sci(r.smallest_step_s, 1),
            sci(r.drift_position, 1),
            sci(r.energy_residual_j, 2),
            sci(r.energy_relative_residual, 1),
            peaks(r, ", "),
            r.wall_time_s
        );
    }
    let worn: Vec<&CaseResult> = results
        .iter()
        .filter(|r| !r.wear_depth_m.is_empty())
        .collect();
    if !worn.is_empty() {
        out.push_str(
            "\nWear accumulated on every accepted step (surfaces frozen during the run, so the \
             dynamics do not depend on the grid): deepest cell and grid/Archard volume ratio\n\n",
        );
        for r in worn {
            let parts: Vec<String> = r
                .wear_depth_m
                .iter()
                .zip(&r.wear_volume_ratio)
                .map(|((n, d), (_, v))| format!("{n} {d:.2e} m, ratio {v:.4}"))
                .collect();
            let _ = writeln!(out, "- {}: {}", r.name, parts.join("; "));
        }
    }
    let notes: Vec<&CaseResult> = results
        .iter()
        .filter(|r| !matches!(r.outcome, Outcome::Completed))
        .collect();
    if !notes.is_empty() {
        out.push('\n');
        for r in notes {
            let _ = writeln!(
                out,
                "- **{}** ({}): {}",
                r.name,
                r.outcome.label(),
                r.outcome.detail()
            );
        }
    }
    out
}

/// Writes `stress.csv`, `stress.md` and `stress.json` into `dir`; returns their paths.
pub fn write_report(results: &[CaseResult], dir: &Path) -> Result<Vec<PathBuf>, OutputError> {
    let files = [
        (dir.join("stress.csv"), csv(results)),
        (dir.join("stress.md"), markdown(results)),
    ];
    let mut paths = Vec::new();
    for (path, text) in files {
        write_atomic(&path, text.as_bytes())?;
        paths.push(path);
    }
    let json = dir.join("stress.json");
    crate::output::write_json(&json, &results)?;
    paths.push(json);
    Ok(paths)
}
