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

use std::fmt::Write as _;
use std::path::{Path, PathBuf};
use std::time::Instant;

use multibody::{Frame, Observer, OutputTimes, SimulationError, State};
use serde::Serialize;

use crate::build::{Built, Surfaces, build, unworn_joints};
use crate::clearance::WornClearanceForce;
use crate::output::{OutputError, sci, write_atomic};
use crate::plot::{self, Panel, Series};
use crate::run::simulation_options;
use crate::scene::{Integrator, Scene, SceneError};

/// Relative tolerances of the sweep.
pub const DEFAULT_RTOLS: [f64; 8] = [1e-3, 1e-4, 1e-5, 1e-6, 1e-7, 1e-8, 1e-9, 1e-10];
/// Every integrator the project offers, in the order of the report.
pub const ALL_METHODS: [Integrator; 4] = [
    Integrator::Bdf,
    Integrator::TrBdf2,
    Integrator::Esdirk34,
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

/// Command-line and report name of an integrator.
pub fn method_name(method: Integrator) -> &'static str {
    match method {
        Integrator::Bdf => "bdf",
        Integrator::TrBdf2 => "tr-bdf2",
        Integrator::Esdirk34 => "esdirk34",
        Integrator::Tsit45 => "tsit45",
    }
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
    pub formulation: crate::scene::Formulation,
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

/// Records the rod position and journal-centre paths at output frames.
struct PathRecorder<'a> {
    built_joints: &'a [crate::build::JointHandle],
    body: usize,
    paths: Paths,
}

impl Observer for PathRecorder<'_> {
    fn output(&mut self, frame: &Frame<'_>) {
        self.paths.times.push(frame.t);
        let i = 3 * self.body;
        self.paths.rod.push([frame.q[i], frame.q[i + 1]]);
        for (path, handle) in self.paths.journals.iter_mut().zip(self.built_joints) {
            let e = handle.probe(frame.elements).map_or([f64::NAN; 2], |p| {
                let d = p.contact(frame.q, frame.qd).diagnostics;
                let (s, c) = d.contact_angle.sin_cos();
                [d.eccentricity * c, d.eccentricity * s]
            });
            path.push(e);
        }
    }
}

/// The scene at one sweep point: integrator, rtol and the atol scaled with it.
fn configured(scene: &Scene, method: Integrator, rtol: f64) -> Scene {
    let tol = scene.tolerances();
    let scale = rtol / scene.solver.rtol;
    let mut s = scene.clone();
    s.solver.integrator = method;
    s.solver.rtol = rtol;
    s.solver.atol_position = Some(tol.position * scale);
    s.solver.atol_angle = Some(tol.angle * scale);
    s.solver.atol_velocity = tol.velocity * scale;
    s
}

/// Everything fixed across the runs of a sweep.
struct Setup<'a> {
    scene: &'a Scene,
    options: &'a PrecisionOptions,
    body: usize,
    t_end: f64,
    /// Ideal response body positions at the output times.
    ideal: Vec<[f64; 2]>,
    joint_names: Vec<String>,
}

impl Setup<'_> {
    fn build(&self, scene: &Scene, wear: bool) -> Result<(Built, State), String> {
        let unworn = if wear {
            unworn_joints(scene).map_err(|e| e.to_string())?
        } else {
            Vec::new()
        };
        let built = build(
            scene,
            Surfaces {
                worn: &unworn,
                accumulate_from: wear.then_some(scene.run.transient_window),
                split_halves_at: None,
            },
        )
        .map_err(|e| e.to_string())?;
        let (q, qd) = built.system.initial_guess();
        let state = built
            .system
            .assemble(0.0, &q, &qd)
            .map_err(|e| e.to_string())?;
        Ok((built, state))
    }

    /// The measured run: dense output, energy audit, wear accumulation; `budget` caps its
    /// accepted steps (none for the references: without them nothing can be measured).
    fn measure(
        &self,
        method: Integrator,
        rtol: f64,
        budget: Option<usize>,
    ) -> Result<Measured, Failure> {
        let scene = configured(self.scene, method, rtol);
        let (mut built, state) = self.build(&scene, true).map_err(Failure::from)?;
        let mut options = simulation_options(
            &scene,
            self.t_end,
            OutputTimes::Every(self.options.output_interval),
            false,
        );
        options.energy_audit = true;
        options.max_steps = budget;
        let joints = built.joints.clone();
        let mut recorder = PathRecorder {
            built_joints: &joints,
            body: self.body,
            paths: Paths {
                journals: vec![Vec::new(); joints.len()],
                ..Paths::default()
            },
        };
        let started = Instant::now();
        let result = built
            .system
            .simulate(&state, &options, &mut recorder)
            .map_err(Failure::from)?;
        let wall_s = started.elapsed().as_secs_f64();
        let paths = recorder.paths;
        if let Some(k) = (0..paths.times.len()).find(|&k| {
            !(paths.rod[k].iter().all(|v| v.is_finite())
                && paths
                    .journals
                    .iter()
                    .all(|j| j[k].iter().all(|v| v.is_finite())))
        }) {
            return Err(format!("non-finite state at t = {}", paths.times[k]).into());
        }
        let mut friction = 0.0;
        let mut contact_work = 0.0;
        let mut wear_volume = Vec::new();
        for h in &joints {
            if let Some(p) = h.probe(built.system.elements()) {
                friction += p.friction_dissipation();
            }
            contact_work -= result
                .energy
                .as_ref()
                .and_then(|e| e.element_work.iter().find(|(n, _)| n == &h.name))
                .map_or(0.0, |(_, w)| *w);
            wear_volume.push(
                built
                    .system
                    .element::<WornClearanceForce>(h.element)
                    .and_then(WornClearanceForce::stage_wear)
                    .map_or(0.0, wear::StageWear::archard_volume),
            );
        }
        let squares: f64 = paths
            .rod
            .iter()
            .zip(&self.ideal)
            .map(|(r, i)| (r[0] - i[0]).powi(2) + (r[1] - i[1]).powi(2))
            .sum();
        let s = &result.statistics;
        Ok(Measured {
            quantities: CycleQuantities {
                deviation_rms_m: (squares / paths.rod.len().max(1) as f64).sqrt(),
                damping_j: contact_work - friction,
                friction_j: friction,
                wear_volume_m3: wear_volume,
            },
            paths,
            final_state: result.final_state,
            steps: s.steps,
            rejected: s.rejected_steps,
            rhs: s.rhs_evaluations,
            factorizations: s.factorizations,
            wall_s,
        })
    }

    /// One timed run (sparse output, no audit); its wall time and final state.
    fn time_once(
        &self,
        method: Integrator,
        rtol: f64,
        wear: bool,
    ) -> Result<(f64, State), Failure> {
        let scene = configured(self.scene, method, rtol);
        let (mut built, state) = self.build(&scene, wear).map_err(Failure::from)?;
        let mut options =
            simulation_options(&scene, self.t_end, OutputTimes::At(vec![self.t_end]), false);
        options.energy_audit = false;
        options.max_steps = Some(self.options.max_steps);
        let started = Instant::now();
        let result = built
            .system
            .simulate(&state, &options, &mut ())
            .map_err(Failure::from)?;
        let wall = started.elapsed().as_secs_f64();
        drop(built);
        Ok((wall, result.final_state))
    }

    /// Errors of `run` against `reference`.
    fn errors(&self, run: &Measured, reference: &Measured) -> Errors {
        let (a, b) = (&run.paths, &reference.paths);
        let frames = a.times.len().min(b.times.len());
        let distance = |p: [f64; 2], q: [f64; 2]| (p[0] - q[0]).hypot(p[1] - q[1]);
        let mut rod = 0.0_f64;
        let mut journal = 0.0_f64;
        let mut separation = None;
        for k in 0..frames {
            let t = a.times[k];
            let apart: Vec<f64> = a
                .journals
                .iter()
                .zip(&b.journals)
                .map(|(x, y)| distance(x[k], y[k]))
                .collect();
            if t <= self.options.start_up * (1.0 + 1e-12) {
                rod = rod.max(distance(a.rod[k], b.rod[k]));
                journal = apart.iter().copied().fold(journal, f64::max);
            }
            let clearances = self.scene.active_clearance_joints().map(|c| c.clearance);
            if separation.is_none()
                && apart
                    .iter()
                    .zip(clearances)
                    .any(|(d, c)| *d > self.options.separation_fraction * c)
            {
                separation = Some(t);
            }
        }
        // A quantity the reference has none of (no wear gathered in a short run) is exact
        // when the run has none either, and unboundedly wrong otherwise.
        let relative = |x: f64, r: f64| match (r != 0.0, x == r) {
            (true, _) => ((x - r) / r).abs(),
            (false, true) => 0.0,
            (false, false) => f64::INFINITY,
        };
        let ours = run.quantities.named(&self.joint_names);
        let theirs = reference.quantities.named(&self.joint_names);
        Errors {
            start_up_rod_m: rod,
            start_up_journal_m: journal,
            cycle_relative: ours
                .into_iter()
                .zip(theirs)
                .map(|((name, x), (_, r))| (name, relative(x, r)))
                .collect(),
            separation_s: separation,
        }
    }
}

/// Why a run of the sweep did not complete.
struct Failure {
    reason: String,
    /// It ran out of the step budget (tighter tolerances of the method would too).
    out_of_budget: bool,
}

impl From<String> for Failure {
    fn from(reason: String) -> Self {
        Self {
            reason,
            out_of_budget: false,
        }
    }
}

impl From<SimulationError> for Failure {
    fn from(e: SimulationError) -> Self {
        Self {
            out_of_budget: matches!(e, SimulationError::StepLimit { .. }),
            reason: e.to_string(),
        }
    }
}

fn median(mut v: Vec<f64>) -> f64 {
    if v.is_empty() {
        return f64::NAN;
    }
    v.sort_by(f64::total_cmp);
    let n = v.len();
    if n % 2 == 1 {
        v[n / 2]
    } else {
        0.5 * (v[n / 2 - 1] + v[n / 2])
    }
}

fn check_options(o: &PrecisionOptions) -> Result<(), PrecisionError> {
    let bad = |field, reason: String| Err(PrecisionError::Options { field, reason });
    if o.methods.is_empty() {
        return bad("methods", "at least one integrator is needed".into());
    }
    if let Some(r) = o
        .rtols
        .iter()
        .find(|r| !(r.is_finite() && **r > 0.0 && **r < 1.0))
    {
        return bad("rtols", format!("{r} is not in (0, 1)"));
    }
    if o.rtols.is_empty() {
        return bad("rtols", "at least one tolerance is needed".into());
    }
    let [(m0, r0), (m1, r1)] = o.references;
    if m0 == m1 {
        return bad(
            "references",
            format!(
                "the two references must use different methods, both are {}",
                method_name(m0)
            ),
        );
    }
    let loosest_reference = r0.max(r1);
    let tightest = o.rtols.iter().copied().fold(f64::INFINITY, f64::min);
    if !(loosest_reference > 0.0 && loosest_reference < tightest) {
        return bad(
            "references",
            format!(
                "reference tolerances ({r0:e}, {r1:e}) must be positive and tighter than the \
                 tightest swept tolerance {tightest:e}"
            ),
        );
    }
    if let Some(d) = o.duration.filter(|d| !(d.is_finite() && *d > 0.0)) {
        return bad("duration", format!("{d} s must be positive"));
    }
    if !(o.start_up.is_finite() && o.start_up > 0.0) {
        return bad("start_up", format!("{} s must be positive", o.start_up));
    }
    if !(o.separation_fraction.is_finite() && o.separation_fraction > 0.0) {
        return bad(
            "separation_fraction",
            format!("{} must be positive", o.separation_fraction),
        );
    }
    if !(o.output_interval.is_finite() && o.output_interval > 0.0) {
        return bad(
            "output_interval",
            format!("{} s must be positive", o.output_interval),
        );
    }
    if o.max_steps == 0 {
        return bad("max_steps", "must be at least 1".into());
    }
    Ok(())
}

/// Progress of a sweep, for a caller that shows it.
pub enum Event<'a> {
    /// A run starts: (method, rtol, what: "reference" / "measure" / "time").
    Start(&'static str, f64, &'static str),
    /// A row is done.
    Row(&'a Row),
}

/// Runs the sweep on `scene` (see the module docs).
pub fn run_sweep(
    name: &str,
    scene: &Scene,
    options: &PrecisionOptions,
    on_event: &mut dyn FnMut(Event<'_>),
) -> Result<PrecisionReport, PrecisionError> {
    check_options(options)?;
    let started = Instant::now();
    let unsuitable = |m: &str| PrecisionError::Unsuitable(m.to_string());
    let period = scene
        .cycle_period()
        .ok_or_else(|| unsuitable("no drive period (run.period or a periodic driver)"))?;
    let body = scene
        .response_body()
        .ok_or_else(|| unsuitable("no response body"))?;
    let joint_names: Vec<String> = scene
        .active_clearance_joints()
        .map(|c| c.name.clone())
        .collect();
    if joint_names.is_empty() {
        return Err(unsuitable(
            "no active clearance joint: there is nothing to integrate",
        ));
    }
    let t_end = options.duration.unwrap_or(period);
    if options.start_up > t_end {
        return Err(PrecisionError::Options {
            field: "start_up",
            reason: format!("{} s is longer than the run ({t_end} s)", options.start_up),
        });
    }
    let ideal_scene = scene.idealized();
    let ideal_built = build(&ideal_scene, Surfaces::default())
        .map_err(|e| unsuitable(&format!("the ideal mechanism does not build: {e}")))?;
    let (q0, _) = ideal_built.system.initial_guess();
    let count = (t_end / options.output_interval * (1.0 + 1e-12)).floor() as usize;
    let times: Vec<f64> = (0..=count)
        .map(|i| (i as f64 * options.output_interval).min(t_end))
        .collect();
    let kin = ideal_built
        .system
        .kinematics(&times, &q0)
        .map_err(|e| unsuitable(&format!("the ideal mechanism does not move: {e}")))?;
    let ideal = (0..kin.times.len())
        .map(|f| [kin.q(f)[3 * body], kin.q(f)[3 * body + 1]])
        .collect();
    let setup = Setup {
        scene,
        options,
        body,
        t_end,
        ideal,
        joint_names: joint_names.clone(),
    };

    let mut references = Vec::new();
    for (method, rtol) in options.references {
        on_event(Event::Start(method_name(method), rtol, "reference"));
        let m = setup
            .measure(method, rtol, None)
            .map_err(|f| PrecisionError::Reference {
                method: method_name(method),
                rtol,
                reason: f.reason,
            })?;
        references.push((method, rtol, m));
    }
    let reference_agreement = setup.errors(&references[1].2, &references[0].2);

    let mut rows = Vec::new();
    for &method in &options.methods {
        let (reference_method, _, reference) = references
            .iter()
            .find(|(m, _, _)| *m != method)
            .unwrap_or(&references[0]);
        let mut exhausted: Option<f64> = None;
        for &rtol in &options.rtols {
            let atol_position_m = configured(scene, method, rtol).tolerances().position;
            let mut row = Row {
                method: method_name(method),
                rtol,
                atol_position_m,
                steps: 0,
                rejected_steps: 0,
                rhs_evaluations: 0,
                factorizations: 0,
                measured_wall_s: f64::NAN,
                wall_s: f64::NAN,
                wall_wear_s: f64::NAN,
                timed_runs_identical: true,
                reference: method_name(*reference_method),
                outcome: RowOutcome::Skipped {
                    reason: String::new(),
                },
            };
            if let Some(looser) = exhausted {
                row.outcome = RowOutcome::Skipped {
                    reason: format!(
                        "rtol {looser:e} already exceeded the budget of {} steps",
                        options.max_steps
                    ),
                };
                on_event(Event::Row(&row));
                rows.push(row);
                continue;
            }
            on_event(Event::Start(method_name(method), rtol, "measure"));
            match setup.measure(method, rtol, Some(options.max_steps)) {
                Err(f) => {
                    if f.out_of_budget {
                        exhausted = Some(rtol);
                    }
                    row.outcome = RowOutcome::Failed { reason: f.reason };
                }
                Ok(m) => {
                    row.steps = m.steps;
                    row.rejected_steps = m.rejected;
                    row.rhs_evaluations = m.rhs;
                    row.factorizations = m.factorizations;
                    row.measured_wall_s = m.wall_s;
                    if options.repeats > 0 {
                        on_event(Event::Start(method_name(method), rtol, "time"));
                    }
                    let mut plain = Vec::new();
                    let mut worn = Vec::new();
                    for _ in 0..options.repeats {
                        for (wear, walls) in [(false, &mut plain), (true, &mut worn)] {
                            match setup.time_once(method, rtol, wear) {
                                Ok((wall, state)) => {
                                    walls.push(wall);
                                    row.timed_runs_identical &=
                                        state.q == m.final_state.q && state.qd == m.final_state.qd;
                                }
                                Err(_) => row.timed_runs_identical = false,
                            }
                        }
                    }
                    row.wall_s = median(plain);
                    row.wall_wear_s = median(worn);
                    row.outcome = RowOutcome::Completed {
                        errors: setup.errors(&m, reference),
                        quantities: m.quantities,
                    };
                }
            }
            on_event(Event::Row(&row));
            rows.push(row);
        }
    }
    Ok(PrecisionReport {
        scene: name.to_string(),
        formulation: scene.solver.formulation,
        duration_s: t_end,
        start_up_s: options.start_up,
        separation_fraction: options.separation_fraction,
        clearances_m: scene
            .active_clearance_joints()
            .map(|c| c.clearance)
            .collect(),
        joints: joint_names,
        repeats: options.repeats,
        references: references
            .into_iter()
            .map(|(method, rtol, m)| ReferenceRun {
                method: method_name(method),
                rtol,
                steps: m.steps,
                wall_s: m.wall_s,
                quantities: m.quantities,
            })
            .collect(),
        reference_agreement,
        rows,
        wall_time_s: started.elapsed().as_secs_f64(),
    })
}

/// Run time a row is plotted and ranked at: the timed median, else the measured run's.
fn run_time(row: &Row) -> f64 {
    if row.wall_s.is_finite() {
        row.wall_s
    } else {
        row.measured_wall_s
    }
}

/// Least-squares slope of log10 y against log10 x (`None` with fewer than two distinct x).
fn log_log_slope(points: &[(f64, f64)]) -> Option<f64> {
    let logs: Vec<(f64, f64)> = points.iter().map(|(x, y)| (x.log10(), y.log10())).collect();
    let n = logs.len() as f64;
    let mean_x = logs.iter().map(|p| p.0).sum::<f64>() / n;
    let mean_y = logs.iter().map(|p| p.1).sum::<f64>() / n;
    let sxx: f64 = logs.iter().map(|p| (p.0 - mean_x).powi(2)).sum();
    let sxy: f64 = logs.iter().map(|p| (p.0 - mean_x) * (p.1 - mean_y)).sum();
    (sxx > 0.0).then(|| sxy / sxx)
}

impl PrecisionReport {
    /// Names of the cycle quantities, in the order of [`Errors::cycle_relative`].
    pub fn quantity_names(&self) -> Vec<String> {
        CycleQuantities {
            wear_volume_m3: vec![0.0; self.joints.len()],
            ..CycleQuantities::default()
        }
        .named(&self.joints)
        .into_iter()
        .map(|(n, _)| n)
        .collect()
    }

    /// One row a run, errors and timings in SI units.
    pub fn csv(&self) -> String {
        let names = self.quantity_names();
        let column = |n: &str| n.replace(' ', "_");
        let mut out = String::from(
            "method,rtol,atol_position_m,status,reference,steps,rejected_steps,rhs_evaluations,\
             factorizations,measured_wall_s,wall_s,wall_wear_s,timed_runs_identical,\
             start_up_rod_m,start_up_journal_m,start_up_m,cycle_max_relative",
        );
        for n in &names {
            let _ = write!(out, ",relative_error_{}", column(n));
        }
        out.push_str(",separation_s");
        for n in &names {
            let _ = write!(out, ",value_{}", column(n));
        }
        out.push_str(",detail\n");
        for r in &self.rows {
            let status = match &r.outcome {
                RowOutcome::Completed { .. } => "completed",
                RowOutcome::Failed { .. } => "failed",
                RowOutcome::Skipped { .. } => "skipped",
            };
            let _ = write!(
                out,
                "{},{:e},{:e},{status},{},{},{},{},{},{},{},{},{}",
                r.method,
                r.rtol,
                r.atol_position_m,
                r.reference,
                r.steps,
                r.rejected_steps,
                r.rhs_evaluations,
                r.factorizations,
                r.measured_wall_s,
                r.wall_s,
                r.wall_wear_s,
                r.timed_runs_identical
            );
            match &r.outcome {
                RowOutcome::Completed { errors, quantities } => {
                    let _ = write!(
                        out,
                        ",{:e},{:e},{:e},{:e}",
                        errors.start_up_rod_m,
                        errors.start_up_journal_m,
                        errors.start_up_m(),
                        errors.cycle_max()
                    );
                    for (_, e) in &errors.cycle_relative {
                        let _ = write!(out, ",{e:e}");
                    }
                    let _ = write!(
                        out,
                        ",{}",
                        errors.separation_s.map_or("none".into(), |t| t.to_string())
                    );
                    for (_, v) in quantities.named(&self.joints) {
                        let _ = write!(out, ",{v:e}");
                    }
                    out.push_str(",\n");
                }
                RowOutcome::Failed { reason } | RowOutcome::Skipped { reason } => {
                    out.push_str(&",".repeat(5 + 2 * names.len()));
                    let _ = writeln!(out, ",\"{}\"", reason.replace('"', "\"\""));
                }
            }
        }
        out
    }

    /// The methods of the sweep, in the order they first appear.
    fn methods(&self) -> Vec<&'static str> {
        let mut methods: Vec<&'static str> = Vec::new();
        for r in &self.rows {
            if !methods.contains(&r.method) {
                methods.push(r.method);
            }
        }
        methods
    }

    /// The fastest completed run whose error `metric` is at most `level`.
    fn fastest(&self, level: f64, metric: impl Fn(&Errors) -> f64) -> Option<&Row> {
        self.rows
            .iter()
            .filter(|r| r.errors().is_some_and(|e| metric(e) <= level))
            .min_by(|a, b| run_time(a).total_cmp(&run_time(b)))
    }

    /// The report: settings, references and their agreement, the table, the fastest run per
    /// accuracy level.
    pub fn markdown(&self, figure: Option<&str>) -> String {
        let mut out = String::new();
        let _ = writeln!(
            out,
            "# Work–precision: scene `{}`, {} formulation\n",
            self.scene,
            self.formulation.name()
        );
        let _ = writeln!(
            out,
            "Generated by `wearsim precision {}` ({:.0} s of wall time for the whole sweep). \
             Every run integrates {:.4} s from the concentric start with both clearance joints; the \
             absolute tolerances are the scene's clearance-scaled ones times `rtol / \
             solver.rtol`. Run time is the median of {} timed runs with sparse output and no \
             energy audit (the configuration of a wear-stage run; build and assembly excluded), \
             without (`wall`) and with (`wall, wear`) wear accumulation. Errors come from one \
             measured run with output every frame, the energy audit and wear accumulation on. \
             Method and error definitions: `lgres::precision` (crate docs).\n",
            self.scene, self.wall_time_s, self.duration_s, self.repeats
        );
        let _ = writeln!(
            out,
            "- (a) start-up error: largest distance from the reference of the rod position and \
             of the journal-centre paths at {} up to t = {} s (the first impacts);\n\
             - (b) cycle error: largest relative error of the RMS deviation from the ideal \
             mechanism, the energy dissipated by contact damping and by friction, and the wear \
             volume per joint (gathered after the transient window);\n\
             - (c) separation: first time a journal-centre path is {}·clearance away from the \
             reference's (`-`: not within the run).\n",
            self.joints.join(" and "),
            self.start_up_s,
            self.separation_fraction
        );
        if let Some(f) = figure {
            let _ = writeln!(out, "![work–precision diagram]({f})\n");
        }
        out.push_str("## References\n\n| method | rtol | steps | wall (s) |");
        let names = self.quantity_names();
        for n in &names {
            let _ = write!(out, " {n} |");
        }
        out.push_str("\n|---|---:|---:|---:|");
        out.push_str(&"---:|".repeat(names.len()));
        out.push('\n');
        for r in &self.references {
            let _ = write!(
                out,
                "| {} | {:.0e} | {} | {:.2} |",
                r.method, r.rtol, r.steps, r.wall_s
            );
            for (_, v) in r.quantities.named(&self.joints) {
                let _ = write!(out, " {} |", sci(v, 5));
            }
            out.push('\n');
        }
        let a = &self.reference_agreement;
        let _ = writeln!(
            out,
            "\nUnits: deviation m, energies J, wear m³. The two references against each other \
             (the floor below which errors are not resolved): start-up {} m (rod {} m, journals \
             {} m); cycle quantities {} relative ({}); separation {}.\n",
            sci(a.start_up_m(), 2),
            sci(a.start_up_rod_m, 2),
            sci(a.start_up_journal_m, 2),
            sci(a.cycle_max(), 2),
            a.cycle_relative
                .iter()
                .map(|(n, e)| format!("{n} {}", sci(*e, 1)))
                .collect::<Vec<_>>()
                .join(", "),
            a.separation_s
                .map_or("none within the run".into(), |t| format!("at t = {t:.4} s"))
        );
        out.push_str(
            "## Convergence\n\nSlope of log (a) start-up error against log rtol (least squares over \
             the completed runs; 1 means the error falls in proportion to the tolerance asked \
             for):\n\n| method | runs | slope | (a) at the loosest rtol (m) | (a) at the tightest \
             rtol (m) |\n|---|---:|---:|---:|---:|\n",
        );
        for method in self.methods() {
            let points: Vec<(f64, f64)> = self
                .rows
                .iter()
                .filter(|r| r.method == method)
                .filter_map(|r| r.errors().map(|e| (r.rtol, e.start_up_m())))
                .filter(|(rtol, e)| *rtol > 0.0 && *e > 0.0 && e.is_finite())
                .collect();
            let loosest = points.iter().max_by(|a, b| a.0.total_cmp(&b.0));
            let tightest = points.iter().min_by(|a, b| a.0.total_cmp(&b.0));
            let _ = writeln!(
                out,
                "| {method} | {} | {} | {} | {} |",
                points.len(),
                log_log_slope(&points).map_or("-".into(), |p| format!("{p:.2}")),
                loosest.map_or("-".into(), |p| sci(p.1, 1)),
                tightest.map_or("-".into(), |p| sci(p.1, 1)),
            );
        }
        out.push('\n');
        out.push_str(
            "## Runs\n\n| method | rtol | steps | rejected | wall (s) | wall, wear (s) | \
             (a) start-up (m) | (b) cycle (rel.) | worst (b) quantity | (c) separation (s) | \
             vs | note |\n|---|---:|---:|---:|---:|---:|---:|---:|---|---:|---|---|\n",
        );
        for r in &self.rows {
            match &r.outcome {
                RowOutcome::Completed { errors, .. } => {
                    let worst = errors
                        .cycle_relative
                        .iter()
                        .max_by(|a, b| a.1.total_cmp(&b.1))
                        .map_or("-".into(), |(n, _)| n.clone());
                    let _ = writeln!(
                        out,
                        "| {} | {:.0e} | {} | {} | {} | {} | {} | {} | {worst} | {} | {} | {} |",
                        r.method,
                        r.rtol,
                        r.steps,
                        r.rejected_steps,
                        sci(r.wall_s, 2),
                        sci(r.wall_wear_s, 2),
                        sci(errors.start_up_m(), 2),
                        sci(errors.cycle_max(), 2),
                        errors
                            .separation_s
                            .map_or("-".into(), |t| format!("{t:.4}")),
                        r.reference,
                        if r.timed_runs_identical {
                            ""
                        } else {
                            "timed runs differ"
                        }
                    );
                }
                RowOutcome::Failed { reason } | RowOutcome::Skipped { reason } => {
                    let label = if matches!(r.outcome, RowOutcome::Failed { .. }) {
                        "failed"
                    } else {
                        "skipped"
                    };
                    let _ = writeln!(
                        out,
                        "| {} | {:.0e} | - | - | - | - | - | - | - | - | {} | {label}: {} |",
                        r.method,
                        r.rtol,
                        r.reference,
                        reason.replace('|', "/")
                    );
                }
            }
        }
        let _ = write!(
            out,
            "\n## Cycle quantities, relative error of each\n\nThe first line is the second \
             reference against the first ({}): the floor below which no run can be judged.\n\n\
             | method | rtol |",
            a.separation_s.map_or(
                "their paths do not separate within the run".to_string(),
                |t| format!(
                    "their journal paths separate at t = {t:.3} s, so after that this is the \
                     quantities' spread between two converged but different trajectories: chaos"
                )
            )
        );
        for n in &names {
            let _ = write!(out, " {n} |");
        }
        out.push_str("\n|---|---:|");
        out.push_str(&"---:|".repeat(names.len()));
        out.push('\n');
        let floor_row = self.references.get(1).map(|r| (r.method, r.rtol));
        let quantity_rows = floor_row
            .map(|(m, rtol)| (format!("{m} (reference)"), rtol, &self.reference_agreement))
            .into_iter()
            .chain(
                self.rows
                    .iter()
                    .filter_map(|r| r.errors().map(|e| (r.method.to_string(), r.rtol, e))),
            );
        for (method, rtol, e) in quantity_rows {
            let _ = write!(out, "| {method} | {rtol:.0e} |");
            for (_, v) in &e.cycle_relative {
                let _ = write!(out, " {} |", sci(*v, 1));
            }
            out.push('\n');
        }
        out.push_str("\n## Fastest run per accuracy level\n\n");
        let describe = |r: Option<&Row>| {
            r.map_or("none".to_string(), |r| {
                format!("{} rtol {:.0e}, {:.3} s", r.method, r.rtol, run_time(r))
            })
        };
        out.push_str("| (a) start-up error ≤ (m) | fastest run |\n|---:|---|\n");
        for level in [1e-3, 1e-4, 1e-5, 1e-6, 1e-7, 1e-8] {
            let _ = writeln!(
                out,
                "| {level:.0e} | {} |",
                describe(self.fastest(level, Errors::start_up_m))
            );
        }
        // Cycle quantities cannot be judged below the references' own spread, so their levels
        // are multiples of it.
        let floor = self.reference_agreement.cycle_max();
        out.push_str("\n| (b) cycle error ≤ (relative) | fastest run |\n|---:|---|\n");
        for multiple in [1.0, 2.0, 4.0] {
            let level = multiple * floor;
            let _ = writeln!(
                out,
                "| {} ({multiple}× the references' spread) | {} |",
                sci(level, 1),
                describe(self.fastest(level, Errors::cycle_max))
            );
        }
        out
    }

    /// The work–precision diagram: errors (a), (b), (c) against run time, and error (a)
    /// against the tolerance asked for, one line per method.
    pub fn plot(&self, path: &Path) -> Result<(), OutputError> {
        let methods = self.methods();
        let column = |method: &str, x: &dyn Fn(&Row) -> f64, y: &dyn Fn(&Errors) -> f64| {
            let rows: Vec<&Row> = self
                .rows
                .iter()
                .filter(|r| r.method == method && r.errors().is_some())
                .collect();
            let xs: Vec<f64> = rows.iter().map(|r| x(r)).collect();
            let ys: Vec<f64> = rows.iter().filter_map(|r| r.errors()).map(y).collect();
            (xs, ys)
        };
        let separation = |e: &Errors| e.separation_s.unwrap_or(f64::NAN);
        let data: Vec<[(Vec<f64>, Vec<f64>); 4]> = methods
            .iter()
            .map(|m| {
                [
                    column(m, &run_time, &Errors::start_up_m),
                    column(m, &run_time, &Errors::cycle_max),
                    column(m, &run_time, &separation),
                    column(m, &|r| r.rtol, &Errors::start_up_m),
                ]
            })
            .collect();
        let series = |k: usize| -> Vec<Series<'_>> {
            methods
                .iter()
                .zip(&data)
                .map(|(m, d)| Series {
                    label: m,
                    x: &d[k].0,
                    y: &d[k].1,
                })
                .collect()
        };
        let a = &self.reference_agreement;
        let floor = "references vs each other";
        let panels = [
            Panel {
                title: "(a) start-up paths: error vs run time",
                x_label: "run time per cycle (s)",
                y_label: "max error (m)",
                series: series(0),
                levels: vec![(a.start_up_m(), floor)],
                legend_top: false,
            },
            Panel {
                title: "(b) cycle quantities: largest relative error",
                x_label: "run time per cycle (s)",
                y_label: "relative error",
                series: series(1),
                levels: vec![(a.cycle_max(), floor)],
                legend_top: false,
            },
            Panel {
                title: "(c) journal paths separate from the reference at",
                x_label: "run time per cycle (s)",
                y_label: "separation time (s)",
                series: series(2),
                levels: a.separation_s.map(|t| vec![(t, floor)]).unwrap_or_default(),
                legend_top: true,
            },
            Panel {
                title: "(a) start-up error vs tolerance asked for",
                x_label: "rtol (atol scaled with it)",
                y_label: "max error (m)",
                series: series(3),
                levels: vec![(a.start_up_m(), floor)],
                legend_top: false,
            },
        ];
        let title = format!(
            "Work–precision, scene {}: {:.3} s from the concentric start",
            self.scene, self.duration_s
        );
        plot::log_panels(path, &title, (1400, 1050), 2, &panels)
    }

    /// Writes `precision.csv`, `precision.md`, `precision.json` and `precision.png` into `dir`.
    pub fn write(&self, dir: &Path) -> Result<Vec<PathBuf>, OutputError> {
        let png = dir.join("precision.png");
        self.plot(&png)?;
        let files = [
            (dir.join("precision.csv"), self.csv()),
            (
                dir.join("precision.md"),
                self.markdown(Some("precision.png")),
            ),
        ];
        let mut paths = vec![png];
        for (path, text) in files {
            write_atomic(&path, text.as_bytes())?;
            paths.push(path);
        }
        let json = dir.join("precision.json");
        crate::output::write_json(&json, self)?;
        paths.push(json);
        Ok(paths)
    }
}
