//! The `[run]` table of a scene: cycles, wear stages and their extrapolation, the start-up
//! window, the animation and the maintenance limit.

use serde::{Deserialize, Serialize};

use super::defaults::yes;

/// How long to run and how to stage wear.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct RunSettings {
    /// Drive cycles of the response run (before any wear).
    #[serde(default = "one")]
    pub cycles: u32,
    /// Duration of one cycle, s; default: from the drivers' time law (2π/ω).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub period: Option<f64>,
    /// Wear stages `S` (0: no wear update).
    #[serde(default = "one")]
    pub wear_stages: u32,
    /// Simulated cycles per wear stage `K`.
    #[serde(default = "cycles_per_stage")]
    pub cycles_per_stage: u32,
    /// Trajectories the `cycles_per_stage` simulated cycles of a wear sub-step are spread over
    /// (a divisor of it; default 1). With 1, every sub-step restarts the mechanism from its
    /// assembled state and simulates its cycles one after the other after the start-up window;
    /// with `M ≥ 2`, `M` trajectories of `K/M` cycles each run on threads, each continuing from
    /// where it ended in the previous sub-step (`clearance::Ensemble`). Both estimate the same
    /// average wear of the chaotic motion (docs/convergence.md); the results do not depend on
    /// the number of threads.
    #[serde(default = "one")]
    pub trajectories: u32,
    /// Factor scaling the wear of one stage's simulated cycles (a stage stands for
    /// `cycles_per_stage × amplification` cycles).
    #[serde(default = "amplification")]
    pub amplification: f64,
    /// Split a stage's extrapolation into steps, re-simulating in between.
    #[serde(default = "yes")]
    pub adaptive_extrapolation: bool,
    /// Largest clearance change per extrapolation step, as a fraction of the current clearance.
    #[serde(default = "max_clearance_change")]
    pub max_clearance_change: f64,
    /// How a sub-step extrapolates its cycles' wear: `"explicit"` (the rate at the start
    /// times the amplification; the paper's jump) or `"linearly-implicit"` (the wear rate's
    /// fall where a surface wore more, gathered from the same cycles' contact zones, taken
    /// implicitly: [`wear::StageWear::implicit`]; the foundation contact only, the same as
    /// explicit with the line-of-centres contact). Error-controlled stages (`wear_tolerance`)
    /// are explicit whatever this says.
    #[serde(default)]
    pub wear_stepping: wear::WearStepping,
    /// Largest relative change of the clearance's slope per extrapolation step,
    /// `|Δc'|/(c0 + |c'|)`: bounds how fast a sub-step reshapes the worn profile. Default: 0.25
    /// when a clearance joint uses the line-of-centres contact (whose validity the shape
    /// limits), unbounded when all use the foundation, which follows any shape
    /// ([`RunSettings::shape_change_bounds`]).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub max_slope_change: Option<f64>,
    /// Largest relative change of the clearance's curvature per extrapolation step,
    /// `|Δc''|/(c0 + |c''|)`; default as for `max_slope_change`.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub max_curvature_change: Option<f64>,
    /// Error-controlled sub-steps at this tolerance, in `(0, 1]`, instead of the fixed bounds
    /// ([`wear::Extrapolation::Controlled`]): a predictor–corrector in cycles whose step
    /// follows an error estimate with the runs' sampling noise taken out, and which keeps the
    /// stage's own sampling noise near the tolerance. `max_clearance_change` then bounds the
    /// first sub-step's predictor and is the smallest the estimate or the noise bound cuts one
    /// to (a tolerance tighter than the noise allows runs at that floor); no predictor
    /// changes a local clearance by more than
    /// [`wear::Extrapolation::DEFAULT_CONTROLLED_MAX_FRACTION`] (or
    /// `max_clearance_change`, if larger); the shape bounds do not apply. The noise is measured
    /// from the two halves of each run's cycles, so give an even K (one trajectory) or an even
    /// `trajectories`. Needs `adaptive_extrapolation`.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub wear_tolerance: Option<f64>,
    /// The target relative sampling noise of each wearing joint's peak depths at the end of a
    /// stage, in `(0, 1]` (optional; unset: every sub-step at `max_clearance_change`). The
    /// stage measures its noise from the runs' independent halves as it goes and, after a
    /// warm-up of [`wear::NOISE_WARM_UP`] sub-steps at `max_clearance_change`, lengthens the
    /// sub-steps as far as the target allows, up to a clearance change of
    /// [`wear::NOISE_MAX_FRACTION`] (never below `max_clearance_change`: the target only
    /// saves cycles, it never adds any). Needs `adaptive_extrapolation` without
    /// `wear_tolerance`, and the runs' halves (an even K on one trajectory, or an even number
    /// of trajectories). `K` and the trajectories stay the scene's.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub wear_noise: Option<f64>,
    /// Standard deviation, in degrees of the surfaces, of the Gaussian that smooths each
    /// sub-step's simulated wear before it is extrapolated (0: none): the wear of K chaotic
    /// cycles is a noisy estimate of the expected wear, and amplified its cell-scale noise
    /// would become ridges. Default [`DEFAULT_WEAR_SMOOTHING_DEG`] (8 cells of the paper's
    /// 1000; docs/model.md §10.4).
    #[serde(default = "wear_smoothing_deg")]
    pub wear_smoothing_deg: f64,
    /// Finer sub-steps while a joint's groove forms (optional; unset: none): as long as a
    /// wearing joint's deeper worn peak is shallower than `forming_depth` of its nominal
    /// clearance, a sub-step changes its local clearance by at most this fraction, in
    /// `(0, 1]` ([`wear::FormingBound`]; error-controlled stages lower their floor and cap to
    /// it). On the built-in LGRES, 0.0025 with `forming_depth = 0.16` brings joint B's peaks
    /// from 1.2–1.6 noises shallow to within half a noise of sub-steps 20× finer, for 60 % more
    /// sub-steps; B's worn volume stays 0.7 noise above (docs/convergence.md, "Where the bias
    /// forms", "Four reference runs").
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub forming_clearance_change: Option<f64>,
    /// Depth, as a fraction of a joint's nominal clearance in `(0, 1]`, up to which
    /// `forming_clearance_change` bounds its sub-steps (optional; unset:
    /// [`DEFAULT_FORMING_DEPTH`]). Refused without `forming_clearance_change`, where it would
    /// change nothing ([`RunSettings::forming_bound`]).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub forming_depth: Option<f64>,
    /// Most extrapolation sub-steps per stage; a stage that needs more fails, naming this.
    #[serde(default = "max_substeps")]
    pub max_substeps: u32,
    /// With adaptive extrapolation, end a stage early where the worn geometry would leave the
    /// contact model's validity (slope 0.3, conformity 1; docs/model.md §9): beyond it the
    /// line-of-centres contact, and so the wear it drives, is not credible. The summary says how
    /// many of the stage's cycles were applied.
    #[serde(default = "yes")]
    pub stop_at_validity_limits: bool,
    /// Start-up window excluded from peak statistics, s.
    #[serde(default = "transient_window")]
    pub transient_window: f64,
    /// Draw `mechanism.gif` (and `mechanism_worn.gif` after wear stages): one drive cycle after
    /// the start-up window animated, the ideal mechanism faint behind and every clearance
    /// magnified in an inset (`output::animation`). False: skip it and the pose recording.
    #[serde(default = "yes")]
    pub animation: bool,
    /// Maintenance limit on the largest local clearance, m (optional; above every clearance
    /// joint's initial `clearance`). The summary then says, per wearing joint, after how many
    /// drive cycles its largest local clearance `c0 + (max h_i + max h_j)/2` reaches it,
    /// interpolated linearly between the wear sub-steps, or that the run does not reach it.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub clearance_limit: Option<f64>,
    /// Run the wear stages until every wearing joint's largest local clearance reaches
    /// `clearance_limit` (needs it and `max_cycles`): stages of `cycles_per_stage ×
    /// amplification` drive cycles follow each other, the last ending at the sub-step where the
    /// last joint reaches the limit, and `wear_stages` counts nothing.
    #[serde(default, skip_serializing_if = "is_false")]
    pub until_limit: bool,
    /// With `until_limit`: the most drive cycles the stages may stand for; a joint that has
    /// not reached the limit by then is reported as not reaching it.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub max_cycles: Option<f64>,
    /// How the wearing joints' wear coefficients scatter together
    /// (`clearance_joints[*].wear.k_d_scatter`) in the joints' and the mechanism's (the first
    /// joint to reach the limit) B lives: all as one (`"shared"`, the default: one material
    /// pair, one batch; exact from the simulated life) or each on its own (`"independent"`:
    /// approximate, see [`KdCorrelation::Independent`]).
    #[serde(default, skip_serializing_if = "KdCorrelation::is_shared")]
    pub k_d_correlation: KdCorrelation,
    /// Body whose centroid response is recorded and compared with the ideal mechanism;
    /// default: `rod3` if the scene has one, else the last body.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub response_body: Option<String>,
}

/// How the wear coefficients of a mechanism's wearing joints scatter together.
#[derive(Debug, Clone, Copy, Default, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "kebab-case")]
pub enum KdCorrelation {
    /// One factor scales every joint's `k_d` (one material pair, one batch): the whole
    /// mechanism's wear scales as one, so every life follows exactly from the simulated one.
    #[default]
    Shared,
    /// Each joint's `k_d` on its own: the mechanism survives `n` cycles when every joint does,
    /// `S(n) = Π S_j(n)`, each joint's life rescaled alone. Approximate: one joint's wear
    /// changes the dynamics that wear the other (on the LGRES, B's wear hastens A's: with A's
    /// `k_d` doubled alone A reaches the limit 13 % later than rescaling says, with B's
    /// doubled alone 20 % sooner; B moves by 0.1 %; docs/life.md). A sweep drawing each
    /// joint's `k_d` samples it without the rescaling.
    Independent,
}

impl KdCorrelation {
    fn is_shared(&self) -> bool {
        *self == Self::Shared
    }

    /// As a scene writes it: `"shared"`, `"independent"`.
    pub fn name(self) -> &'static str {
        match self {
            Self::Shared => "shared",
            Self::Independent => "independent",
        }
    }
}

fn is_false(b: &bool) -> bool {
    !*b
}

fn one() -> u32 {
    1
}
fn cycles_per_stage() -> u32 {
    100
}
fn amplification() -> f64 {
    20_000.0
}
fn max_clearance_change() -> f64 {
    0.1
}
fn transient_window() -> f64 {
    0.1
}
/// Default [`RunSettings::wear_smoothing_deg`], degrees: 8 cells of a 1000-cell grid.
pub const DEFAULT_WEAR_SMOOTHING_DEG: f64 = 2.88;

fn wear_smoothing_deg() -> f64 {
    DEFAULT_WEAR_SMOOTHING_DEG
}
/// Default [`RunSettings::forming_depth`]: 8 % of the nominal clearance.
pub const DEFAULT_FORMING_DEPTH: f64 = 0.08;
fn max_substeps() -> u32 {
    400
}

impl RunSettings {
    /// The most wear stages the run may take: `wear_stages`, or with `until_limit` the stages
    /// `max_cycles` stands for (rounded up; `None` while a factor is not a positive finite
    /// number, which validation names).
    pub fn most_stages(&self) -> Option<f64> {
        if !self.until_limit {
            return Some(f64::from(self.wear_stages));
        }
        let represented = f64::from(self.cycles_per_stage) * self.amplification;
        let stages = (self.max_cycles? / represented).ceil();
        (stages.is_finite() && stages > 0.0).then_some(stages)
    }

    /// The finer sub-steps while a groove forms, if `forming_clearance_change` asks for them:
    /// up to `forming_depth`, else [`DEFAULT_FORMING_DEPTH`].
    pub fn forming_bound(&self) -> Option<wear::FormingBound> {
        self.forming_clearance_change.map(|fraction| {
            wear::FormingBound::new(
                fraction,
                self.forming_depth.unwrap_or(DEFAULT_FORMING_DEPTH),
            )
        })
    }

    /// The slope and curvature bounds per extrapolation sub-step: the scene's, else 0.25 each
    /// when `shape_limited` (some joint's contact model needs its worn outlines within shape
    /// limits, `contact::ContactModel::shape_limits`: the line of centres) and unbounded
    /// otherwise, since only such a model can leave its validity through a sub-step's change of
    /// shape.
    pub fn shape_change_bounds(&self, shape_limited: bool) -> (f64, f64) {
        let default = |bound: f64| if shape_limited { bound } else { f64::INFINITY };
        (
            self.max_slope_change
                .unwrap_or(default(wear::Extrapolation::DEFAULT_SLOPE_CHANGE)),
            self.max_curvature_change
                .unwrap_or(default(wear::Extrapolation::DEFAULT_CURVATURE_CHANGE)),
        )
    }
}

impl Default for RunSettings {
    fn default() -> Self {
        Self {
            cycles: one(),
            period: None,
            wear_stages: one(),
            cycles_per_stage: cycles_per_stage(),
            trajectories: one(),
            amplification: amplification(),
            adaptive_extrapolation: true,
            max_clearance_change: max_clearance_change(),
            wear_stepping: wear::WearStepping::default(),
            max_slope_change: None,
            max_curvature_change: None,
            wear_tolerance: None,
            wear_noise: None,
            wear_smoothing_deg: wear_smoothing_deg(),
            forming_clearance_change: None,
            forming_depth: None,
            max_substeps: max_substeps(),
            stop_at_validity_limits: true,
            transient_window: transient_window(),
            animation: true,
            clearance_limit: None,
            until_limit: false,
            max_cycles: None,
            k_d_correlation: KdCorrelation::default(),
            response_body: None,
        }
    }
}
