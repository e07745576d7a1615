//! The scene's data types: what a TOML scene file deserializes into, with the defaults of
//! every optional key.

use std::f64::consts::TAU;

use serde::{Deserialize, Serialize};

use super::defaults::yes;
use super::{ContactSpec, RunSettings};

use super::{
    Coordinate, Formulation, FrictionLawParams, Integrator, MaterialParams, NormalLawParams,
    SlidingVelocity,
};

/// Reserved body name for the fixed frame.
pub const GROUND: &str = "ground";

/// An angle stored in radians, written in the file in degrees.
#[derive(Debug, Clone, Copy, PartialEq, Default, Serialize, Deserialize)]
#[serde(from = "f64", into = "f64")]
pub struct Angle(f64);

impl Angle {
    /// From radians.
    pub fn from_rad(rad: f64) -> Self {
        Self(rad)
    }
    /// From degrees.
    pub fn from_deg(deg: f64) -> Self {
        Self(deg.to_radians())
    }
    /// Value in radians.
    pub fn rad(self) -> f64 {
        self.0
    }
    /// Value in degrees.
    pub fn deg(self) -> f64 {
        self.0.to_degrees()
    }
}

impl From<f64> for Angle {
    fn from(deg: f64) -> Self {
        Self::from_deg(deg)
    }
}

impl From<Angle> for f64 {
    fn from(a: Angle) -> f64 {
        a.deg()
    }
}

/// A whole mechanism plus the settings of how to simulate it.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct Scene {
    /// What this scene is, where its numbers come from (free text).
    pub description: String,
    /// Which inertia convention the bodies use, e.g. "transverse m L²/12" (free text, required so
    /// every scene says it).
    pub inertia_convention: String,
    /// Gravitational acceleration `[gx, gy]`, m/s².
    #[serde(deserialize_with = "exactly_two")]
    pub gravity: [f64; 2],
    /// Rigid bodies; names must be unique and not `ground`.
    pub bodies: Vec<Body>,
    /// Ideal revolute joints (2 constraint equations each).
    #[serde(default, skip_serializing_if = "Vec::is_empty")]
    pub revolute_joints: Vec<RevoluteJoint>,
    /// Prismatic joints (1 equation, 2 with locked rotation).
    #[serde(default, skip_serializing_if = "Vec::is_empty")]
    pub prismatic_joints: Vec<PrismaticJoint>,
    /// Driving constraints (1 equation each).
    #[serde(default, skip_serializing_if = "Vec::is_empty")]
    pub drivers: Vec<Driver>,
    /// Revolute joints with clearance: contact force elements, no constraint equations.
    #[serde(default, skip_serializing_if = "Vec::is_empty")]
    pub clearance_joints: Vec<ClearanceJointSpec>,
    /// Integrator settings.
    #[serde(default)]
    pub solver: Solver,
    /// How long to run and how to stage wear.
    #[serde(default)]
    pub run: RunSettings,
}

/// A rigid body; its frame has its origin at the centroid.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct Body {
    /// Unique name, referenced by joints.
    pub name: String,
    /// Mass, kg.
    pub mass: f64,
    /// Moment of inertia about the centroid, normal to the plane, kg·m².
    pub inertia: f64,
    /// Initial centroid x, m.
    pub x: f64,
    /// Initial centroid y, m.
    pub y: f64,
    /// Initial angle of the body frame, **degrees** in the file (radians in memory).
    #[serde(rename = "theta_deg")]
    pub theta: Angle,
    /// Initial centroid velocity `[vx, vy]`, m/s (an estimate; the solver makes it consistent).
    #[serde(
        default,
        skip_serializing_if = "is_zero2",
        deserialize_with = "exactly_two"
    )]
    pub velocity: [f64; 2],
    /// Initial angular velocity, rad/s.
    #[serde(default, skip_serializing_if = "is_zero")]
    pub omega: f64,
}

/// A 2-vector `[x, y]`: exactly two numbers. (The TOML deserializer would otherwise drop extra
/// elements of a fixed-size array read from text, but reject them from a merged `extends`.)
fn exactly_two<'de, D: serde::Deserializer<'de>>(d: D) -> Result<[f64; 2], D::Error> {
    let v = Vec::<f64>::deserialize(d)?;
    <[f64; 2]>::try_from(v.as_slice()).map_err(|_| {
        serde::de::Error::custom(format!(
            "expected exactly two numbers [x, y], got {} ({v:?})",
            v.len()
        ))
    })
}

fn is_zero(v: &f64) -> bool {
    *v == 0.0
}
fn is_zero2(v: &[f64; 2]) -> bool {
    v.iter().all(|c| *c == 0.0)
}

/// An ideal pin joint: `body`'s point coincides with `other`'s point.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct RevoluteJoint {
    /// Unique joint name (among all joints).
    pub name: String,
    /// First body.
    pub body: String,
    /// Joint point in `body`'s frame, m.
    #[serde(deserialize_with = "exactly_two")]
    pub point: [f64; 2],
    /// Second body, or `ground`.
    pub other: String,
    /// Joint point in `other`'s frame (global coordinates when `other` is ground), m.
    #[serde(deserialize_with = "exactly_two")]
    pub other_point: [f64; 2],
}

/// `body`'s point slides along a line fixed in `other` (or ground).
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct PrismaticJoint {
    /// Unique joint name.
    pub name: String,
    /// Sliding body.
    pub body: String,
    /// Point of `body` that stays on the line, in `body`'s frame, m.
    #[serde(deserialize_with = "exactly_two")]
    pub point: [f64; 2],
    /// Body carrying the guide line, or `ground`.
    pub other: String,
    /// A point of the line in `other`'s frame (global when ground), m.
    #[serde(deserialize_with = "exactly_two")]
    pub other_point: [f64; 2],
    /// Direction of the line in `other`'s frame (any non-zero length), dimensionless.
    #[serde(deserialize_with = "exactly_two")]
    pub direction: [f64; 2],
    /// Keep the angle between `body` and `other` at its initial value (adds one equation).
    #[serde(default = "yes")]
    pub lock_rotation: bool,
}

/// A prescribed coordinate.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct Driver {
    /// Unique driver name.
    pub name: String,
    /// What is driven.
    pub target: DriverTarget,
    /// How it moves: values in m for x/y, rad for angles.
    pub law: TimeLaw,
}

/// The driven quantity.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(tag = "kind", rename_all = "kebab-case", deny_unknown_fields)]
pub enum DriverTarget {
    /// A coordinate of a body's centroid pose.
    BodyCoordinate {
        /// Body name.
        body: String,
        /// `x`, `y` or `theta`.
        coordinate: Coordinate,
    },
    /// The relative angle `θ_other − θ_body` of a revolute joint (`θ_other` = 0 for ground).
    JointAngle {
        /// Revolute joint name.
        joint: String,
    },
}

/// A time law `f(t)`; its unit is the driven quantity's (m or rad).
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(tag = "kind", rename_all = "kebab-case", deny_unknown_fields)]
pub enum TimeLaw {
    /// `f = value`.
    Constant {
        /// m or rad.
        value: f64,
    },
    /// `f = value + rate·t`.
    Ramp {
        /// Value at t = 0, m or rad.
        value: f64,
        /// m/s or rad/s.
        rate: f64,
    },
    /// `f = offset + amplitude·(1 − cos ωt)`; give exactly one of `rpm`, `omega`.
    Harmonic {
        /// m or rad.
        offset: f64,
        /// m or rad.
        amplitude: f64,
        /// Cycles per minute (ω = 2π·rpm/60).
        #[serde(default, skip_serializing_if = "Option::is_none")]
        rpm: Option<f64>,
        /// Angular frequency, rad/s.
        #[serde(default, skip_serializing_if = "Option::is_none")]
        omega: Option<f64>,
    },
}

impl TimeLaw {
    /// Angular frequency of a harmonic law, rad/s (`None` for other laws or if unset).
    pub fn omega(&self) -> Option<f64> {
        match self {
            TimeLaw::Harmonic { rpm, omega, .. } => omega.or(rpm.map(|r| TAU * r / 60.0)),
            _ => None,
        }
    }

    /// Value, first and second time derivative at `t` (s).
    pub fn eval(&self, t: f64) -> [f64; 3] {
        match self {
            TimeLaw::Constant { value } => [*value, 0.0, 0.0],
            TimeLaw::Ramp { value, rate } => [value + rate * t, *rate, 0.0],
            TimeLaw::Harmonic {
                offset, amplitude, ..
            } => {
                let w = self.omega().unwrap_or(0.0);
                let (s, c) = (w * t).sin_cos();
                [
                    offset + amplitude * (1.0 - c),
                    amplitude * w * s,
                    amplitude * w * w * c,
                ]
            }
        }
    }

    /// Duration of one drive cycle, s: 2π/ω for a harmonic law, one turn for a ramp.
    pub fn period(&self) -> Option<f64> {
        match self {
            TimeLaw::Harmonic { .. } => self.omega().map(|w| TAU / w),
            TimeLaw::Ramp { rate, .. } if *rate != 0.0 => Some(TAU / rate.abs()),
            _ => None,
        }
    }
}

/// A revolute joint with radial clearance: a pin (journal) inside a bearing (hole).
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct ClearanceJointSpec {
    /// Unique joint name.
    pub name: String,
    /// Body with the hole, or `ground`.
    pub bearing_body: String,
    /// Bearing centre in `bearing_body`'s frame, m.
    #[serde(deserialize_with = "exactly_two")]
    pub bearing_point: [f64; 2],
    /// Bearing (hole) radius `R_i`, m.
    pub bearing_radius: f64,
    /// Body with the journal, or `ground`.
    pub pin_body: String,
    /// Pin centre in `pin_body`'s frame, m.
    #[serde(deserialize_with = "exactly_two")]
    pub pin_point: [f64; 2],
    /// Radial clearance `c = R_i − R_j`, m; the pin radius is `bearing_radius − clearance`.
    pub clearance: f64,
    /// Bearing material.
    pub bearing_material: MaterialParams,
    /// Pin material.
    pub pin_material: MaterialParams,
    /// Normal contact force law.
    pub normal_law: NormalLawParams,
    /// Tangential (friction) law.
    pub friction: FrictionLawParams,
    /// Archard wear of both surfaces; absent: no wear.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub wear: Option<WearSpec>,
    /// Which sliding velocity drives friction and wear (default: the material points', the
    /// physical one; `paper` is the paper's `δ φ̇`, see docs/model.md §9).
    #[serde(default, skip_serializing_if = "Sliding::is_default")]
    pub sliding: Sliding,
    /// The contact model (default: the elastic foundation over the true outlines, its layer
    /// calibrated to the Hertz stiffness; `{ model = "line-of-centres" }` for the one-point
    /// model, docs/model.md §10).
    #[serde(default, skip_serializing_if = "ContactSpec::is_default")]
    pub contact: ContactSpec,
    /// Treat as an ideal revolute joint (2 constraint equations, centres coincide) — the
    /// reference mechanism of the studies. Contact and wear settings are then unused.
    #[serde(default, skip_serializing_if = "std::ops::Not::not")]
    pub ideal: bool,
}

impl ClearanceJointSpec {
    /// Pin (journal) radius `R_j = R_i − c`, m.
    pub fn pin_radius(&self) -> f64 {
        self.bearing_radius - self.clearance
    }
}

/// The sliding velocity each of friction and wear uses, e.g.
/// `sliding = { friction = "material", wear = "paper" }`.
#[derive(Debug, Clone, Copy, Default, PartialEq, Eq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct Sliding {
    /// For the friction force.
    #[serde(default)]
    pub friction: SlidingVelocity,
    /// For Archard wear.
    #[serde(default)]
    pub wear: SlidingVelocity,
}

impl Sliding {
    fn is_default(&self) -> bool {
        *self == Self::default()
    }
}

/// Archard wear of a clearance joint.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct WearSpec {
    /// Dimensional wear coefficient `K_d = K_w/H`, m²/N (wear volume per sliding distance per
    /// normal force).
    pub k_d: f64,
    /// Hardness `H` of the softer surface, Pa; only used to report `K_w = K_d·H`.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub hardness: Option<f64>,
    /// Hinge (contact) width `w`, m.
    pub width: f64,
    /// Cells per surface over 360°.
    #[serde(default = "wear_cells")]
    pub cells: usize,
    /// Scatter of the wear coefficient between nominally equal joints: the standard deviation
    /// of `ln k_d` (lognormal, `k_d` its median; 0: none, the default). Wear coefficients of
    /// equal parts scatter by tens of percent; with `run.clearance_limit` the summary gives
    /// this joint's B10 and B50 lives under it, rescaled from the one simulated life (Archard
    /// wear is linear in `k_d`: a life at `k_d'` is the simulated one with its cycles scaled
    /// by `k_d/k_d'`; exact when one factor scales every joint's `k_d`,
    /// `run.k_d_correlation`).
    #[serde(default, skip_serializing_if = "is_zero")]
    pub k_d_scatter: f64,
}

impl WearSpec {
    /// Dimensionless Archard coefficient `K_w = K_d·H`, if the hardness is given.
    pub fn k_w(&self) -> Option<f64> {
        self.hardness.map(|h| self.k_d * h)
    }
}

/// Upper bound on wear grid cells (a typo like 1e9 would otherwise exhaust memory later).
pub const MAX_WEAR_CELLS: usize = 1_000_000;

fn wear_cells() -> usize {
    1000
}

/// Integrator settings.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct Solver {
    /// Integration method: `bdf` (default), `tr-bdf2`, `esdirk34`, `radau` (Radau IIA, order
    /// 5) or `tsit45` (explicit).
    #[serde(default)]
    pub integrator: Integrator,
    /// Coordinates to integrate in (`cartesian` or `joint`); both give the same motion within
    /// the tolerances (tests/formulations.rs). Default `joint`: relative coordinates of the
    /// ideal joints' spanning tree, with constraints only where ideal joints close a loop (none
    /// in the LGRES, whose loops are cut by its clearance joints); about half the work per
    /// drive cycle (docs/performance.md).
    #[serde(
        default = "joint_formulation",
        skip_serializing_if = "is_joint_formulation"
    )]
    pub formulation: Formulation,
    /// Relative tolerance, dimensionless.
    #[serde(default = "rtol")]
    pub rtol: f64,
    /// Absolute tolerance on positions, m. Default: [`DEFAULT_ATOL_POSITION_PER_CLEARANCE`] ×
    /// the smallest clearance, so the local error stays well below a penetration (tens of µm);
    /// 1e-6 m when the scene has no clearance joint.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub atol_position: Option<f64>,
    /// Absolute tolerance on angles, rad. Default: the position tolerance over 1 m (an angle
    /// error at a 1 m arm gives the same position error).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub atol_angle: Option<f64>,
    /// Absolute tolerance on velocities, m/s and rad/s.
    #[serde(default = "atol_velocity")]
    pub atol_velocity: f64,
    /// Time between output samples, s.
    #[serde(default = "output_interval")]
    pub output_interval: f64,
    /// Baumgarte velocity gain `α`, 1/s.
    #[serde(default = "baumgarte")]
    pub baumgarte_alpha: f64,
    /// Baumgarte position gain `β`, 1/s.
    #[serde(default = "baumgarte")]
    pub baumgarte_beta: f64,
    /// Accepted-step budget of each simulation of a run; past it the run fails naming this
    /// field instead of running on. Default [`DEFAULT_MAX_STEPS`].
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub max_steps: Option<usize>,
    /// Wall-time budget of each simulation of a run, s; past it the run fails naming this
    /// field. Default [`DEFAULT_MAX_WALL_TIME`].
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub max_wall_time: Option<f64>,
}

/// Default accepted-step budget per simulation: ~20 min of the default scene, 8 000 of its
/// drive cycles (a cycle takes ~12 000 steps).
pub const DEFAULT_MAX_STEPS: usize = 100_000_000;
/// Default wall-time budget per simulation, s.
pub const DEFAULT_MAX_WALL_TIME: f64 = 3600.0;

/// Default position tolerance per metre of clearance (so 1e-7 m at 0.5 mm).
pub const DEFAULT_ATOL_POSITION_PER_CLEARANCE: f64 = 2e-4;

fn rtol() -> f64 {
    1e-6
}
fn joint_formulation() -> Formulation {
    Formulation::JointCoordinates
}
fn is_joint_formulation(formulation: &Formulation) -> bool {
    *formulation == joint_formulation()
}
fn atol_velocity() -> f64 {
    1e-5
}
fn output_interval() -> f64 {
    1e-4
}
fn baumgarte() -> f64 {
    50.0
}

impl Default for Solver {
    fn default() -> Self {
        Self {
            integrator: Integrator::default(),
            formulation: joint_formulation(),
            rtol: rtol(),
            atol_position: None,
            atol_angle: None,
            atol_velocity: atol_velocity(),
            output_interval: output_interval(),
            baumgarte_alpha: baumgarte(),
            baumgarte_beta: baumgarte(),
            max_steps: None,
            max_wall_time: None,
        }
    }
}

/// Absolute tolerances with the defaults resolved against a scene.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Tolerances {
    /// m.
    pub position: f64,
    /// rad.
    pub angle: f64,
    /// m/s and rad/s.
    pub velocity: f64,
}
