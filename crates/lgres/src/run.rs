//! One run of a scene: the response over `cycles` drive periods against the ideal mechanism,
//! then the wear stages, with every summary number kept in memory ([`RunOutcome`]).
//!
//! [`run_scene`] is what the CLI's `run` calls and what a study loop can call repeatedly; it
//! writes nothing (see [`crate::artifacts`]) and reports progress through [`Progress`].
//!
//! - **Response run**: assembled from the scene's initial poses (pins concentric), integrated
//!   over `run.cycles` periods on unworn surfaces, sampled every `solver.output_interval`.
//! - **Reference**: the all-ideal mechanism ([`Scene::idealized`]) by kinematic analysis at the
//!   same times. A scene without active clearance joints runs this kinematic path only.
//! - **Wear stages** ([`wear::run_stage`]): each sub-step rebuilds the system on the current
//!   (frozen) worn surfaces and integrates `run.transient_window + K` periods, gathering wear
//!   over the last `K` only: the concentric start-up impact (MODEL §8) is not amplified, and a
//!   periodic drive makes any `K` consecutive periods `K` full cycles. After the stages the
//!   response is simulated once more on the worn surfaces.
//! - **Peaks** are statistics over cycles, with and without the start-up window (MODEL §8:
//!   the clearance dynamics are chaotic, single peaks are not reproducible).

use std::time::Instant;

use multibody::{
    AbsoluteTolerances, AssemblyError, Baumgarte, Frame, Integrator, KinematicsError, Observer,
    OutputTimes, SimulationError, SimulationOptions, SimulationResult,
};
use serde::Serialize;
use wear::{Extrapolation, GeometryLimits, StagePlan, StageWear, StagingError, WornJoint};

use crate::build::{BuildError, Built, JointHandle, Surfaces, build, unworn_joints};
use crate::clearance::WornClearanceForce;
use crate::scene::{self, Scene};
use crate::validity::{Limits, Tally, Validity};

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
    /// `wear_<joint>_stage<k>.csv` files (see [`crate::surfaces`]). The response run and the
    /// stages then begin from those surfaces.
    pub surfaces: Option<std::path::PathBuf>,
    /// Simulated cycles per wear stage `K` instead of `run.cycles_per_stage`; the
    /// amplification is rescaled so a stage still stands for `K_scene × amplification` cycles.
    pub cycles_per_stage: Option<u32>,
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
    /// The ideal mechanism's kinematic analysis failed.
    #[error("kinematic analysis of the ideal mechanism: {0}")]
    Kinematics(#[from] KinematicsError),
    /// The integrator failed or ran out of its budget (the hint names the scene field).
    #[error("{what}: {source}{}", crate::limits::budget_hint(source))]
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
    Surfaces(#[from] crate::surfaces::SurfacesError),
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
    /// A contact penetrated beyond [`crate::limits::MAX_PENETRATION_FRACTION`] of its
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
                | RunError::Kinematics(_)
                | RunError::Assembly { .. }
                | RunError::PinOutsideBearing { .. }
                | RunError::NoPeriod
                | RunError::NoResponseBody
        )
    }
}

/// Centroid motion of one body at the output times.
#[derive(Debug, Clone, Default, Serialize)]
pub struct Motion {
    /// x, m.
    pub x: Vec<f64>,
    /// y, m.
    pub y: Vec<f64>,
    /// ẋ, m/s.
    pub vx: Vec<f64>,
    /// ẏ, m/s.
    pub vy: Vec<f64>,
    /// ẍ, m/s².
    pub ax: Vec<f64>,
    /// ÿ, m/s².
    pub ay: Vec<f64>,
}

impl Motion {
    fn push(&mut self, k: usize, q: &[f64], qd: &[f64], qdd: &[f64]) {
        let i = 3 * k;
        self.x.push(q[i]);
        self.y.push(q[i + 1]);
        self.vx.push(qd[i]);
        self.vy.push(qd[i + 1]);
        self.ax.push(qdd[i]);
        self.ay.push(qdd[i + 1]);
    }

    /// The six series in the order x, y, vx, vy, ax, ay.
    pub fn series(&self) -> [&[f64]; 6] {
        [&self.x, &self.y, &self.vx, &self.vy, &self.ax, &self.ay]
    }
}

/// Contact history of one clearance joint at the output times.
#[derive(Debug, Clone, Default, Serialize)]
pub struct ContactSeries {
    /// Joint name.
    pub name: String,
    /// Nominal clearance, m.
    pub clearance: f64,
    /// Normal force `F_n`, N.
    pub normal_force: Vec<f64>,
    /// Signed friction force along the tangent, N.
    pub friction_force: Vec<f64>,
    /// Penetration `δ` (negative: free), m.
    pub penetration: Vec<f64>,
    /// Eccentricity `|e|`, m.
    pub eccentricity: Vec<f64>,
    /// Journal-centre offset `e = r_pin − r_bearing` in the global frame, m.
    pub ex: Vec<f64>,
    /// See `ex`.
    pub ey: Vec<f64>,
    /// The same offset in the bearing body's frame (where the bearing wears), m.
    pub ex_bearing: Vec<f64>,
    /// See `ex_bearing`.
    pub ey_bearing: Vec<f64>,
    /// Whether the worn geometry stayed inside the contact model's validity (measured at the
    /// output frames; `None` until the run is over).
    pub validity: Option<Validity>,
}

/// One simulated response with its reference.
#[derive(Debug, Clone, Default)]
pub struct Response {
    /// Output times, s.
    pub times: Vec<f64>,
    /// The recorded body (with clearance).
    pub motion: Motion,
    /// The ideal mechanism at the same times.
    pub ideal: Motion,
    /// Per active clearance joint.
    pub contact: Vec<ContactSeries>,
}

/// Wear of one joint after each stage.
#[derive(Debug, Clone)]
pub struct JointWearHistory {
    /// Joint name.
    pub name: String,
    /// Nominal bearing radius, m.
    pub bearing_radius: f64,
    /// Nominal pin radius, m.
    pub pin_radius: f64,
    /// The joint after stage 1, 2, … (cumulative surfaces).
    pub stages: Vec<WornJoint>,
}

/// Statistics of per-cycle peaks.
#[derive(Debug, Clone, Copy, Default, Serialize)]
pub struct PeakStats {
    /// Largest value over the whole window, N.
    pub max: f64,
    /// Cycles with samples in the window.
    pub cycles: usize,
    /// Median of the per-cycle peaks, N.
    pub cycle_median: f64,
    /// Smallest per-cycle peak, N.
    pub cycle_min: f64,
    /// Largest per-cycle peak, N (equals `max`).
    pub cycle_max: f64,
    /// Interquartile range of the per-cycle peaks, N.
    pub cycle_iqr: f64,
}

/// Contact summary of one joint in one response run.
#[derive(Debug, Clone, Serialize)]
pub struct JointSummary {
    /// Joint name.
    pub name: String,
    /// Nominal clearance, m.
    pub clearance_m: f64,
    /// Normal-force peaks over all output samples.
    pub normal_force_all: PeakStats,
    /// Normal-force peaks after the start-up window `run.transient_window`.
    pub normal_force_after_transient: PeakStats,
    /// Largest penetration, m.
    pub max_penetration_m: f64,
    /// Largest eccentricity, m.
    pub max_eccentricity_m: f64,
    /// Whether the (worn) geometry stayed where the contact model holds, with the measures
    /// (see [`crate::validity`]). Force peaks of a run outside it are not results.
    pub validity: Option<Validity>,
    /// Energy friction dissipates per cycle, `∫ F_t v_t dt` on the material sliding, J
    /// (`ClearanceForce::friction_dissipation`, trapezoid over accepted steps).
    pub friction_dissipation_per_cycle_j: f64,
    /// Energy the normal force dissipates per cycle beyond its elastic part,
    /// `∫ (F_n − F_e) δ̇ dt`, J (`ClearanceForce::damping_dissipation`).
    pub damping_dissipation_per_cycle_j: f64,
    /// Elastic energy stored in the contact at the start of the run, J.
    pub elastic_energy_start_j: f64,
    /// Elastic energy stored in the contact at the end of the run, J.
    pub elastic_energy_end_j: f64,
    /// Energy the whole contact force takes out of the mechanism per cycle, from the energy
    /// audit's work `W = ∫ Q·q̇ dt` (Gauss quadrature on the integrator's interpolant) net of
    /// the stored energy: `(−W − (V_end − V_start)) / cycles`, J. Equals damping + friction up
    /// to integration error; an elastic, frictionless contact whose force derives from a
    /// potential gives zero.
    pub contact_dissipation_per_cycle_j: f64,
    /// `contact_dissipation − damping − friction` per cycle, J: how well the books close.
    pub energy_books_residual_per_cycle_j: f64,
}

/// Largest deviation of the recorded body from the ideal mechanism.
#[derive(Debug, Clone, Copy, Default, Serialize)]
pub struct Deviation {
    /// m.
    pub x_m: f64,
    /// m.
    pub y_m: f64,
    /// m/s.
    pub vx_m_s: f64,
    /// m/s.
    pub vy_m_s: f64,
    /// m/s².
    pub ax_m_s2: f64,
    /// m/s².
    pub ay_m_s2: f64,
}

/// Integrator statistics, drift and energy balance of one dynamic run.
#[derive(Debug, Clone, Serialize)]
pub struct Numerics {
    /// Accepted steps.
    pub steps: usize,
    /// Rejected steps.
    pub rejected_steps: usize,
    /// Right-hand-side evaluations.
    pub rhs_evaluations: usize,
    /// Jacobian evaluations.
    pub jacobian_evaluations: usize,
    /// Factorizations.
    pub factorizations: usize,
    /// Smallest step, s.
    pub smallest_step_s: f64,
    /// Largest step, s.
    pub largest_step_s: f64,
    /// Located events (contact onsets and separations).
    pub events: usize,
    /// Largest |Φ|, m or rad.
    pub drift_position: f64,
    /// Largest |Φ̇|, m/s or rad/s.
    pub drift_velocity: f64,
    /// Energy-balance residual, J.
    pub energy_residual_j: f64,
    /// Residual relative to the largest energy term.
    pub energy_relative_residual: f64,
    /// Solver wall time, s.
    pub wall_time_s: f64,
}

/// Summary of one response run.
#[derive(Debug, Clone, Serialize)]
pub struct ResponseSummary {
    /// Simulated cycles.
    pub cycles: u32,
    /// Duration, s.
    pub duration_s: f64,
    /// Per active clearance joint.
    pub joints: Vec<JointSummary>,
    /// Peak deviation of the recorded body from the ideal mechanism (whole run).
    pub deviation: Deviation,
    /// The same after the start-up window.
    pub deviation_after_transient: Deviation,
    /// Energy dissipated per cycle by all clearance joints, J: the sum of the joints'
    /// `contact_dissipation_per_cycle_j` (energy audit, net of stored elastic energy).
    pub dissipated_per_cycle_j: f64,
    /// Of which friction, J (sum of the joints' `friction_dissipation_per_cycle_j`).
    pub friction_per_cycle_j: f64,
    /// Of which normal-force damping, J (sum of `damping_dissipation_per_cycle_j`).
    pub damping_per_cycle_j: f64,
    /// What the energy books say is wrong, if anything: a contact that puts energy into the
    /// mechanism (negative dissipation) is reported here, never as dissipation.
    pub energy_warnings: Vec<String>,
    /// Integrator numbers (absent for the kinematic path).
    pub numerics: Option<Numerics>,
}

/// Wear of one joint at the end of all stages.
#[derive(Debug, Clone, Serialize)]
pub struct JointWearSummary {
    /// Joint name.
    pub name: String,
    /// Peak bearing depth `h` (radius grew by h/2), m.
    pub bearing_peak_depth_m: f64,
    /// Body-frame angle of the bearing peak, deg.
    pub bearing_peak_angle_deg: f64,
    /// Peak pin depth, m.
    pub pin_peak_depth_m: f64,
    /// Body-frame angle of the pin peak, deg.
    pub pin_peak_angle_deg: f64,
    /// Bearing ranges with depth ≥ half the peak, `[start, end]` deg, deepest first.
    pub bearing_ranges_deg: Vec<[f64; 2]>,
    /// Pin ranges with depth ≥ half the peak, deg.
    pub pin_ranges_deg: Vec<[f64; 2]>,
}

/// How the wear stages were run.
#[derive(Debug, Clone, Serialize)]
pub struct WearSummary {
    /// Stages.
    pub stages: u32,
    /// Simulated cycles per stage `K` actually used.
    pub cycles_per_stage: u32,
    /// `K` the scene asks for (the paper: 100).
    pub scene_cycles_per_stage: u32,
    /// Amplification used (rescaled when `K` differs from the scene's).
    pub amplification: f64,
    /// Drive cycles one stage stands for (`K × amplification`).
    pub cycles_represented_per_stage: f64,
    /// Start of wear accumulation in each K-cycle run (start-up skipped), s.
    pub wear_start_s: f64,
    /// `adaptive` or `single-jump`.
    pub extrapolation: String,
    /// K-cycle simulations per stage (sub-steps).
    pub substeps_per_stage: Vec<usize>,
    /// Every sub-step: stage, amplification applied, deepest cell after it (m) and the bound
    /// on the relative clearance change it caused.
    pub substeps: Vec<SubstepSummary>,
    /// Convergence of each sub-step's wear estimate: the largest disagreement of the two
    /// halves of its K cycles (absent for odd K), against [`HALVES_TOLERANCE`].
    pub max_halves_difference: Option<f64>,
    /// Whether every sub-step's two halves agree within [`HALVES_TOLERANCE`] (false for odd K:
    /// not checked).
    pub converged: bool,
    /// Per stage: the drive cycles it applied when it ended early at the contact model's
    /// validity limits (`run.stop_at_validity_limits`), else `None` (all of them).
    pub cycles_applied_at_limits: Vec<Option<f64>>,
    /// Single-jump warnings, the convergence check's verdict when it fails, and stages that
    /// ended at the validity limits.
    pub warnings: Vec<String>,
    /// Per wearing joint, after the last stage.
    pub joints: Vec<JointWearSummary>,
    /// Wall time of the stages, s.
    pub wall_time_s: f64,
}

/// One extrapolation sub-step of a wear stage.
#[derive(Debug, Clone, Copy, Serialize)]
pub struct SubstepSummary {
    /// Stage, from 1.
    pub stage: usize,
    /// Amplification applied.
    pub amplification: f64,
    /// Deepest cell on any surface after the update, m.
    pub max_depth_m: f64,
    /// Bound on the relative local-clearance change of the update.
    pub change_fraction: f64,
    /// Bound on the change of the clearance slope `|Δc'|/c0` of the update, 1/rad.
    pub slope_change: f64,
    /// Bound on the change of the clearance curvature `|Δc''|/c0` of the update, 1/rad².
    pub curvature_change: f64,
    /// How far the wear of the two halves of the sub-step's K cycles disagree, per cell,
    /// relative to the peak (see `halves_difference`); absent for odd K.
    pub halves_difference: Option<f64>,
}

/// What `summary.json` holds.
#[derive(Debug, Clone, Serialize)]
pub struct Summary {
    /// Scene name.
    pub scene: String,
    /// Scene description.
    pub description: String,
    /// Body whose response is recorded.
    pub response_body: String,
    /// Drive period, s.
    pub period_s: f64,
    /// Start-up window excluded from the `after_transient` statistics, s.
    pub transient_window_s: f64,
    /// How the ideal reference was computed.
    pub reference: String,
    /// The response on the initial (unworn) surfaces.
    pub response: ResponseSummary,
    /// Wear stages, if any ran.
    pub wear: Option<WearSummary>,
    /// The response on the worn surfaces after the last stage.
    pub worn_response: Option<ResponseSummary>,
    /// Total wall time, s.
    pub wall_time_s: f64,
}

/// Everything a run produced.
#[derive(Debug, Clone)]
pub struct RunOutcome {
    /// The scene as run (overrides applied).
    pub scene: Scene,
    /// The numbers.
    pub summary: Summary,
    /// The response on unworn surfaces.
    pub response: Response,
    /// The response on the worn surfaces after the stages.
    pub worn_response: Option<Response>,
    /// Wear per wearing joint.
    pub wear: Vec<JointWearHistory>,
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

/// Everything `run` checks before it simulates: validation, the drive period, the recorded
/// body, the ideal mechanism's kinematic analysis at the output times, and the scene's system
/// assembled at t = 0 from the file's initial poses. So `check` rejects what `run` would.
pub fn check_assembly(scene: &Scene) -> Result<AssemblyCheck, RunError> {
    let (times, body) = run_plan(scene)?;
    ideal_motion(scene, &times, body)?;
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
    let mut scene = scene.clone();
    let scene_k = scene.run.cycles_per_stage;
    if let Some(k) = options.cycles_per_stage.filter(|k| *k > 0) {
        scene.run.amplification *= f64::from(scene_k) / f64::from(k);
        scene.run.cycles_per_stage = k;
    }
    let (times, body) = run_plan(&scene)?;
    let period = scene.cycle_period().ok_or(RunError::NoPeriod)?;
    let cycles = scene.run.cycles.max(1);
    let t_end = period * f64::from(cycles);
    progress.phase("ideal mechanism", f64::from(cycles));
    let ideal = ideal_motion(&scene, &times, body)?;
    progress.finish();

    let active = scene.active_clearance_joints().count() > 0;
    let unworn = unworn_joints(&scene)?;
    let initial = match &options.surfaces {
        Some(dir) => crate::surfaces::load_last_stage(dir, &scene, &unworn)?,
        None => unworn,
    };
    let mut wear_history = Vec::new();
    let (response, response_summary, wear_summary, worn) = if !active {
        let response = Response {
            times: times.clone(),
            motion: ideal.clone(),
            ideal,
            contact: Vec::new(),
        };
        let summary = summarize(&scene, &response, None, cycles, t_end);
        (response, summary, None, None)
    } else {
        // The unworn response samples round surfaces (no wear code); one from loaded surfaces
        // samples those.
        let start: &[Option<WornJoint>] = if options.surfaces.is_some() {
            &initial
        } else {
            &[]
        };
        let (response, summary) =
            respond(&scene, start, &times, &ideal, body, progress, "response")?;
        // Worn surfaces may legitimately open the clearance past the limit: warn only there.
        match crate::limits::check_penetration(&scene, "response", &response.contact) {
            Err(e) if options.surfaces.is_some() => progress.note(&format!("warning: {e}")),
            checked => checked?,
        }
        let mut wear_summary = None;
        let mut worn = None;
        if scene.run.wear_stages > 0 && initial.iter().any(Option::is_some) {
            let (history, mut ws, surfaces) = stages(&scene, &initial, period, progress)?;
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
                if let Err(e) =
                    crate::limits::check_penetration(&scene, "worn response", &run.0.contact)
                {
                    progress.note(&format!("warning: {e}"));
                }
                worn = Some(run);
            }
        }
        (response, summary, wear_summary, worn)
    };
    let summary = Summary {
        scene: name.to_string(),
        description: scene.description.clone(),
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

/// Validates `scene` and returns the response run's output times and recorded body.
fn run_plan(scene: &Scene) -> Result<(Vec<f64>, usize), RunError> {
    scene.validate("the scene as run")?;
    let period = scene.cycle_period().ok_or(RunError::NoPeriod)?;
    let body = scene.response_body().ok_or(RunError::NoResponseBody)?;
    let t_end = period * f64::from(scene.run.cycles.max(1));
    Ok((
        OutputTimes::uniform(0.0, t_end, scene.solver.output_interval),
        body,
    ))
}

/// The all-ideal mechanism's motion of `body` at `times` (kinematic analysis).
fn ideal_motion(scene: &Scene, times: &[f64], body: usize) -> Result<Motion, RunError> {
    let ideal_built = build(&scene.idealized(), Surfaces::default())?;
    let (q0, _) = ideal_built.system.initial_guess();
    let kin = ideal_built.system.kinematics(times, &q0)?;
    let mut ideal = Motion::default();
    for f in 0..kin.times.len() {
        ideal.push(body, kin.q(f), kin.qd(f), kin.qdd(f));
    }
    Ok(ideal)
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
    o.integrator = match scene.solver.integrator {
        scene::Integrator::Bdf => Integrator::Bdf,
        scene::Integrator::TrBdf2 => Integrator::TrBdf2,
        scene::Integrator::Esdirk34 => Integrator::Esdirk34,
        scene::Integrator::Tsit45 => Integrator::Tsit45,
    };
    o.formulation = match scene.solver.formulation {
        scene::Formulation::Cartesian => multibody::Formulation::Cartesian,
        scene::Formulation::Joint => multibody::Formulation::JointCoordinates,
    };
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

/// Records the response body and the contact state at output frames; forwards progress.
struct Recorder<'a> {
    body: usize,
    joints: &'a [JointHandle],
    period: f64,
    times: Vec<f64>,
    motion: Motion,
    contact: Vec<ContactSeries>,
    /// Validity measures per joint (same order as `contact`).
    validity: Vec<Tally>,
    progress: &'a mut dyn Progress,
    record: bool,
}

/// Points on the pin outline for the true-overlap check (0.5° apart).
const OVERLAP_SAMPLES: usize = 720;
/// The overlap is measured at every this-many-th output frame near contact.
const OVERLAP_EVERY: usize = 4;

impl Observer for Recorder<'_> {
    fn output(&mut self, frame: &Frame<'_>) {
        if !self.record {
            return;
        }
        self.times.push(frame.t);
        self.motion.push(self.body, frame.q, frame.qd, frame.qdd);
        let frame_index = self.times.len();
        for ((series, handle), tally) in self
            .contact
            .iter_mut()
            .zip(self.joints)
            .zip(&mut self.validity)
        {
            let probe = handle.probe(frame.elements);
            let d = probe
                .map(|p| p.contact(frame.q, frame.qd).diagnostics)
                .unwrap_or_default();
            // On round surfaces the overlap is δ itself: measure it on worn ones only.
            let overlap = probe
                .filter(|_| {
                    handle.worn
                        && frame_index.is_multiple_of(OVERLAP_EVERY)
                        && d.penetration > -0.25 * handle.clearance
                })
                .map(|p| p.outline_overlap(frame.q, OVERLAP_SAMPLES).depth);
            tally.frame(&d, overlap);
            series.normal_force.push(d.normal_force);
            series.friction_force.push(d.friction_force);
            series.penetration.push(d.penetration);
            series.eccentricity.push(d.eccentricity);
            let (s, c) = d.contact_angle.sin_cos();
            series.ex.push(d.eccentricity * c);
            series.ey.push(d.eccentricity * s);
            let (s, c) = d.bearing_angle.sin_cos();
            series.ex_bearing.push(d.eccentricity * c);
            series.ey_bearing.push(d.eccentricity * s);
        }
    }

    fn progress(&mut self, t: f64, _t_end: f64) {
        self.progress.advance(t / self.period);
    }
}

/// Assemble `built` from the scene's initial poses at t = 0.
fn assemble(built: &Built, what: &str) -> Result<multibody::State, RunError> {
    let (q0, qd0) = built.system.initial_guess();
    let state = built
        .system
        .assemble(0.0, &q0, &qd0)
        .map_err(|source| RunError::Assembly {
            what: what.to_string(),
            source,
        })?;
    crate::limits::check_initial_penetration(built, &state, what)?;
    Ok(state)
}

/// The response run on `worn` surfaces (empty: round) with its summary.
fn respond(
    scene: &Scene,
    worn: &[Option<WornJoint>],
    times: &[f64],
    ideal: &Motion,
    body: usize,
    progress: &mut dyn Progress,
    what: &str,
) -> Result<(Response, ResponseSummary), RunError> {
    let period = scene.cycle_period().ok_or(RunError::NoPeriod)?;
    let t_end = times.last().copied().unwrap_or(period);
    let cycles = scene.run.cycles.max(1);
    let mut built = build(
        scene,
        Surfaces {
            worn,
            accumulate_from: None,
            split_halves_at: None,
        },
    )?;
    let state = assemble(&built, what)?;
    let opts = simulation_options(scene, t_end, OutputTimes::At(times.to_vec()), false);
    progress.phase(what, f64::from(cycles));
    let joints = built.joints.clone();
    let initial_energy: Vec<f64> = joints
        .iter()
        .map(|h| {
            h.probe(built.system.elements()).map_or(0.0, |p| {
                p.contact(&state.q, &state.qd).diagnostics.elastic_energy
            })
        })
        .collect();
    let mut recorder = Recorder {
        body,
        joints: &joints,
        period,
        times: Vec::with_capacity(times.len()),
        motion: Motion::default(),
        contact: joints
            .iter()
            .map(|j| ContactSeries {
                name: j.name.clone(),
                clearance: j.clearance,
                ..Default::default()
            })
            .collect(),
        validity: joints
            .iter()
            .map(|j| Tally::new(j.clearance, Limits::default()))
            .collect(),
        progress,
        record: true,
    };
    let result = built
        .system
        .simulate(&state, &opts, &mut recorder)
        .map_err(|source| RunError::Simulation {
            what: what.to_string(),
            source,
        })?;
    let Recorder {
        times: rec_times,
        motion,
        mut contact,
        validity,
        progress,
        ..
    } = recorder;
    progress.finish();
    for (series, tally) in contact.iter_mut().zip(validity) {
        series.validity = Some(tally.finish());
    }
    if let Some(k) = (0..rec_times.len()).find(|&k| {
        motion.series().iter().any(|s| !s[k].is_finite())
            || contact.iter().any(|c| !c.normal_force[k].is_finite())
    }) {
        return Err(RunError::NonFinite {
            what: what.to_string(),
            t: rec_times[k],
        });
    }
    let response = Response {
        times: rec_times,
        motion,
        ideal: ideal.clone(),
        contact,
    };
    let audit = Audit {
        built: &built,
        result: &result,
        joints: &joints,
        initial_energy: &initial_energy,
    };
    let summary = summarize(scene, &response, Some(audit), cycles, t_end);
    Ok((response, summary))
}

/// What a dynamic run leaves for its energy books.
struct Audit<'a> {
    built: &'a Built,
    result: &'a SimulationResult,
    joints: &'a [JointHandle],
    /// Elastic energy stored in each joint at the start (joint order).
    initial_energy: &'a [f64],
}

/// Energy books of one joint over a run (J, totals).
#[derive(Default)]
struct JointBooks {
    friction: f64,
    damping: f64,
    stored_start: f64,
    stored_end: f64,
    audited: f64,
}

impl Audit<'_> {
    fn books(&self, k: usize, name: &str) -> JointBooks {
        let probe = self
            .joints
            .get(k)
            .and_then(|h| h.probe(self.built.system.elements()));
        let work = self
            .result
            .energy
            .as_ref()
            .and_then(|e| e.element_work.iter().find(|(n, _)| n == name))
            .map_or(0.0, |(_, w)| *w);
        let stored_start = self.initial_energy.get(k).copied().unwrap_or(0.0);
        let stored_end = probe
            .and_then(|p| p.last_diagnostics())
            .map_or(0.0, |d| d.elastic_energy);
        JointBooks {
            friction: probe.map_or(0.0, |p| p.friction_dissipation()),
            damping: probe.map_or(0.0, |p| p.damping_dissipation()),
            stored_start,
            stored_end,
            audited: -work - (stored_end - stored_start),
        }
    }
}

/// Dissipation below this (J per cycle) counts as round-off of the books, not as energy put in.
const DISSIPATION_FLOOR_J: f64 = 0.05;

fn summarize(
    scene: &Scene,
    response: &Response,
    audit: Option<Audit<'_>>,
    cycles: u32,
    t_end: f64,
) -> ResponseSummary {
    let period = scene.cycle_period().unwrap_or(t_end);
    let window = scene.run.transient_window;
    let per_cycle = 1.0 / f64::from(cycles);
    let mut joint_summaries = Vec::new();
    let (mut dissipated, mut friction, mut damping) = (0.0, 0.0, 0.0);
    let mut energy_warnings = Vec::new();
    for (k, series) in response.contact.iter().enumerate() {
        let books = audit
            .as_ref()
            .map_or_else(JointBooks::default, |a| a.books(k, &series.name));
        dissipated += books.audited;
        friction += books.friction;
        damping += books.damping;
        for (what, value) in [
            ("its contact force", books.audited),
            ("its normal force's damping", books.damping),
            ("its friction", books.friction),
        ] {
            if value * per_cycle < -DISSIPATION_FLOOR_J {
                energy_warnings.push(format!(
                    "joint {}: {what} put {:.3} J per cycle INTO the mechanism (negative \
                     dissipation): the contact is not dissipative on these surfaces, so its \
                     forces are not physical results",
                    series.name,
                    -value * per_cycle
                ));
            }
        }
        joint_summaries.push(JointSummary {
            name: series.name.clone(),
            clearance_m: series.clearance,
            normal_force_all: peak_stats(&response.times, &series.normal_force, period, 0.0),
            normal_force_after_transient: peak_stats(
                &response.times,
                &series.normal_force,
                period,
                window,
            ),
            max_penetration_m: series.penetration.iter().copied().fold(f64::MIN, f64::max),
            max_eccentricity_m: series.eccentricity.iter().copied().fold(0.0, f64::max),
            validity: series.validity.clone(),
            friction_dissipation_per_cycle_j: books.friction * per_cycle,
            damping_dissipation_per_cycle_j: books.damping * per_cycle,
            elastic_energy_start_j: books.stored_start,
            elastic_energy_end_j: books.stored_end,
            contact_dissipation_per_cycle_j: books.audited * per_cycle,
            energy_books_residual_per_cycle_j: (books.audited - books.damping - books.friction)
                * per_cycle,
        });
    }
    ResponseSummary {
        cycles,
        duration_s: t_end,
        joints: joint_summaries,
        deviation: deviation(response, 0.0),
        deviation_after_transient: deviation(response, window),
        dissipated_per_cycle_j: dissipated * per_cycle,
        friction_per_cycle_j: friction * per_cycle,
        damping_per_cycle_j: damping * per_cycle,
        energy_warnings,
        numerics: audit.map(|a| numerics(a.result)),
    }
}

fn numerics(r: &SimulationResult) -> Numerics {
    let s = &r.statistics;
    Numerics {
        steps: s.steps,
        rejected_steps: s.rejected_steps,
        rhs_evaluations: s.rhs_evaluations,
        jacobian_evaluations: s.jacobian_evaluations,
        factorizations: s.factorizations,
        smallest_step_s: s.smallest_step,
        largest_step_s: s.largest_step,
        events: s.events,
        drift_position: r.drift.position,
        drift_velocity: r.drift.velocity,
        energy_residual_j: r.energy.as_ref().map_or(f64::NAN, |e| e.residual),
        energy_relative_residual: r
            .energy
            .as_ref()
            .map_or(f64::NAN, |e| e.relative_residual()),
        wall_time_s: s.wall_time.as_secs_f64(),
    }
}

/// Per-cycle peaks of `values` for samples at `t ≥ from`.
pub fn peak_stats(times: &[f64], values: &[f64], period: f64, from: f64) -> PeakStats {
    let mut peaks: Vec<f64> = Vec::new();
    let mut current: Option<(usize, f64)> = None;
    for (t, v) in times.iter().zip(values) {
        if *t < from {
            continue;
        }
        // A sample exactly at the end of the run belongs to the last cycle.
        let cycle = ((t / period) * (1.0 - 1e-12)).floor().max(0.0) as usize;
        match current {
            Some((c, peak)) if c == cycle => current = Some((c, peak.max(*v))),
            Some((_, peak)) => {
                peaks.push(peak);
                current = Some((cycle, *v));
            }
            None => current = Some((cycle, *v)),
        }
    }
    peaks.extend(current.map(|(_, p)| p));
    if peaks.is_empty() {
        return PeakStats::default();
    }
    peaks.sort_by(f64::total_cmp);
    let quantile = |q: f64| {
        let x = q * (peaks.len() - 1) as f64;
        let (lo, hi) = (x.floor() as usize, x.ceil() as usize);
        peaks[lo] + (x - lo as f64) * (peaks[hi] - peaks[lo])
    };
    PeakStats {
        max: peaks[peaks.len() - 1],
        cycles: peaks.len(),
        cycle_median: quantile(0.5),
        cycle_min: peaks[0],
        cycle_max: peaks[peaks.len() - 1],
        cycle_iqr: quantile(0.75) - quantile(0.25),
    }
}

fn deviation(r: &Response, from: f64) -> Deviation {
    let mut d = [0.0f64; 6];
    let (a, b) = (r.motion.series(), r.ideal.series());
    for (k, t) in r.times.iter().enumerate() {
        if *t < from {
            continue;
        }
        for c in 0..6 {
            if let (Some(x), Some(y)) = (a[c].get(k), b[c].get(k)) {
                d[c] = d[c].max((x - y).abs());
            }
        }
    }
    Deviation {
        x_m: d[0],
        y_m: d[1],
        vx_m_s: d[2],
        vy_m_s: d[3],
        ax_m_s2: d[4],
        ay_m_s2: d[5],
    }
}

/// Largest disagreement of the two halves of a sub-step's cycles, per cell relative to the
/// peak, for which a stage's wear counts as converged in K.
pub const HALVES_TOLERANCE: f64 = 0.25;

/// How far the wear of the two halves of a stage's cycles disagree: the largest per-cell
/// difference `|h₁ − h₂|` over both surfaces, relative to the largest per-cell mean
/// `(h₁ + h₂)/2` (the halves are `first` and `total − first`). 0 for identical halves; a
/// converged per-cycle estimate gives a small value, one chaotic cycle against another a large
/// one.
fn halves_difference(first: &StageWear, total: &StageWear) -> f64 {
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

/// Per-stage history, summary and final surfaces (one slot per active clearance joint).
type Staged = (Vec<JointWearHistory>, WearSummary, Vec<Option<WornJoint>>);

/// Runs the wear stages; returns the per-stage history, the summary and the final surfaces
/// (one slot per active clearance joint).
fn stages(
    scene: &Scene,
    initial: &[Option<WornJoint>],
    period: f64,
    progress: &mut dyn Progress,
) -> Result<Staged, RunError> {
    let started = Instant::now();
    let r = &scene.run;
    let k = r.cycles_per_stage.max(1);
    let plan = StagePlan {
        stages: r.wear_stages as usize,
        amplification: r.amplification,
        geometry_limits: (r.adaptive_extrapolation && r.stop_at_validity_limits)
            .then_some(GeometryLimits::CONTACT_MODEL),
        extrapolation: if r.adaptive_extrapolation {
            Extrapolation::Adaptive {
                max_fraction: r.max_clearance_change,
                max_substeps: r.max_substeps as usize,
                max_slope_change: r.max_slope_change,
                max_curvature_change: r.max_curvature_change,
            }
        } else {
            Extrapolation::SingleJump {
                warn_fraction: r.max_clearance_change,
            }
        },
    };
    // Gather wear after the start-up window only (see the module docs).
    let wear_start = r.transient_window;
    let t_end = wear_start + f64::from(k) * period;
    let slots: Vec<Option<usize>> = {
        let mut next = 0;
        initial
            .iter()
            .map(|w| {
                w.as_ref().map(|_| {
                    next += 1;
                    next - 1
                })
            })
            .collect()
    };
    let mut joints: Vec<WornJoint> = initial.iter().flatten().cloned().collect();
    let names: Vec<String> = scene
        .active_clearance_joints()
        .zip(initial)
        .filter(|(_, w)| w.is_some())
        .map(|(c, _)| c.name.clone())
        .collect();
    let mut history: Vec<JointWearHistory> = joints
        .iter()
        .zip(&names)
        .map(|(j, name)| JointWearHistory {
            name: name.clone(),
            bearing_radius: j.bearing().nominal_radius(),
            pin_radius: j.pin().nominal_radius(),
            stages: Vec::new(),
        })
        .collect();
    let mut substeps = Vec::new();
    let mut details = Vec::new();
    let mut warnings = Vec::new();
    let mut ended_at_limits = Vec::new();
    // Per sub-step: how far the two halves of its K cycles disagree (even K only).
    let halves: std::cell::RefCell<Vec<Option<f64>>> = std::cell::RefCell::default();
    let mut runner = |ctx: wear::RunContext, current: &[WornJoint]| {
        let worn: Vec<Option<WornJoint>> = slots
            .iter()
            .map(|s| s.map(|i| current[i].clone()))
            .collect();
        let what = format!("wear stage {} run {}", ctx.stage + 1, ctx.substep + 1);
        let mut built = build(
            scene,
            Surfaces {
                worn: &worn,
                accumulate_from: Some(wear_start),
                // Whole cycles in each half: only for an even K.
                split_halves_at: k
                    .is_multiple_of(2)
                    .then(|| wear_start + f64::from(k / 2) * period),
            },
        )?;
        let state = assemble(&built, &what)?;
        let mut opts = simulation_options(scene, t_end, OutputTimes::At(vec![t_end]), false);
        // Only the wear matters here; skipping the energy quadrature saves time per step.
        opts.energy_audit = false;
        progress.phase(&what, t_end / period);
        let mut recorder = Recorder {
            body: 0,
            joints: &[],
            period,
            times: Vec::new(),
            motion: Motion::default(),
            contact: Vec::new(),
            validity: Vec::new(),
            progress: &mut *progress,
            record: false,
        };
        built
            .system
            .simulate(&state, &opts, &mut recorder)
            .map_err(|source| RunError::Simulation {
                what: what.clone(),
                source,
            })?;
        progress.finish();
        let mut out: Vec<StageWear> = Vec::with_capacity(names.len());
        let mut difference: Option<f64> = None;
        for h in built.joints.iter().filter(|h| h.worn) {
            let element = built.system.element_mut::<WornClearanceForce>(h.element);
            let lost = || RunError::LostWearBuffer {
                what: what.clone(),
                joint: h.name.clone(),
            };
            let element = element.ok_or_else(lost)?;
            let first = element.take_first_half();
            let wear = element.take_stage_wear().ok_or_else(lost)?;
            if let Some(first) = first {
                let d = halves_difference(&first, &wear);
                difference = Some(difference.map_or(d, |x: f64| x.max(d)));
            }
            out.push(wear);
        }
        halves.borrow_mut().push(difference);
        Ok::<_, RunError>(out)
    };
    for stage in 0..plan.stages {
        let report = match wear::run_stage(&mut joints, stage, &plan, &mut runner) {
            Ok(report) => report,
            Err(StagingError::Wear(e)) => return Err(RunError::Wear(e)),
            Err(StagingError::Runner(e)) => return Err(e),
        };
        substeps.push(report.substeps.len());
        let first = details.len();
        details.extend(report.substeps.iter().enumerate().map(|(i, r)| {
            SubstepSummary {
                stage: stage + 1,
                amplification: r.amplification,
                max_depth_m: r.max_depth,
                change_fraction: r.max_change_fraction,
                slope_change: r.joints.iter().map(|j| j.slope_change).fold(0.0, f64::max),
                curvature_change: r
                    .joints
                    .iter()
                    .map(|j| j.curvature_change)
                    .fold(0.0, f64::max),
                halves_difference: halves.borrow().get(first + i).copied().flatten(),
            }
        }));
        if let Some(w) = report.warning {
            let text = format!("warning: {w}");
            warnings.push(text);
        }
        let applied = report
            .ended_at_limits
            .map(|amplification| amplification * f64::from(k));
        if let (Some(cycles), Some(limits)) = (applied, plan.geometry_limits) {
            warnings.push(format!(
                "note: stage {} ended after {cycles:.3e} of its {:.3e} cycles ({:.2} %): the worn \
                 geometry reached the contact model's slope limit {} (run.stop_at_validity_limits)",
                stage + 1,
                plan.amplification * f64::from(k),
                100.0 * cycles / (plan.amplification * f64::from(k)),
                limits.slope
            ));
        }
        ended_at_limits.push(applied);
        for (h, j) in history.iter_mut().zip(&joints) {
            h.stages.push(j.clone());
        }
    }
    let max_halves_difference = details
        .iter()
        .filter_map(|d| d.halves_difference)
        .reduce(f64::max);
    let converged = max_halves_difference.is_some_and(|d| d <= HALVES_TOLERANCE);
    match max_halves_difference {
        None => warnings.push(format!(
            "warning: K = {k} simulated cycle(s) per sub-step: the wear of one chaotic cycle is \
             not a converged estimate, and with odd K it cannot be checked; give an even K \
             (--cycles-per-stage 2 or more)"
        )),
        Some(d) if d > HALVES_TOLERANCE => warnings.push(format!(
            "warning: the two halves of a sub-step's K = {k} cycles wear differently by up to \
             {:.0} % of the peak (tolerance {:.0} %): the stage's wear is not converged in K",
            100.0 * d,
            100.0 * HALVES_TOLERANCE
        )),
        Some(_) => {}
    }
    for w in &warnings {
        progress.note(w);
    }
    let joints_summary = history
        .iter()
        .filter_map(|h| h.stages.last().map(|j| (h, j)))
        .map(|(h, j)| {
            let (bd, _, ba) = j.bearing().peak();
            let (pd, _, pa) = j.pin().peak();
            let ranges = |p: &wear::WornProfile| {
                p.concentrated_ranges(0.5)
                    .iter()
                    .map(|r| r.degrees())
                    .collect()
            };
            JointWearSummary {
                name: h.name.clone(),
                bearing_peak_depth_m: bd,
                bearing_peak_angle_deg: ba.to_degrees(),
                pin_peak_depth_m: pd,
                pin_peak_angle_deg: pa.to_degrees(),
                bearing_ranges_deg: ranges(j.bearing()),
                pin_ranges_deg: ranges(j.pin()),
            }
        })
        .collect();
    let mut surfaces = vec![None; initial.len()];
    for (slot, index) in slots.iter().enumerate() {
        if let Some(i) = index {
            surfaces[slot] = joints.get(*i).cloned();
        }
    }
    let summary = WearSummary {
        stages: r.wear_stages,
        cycles_per_stage: k,
        scene_cycles_per_stage: 0,
        amplification: r.amplification,
        cycles_represented_per_stage: f64::from(k) * r.amplification,
        wear_start_s: wear_start,
        extrapolation: if r.adaptive_extrapolation {
            format!(
                "adaptive (each sub-step changes a local clearance by at most {:.0} %, its slope \
                 by at most {} c0/rad and its curvature by at most {} c0/rad²)",
                100.0 * r.max_clearance_change,
                r.max_slope_change,
                r.max_curvature_change
            )
        } else {
            "single-jump (the paper's)".into()
        },
        substeps_per_stage: substeps,
        substeps: details,
        max_halves_difference,
        converged,
        cycles_applied_at_limits: ended_at_limits,
        warnings,
        joints: joints_summary,
        wall_time_s: started.elapsed().as_secs_f64(),
    };
    Ok((history, summary, surfaces))
}
