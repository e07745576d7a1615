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

    /// The slope limit of the clearance joint's validity checks, 0.3. The curvature is not
    /// limited here: the wear of one or a few chaotic cycles carries cell-scale curvature that
    /// passes the conformity limit at sub-micrometre depths, long before a pin whose contact
    /// spans tens of cells could feel it; conformity is measured at the contacts instead.
    pub const CONTACT_MODEL: Self = Self {
        slope: 0.3,
        curvature: f64::INFINITY,
    };

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
        }
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
        self.extrapolation.validate()
    }
}

/// What the runner is asked to simulate (for the caller's logging and outputs).
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize, Deserialize)]
pub struct RunContext {
    /// Stage index, from 0.
    pub stage: usize,
    /// Sub-step index within the stage, from 0.
    pub substep: usize,
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

/// Runs all stages of `plan` on `joints` (all joints of the mechanism that wear, updated
/// together so one sub-step bound covers them all).
///
/// `runner(context, joints)` must simulate the K cycles on the joints as given (frozen) and
/// return one [`StageWear`] per joint, same order. On error the joints hold the surfaces of
/// the sub-steps completed so far.
pub fn run_stages<E, F>(
    joints: &mut [WornJoint],
    plan: &StagePlan,
    mut runner: F,
) -> Result<Vec<StageReport>, StagingError<E>>
where
    F: FnMut(RunContext, &[WornJoint]) -> Result<Vec<StageWear>, E>,
{
    plan.validate()?;
    (0..plan.stages)
        .map(|stage| run_stage(joints, stage, plan, &mut runner))
        .collect()
}

/// Runs stage `stage` of `plan` (see [`run_stages`]).
pub fn run_stage<E, F>(
    joints: &mut [WornJoint],
    stage: usize,
    plan: &StagePlan,
    runner: &mut F,
) -> Result<StageReport, StagingError<E>>
where
    F: FnMut(RunContext, &[WornJoint]) -> Result<Vec<StageWear>, E>,
{
    plan.validate()?;
    let mut report = StageReport {
        stage,
        substeps: Vec::new(),
        warning: None,
        ended_at_limits: None,
    };
    let mut used = 0.0;
    loop {
        let context = RunContext {
            stage,
            substep: report.substeps.len(),
        };
        let wear = runner(context, joints).map_err(StagingError::Runner)?;
        if wear.len() != joints.len() {
            return Err(WearError::JointCount {
                expected: joints.len(),
                found: wear.len(),
            }
            .into());
        }
        let mut per_unit: f64 = 0.0;
        let (mut slope_per_unit, mut curvature_per_unit): (f64, f64) = (0.0, 0.0);
        for (joint, w) in joints.iter().zip(&wear) {
            per_unit = per_unit.max(joint.clearance_change_per_amplification(w)?);
            let (slope, curvature) = joint.shape_change_per_amplification(w)?;
            slope_per_unit = slope_per_unit.max(slope);
            curvature_per_unit = curvature_per_unit.max(curvature);
        }
        let remaining = plan.amplification - used;
        let mut at_limits = false;
        let amplification = match plan.extrapolation {
            Extrapolation::Adaptive {
                max_fraction,
                max_slope_change,
                max_curvature_change,
                ..
            } => {
                // The largest amplification every bound allows; the small slack avoids a
                // needless re-run for a rounding-sized remainder.
                let allowed = [
                    (per_unit, max_fraction),
                    (slope_per_unit, max_slope_change),
                    (curvature_per_unit, max_curvature_change),
                ]
                .iter()
                .filter(|(rate, _)| *rate > 0.0)
                .map(|(rate, bound)| bound / rate)
                .fold(f64::INFINITY, f64::min);
                let mut limited = f64::INFINITY;
                if let Some(limits) = plan.geometry_limits {
                    for (joint, w) in joints.iter().zip(&wear) {
                        limited = limited.min(limits.allowed(joint, w)?);
                    }
                }
                if limited < allowed.min(remaining) {
                    at_limits = true;
                    limited
                } else if allowed * (1.0 + 1e-9) < remaining {
                    allowed
                } else {
                    remaining
                }
            }
            Extrapolation::SingleJump { .. } => remaining,
        };
        if at_limits && amplification <= 0.0 {
            report.ended_at_limits = Some(used);
            return Ok(report);
        }
        let substep = apply_all(joints, &wear, amplification, context)?;
        used += amplification;
        if let Extrapolation::SingleJump { warn_fraction } = plan.extrapolation
            && substep.max_change_fraction > warn_fraction
        {
            report.warning = Some(ExtrapolationWarning {
                stage,
                amplification,
                change_fraction: substep.max_change_fraction,
                limit: warn_fraction,
            });
        }
        report.substeps.push(substep);
        if at_limits {
            report.ended_at_limits = Some(used);
            return Ok(report);
        }
        if amplification == remaining {
            return Ok(report);
        }
        if let Extrapolation::Adaptive { max_substeps, .. } = plan.extrapolation
            && report.substeps.len() >= max_substeps
        {
            return Err(WearError::SubstepLimit {
                stage,
                limit: max_substeps,
                remaining: plan.amplification - used,
            }
            .into());
        }
    }
}

/// Checks every joint, then updates them all: no joint moves unless all can.
fn apply_all(
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
    };
    for (joint, w) in joints.iter_mut().zip(wear) {
        let (slope, curvature) = joint.shape_change_per_amplification(w)?;
        let change_fraction = joint.apply(w, amplification)?;
        let step = JointSubstep {
            max_bearing_depth: joint.bearing().peak().depth,
            max_pin_depth: joint.pin().peak().depth,
            change_fraction,
            slope_change: amplification * slope,
            curvature_change: amplification * curvature,
            worn_volume: joint.worn_volume(),
            max_local_clearance: joint.max_local_clearance(),
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
