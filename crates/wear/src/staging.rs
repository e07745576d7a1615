//! Staged wear: simulate K cycles on frozen surfaces, amplify, update, repeat.
//!
//! The crate knows nothing about integrators: the caller supplies the runner, a closure that
//! simulates its K drive cycles on the given (frozen) joints and returns each joint's
//! [`StageWear`]. The paper amplifies once per stage (K = 100, ×20,000). With the printed
//! `K_d` that jump can grow a clearance several-fold (docs/model.md §8), so the default is
//! [`Extrapolation::Adaptive`]: the amplification is spent in sub-steps that each change any
//! local clearance, and the clearance's slope and curvature, by at most a set fraction,
//! re-running the K cycles on the updated surfaces in between. Sub-step amplifications sum to
//! the stage's factor, unless the plan's [`GeometryLimits`] end the stage early where the worn
//! shape would leave what a line-of-centres contact describes ([`StageReport::ended_at_limits`]).
//!
//! [`Extrapolation::Controlled`] chooses the sub-steps by an error estimate instead: a
//! predictor–corrector in cycles (an explicit step predicts the surfaces, the K cycles are
//! simulated on them, and the sub-step applies the mean of the wear rates at both ends), whose
//! step grows while the rate changes slowly and shrinks where it changes fast. Since K chaotic
//! cycles are a noisy sample of the rate, the estimate removes the sampling noise that the
//! runner's two halves of the cycles measure ([`WearSample::halves`]).
//!
//! Layout: this module holds what both extrapolations share — the plan, what the runner is
//! given and returns, the reports, the errors, and a sub-step's bounds and update; `run` runs
//! the stages ([`crate::run_stages`], [`crate::run_stage`]) with the adaptive and single-jump
//! sub-steps, and hands error-controlled stages to `controlled`.

use std::fmt;

use serde::{Deserialize, Serialize};

use crate::accumulate::StageWear;
use crate::error::{WearError, positive, require};
use crate::joint::WornJoint;

/// How a stage's amplification is applied.
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum Extrapolation {
    /// Sub-steps, each changing any local clearance by at most `max_fraction` of its current
    /// value and the clearance's slope and curvature by at most `max_slope_change` and
    /// `max_curvature_change` (relative to the nominal clearance, per rad and rad²); fails
    /// with [`WearError::SubstepLimit`] after `max_substeps` sub-steps.
    Adaptive {
        /// Largest relative clearance change per sub-step, in `(0, 1]`.
        max_fraction: f64,
        /// Most sub-steps (K-cycle re-runs) per stage.
        max_substeps: usize,
        /// Largest relative change of the clearance's slope per sub-step, `|Δc'|/(c0 + |c'|)`
        /// (> 0; infinite: no bound); see [`WornJoint::shape_change_per_amplification`].
        #[serde(default = "unbounded")]
        max_slope_change: f64,
        /// Largest relative change of the clearance's curvature per sub-step,
        /// `|Δc''|/(c0 + |c''|)` (> 0; infinite: no bound).
        #[serde(default = "unbounded")]
        max_curvature_change: f64,
    },
    /// Error-controlled sub-steps (explicit trapezoidal predictor–corrector in cycles).
    ///
    /// A sub-step of amplification `a` from surfaces `h` with wear rate `w` (the wear of the K
    /// cycles simulated on `h`) predicts `h* = h + a·w`, simulates the K cycles on `h*` for the
    /// rate `w*`, and applies `a·(w + w*)/2`; `w*` is the next sub-step's rate, so a sub-step
    /// costs one K-cycle run. Its error estimate, per unit of the sub-step's wear (root sum of
    /// squares over a joint's cells, largest over the joints), is the trapezoid's local error
    /// `(a²/12)·‖w''‖/‖w̄‖` from the last three rates; the stage's first sub-step, with only two,
    /// takes the predictor's `‖w* − w‖/(2‖w̄‖)`, which bounds it. The sampling noise of the
    /// rates is taken out of the squared norms, as the runner's halves measure it
    /// ([`WearSample::halves`], pooled over the stage's runs). A sub-step is accepted when the
    /// estimate is at most `tolerance`, else simulated again with a smaller step; the next step
    /// is scaled by `0.9·(tolerance/estimate)^(1/order)`, between ×0.5 and ×2.
    ///
    /// With halves, a step is also kept small enough that the stage's wear carries sampling
    /// noise of about `tolerance` of it (root mean square over the cells; a sub-step's noise
    /// grows with the square of its amplification, so a stage of few large sub-steps averages
    /// fewer samples). The bounds on the clearance change apply to the predictor (the rate at
    /// the start; the applied mean rate can move a clearance slightly further): no predictor
    /// changes a local clearance by more than `max_fraction`, the first by at most
    /// `min_fraction`, and neither the estimate nor the noise bound cuts a sub-step below that
    /// bound (the noise bound alone asks for `ρ/(2·tolerance²)` sub-steps, 1e4 at a tolerance
    /// of 1e-3, which no stage finishes): noise the halves do
    /// not remove (all of it without halves) does not fall with the step and would otherwise
    /// shrink it without end; at the floor the sub-steps are [`Adaptive`](Self::Adaptive)'s at
    /// `min_fraction`. Fails with [`WearError::SubstepLimit`] after `max_runs` runs of the K
    /// cycles in a stage (accepted or not). `tests/controlled.rs` measures it on closed forms;
    /// docs/convergence.md on the LGRES, whose wear rate changes too fast with the worn shape
    /// for it to lengthen the sub-steps.
    Controlled {
        /// Largest estimated local error per unit of a sub-step's wear, and the stage's
        /// relative sampling noise, in `(0, 1]`.
        tolerance: f64,
        /// Relative clearance change of the first sub-step, and the smallest to which the error
        /// estimate cuts a sub-step, in `(0, 1]`.
        min_fraction: f64,
        /// Largest relative clearance change of any sub-step, in `[min_fraction, 1]`.
        max_fraction: f64,
        /// Most K-cycle runs per stage.
        max_runs: usize,
    },
    /// The paper's single jump; the stage report carries a warning when the jump changes a
    /// local clearance by more than `warn_fraction`.
    SingleJump {
        /// Relative clearance change above which the jump is reported, in `(0, 1]`.
        warn_fraction: f64,
    },
}

impl Extrapolation {
    /// Default bound on the relative clearance change per sub-step.
    pub const DEFAULT_FRACTION: f64 = 0.1;
    /// Default sub-step limit per stage.
    pub const DEFAULT_MAX_SUBSTEPS: usize = 200;

    /// Default bound on the relative change of the clearance's slope per sub-step.
    pub const DEFAULT_SLOPE_CHANGE: f64 = 0.25;
    /// Default bound on the relative change of the clearance's curvature per sub-step.
    pub const DEFAULT_CURVATURE_CHANGE: f64 = 0.25;

    /// Adaptive with the default fraction (10 %), shape bounds and sub-step limit.
    pub fn adaptive() -> Self {
        Self::Adaptive {
            max_fraction: Self::DEFAULT_FRACTION,
            max_substeps: Self::DEFAULT_MAX_SUBSTEPS,
            max_slope_change: Self::DEFAULT_SLOPE_CHANGE,
            max_curvature_change: Self::DEFAULT_CURVATURE_CHANGE,
        }
    }

    /// Default largest relative clearance change of a controlled sub-step.
    pub const DEFAULT_CONTROLLED_MAX_FRACTION: f64 = 0.5;

    /// Controlled sub-steps at `tolerance` (see [`Extrapolation::Controlled`]), the first
    /// bounded like [`adaptive`](Self::adaptive)'s, none changing a local clearance by more than
    /// half, at most [`DEFAULT_MAX_SUBSTEPS`](Self::DEFAULT_MAX_SUBSTEPS) runs a stage.
    pub fn controlled(tolerance: f64) -> Self {
        Self::Controlled {
            tolerance,
            min_fraction: Self::DEFAULT_FRACTION,
            max_fraction: Self::DEFAULT_CONTROLLED_MAX_FRACTION,
            max_runs: Self::DEFAULT_MAX_SUBSTEPS,
        }
    }

    /// The paper's single jump, warning above the default fraction (10 %).
    pub fn single_jump() -> Self {
        Self::SingleJump {
            warn_fraction: Self::DEFAULT_FRACTION,
        }
    }

    fn validate(&self) -> Result<(), WearError> {
        let (name, fraction) = match *self {
            Self::Adaptive {
                max_fraction,
                max_substeps,
                max_slope_change,
                max_curvature_change,
            } => {
                require(
                    "max_substeps",
                    max_substeps as f64,
                    max_substeps > 0,
                    ">= 1",
                )?;
                for (name, bound) in [
                    ("max_slope_change", max_slope_change),
                    ("max_curvature_change", max_curvature_change),
                ] {
                    require(name, bound, bound > 0.0, "> 0 (infinite: no bound)")?;
                }
                ("max_fraction", max_fraction)
            }
            Self::Controlled {
                tolerance,
                min_fraction,
                max_fraction,
                max_runs,
            } => {
                require("max_runs", max_runs as f64, max_runs > 0, ">= 1")?;
                require(
                    "tolerance",
                    tolerance,
                    tolerance > 0.0 && tolerance <= 1.0,
                    "in (0, 1]",
                )?;
                require(
                    "min_fraction",
                    min_fraction,
                    min_fraction > 0.0 && min_fraction <= 1.0,
                    "in (0, 1]",
                )?;
                require(
                    "max_fraction",
                    max_fraction,
                    max_fraction >= min_fraction,
                    ">= min_fraction",
                )?;
                ("max_fraction", max_fraction)
            }
            Self::SingleJump { warn_fraction } => ("warn_fraction", warn_fraction),
        };
        require(
            name,
            fraction,
            fraction > 0.0 && fraction <= 1.0,
            "in (0, 1]",
        )?;
        Ok(())
    }
}

fn unbounded() -> f64 {
    f64::INFINITY
}

/// A staged-wear plan: `stages` stages, each standing for `amplification ×` the simulated
/// cycles. Built with [`StagePlan::new`] or [`StagePlan::paper`] and the `with_*` methods (new
/// settings can be added without breaking callers, so it is no literal outside this crate).
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize)]
#[non_exhaustive]
pub struct StagePlan {
    /// Number of stages S.
    pub stages: usize,
    /// Amplification factor of a stage (paper: 20,000).
    pub amplification: f64,
    /// How the factor is applied.
    pub extrapolation: Extrapolation,
    /// With adaptive extrapolation: end a stage early, before the worn geometry leaves these
    /// limits (`None`: no limit). The rest of the stage's amplification is not applied and the
    /// report says how much was.
    #[serde(default)]
    pub geometry_limits: Option<GeometryLimits>,
    /// Standard deviation, in radians, of the Gaussian that smooths each run's wear before it
    /// is extrapolated ([`StageWear::smooth`]; 0: none). Applied by the caller that gathers the
    /// wear (the `clearance` crate's driver), so its halves check sees the smoothed wear too.
    #[serde(default)]
    pub smoothing: f64,
    /// How a sub-step's wear is extrapolated over its amplification (adaptive and single-jump
    /// stages; error-controlled stages are their own explicit trapezoidal scheme). Default:
    /// explicit.
    #[serde(default)]
    pub stepping: WearStepping,
    /// With adaptive extrapolation: the target relative sampling noise of each joint's peak
    /// depths at the end of a stage, in `(0, 1]` (`None`: every sub-step at the plan's
    /// `max_fraction`). The sub-steps then change a local clearance by as much as the target
    /// allows, between `max_fraction` and [`NOISE_MAX_FRACTION`] (see
    /// `crate::noise::noise_fraction`); it needs the runs' halves to measure the noise.
    #[serde(default)]
    pub noise_target: Option<f64>,
    /// Run to a clearance limit (`None`: the plan's `stages` stages): see [`ClearanceStop`].
    #[serde(default)]
    pub clearance_stop: Option<ClearanceStop>,
    /// Finer sub-steps while a joint's groove forms (`None`: none): see [`FormingBound`].
    #[serde(default)]
    pub forming: Option<FormingBound>,
}

/// A finer bound on the sub-steps while a joint's groove forms: as long as a wearing joint's
/// deeper worn peak (bearing or pin) is shallower than `depth` times its nominal clearance, a
/// sub-step changes that joint's local clearance by at most `max_fraction` of its current
/// value (where that is tighter than the stage's own bound).
///
/// Why: from concentric surfaces the contact goes from a line to a groove that fits the pin,
/// and the wear pattern's shape changes fastest while it does. On the built-in LGRES the
/// explicit step at the 2 % bound leaves joint B's peaks 2 µm shallow by the tenth of the life
/// in which they reach 15 % of the clearance, and they stay so; 0.25 % sub-steps up to 16 %
/// bring them within half their noise of a 20× finer reference, for 60 % more sub-steps
/// (docs/convergence.md, "Where the bias forms"). The forming sub-steps are bounded in number
/// whatever the joint's wear rate: about `depth / max_fraction` per joint.
///
/// With [`Extrapolation::Adaptive`] it bounds each forming joint's clearance change; with
/// [`Extrapolation::Controlled`] it lowers both the floor and the cap of the forming joints'
/// sub-steps; a single jump ignores it.
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize)]
#[non_exhaustive]
pub struct FormingBound {
    /// Largest relative clearance change per sub-step of a forming joint, in `(0, 1]`.
    pub max_fraction: f64,
    /// Depth, as a fraction of the joint's nominal clearance (> 0), below which its deeper
    /// worn peak counts as forming.
    pub depth: f64,
}

impl FormingBound {
    /// Sub-steps changing a forming joint's local clearance by at most `max_fraction`, while
    /// its deeper peak is below `depth × c0`.
    pub fn new(max_fraction: f64, depth: f64) -> Self {
        Self {
            max_fraction,
            depth,
        }
    }

    /// Whether `joint`'s groove is still forming.
    pub fn forming(&self, joint: &WornJoint) -> bool {
        let peak = joint.bearing().peak().depth.max(joint.pin().peak().depth);
        peak < self.depth * joint.nominal_clearance()
    }

    /// `fraction`, or this bound's where `joint` is forming and it is tighter.
    pub(crate) fn fraction(bound: Option<&Self>, joint: &WornJoint, fraction: f64) -> f64 {
        match bound {
            Some(b) if b.forming(joint) => fraction.min(b.max_fraction),
            _ => fraction,
        }
    }

    fn validate(&self) -> Result<(), WearError> {
        require(
            "forming.max_fraction",
            self.max_fraction,
            self.max_fraction > 0.0 && self.max_fraction <= 1.0,
            "in (0, 1]",
        )?;
        positive("forming.depth", self.depth)?;
        Ok(())
    }
}

/// Run the stages until every joint's largest local clearance
/// ([`WornJoint::max_local_clearance`]) reaches `limit`, or until `max_amplification` in all
/// has been applied, whichever comes first; the plan's stage count is then no bound.
///
/// A stage ends after the sub-step at which the last joint reaches the limit
/// ([`StageReport::reached_clearance_limit`]); the last stage is shortened to what is left of
/// `max_amplification` ([`StagePlan::next_stage`]). Sub-steps are sized as without the stop:
/// the surfaces of a run to a limit are those of the same plan with enough stages, up to where
/// it stops.
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize)]
#[non_exhaustive]
pub struct ClearanceStop {
    /// Largest local clearance every joint must reach (m).
    pub limit: f64,
    /// Most amplification applied over all stages (the caller's cycle budget over its K).
    pub max_amplification: f64,
}

impl ClearanceStop {
    /// Stop when every joint's largest local clearance reaches `limit` (m, > 0), or after
    /// `max_amplification` (> 0) in all.
    pub fn new(limit: f64, max_amplification: f64) -> Self {
        Self {
            limit,
            max_amplification,
        }
    }

    /// Whether every joint of `joints` has reached the limit.
    pub fn reached(&self, joints: &[WornJoint]) -> bool {
        joints.iter().all(|j| j.max_local_clearance() >= self.limit)
    }
}

/// The largest relative clearance change of a sub-step whose length a noise target sets: the
/// coarsest bound whose LGRES stage stays within its noise of a reference with 14× finer
/// sub-steps (7 %: A +2.7 %, B +1.0 %; at 10 % B's peaks are 5–6 % too deep, a bias ten
/// times their noise; docs/convergence.md).
pub const NOISE_MAX_FRACTION: f64 = 0.07;

/// How a sub-step extrapolates the wear of its simulated cycles over its amplification `a`.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "kebab-case")]
pub enum WearStepping {
    /// Forward: the surfaces take `a·w`, the wear `w` of the cycles simulated on them. A
    /// pattern that relaxes at `λ` per unit amplification is multiplied by `1 − aλ`: unstable
    /// past `aλ = 2` unless something else (the runs' smoothing) removes it.
    /// [`JointSubstep::wear_stiffness`] reports `aλ`.
    #[default]
    Explicit,
    /// Linearly implicit: the surfaces take `a·w̃`, `(I − aJ) w̃ = w`, with the rate's
    /// Jacobian in the depths gathered from the same cycles' contact zones
    /// ([`StageWear::implicit`]): backward Euler for the shape of the wear pattern within the
    /// zones, which relaxes at `λ`; what is a translation over every zone that saw it passes
    /// unchanged. The same as [`Explicit`](Self::Explicit) where the contact reports no zones
    /// (the line-of-centres contact).
    LinearlyImplicit,
}

/// Limits on the shape of the worn clearance `c = R_i − R_j` beyond which a line-of-centres
/// contact model no longer describes the joint. They bound, from the surfaces alone, the
/// measures a run checks at its contacts: the slope `|c'|/|e| ≤ (max|R_i'| + max|R_j'|)/c0`
/// and the conformity `(R_j'' − R_i'')/c ≤ (max|R_i''| + max|R_j''|)/c0`.
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize)]
#[non_exhaustive]
pub struct GeometryLimits {
    /// Largest `(max|R_i'| + max|R_j'|)/c0` (1/rad).
    pub slope: f64,
    /// Largest `(max|R_i''| + max|R_j''|)/c0` (1/rad²).
    pub curvature: f64,
}

impl GeometryLimits {
    /// Limits on `(max|R_i'| + max|R_j'|)/c0` (1/rad) and `(max|R_i''| + max|R_j''|)/c0`
    /// (1/rad²); infinite: no limit.
    pub fn new(slope: f64, curvature: f64) -> Self {
        Self { slope, curvature }
    }

    /// The largest amplification of `wear` that keeps `joint` within the limits (0 when it is
    /// already at them; infinite when the wear does not change the shape).
    fn allowed(&self, joint: &WornJoint, wear: &StageWear) -> Result<f64, WearError> {
        let [now, rate] = joint.shape_bounds(wear)?;
        let (slope, curvature, d_slope, d_curvature) =
            (now.slope, now.curvature, rate.slope, rate.curvature);
        let room = |limit: f64, now: f64, rate: f64| {
            if rate > 0.0 {
                ((limit - now) / rate).max(0.0)
            } else {
                f64::INFINITY
            }
        };
        Ok(room(self.slope, slope, d_slope).min(room(self.curvature, curvature, d_curvature)))
    }
}

impl StagePlan {
    /// The paper's amplification of a stage: 100 simulated cycles stand for 2 million.
    pub const PAPER_AMPLIFICATION: f64 = 20_000.0;

    /// `stages` stages, each amplifying the simulated cycles by `amplification` (> 0) the way
    /// `extrapolation` says, with no geometry limits.
    pub fn new(stages: usize, amplification: f64, extrapolation: Extrapolation) -> Self {
        Self {
            stages,
            amplification,
            extrapolation,
            geometry_limits: None,
            smoothing: 0.0,
            stepping: WearStepping::default(),
            noise_target: None,
            clearance_stop: None,
            forming: None,
        }
    }

    /// The same plan with finer sub-steps while a joint's groove forms (see [`FormingBound`];
    /// `None`: none).
    pub fn with_forming_bound(mut self, forming: Option<FormingBound>) -> Self {
        self.forming = forming;
        self
    }

    /// The same plan running to a clearance limit (see [`ClearanceStop`]; `None`: `stages`
    /// stages).
    pub fn with_clearance_stop(mut self, stop: Option<ClearanceStop>) -> Self {
        self.clearance_stop = stop;
        self
    }

    /// The plan of the stage that follows the stages `done` (in order), or `None` when the
    /// run is over: after `stages` stages; with a [`ClearanceStop`], once a stage reached the
    /// limit or ended at the geometry limits (the next would apply nothing), or once the
    /// stop's `max_amplification` is spent, the last stage being shortened to what is left
    /// of it.
    pub fn next_stage(&self, done: &[StageReport]) -> Option<StagePlan> {
        let Some(stop) = self.clearance_stop else {
            return (done.len() < self.stages).then_some(*self);
        };
        if done
            .last()
            .is_some_and(|r| r.reached_clearance_limit || r.ended_at_limits.is_some())
        {
            return None;
        }
        let applied: f64 = done.iter().map(StageReport::applied).sum();
        let left = stop.max_amplification - applied;
        // A rounding-sized remainder is no stage.
        (left > 1e-9 * stop.max_amplification)
            .then(|| self.with_amplification(self.amplification.min(left)))
    }

    /// The same plan sizing adaptive sub-steps for a relative noise `target` of the stage's
    /// peak depths (see [`StagePlan::noise_target`]; `None`: fixed bounds).
    pub fn with_noise_target(mut self, target: Option<f64>) -> Self {
        self.noise_target = target;
        self
    }

    /// The same plan extrapolating each sub-step's wear the way `stepping` says.
    pub fn with_stepping(mut self, stepping: WearStepping) -> Self {
        self.stepping = stepping;
        self
    }

    /// The same plan smoothing each run's wear over `sigma` radians (see
    /// [`StagePlan::smoothing`]).
    pub fn with_smoothing(mut self, sigma: f64) -> Self {
        self.smoothing = sigma;
        self
    }

    /// `stages` stages of the paper's factor, extrapolated adaptively.
    pub fn paper(stages: usize) -> Self {
        Self::new(stages, Self::PAPER_AMPLIFICATION, Extrapolation::adaptive())
    }

    /// The same plan with amplification factor `amplification` per stage.
    pub fn with_amplification(mut self, amplification: f64) -> Self {
        self.amplification = amplification;
        self
    }

    /// The same plan applying the factor as `extrapolation` says.
    pub fn with_extrapolation(mut self, extrapolation: Extrapolation) -> Self {
        self.extrapolation = extrapolation;
        self
    }

    /// The same plan ending stages early at `limits` (`None`: no limit; adaptive only).
    pub fn with_geometry_limits(mut self, limits: Option<GeometryLimits>) -> Self {
        self.geometry_limits = limits;
        self
    }

    /// Checks amplification (> 0, finite) and the extrapolation's fraction and limit.
    pub fn validate(&self) -> Result<(), WearError> {
        positive("amplification", self.amplification)?;
        require(
            "smoothing",
            self.smoothing,
            self.smoothing >= 0.0 && self.smoothing.is_finite(),
            ">= 0 rad",
        )?;
        if let Some(stop) = self.clearance_stop {
            positive("clearance_stop.limit", stop.limit)?;
            positive("clearance_stop.max_amplification", stop.max_amplification)?;
        }
        if let Some(forming) = &self.forming {
            forming.validate()?;
        }
        if let Some(target) = self.noise_target {
            require(
                "noise_target",
                target,
                target > 0.0 && target <= 1.0,
                "in (0, 1]",
            )?;
        }
        self.extrapolation.validate()
    }
}

/// What the runner is asked to simulate (for the caller's logging and outputs).
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize)]
pub struct RunContext {
    /// Stage index, from 0.
    pub stage: usize,
    /// Run index within the stage, from 0: with adaptive extrapolation and a single jump, the
    /// sub-step's; with controlled extrapolation run 0 measures the first rate and each later
    /// run a sub-step's prediction (accepted or not).
    pub substep: usize,
    /// The fraction of the stage's amplification applied before this run, in `[0, 1)`: with
    /// `substep`, about how many runs the stage will take (for progress).
    #[serde(default)]
    pub applied: f64,
}

/// One joint after a sub-step.
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize)]
pub struct JointSubstep {
    /// Largest bearing cell depth `h` after the update (m); the radius grew by `h/2`.
    pub max_bearing_depth: f64,
    /// Largest pin cell depth `h` after the update (m); the radius shrank by `h/2`.
    pub max_pin_depth: f64,
    /// Bound on the relative local-clearance change of this update.
    pub change_fraction: f64,
    /// Bound on the relative change of the clearance slope, `|Δc'|/(c0 + |c'|)`, of this
    /// update.
    pub slope_change: f64,
    /// Bound on the relative change of the clearance curvature, `|Δc''|/(c0 + |c''|)`, of
    /// this update.
    pub curvature_change: f64,
    /// Material removed from both surfaces so far, after the update (m³;
    /// [`WornJoint::worn_volume`]).
    pub worn_volume: f64,
    /// Largest local clearance after the update (m): `c0 + (max h_i + max h_j)/2`, the
    /// clearance where the deepest dents of bearing and pin face each other
    /// ([`WornJoint::max_local_clearance`]).
    pub max_local_clearance: f64,
    /// How stiff this update was: `a λ` (amplification times the relaxation of each cell,
    /// [`StageWear::bearing_relaxation`]) averaged over the cells with their wear as
    /// weights, the larger of the two surfaces. A pattern of cells relaxing at `λ` is
    /// multiplied by `1 − aλ` by an explicit update: above 2 such a pattern would grow, and
    /// only the smoothing of the runs' wear keeps it out. 0 where the contact reports no layer
    /// stiffness (the line-of-centres contact).
    #[serde(default)]
    pub wear_stiffness: f64,
}

/// One amplification sub-step (a single jump is one sub-step).
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct SubstepReport {
    /// Stage and sub-step index.
    pub context: RunContext,
    /// Amplification applied in this sub-step.
    pub amplification: f64,
    /// Largest cell depth on any surface after the update (m).
    pub max_depth: f64,
    /// Largest clearance-change bound over the joints.
    pub max_change_fraction: f64,
    /// Per joint, in the order given.
    pub joints: Vec<JointSubstep>,
    /// With controlled extrapolation, the sub-step's error estimate (per unit of its wear,
    /// noise removed; see [`Extrapolation::Controlled`]).
    #[serde(default)]
    pub error_estimate: Option<f64>,
}

/// A single jump that changed a local clearance by more than the plan allows.
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize)]
pub struct ExtrapolationWarning {
    /// Stage index.
    pub stage: usize,
    /// Amplification of the jump.
    pub amplification: f64,
    /// Bound on the relative clearance change the jump caused.
    pub change_fraction: f64,
    /// The plan's `warn_fraction`.
    pub limit: f64,
}

impl fmt::Display for ExtrapolationWarning {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        write!(
            f,
            "stage {}: single wear jump ×{} changed a local clearance by up to {:.1} % \
             (limit {:.1} %); the linear extrapolation is not credible, use adaptive sub-steps",
            // Counted from 1 for people, like the stage numbers of the outputs.
            self.stage + 1,
            self.amplification,
            100.0 * self.change_fraction,
            100.0 * self.limit
        )
    }
}

/// The outcome of one stage.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct StageReport {
    /// Stage index.
    pub stage: usize,
    /// Sub-steps in order; their amplifications sum to the plan's factor.
    pub substeps: Vec<SubstepReport>,
    /// Set when a single jump exceeded its `warn_fraction`.
    pub warning: Option<ExtrapolationWarning>,
    /// Set when the stage ended early at the plan's geometry limits: the amplification that
    /// was applied (less than the plan's).
    pub ended_at_limits: Option<f64>,
    /// Per run of the K cycles, in order ([`RunContext::substep`]): the amplification its wear
    /// received in all. Adaptive: its sub-step's (0 for a run the geometry limits left unused).
    /// Controlled: half of each sub-step it bounds, 0 for a rejected prediction. Sums to the
    /// stage's applied amplification.
    #[serde(default)]
    pub run_weights: Vec<f64>,
    /// Set when the plan's [`ClearanceStop`] ended the stage: every joint reached the limit
    /// after its last sub-step.
    #[serde(default)]
    pub reached_clearance_limit: bool,
}

impl StageReport {
    /// An empty report of stage `stage`, before its first sub-step.
    pub(crate) fn start(stage: usize) -> Self {
        Self {
            stage,
            substeps: Vec::new(),
            warning: None,
            ended_at_limits: None,
            run_weights: Vec::new(),
            reached_clearance_limit: false,
        }
    }

    /// The amplification the stage applied: its sub-steps' sum.
    pub fn applied(&self) -> f64 {
        self.substeps.iter().map(|s| s.amplification).sum()
    }

    /// Records `substep`; returns whether the plan's clearance stop (if any) ends the stage
    /// now that `joints` took it.
    pub(crate) fn push_substep(
        &mut self,
        substep: SubstepReport,
        plan: &StagePlan,
        joints: &[WornJoint],
    ) -> bool {
        self.substeps.push(substep);
        self.reached_clearance_limit = plan.clearance_stop.is_some_and(|s| s.reached(joints));
        self.reached_clearance_limit
    }

    /// Runs whose prediction the controlled extrapolation rejected (0 otherwise).
    pub fn rejected_runs(&self) -> usize {
        // Run 0 is the first rate, never a prediction.
        self.run_weights
            .iter()
            .skip(1)
            .filter(|w| **w == 0.0)
            .count()
    }
}

/// What a runner returns for one run: each joint's wear over the simulated cycles and,
/// optionally, each joint's wear from two halves of those cycles that sample the motion
/// independently (summing to the whole; e.g. the first and the second half of an ensemble's
/// trajectories). The halves measure the sampling noise of the wear, which the controlled
/// extrapolation removes from its error estimate; without them the noise counts as error
/// (smaller sub-steps).
#[derive(Clone, Debug, PartialEq)]
pub struct WearSample {
    /// Per joint, in the order given to the runner.
    pub wear: Vec<StageWear>,
    /// Per joint, the two halves, or `None`.
    pub halves: Option<Vec<[StageWear; 2]>>,
}

impl From<Vec<StageWear>> for WearSample {
    fn from(wear: Vec<StageWear>) -> Self {
        Self { wear, halves: None }
    }
}

/// A staging failure: invalid plan or wear data, or the caller's runner failed.
#[derive(Debug, thiserror::Error)]
pub enum StagingError<E> {
    /// Wear-side error.
    #[error(transparent)]
    Wear(#[from] WearError),
    /// The caller's K-cycle simulation failed.
    #[error("stage runner failed: {0}")]
    Runner(E),
}

/// One run of the runner, its joint count checked.
pub(crate) fn sample<E, W, F>(
    runner: &mut F,
    context: RunContext,
    joints: &[WornJoint],
) -> Result<WearSample, StagingError<E>>
where
    W: Into<WearSample>,
    F: FnMut(RunContext, &[WornJoint]) -> Result<W, E>,
{
    let sample: WearSample = runner(context, joints)
        .map_err(StagingError::Runner)?
        .into();
    let halves = sample.halves.as_ref().map_or(joints.len(), Vec::len);
    for found in [sample.wear.len(), halves] {
        if found != joints.len() {
            return Err(WearError::JointCount {
                expected: joints.len(),
                found,
            }
            .into());
        }
    }
    Ok(sample)
}

/// Each joint's relative local-clearance change per unit of amplification of its `wear`
/// ([`WornJoint::clearance_change_per_amplification`]).
pub(crate) fn clearance_changes_per_amplification(
    joints: &[WornJoint],
    wear: &[StageWear],
) -> Result<Vec<f64>, WearError> {
    joints
        .iter()
        .zip(wear)
        .map(|(joint, w)| joint.clearance_change_per_amplification(w))
        .collect()
}

/// The largest amplification that changes every joint's local clearance by at most `fraction`
/// of its current value, or the forming bound's fraction for a joint whose groove forms, given
/// each joint's change per unit (`per_unit`, from [`clearance_changes_per_amplification`];
/// infinite when no clearance changes).
pub(crate) fn clearance_bounded_amplification(
    joints: &[WornJoint],
    per_unit: &[f64],
    fraction: f64,
    forming: Option<&FormingBound>,
) -> f64 {
    joints
        .iter()
        .zip(per_unit)
        .filter(|(_, rate)| **rate > 0.0)
        .map(|(joint, rate)| FormingBound::fraction(forming, joint, fraction) / rate)
        .fold(f64::INFINITY, f64::min)
}

/// The largest amplification of `wear` the plan's geometry limits allow (infinite: none).
pub(crate) fn limited_amplification(
    plan: &StagePlan,
    joints: &[WornJoint],
    wear: &[StageWear],
) -> Result<f64, WearError> {
    let mut limited = f64::INFINITY;
    if let Some(limits) = plan.geometry_limits {
        for (joint, w) in joints.iter().zip(wear) {
            limited = limited.min(limits.allowed(joint, w)?);
        }
    }
    Ok(limited)
}

/// Checks every joint, then updates them all: no joint moves unless all can.
pub(crate) fn apply_all(
    joints: &mut [WornJoint],
    wear: &[StageWear],
    amplification: f64,
    context: RunContext,
) -> Result<SubstepReport, WearError> {
    for (joint, w) in joints.iter().zip(wear) {
        joint.check_apply(w, amplification)?;
    }
    let mut report = SubstepReport {
        context,
        amplification,
        max_depth: 0.0,
        max_change_fraction: 0.0,
        joints: Vec::with_capacity(joints.len()),
        error_estimate: None,
    };
    for (joint, w) in joints.iter_mut().zip(wear) {
        let (slope, curvature) = joint.shape_change_per_amplification(w)?;
        let wear_stiffness = amplification * w.relaxation_weighted();
        let change_fraction = joint.apply(w, amplification)?;
        let step = JointSubstep {
            max_bearing_depth: joint.bearing().peak().depth,
            max_pin_depth: joint.pin().peak().depth,
            change_fraction,
            slope_change: amplification * slope,
            curvature_change: amplification * curvature,
            worn_volume: joint.worn_volume(),
            max_local_clearance: joint.max_local_clearance(),
            wear_stiffness,
        };
        report.max_depth = report
            .max_depth
            .max(step.max_bearing_depth)
            .max(step.max_pin_depth);
        report.max_change_fraction = report.max_change_fraction.max(change_fraction);
        report.joints.push(step);
    }
    Ok(report)
}
