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
//! - **Non-finite numbers**: finite states are not enough; a case that measures a NaN or
//!   infinite number (smallest step, drift, energy residual, a peak force, a wear depth or
//!   volume ratio) is FAILED (`NonFinite`, the number named), never `ok`. A number the case
//!   does not measure (the energy books with the audit off) is NaN in [`CaseResult`] and an
//!   empty cell in the CSV.
//! - **Long run** (1000 cycles) is skipped with `--quick`; when run, it samples once per cycle
//!   and turns the energy audit off (its quadrature costs about a third of a run), so it reports
//!   no energy residual.
//! - **Doubled clearance by wear**: both surfaces carry a uniform Archard depth `h = c0`, so the
//!   local clearance `c0 + (h_bearing + h_pin)/2 = 2 c0` everywhere; the tolerances stay those
//!   of the nominal clearance (the scene's default `2e-4 × c0`).

mod engine;
mod render;

pub use engine::{run_battery, run_case, run_cases};
pub use render::{csv, markdown, write_report};

use contact::FrictionLawParams;
use serde::Serialize;

use output::files::OutputError;
use scene::{Scene, TimeLaw};

/// Simulated time of a short case, s: the start-up impacts (first 0.02 s) plus contact.
pub const DEFAULT_DURATION: f64 = 0.3;
/// Drive cycles of the long case (skipped with `quick`).
pub const LONG_CYCLES: u32 = 1000;

/// What a case is expected to do.
#[derive(Debug, Clone, PartialEq, Eq, Serialize)]
pub enum Expect {
    /// Integrate to the end, finite (states and every reported number).
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
    /// Integrated to the end; every sampled state and every measured number finite.
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

/// Numbers of one case (NaN where not measured: an empty CSV cell). A case is
/// [`Outcome::Completed`] only if every number it measured is finite.
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
    Scene(#[from] scene::SceneError),
    /// A report file could not be written.
    #[error(transparent)]
    Output(#[from] OutputError),
}

fn each_joint(scene: &mut Scene, f: impl Fn(&mut scene::ClearanceJointSpec)) {
    scene.clearance_joints.iter_mut().for_each(f);
}

fn set_wear_cells(scene: &mut Scene, cells: usize) {
    each_joint(scene, |c| {
        if let Some(w) = &mut c.wear {
            w.cells = cells;
        }
    })
}

fn set_restitution(scene: &mut Scene, e: f64) {
    each_joint(scene, |c| c.normal_law = c.normal_law.with_restitution(e));
}

fn set_friction(scene: &mut Scene, cf: f64) {
    each_joint(scene, |c| c.friction = c.friction.with_coefficient(cf));
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
                set_wear_cells(s, 10)
            })
        },
        StressCase {
            surfaces: SurfaceSetup::WearOn,
            ..case("wear, 100000 cells", "wear on, 100,000 grid cells", &|s| {
                set_wear_cells(s, 100_000)
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
