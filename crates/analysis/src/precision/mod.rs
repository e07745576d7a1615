//! Work–precision: error against run time for every integrator over a tolerance sweep.
//!
//! Each run integrates the scene from the concentric start for `duration` (default one drive
//! period) with one integrator at one relative tolerance. The absolute tolerances move with
//! the relative one: they are the scene's clearance-scaled tolerances (docs/model.md §8) times
//! `rtol / solver.rtol`, so the scene's own settings are the point `rtol = solver.rtol` of a
//! one-parameter family, and a loose run is loose in every variable.
//!
//! **Reference.** Two runs at a much tighter tolerance with two different methods. A run is
//! compared with the first reference unless it uses the first reference's method, then with
//! the second: the error of a method is never measured against itself. The two references
//! compared with each other give the floor of every error below (shown in the report and the
//! diagram): errors at or under it are not resolved.
//!
//! **Errors** (docs/model.md §8: the clearance dynamics are chaotic, a single peak force is no
//! measure of accuracy):
//! - (a) **start-up**: the largest distance between the run's and the reference's rod position
//!   and journal-centre paths (pin centre relative to bearing centre, every clearance joint)
//!   at the output times up to `start_up` — the first impacts, before paths separate;
//! - (b) **cycle quantities**: relative errors of the RMS deviation of the response body from
//!   the ideal mechanism, of the energy dissipated by contact damping and by friction, and of
//!   the Archard wear volume of each joint gathered after the transient window;
//! - (c) **separation time**: the first output time at which a journal-centre path leaves the
//!   reference's by `separation_fraction` of that joint's clearance.
//!
//! **Timing.** After the measured run (dense output, energy audit and wear accumulation on),
//! the same configuration is integrated `repeats` times with sparse output and no energy audit
//! — the configuration of a wear-stage run — once with wear accumulation and once without; the
//! report gives the median wall time of each (build and assembly excluded). Every timed run
//! must end in the measured run's final state bit for bit: output frames, the energy audit and
//! wear accumulation only observe the integration (checked and reported per row).

mod engine;
mod render;

pub use engine::{Event, run_sweep};

use multibody::State;
use serde::Serialize;

use output::files::OutputError;
use scene::{Integrator, SceneError};

/// Relative tolerances of the sweep.
pub const DEFAULT_RTOLS: [f64; 8] = [1e-3, 1e-4, 1e-5, 1e-6, 1e-7, 1e-8, 1e-9, 1e-10];
/// Every integrator the project offers, in the order of the report.
pub const ALL_METHODS: [Integrator; 5] = [
    Integrator::Bdf,
    Integrator::TrBdf2,
    Integrator::Esdirk34,
    Integrator::Radau5,
    Integrator::Tsit45,
];
/// The references: much tighter than the sweep, two different methods.
pub const DEFAULT_REFERENCES: [(Integrator, f64); 2] =
    [(Integrator::Bdf, 1e-12), (Integrator::Esdirk34, 1e-12)];
/// End of the start-up window of error (a), s: the mechanism drops into the clearances and
/// the first impacts happen at A (t ≈ 0.012 s) and B (≈ 0.013 s) of the default scene, with
/// the start-up force peaks before 0.02 s (docs/model.md §8).
pub const DEFAULT_START_UP: f64 = 0.02;
/// Fraction of the clearance by which a journal-centre path must leave the reference's to
/// count as separated (error (c)).
pub const DEFAULT_SEPARATION_FRACTION: f64 = 0.1;
/// Output interval of the measured runs, s.
pub const DEFAULT_OUTPUT_INTERVAL: f64 = 1e-4;
/// Accepted-step budget of one run: a method that needs more is reported as too slow.
pub const DEFAULT_MAX_STEPS: usize = 2_000_000;

/// Settings of a sweep.
#[derive(Debug, Clone, PartialEq)]
pub struct PrecisionOptions {
    /// Integrators to sweep.
    pub methods: Vec<Integrator>,
    /// Relative tolerances to sweep.
    pub rtols: Vec<f64>,
    /// The two reference runs (method, rtol); the methods must differ.
    pub references: [(Integrator, f64); 2],
    /// Simulated time, s (`None`: one drive period).
    pub duration: Option<f64>,
    /// End of the start-up window of error (a), s.
    pub start_up: f64,
    /// Separation threshold of error (c), as a fraction of each joint's clearance.
    pub separation_fraction: f64,
    /// Output interval of the measured runs, s.
    pub output_interval: f64,
    /// Timed repeats per run and variant (median reported); 0 skips timing.
    pub repeats: usize,
    /// Accepted-step budget of one swept run (not of the references); once a method exceeds
    /// it, its tighter tolerances are skipped.
    pub max_steps: usize,
}

impl Default for PrecisionOptions {
    fn default() -> Self {
        Self {
            methods: ALL_METHODS.to_vec(),
            rtols: DEFAULT_RTOLS.to_vec(),
            references: DEFAULT_REFERENCES,
            duration: None,
            start_up: DEFAULT_START_UP,
            separation_fraction: DEFAULT_SEPARATION_FRACTION,
            output_interval: DEFAULT_OUTPUT_INTERVAL,
            repeats: 3,
            max_steps: DEFAULT_MAX_STEPS,
        }
    }
}

/// Why a sweep could not run (a failing run is a row of the report, not an error).
#[derive(Debug, thiserror::Error)]
pub enum PrecisionError {
    /// Bad settings (the field is named).
    #[error("precision option {field}: {reason}")]
    Options {
        /// Option name.
        field: &'static str,
        /// What is wrong with its value.
        reason: String,
    },
    /// The scene cannot be used.
    #[error(transparent)]
    Scene(#[from] SceneError),
    /// The scene has no active clearance joint, no response body or no drive period.
    #[error("scene unsuitable for a work–precision sweep: {0}")]
    Unsuitable(String),
    /// A reference run failed: without it no error can be measured.
    #[error("reference run {method} at rtol {rtol:e} failed: {reason}")]
    Reference {
        /// Method name.
        method: &'static str,
        /// Its relative tolerance.
        rtol: f64,
        /// Why.
        reason: String,
    },
    /// A report file could not be written.
    #[error(transparent)]
    Output(#[from] OutputError),
}

/// Command-line and report name of an integrator (its scene-file spelling).
pub fn method_name(method: Integrator) -> &'static str {
    match method {
        Integrator::Bdf => "bdf",
        Integrator::TrBdf2 => "tr-bdf2",
        Integrator::Esdirk34 => "esdirk34",
        Integrator::Tsit45 => "tsit45",
        Integrator::Radau5 => "radau",
    }
}

/// The integrator of a [`method_name`].
pub fn method_by_name(name: &str) -> Option<Integrator> {
    ALL_METHODS.into_iter().find(|m| method_name(*m) == name)
}

/// Paths sampled at the output times of a measured run.
#[derive(Debug, Clone, Default)]
struct Paths {
    times: Vec<f64>,
    /// Response body position (x, y), m.
    rod: Vec<[f64; 2]>,
    /// Per clearance joint: eccentricity vector (pin centre − bearing centre), m.
    journals: Vec<Vec<[f64; 2]>>,
}

/// The quantities of error (b).
#[derive(Debug, Clone, Default, Serialize)]
pub struct CycleQuantities {
    /// RMS distance of the response body from the ideal mechanism over the run, m.
    pub deviation_rms_m: f64,
    /// Energy dissipated by contact damping, all joints, J.
    pub damping_j: f64,
    /// Energy dissipated by friction, all joints, J.
    pub friction_j: f64,
    /// Archard wear volume gathered after the transient window, per joint, m³.
    pub wear_volume_m3: Vec<f64>,
}

impl CycleQuantities {
    /// (name, value) of every quantity, joints named.
    fn named(&self, joints: &[String]) -> Vec<(String, f64)> {
        let mut v = vec![
            ("deviation".to_string(), self.deviation_rms_m),
            ("damping".to_string(), self.damping_j),
            ("friction".to_string(), self.friction_j),
        ];
        for (name, w) in joints.iter().zip(&self.wear_volume_m3) {
            v.push((format!("wear {name}"), *w));
        }
        v
    }
}

/// A measured run: its paths, quantities and solver counts.
struct Measured {
    paths: Paths,
    quantities: CycleQuantities,
    final_state: State,
    steps: usize,
    rejected: usize,
    rhs: usize,
    factorizations: usize,
    wall_s: f64,
}

/// Errors of one run against a reference.
#[derive(Debug, Clone, Serialize)]
pub struct Errors {
    /// (a) rod position, max over the start-up window, m.
    pub start_up_rod_m: f64,
    /// (a) journal-centre paths, max over joints and the start-up window, m.
    pub start_up_journal_m: f64,
    /// (b) relative error of each cycle quantity, in [`CycleQuantities`] order.
    pub cycle_relative: Vec<(String, f64)>,
    /// (c) first output time the journal paths are apart by the threshold (`None`: never).
    pub separation_s: Option<f64>,
}

impl Errors {
    /// Error (a): the larger of the rod and journal errors, m.
    pub fn start_up_m(&self) -> f64 {
        self.start_up_rod_m.max(self.start_up_journal_m)
    }

    /// Error (b): the largest relative error of the cycle quantities.
    pub fn cycle_max(&self) -> f64 {
        self.cycle_relative
            .iter()
            .map(|(_, e)| *e)
            .fold(0.0, f64::max)
    }
}

/// What became of one run of the sweep.
#[derive(Debug, Clone, Serialize)]
#[serde(tag = "status", rename_all = "kebab-case")]
pub enum RowOutcome {
    /// Integrated to the end.
    Completed {
        /// Errors against the reference.
        errors: Errors,
        /// The run's cycle quantities.
        quantities: CycleQuantities,
    },
    /// The integrator stopped (step budget, step-size collapse, Newton failure, …).
    Failed {
        /// The error, verbatim.
        reason: String,
    },
    /// Not run: a looser tolerance of the same method already exceeded the step budget.
    Skipped {
        /// Why.
        reason: String,
    },
}

/// One row: a method at a tolerance.
#[derive(Debug, Clone, Serialize)]
pub struct Row {
    /// Integrator name.
    pub method: &'static str,
    /// Relative tolerance.
    pub rtol: f64,
    /// Position absolute tolerance used, m.
    pub atol_position_m: f64,
    /// Accepted steps.
    pub steps: usize,
    /// Steps rejected by the error test.
    pub rejected_steps: usize,
    /// Right-hand-side evaluations.
    pub rhs_evaluations: usize,
    /// Factorizations of the iteration matrix.
    pub factorizations: usize,
    /// Wall time of the measured run (dense output, audit, wear), s.
    pub measured_wall_s: f64,
    /// Median wall time, sparse output, no audit, no wear accumulation, s (NaN: not timed).
    pub wall_s: f64,
    /// Median wall time, the same with wear accumulation, s (NaN: not timed).
    pub wall_wear_s: f64,
    /// Whether every timed run ended in the measured run's final state bit for bit.
    pub timed_runs_identical: bool,
    /// Which reference the errors are against (its method).
    pub reference: &'static str,
    /// The outcome.
    pub outcome: RowOutcome,
}

impl Row {
    /// The errors, if the run completed.
    pub fn errors(&self) -> Option<&Errors> {
        match &self.outcome {
            RowOutcome::Completed { errors, .. } => Some(errors),
            _ => None,
        }
    }
}

/// A reference run's description.
#[derive(Debug, Clone, Serialize)]
pub struct ReferenceRun {
    /// Method name.
    pub method: &'static str,
    /// Relative tolerance.
    pub rtol: f64,
    /// Accepted steps.
    pub steps: usize,
    /// Wall time, s.
    pub wall_s: f64,
    /// Its cycle quantities.
    pub quantities: CycleQuantities,
}

/// The whole sweep.
#[derive(Debug, Clone, Serialize)]
pub struct PrecisionReport {
    /// Scene name.
    pub scene: String,
    /// The scene's `solver.formulation`, which every run uses.
    pub formulation: multibody::Formulation,
    /// Simulated time, s.
    pub duration_s: f64,
    /// Start-up window of error (a), s.
    pub start_up_s: f64,
    /// Separation threshold, fraction of the clearance.
    pub separation_fraction: f64,
    /// Clearance joint names, in the order of the per-joint columns.
    pub joints: Vec<String>,
    /// Their clearances, m.
    pub clearances_m: Vec<f64>,
    /// Timed repeats per variant.
    pub repeats: usize,
    /// The two references.
    pub references: Vec<ReferenceRun>,
    /// The second reference measured against the first: the floor of every error.
    pub reference_agreement: Errors,
    /// Every row, by method then tolerance.
    pub rows: Vec<Row>,
    /// Wall time of the whole sweep, s.
    pub wall_time_s: f64,
}
