//! What a run returns: the recorded series and every summary number, serialized as
//! `summary.json`.

use serde::Serialize;
use wear::WornJoint;

use crate::validity::Validity;
use scene::ValidScene;

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
    pub(super) fn push(&mut self, k: usize, q: &[f64], qd: &[f64], qdd: &[f64]) {
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
    /// Its conservative part (the contact law's elastic force or the layer's elastic
    /// resultant), N: `normal_force − elastic_force` is the damping.
    pub elastic_force: Vec<f64>,
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
    /// Energy the joint's contact law dissipated since the start (damping and friction over
    /// the accepted steps so far), J: its differences over the cycles are the samples the
    /// noise of the dissipation per cycle comes from.
    pub dissipated: Vec<f64>,
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
    /// Poses of every body at the frames of the animation (`None` when `run.animation` is
    /// false).
    pub frames: Option<MechanismFrames>,
}

/// Poses of every body at the frames an animation shows: one drive cycle after the start-up
/// window.
///
/// The frames start at the first output time at or after `run.transient_window` and are
/// spaced evenly over one period `T` (the last frame `T/n` before the cycle closes, so the
/// animation loops). A run shorter than the window plus one period shows its last period
/// instead, and a run shorter than one period all of it; an output interval coarser than
/// `T/n` gives every output time in the period.
#[derive(Debug, Clone, Default)]
pub struct MechanismFrames {
    /// Indices into [`Response::times`] of the frames shown (at most
    /// [`MAX_ANIMATION_FRAMES`](crate::MAX_ANIMATION_FRAMES), increasing, spanning at most
    /// one period).
    pub frames: Vec<usize>,
    /// `[x, y, θ]` (m, m, rad) of every scene body (scene order) at each frame, with
    /// clearance.
    pub poses: Vec<Vec<[f64; 3]>>,
    /// The same for the ideal mechanism (clearance joints made ideal) at the same times.
    pub ideal_poses: Vec<Vec<[f64; 3]>>,
}

impl MechanismFrames {
    /// The poses of every body (3 coordinates each) taken from a system's coordinates `q`.
    pub(super) fn poses_of(q: &[f64]) -> Vec<[f64; 3]> {
        q.chunks_exact(3).map(|c| [c[0], c[1], c[2]]).collect()
    }
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
    /// Its life curve: the surfaces the stages started from at 0 cycles, then one point after
    /// every wear sub-step (`wear_life.csv`).
    pub life: Vec<LifePoint>,
    /// The sampling noise of each point of `life` (`clearance::WearStages::life_noise`;
    /// `None` where not measured, as at the start).
    pub life_noise: Vec<Option<wear::JointNoise>>,
    /// Per stage: the jackknife replicas of its surfaces at the stage's end, from which the
    /// noise of any measure of them follows (`wear::Replicas::noise`).
    pub stage_replicas: Vec<wear::Replicas>,
}

/// A joint's wear after `cycles` drive cycles: one point of its life curve.
#[derive(Debug, Clone, Copy, PartialEq, Serialize)]
pub struct LifePoint {
    /// Stage, from 1 (0: the surfaces the stages started from).
    pub stage: usize,
    /// Sub-step within the stage, from 1 (0: the start).
    pub substep: usize,
    /// Drive cycles the wear applied so far stands for: the sum over the run's sub-steps of
    /// amplification × simulated cycles per stage `K`.
    pub cycles: f64,
    /// Peak bearing depth `h` (the radius grew by h/2), m.
    pub bearing_peak_depth_m: f64,
    /// Peak pin depth `h`, m.
    pub pin_peak_depth_m: f64,
    /// Material removed from both surfaces, m³.
    pub worn_volume_m3: f64,
    /// Largest local clearance `c0 + (max h_i + max h_j)/2` (the deepest dents facing each
    /// other), m.
    pub max_local_clearance_m: f64,
    /// How stiff the sub-step's update was, `aλ` weighted by the wear
    /// ([`wear::JointSubstep::wear_stiffness`]; 0 at the start): an explicit update multiplies
    /// a pattern relaxing at `λ` by `1 − aλ`.
    pub wear_stiffness: f64,
}

/// When a joint's largest local clearance reaches the maintenance limit `run.clearance_limit`.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct ClearanceLimitReport {
    /// The limit, m.
    pub limit_m: f64,
    /// Drive cycles after which the largest local clearance reaches it, interpolated linearly
    /// between the sub-steps of the life curve; `None` when the run does not reach it.
    pub cycles: Option<f64>,
    /// Its sampling noise: the largest local clearance's noise where the curve reaches the
    /// limit over the curve's slope there; `None` when not reached or not measured.
    pub cycles_noise: Option<f64>,
    /// The same in words (`not reached within the run` when `cycles` is `None`).
    pub message: String,
    /// The scatter of the joint's `ln k_d` its B lives assume
    /// (`clearance_joints[*].wear.k_d_scatter`; 0: none).
    pub k_d_scatter: f64,
    /// Cycles by which 10 % of such joints reach the limit, under that scatter, rescaled
    /// exactly from the simulated life (`crate::life_distribution`); `None` when not reached.
    pub b10_cycles: Option<f64>,
    /// Its sampling noise (that of `cycles`, scaled).
    pub b10_noise: Option<f64>,
    /// Cycles by which half of them do: `cycles` itself (the scatter's median is the scene's
    /// `k_d`).
    pub b50_cycles: Option<f64>,
    /// Its sampling noise.
    pub b50_noise: Option<f64>,
}

impl ClearanceLimitReport {
    /// The joint's life to the limit, when it reached the limit after some cycles.
    pub fn joint_life(&self) -> Option<crate::life_distribution::JointLife> {
        Some(crate::life_distribution::JointLife {
            cycles: self.cycles.filter(|c| *c > 0.0)?,
            noise: self.cycles_noise,
            scatter: self.k_d_scatter,
        })
    }

    /// Its B lives as reported (`None` when not reached).
    pub fn b_lives(&self) -> Option<crate::life_distribution::BLives> {
        Some(crate::life_distribution::BLives {
            b10_cycles: self.b10_cycles?,
            b10_noise: self.b10_noise,
            b50_cycles: self.b50_cycles?,
            b50_noise: self.b50_noise,
        })
    }
}

/// The life to the clearance limit under the scatter of the wear coefficients: how the run
/// ended, and the mechanism's B lives (its first joint to reach the limit).
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct LifeSummary {
    /// The limit on the largest local clearance, m (`run.clearance_limit`).
    pub limit_m: f64,
    /// Whether the run ran until every joint reached it (`run.until_limit`).
    pub until_limit: bool,
    /// The most cycles it could run (`run.max_cycles`, with `until_limit`).
    pub max_cycles: Option<f64>,
    /// How the stages ended, in words.
    pub ended: String,
    /// How the joints' wear coefficients scatter together in the mechanism's life
    /// (`run.k_d_correlation`).
    pub k_d_correlation: scene::KdCorrelation,
    /// That assumption in words, with what it leaves out.
    pub assumption: String,
    /// The mechanism's B10 and B50 lives, when every wearing joint reached the limit.
    pub mechanism: Option<crate::life_distribution::BLives>,
    /// The mechanism's lives in words, or why there are none.
    pub mechanism_message: String,
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
    /// Sampling noise of `cycle_median`: the standard deviation of the median over bootstrap
    /// resamples of the per-cycle peaks (N; 0 with one cycle, where it is unknown).
    pub cycle_median_noise: f64,
    /// Median over the cycles of the elastic share `F_e/F_n` at each cycle's peak: near 1 the
    /// peak is a load the surfaces carry; well below, the damping term of the law holds it up.
    pub elastic_share_median: f64,
    /// Smallest elastic share at a cycle's peak.
    pub elastic_share_min: f64,
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
    /// Normal-force peaks after the start-up window `run.transient_window` (`None`, `null`
    /// in JSON, when the window covers the whole run).
    pub normal_force_after_transient: Option<PeakStats>,
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
    /// The same after the start-up window (`None`, `null` in JSON, when the window covers
    /// the whole run: no sample to measure).
    pub deviation_after_transient: Option<Deviation>,
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
    /// Its sampling noise (a standard error; `wear::NoiseBatches`), m; `None` when the runs
    /// kept no halves to measure it from.
    pub bearing_peak_depth_noise_m: Option<f64>,
    /// Body-frame angle of the bearing peak, deg.
    pub bearing_peak_angle_deg: f64,
    /// Peak pin depth, m.
    pub pin_peak_depth_m: f64,
    /// Its sampling noise, m.
    pub pin_peak_depth_noise_m: Option<f64>,
    /// Body-frame angle of the pin peak, deg.
    pub pin_peak_angle_deg: f64,
    /// Material removed from both surfaces, m³.
    pub worn_volume_m3: f64,
    /// Its sampling noise, m³.
    pub worn_volume_noise_m3: Option<f64>,
    /// Bearing ranges with depth ≥ half the peak, `[start, end]` deg, deepest first.
    pub bearing_ranges_deg: Vec<[f64; 2]>,
    /// Pin ranges with depth ≥ half the peak, deg.
    pub pin_ranges_deg: Vec<[f64; 2]>,
    /// Largest local clearance `c0 + (max h_i + max h_j)/2` after the last stage, m.
    pub max_local_clearance_m: f64,
    /// Its sampling noise, m.
    pub max_local_clearance_noise_m: Option<f64>,
    /// The jackknife replicas the noises come from (batches of the runs' independent halves
    /// that hold samples; 0: no noise measured).
    pub noise_batches: usize,
    /// When the largest local clearance reaches `run.clearance_limit` (absent without one).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub clearance_limit: Option<ClearanceLimitReport>,
}

/// How the wear stages were run.
#[derive(Debug, Clone, Serialize)]
pub struct WearSummary {
    /// Stages run (`run.wear_stages`, or with `run.until_limit` as many as it took).
    pub stages: u32,
    /// Simulated cycles per stage `K` actually used.
    pub cycles_per_stage: u32,
    /// `K` the scene asks for (the paper: 100).
    pub scene_cycles_per_stage: u32,
    /// Trajectories the `K` cycles of a sub-step were spread over (`run.trajectories`; 1: one
    /// trajectory restarted at every sub-step).
    pub trajectories: u32,
    /// Amplification used (rescaled when `K` differs from the scene's).
    pub amplification: f64,
    /// Drive cycles one stage stands for (`K × amplification`).
    pub cycles_represented_per_stage: f64,
    /// Drive cycles the wear applied over all stages stands for: the sum of every sub-step's
    /// amplification × `K` (less than `stages × cycles_represented_per_stage` when a stage
    /// ended at the validity limits). The last `cycles` of `wear_life.csv`.
    pub cycles_applied: f64,
    /// Start of wear accumulation in each K-cycle run (start-up skipped), s.
    pub wear_start_s: f64,
    /// `adaptive`, `controlled` or `single-jump`, with the bounds.
    pub extrapolation: String,
    /// Extrapolation sub-steps per stage.
    pub substeps_per_stage: Vec<usize>,
    /// K-cycle simulations per stage: one per sub-step with fixed bounds; with controlled
    /// extrapolation one more (the first rate), and the rejected predictions.
    pub runs_per_stage: Vec<usize>,
    /// Of those, predictions the controlled extrapolation rejected (0 with fixed bounds).
    pub rejected_runs_per_stage: Vec<usize>,
    /// Every sub-step: stage, amplification applied, deepest cell after it (m) and the bound
    /// on the relative clearance change it caused.
    pub substeps: Vec<SubstepSummary>,
    /// Noise of each sub-step's wear estimate: the largest per-cell disagreement of the two
    /// halves of its K cycles (absent for odd K). Informative only: a stage averages many
    /// sub-steps, and `stage_halves` measures what reaches its result.
    pub max_halves_difference: Option<f64>,
    /// Per stage (even K): the stage's wear extrapolated from each half of the simulated
    /// cycles alone, their peak depths' and worn volumes' relative difference
    /// (`clearance::StageHalves`), against [`STAGE_HALVES_TOLERANCE`](crate::STAGE_HALVES_TOLERANCE).
    pub stage_halves: Vec<Option<StageHalvesSummary>>,
    /// Whether every stage's halves agree within [`STAGE_HALVES_TOLERANCE`](crate::STAGE_HALVES_TOLERANCE) (false for
    /// odd K: not checked).
    pub converged: bool,
    /// Per stage: the drive cycles it applied when it ended early at the contact model's
    /// validity limits (`run.stop_at_validity_limits`), else `None` (all of them).
    pub cycles_applied_at_limits: Vec<Option<f64>>,
    /// Single-jump warnings, the convergence check's verdict when it fails, and stages that
    /// ended at the validity limits.
    pub warnings: Vec<String>,
    /// Per wearing joint, after the last stage.
    pub joints: Vec<JointWearSummary>,
    /// With `run.clearance_limit`: the life to it, and the mechanism's B lives.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub life: Option<LifeSummary>,
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
    /// relative to the peak (see `clearance::halves_difference`); absent for odd K.
    pub halves_difference: Option<f64>,
    /// With controlled extrapolation, the sub-step's error estimate per unit of its wear
    /// (`wear::Extrapolation::Controlled`).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub error_estimate: Option<f64>,
}

/// What `summary.json` holds.
#[derive(Debug, Clone, Serialize)]
pub struct Summary {
    /// Scene name.
    pub scene: String,
    /// Scene description.
    pub description: String,
    /// The contact that ran at each clearance joint, `name: model, law and damping; friction`
    /// (the description is the scene author's words; this is what the code ran).
    pub contacts: Vec<String>,
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
    pub scene: ValidScene,
    /// The numbers.
    pub summary: Summary,
    /// The response on unworn surfaces.
    pub response: Response,
    /// The response on the worn surfaces after the stages.
    pub worn_response: Option<Response>,
    /// Wear per wearing joint.
    pub wear: Vec<JointWearHistory>,
}

/// [`WearSummary::stage_halves`] of one stage.
#[derive(Debug, Clone, Copy, PartialEq, Serialize)]
pub struct StageHalvesSummary {
    /// Largest `|peak₁ − peak₂|/mean` of the two halves' extrapolated peak depths.
    pub peak_depth: f64,
    /// Largest `|V₁ − V₂|/mean` of their worn volumes.
    pub worn_volume: f64,
}
