//! The scene format: a planar mechanism with ideal and clearance revolute joints, as TOML.
//!
//! A scene is data only. Units are SI throughout (m, kg, s, N, Pa, rad) with one exception made
//! for people who read and write files by hand: initial body angles are given in degrees
//! (`theta_deg`) and stored in radians ([`Angle`]). Every struct rejects unknown keys, so a typo
//! is an error rather than a silently ignored setting.
//!
//! Get a validated scene from [`crate::scenes::builtin`], [`load_path`] or [`load_str`]; all
//! three resolve `extends` (see below) and run [`Scene::validate`], so a scene returned by them
//! names only existing bodies, has finite numbers and physically meaningful parameters.
//!
//! # Variants (`extends`)
//! A scene file may start with `extends = "<name>"` (a built-in scene, or a file path relative
//! to the extending file) and give only what changes. The patch is merged into the base: tables
//! merge key by key, and arrays of tables (`bodies`, `revolute_joints`, …) merge element by
//! element matched on `name`, an unmatched name being appended (a name given twice in one patch
//! is an error). Other values replace, and so do an empty array (`drivers = []` removes the
//! base's) and a table whose `law` or `kind` differs from the base's. This keeps
//! the study variants a few lines each and the reconstructed geometry in one file.

use std::collections::{HashMap, HashSet};
use std::f64::consts::TAU;
use std::fmt;
use std::path::{Path, PathBuf};

use serde::{Deserialize, Serialize};

/// Reserved body name for the fixed frame.
pub const GROUND: &str = "ground";

/// How many `extends` levels are followed before giving up (guards against cycles).
const MAX_EXTENDS_DEPTH: usize = 8;

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
    pub clearance_joints: Vec<ClearanceJoint>,
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

fn yes() -> bool {
    true
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

/// A pose coordinate.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "lowercase")]
pub enum Coordinate {
    /// Centroid x, m.
    X,
    /// Centroid y, m.
    Y,
    /// Body angle, rad.
    Theta,
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
pub struct ClearanceJoint {
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
    pub bearing_material: Material,
    /// Pin material.
    pub pin_material: Material,
    /// Normal contact force law.
    pub normal_law: NormalLaw,
    /// Tangential (friction) law.
    pub friction: FrictionLaw,
    /// Archard wear of both surfaces; absent: no wear.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub wear: Option<WearSpec>,
    /// Which sliding velocity drives friction and wear (default: the material points', the
    /// physical one; `paper` is the paper's `δ φ̇`, see docs/model.md §9).
    #[serde(default, skip_serializing_if = "Sliding::is_default")]
    pub sliding: Sliding,
    /// Treat as an ideal revolute joint (2 constraint equations, centres coincide) — the
    /// reference mechanism of the studies. Contact and wear settings are then unused.
    #[serde(default, skip_serializing_if = "std::ops::Not::not")]
    pub ideal: bool,
}

impl ClearanceJoint {
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
    pub friction: contact::SlidingVelocity,
    /// For Archard wear.
    #[serde(default)]
    pub wear: contact::SlidingVelocity,
}

impl Sliding {
    fn is_default(&self) -> bool {
        *self == Self::default()
    }
}

/// Elastic constants of one contacting surface.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct Material {
    /// Young's modulus `E`, Pa.
    pub youngs_modulus: f64,
    /// Poisson's ratio `ν`, dimensionless, in (−1, 0.5).
    pub poisson_ratio: f64,
}

/// Normal contact force law `F_n(δ, δ̇)`.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
#[serde(tag = "law", rename_all = "kebab-case", deny_unknown_fields)]
pub enum NormalLaw {
    /// `K δⁿ (1 + 3(1−c_e²)/4 · δ̇/δ̇⁻)` — Lankarani & Nikravesh.
    HertzLankaraniNikravesh(DissipativeLaw),
    /// `K δⁿ (1 + 3(1−c_e)/2 · δ̇/δ̇⁻)` — Hunt & Crossley.
    HuntCrossley(DissipativeLaw),
    /// `K δⁿ (1 + 8(1−c_e)/(5 c_e) · δ̇/δ̇⁻)` — Flores et al.
    Flores(DissipativeLaw),
    /// `K δⁿ`, no damping.
    Hertz(ElasticLaw),
}

/// Parameters of a damped Hertz-type law.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct DissipativeLaw {
    /// Hertz exponent `n`, dimensionless (1.5 for Hertz contact).
    #[serde(default = "hertz_exponent")]
    pub exponent: f64,
    /// Coefficient of restitution `c_e` in (0, 1].
    pub restitution: f64,
    /// Floor on the impact velocity `δ̇⁻` used in the damping term, m/s: a contact that starts
    /// gently would otherwise get unbounded damping.
    #[serde(default = "impact_velocity_floor")]
    pub impact_velocity_floor: f64,
}

/// Parameters of the undamped Hertz law.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct ElasticLaw {
    /// Hertz exponent `n`, dimensionless.
    #[serde(default = "hertz_exponent")]
    pub exponent: f64,
}

fn hertz_exponent() -> f64 {
    1.5
}
fn impact_velocity_floor() -> f64 {
    1e-4
}

/// Friction law at the contact.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
#[serde(tag = "law", rename_all = "kebab-case", deny_unknown_fields)]
pub enum FrictionLaw {
    /// Ambrósio's modified Coulomb law: `c_f c_d F_n`, `c_d` ramps 0→1 for `v0 ≤ |v_t| ≤ v1`.
    Ambrosio {
        /// Friction coefficient `c_f`, dimensionless.
        coefficient: f64,
        /// Sliding speed below which there is no friction, m/s.
        v0: f64,
        /// Sliding speed above which friction is fully developed, m/s.
        v1: f64,
    },
    /// Coulomb friction `c_f F_n sgn(v_t)`: parsed, but validation rejects it (the integrator
    /// cannot step over its jump at `v_t = 0`; runs hung) and suggests `ambrosio`.
    Coulomb {
        /// Friction coefficient `c_f`, dimensionless.
        coefficient: f64,
    },
    /// Frictionless contact.
    None,
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

/// Time integrator.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default, Serialize, Deserialize)]
#[serde(rename_all = "kebab-case")]
pub enum Integrator {
    /// Variable-order BDF (the `ode15s` analogue).
    #[default]
    Bdf,
    /// TR-BDF2 (SDIRK).
    TrBdf2,
    /// ESDIRK3(4).
    Esdirk34,
    /// Explicit Tsitouras 5(4): for non-stiff checks only.
    Tsit45,
}

/// Integrator settings.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct Solver {
    /// Integration method.
    #[serde(default)]
    pub integrator: Integrator,
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

/// Arm (m) converting the default position tolerance into the default angle tolerance.
const REFERENCE_ARM: f64 = 1.0;

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
    /// Largest relative change of the clearance's slope per extrapolation step,
    /// `|Δc'|/(c0 + |c'|)`: bounds how fast a sub-step reshapes the worn profile.
    #[serde(default = "max_slope_change")]
    pub max_slope_change: f64,
    /// Largest relative change of the clearance's curvature per extrapolation step,
    /// `|Δc''|/(c0 + |c''|)`.
    #[serde(default = "max_curvature_change")]
    pub max_curvature_change: f64,
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
    /// Body whose centroid response is recorded and compared with the ideal mechanism;
    /// default: `rod3` if the scene has one, else the last body.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub response_body: Option<String>,
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
fn max_substeps() -> u32 {
    400
}
fn max_slope_change() -> f64 {
    wear::Extrapolation::DEFAULT_SLOPE_CHANGE
}
fn max_curvature_change() -> f64 {
    wear::Extrapolation::DEFAULT_CURVATURE_CHANGE
}

impl Default for RunSettings {
    fn default() -> Self {
        Self {
            cycles: one(),
            period: None,
            wear_stages: one(),
            cycles_per_stage: cycles_per_stage(),
            amplification: amplification(),
            adaptive_extrapolation: true,
            max_clearance_change: max_clearance_change(),
            max_slope_change: max_slope_change(),
            max_curvature_change: max_curvature_change(),
            max_substeps: max_substeps(),
            stop_at_validity_limits: true,
            transient_window: transient_window(),
            response_body: None,
        }
    }
}

/// A body reference resolved against a scene.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum BodyRef {
    /// The fixed frame.
    Ground,
    /// Index into [`Scene::bodies`].
    Body(usize),
}

/// One problem found by validation.
#[derive(Debug, Clone, PartialEq)]
pub struct Issue {
    /// Field path, e.g. `clearance_joints[0].clearance`.
    pub path: String,
    /// The offending value as written.
    pub value: String,
    /// Why it is rejected.
    pub reason: String,
}

impl fmt::Display for Issue {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        write!(f, "{} = {}: {}", self.path, self.value, self.reason)
    }
}

/// Why a scene could not be loaded.
#[derive(Debug, thiserror::Error)]
pub enum SceneError {
    /// The file could not be read.
    #[error("cannot read scene file {path}: {source}")]
    Io {
        /// File path.
        path: PathBuf,
        /// Cause.
        source: std::io::Error,
    },
    /// TOML syntax or type error; the message carries line and column when known.
    #[error("in scene {origin}: {source}")]
    Toml {
        /// File path or scene name.
        origin: String,
        /// Cause.
        source: toml::de::Error,
    },
    /// The scene merged with its `extends` base has a value of the wrong type or a missing or
    /// unknown key; `path` is the field (in the merged scene).
    #[error("in scene {origin} (merged with its `extends` base): {path}{}: {source}", line.map_or(String::new(), |l| format!(" (line {l})")))]
    Merged {
        /// File path or scene name.
        origin: String,
        /// Field path, e.g. `bodies[2].mass`.
        path: String,
        /// Line in the extending file, when the field is given there.
        line: Option<usize>,
        /// Cause (boxed: keeps the error type small).
        source: Box<toml::de::Error>,
    },
    /// `extends` names no built-in scene and no file, or nests too deep.
    #[error("in scene {origin}: extends = {target:?}: {reason}")]
    Extends {
        /// File path or scene name.
        origin: String,
        /// The `extends` value.
        target: String,
        /// Why it could not be followed.
        reason: String,
    },
    /// The scene parsed but its values are not acceptable.
    #[error("in scene {origin}: {}", list_issues(.issues))]
    Invalid {
        /// File path or scene name.
        origin: String,
        /// Every problem found, in file order.
        issues: Vec<Issue>,
    },
    /// A scene given as a table (see [`from_table`]) has a value of the wrong type or a missing
    /// or unknown key; `path` is the field.
    #[error("in scene {origin}: {path}: {source}")]
    Field {
        /// Scene name.
        origin: String,
        /// Field path, e.g. `clearance_joints[0].clearance`.
        path: String,
        /// Cause (boxed: keeps the error type small).
        source: Box<toml::de::Error>,
    },
    /// No built-in scene of that name.
    #[error("no built-in scene named {name:?} (known: {known})")]
    UnknownBuiltin {
        /// Requested name.
        name: String,
        /// Comma-separated list of built-in names.
        known: String,
    },
}

fn list_issues(issues: &[Issue]) -> String {
    match issues {
        [one] => one.to_string(),
        many => {
            let lines: Vec<String> = many.iter().map(|i| format!("\n  {i}")).collect();
            format!("{} problems:{}", many.len(), lines.concat())
        }
    }
}

impl Scene {
    /// Resolve a body name (`ground` included).
    pub fn resolve(&self, name: &str) -> Option<BodyRef> {
        if name == GROUND {
            return Some(BodyRef::Ground);
        }
        self.bodies
            .iter()
            .position(|b| b.name == name)
            .map(BodyRef::Body)
    }

    /// Initial global position of a point given in `body`'s frame (`ground`: the point itself).
    /// `None` if the body does not exist.
    pub fn initial_point(&self, body: &str, local: [f64; 2]) -> Option<[f64; 2]> {
        match self.resolve(body)? {
            BodyRef::Ground => Some(local),
            BodyRef::Body(k) => {
                let b = &self.bodies[k];
                let (s, c) = b.theta.rad().sin_cos();
                Some([
                    b.x + c * local[0] - s * local[1],
                    b.y + s * local[0] + c * local[1],
                ])
            }
        }
    }

    /// Number of constraint equations: 2 per revolute, 1 or 2 per prismatic, 1 per driver, 2 per
    /// clearance joint marked `ideal`, 0 per clearance joint.
    pub fn constraint_count(&self) -> usize {
        2 * self.revolute_joints.len()
            + self
                .prismatic_joints
                .iter()
                .map(|p| 1 + usize::from(p.lock_rotation))
                .sum::<usize>()
            + self.drivers.len()
            + 2 * self.clearance_joints.iter().filter(|c| c.ideal).count()
    }

    /// Degrees of freedom `3·bodies − constraints` (a count, not a rank: redundant constraints
    /// show up only in the assembly check).
    pub fn degrees_of_freedom(&self) -> i64 {
        3 * self.bodies.len() as i64 - self.constraint_count() as i64
    }

    /// Clearance joints that act as contact force elements (not marked `ideal`).
    pub fn active_clearance_joints(&self) -> impl Iterator<Item = &ClearanceJoint> {
        self.clearance_joints.iter().filter(|c| !c.ideal)
    }

    /// Duration of one drive cycle, s: `run.period`, else the first driver law with a period.
    pub fn cycle_period(&self) -> Option<f64> {
        self.run
            .period
            .or_else(|| self.drivers.iter().find_map(|d| d.law.period()))
    }

    /// Index of the body whose response is recorded (see [`RunSettings::response_body`]).
    pub fn response_body(&self) -> Option<usize> {
        match &self.run.response_body {
            Some(name) => match self.resolve(name)? {
                BodyRef::Body(k) => Some(k),
                BodyRef::Ground => None,
            },
            None => self
                .bodies
                .iter()
                .position(|b| b.name == "rod3")
                .or(self.bodies.len().checked_sub(1)),
        }
    }

    /// Absolute tolerances with defaults resolved (see [`Solver`]).
    pub fn tolerances(&self) -> Tolerances {
        let position = self.solver.atol_position.unwrap_or_else(|| {
            self.active_clearance_joints()
                .map(|c| c.clearance * DEFAULT_ATOL_POSITION_PER_CLEARANCE)
                .reduce(f64::min)
                .unwrap_or(1e-6)
        });
        Tolerances {
            position,
            angle: self.solver.atol_angle.unwrap_or(position / REFERENCE_ARM),
            velocity: self.solver.atol_velocity,
        }
    }

    /// The same mechanism with every clearance joint made ideal: the reference of the studies.
    pub fn idealized(&self) -> Scene {
        let mut s = self.clone();
        s.clearance_joints.iter_mut().for_each(|c| c.ideal = true);
        s
    }

    /// Serialize back to TOML (angles in degrees), e.g. to record the scene next to outputs.
    pub fn to_toml(&self) -> String {
        // Every field is a plain number, string, array or table, which TOML can always express.
        toml::to_string_pretty(self).unwrap_or_else(|e| format!("# cannot serialize: {e}\n"))
    }

    /// Check every value; `origin` names the scene in the error.
    pub fn validate(&self, origin: &str) -> Result<(), SceneError> {
        let mut v = Validator::default();
        v.scene(self);
        crate::limits::check(&mut v, self);
        if v.issues.is_empty() {
            Ok(())
        } else {
            Err(SceneError::Invalid {
                origin: origin.to_string(),
                issues: v.issues,
            })
        }
    }
}

/// Collects [`Issue`]s while walking a scene (here and in [`crate::limits`]).
#[derive(Default)]
pub(crate) struct Validator {
    issues: Vec<Issue>,
}

impl Validator {
    pub(crate) fn push(
        &mut self,
        path: impl Into<String>,
        value: impl fmt::Debug,
        reason: impl Into<String>,
    ) {
        self.issues.push(Issue {
            path: path.into(),
            value: format!("{value:?}"),
            reason: reason.into(),
        });
    }

    /// Finite and, if `positive`, > 0; returns whether it passed.
    fn number(&mut self, path: &str, x: f64, positive: bool) -> bool {
        if !x.is_finite() {
            self.push(path, x, "must be a finite number");
            false
        } else if positive && x <= 0.0 {
            self.push(path, x, "must be positive");
            false
        } else {
            true
        }
    }

    fn vector(&mut self, path: &str, v: [f64; 2]) {
        for (k, x) in v.iter().enumerate() {
            self.number(&format!("{path}[{k}]"), *x, false);
        }
    }

    fn body_name(&mut self, scene: &Scene, path: &str, name: &str) {
        if scene.resolve(name).is_none() {
            self.push(path, name, format!("no body of this name (nor `{GROUND}`)"));
        }
    }

    fn unique<'a>(&mut self, seen: &mut HashSet<&'a str>, path: &str, name: &'a str) {
        if name.trim().is_empty() {
            self.push(path, name, "must not be empty");
        } else if !seen.insert(name) {
            self.push(path, name, "duplicate name");
        }
    }

    fn scene(&mut self, s: &Scene) {
        self.vector("gravity", s.gravity);
        if s.bodies.is_empty() {
            self.push("bodies", "[]", "a scene needs at least one body");
        }
        let mut seen = HashSet::new();
        for (k, b) in s.bodies.iter().enumerate() {
            let p = format!("bodies[{k}]");
            if b.name == GROUND {
                self.push(format!("{p}.name"), &b.name, "`ground` is reserved");
            }
            self.unique(&mut seen, &format!("{p}.name"), &b.name);
            self.number(&format!("{p}.mass"), b.mass, true);
            self.number(&format!("{p}.inertia"), b.inertia, true);
            self.number(&format!("{p}.x"), b.x, false);
            self.number(&format!("{p}.y"), b.y, false);
            self.number(&format!("{p}.theta_deg"), b.theta.deg(), false);
            self.vector(&format!("{p}.velocity"), b.velocity);
            self.number(&format!("{p}.omega"), b.omega, false);
        }
        let mut joints = HashSet::new();
        for (k, j) in s.revolute_joints.iter().enumerate() {
            let p = format!("revolute_joints[{k}]");
            self.unique(&mut joints, &format!("{p}.name"), &j.name);
            self.pair(
                s,
                &p,
                ("body", &j.body, j.point),
                ("other", &j.other, j.other_point),
            );
        }
        for (k, j) in s.prismatic_joints.iter().enumerate() {
            let p = format!("prismatic_joints[{k}]");
            self.unique(&mut joints, &format!("{p}.name"), &j.name);
            self.pair(
                s,
                &p,
                ("body", &j.body, j.point),
                ("other", &j.other, j.other_point),
            );
            self.vector(&format!("{p}.direction"), j.direction);
            if j.direction.iter().all(|x| *x == 0.0) {
                self.push(format!("{p}.direction"), j.direction, "must not be zero");
            }
        }
        for (k, c) in s.clearance_joints.iter().enumerate() {
            let p = format!("clearance_joints[{k}]");
            self.unique(&mut joints, &format!("{p}.name"), &c.name);
            self.clearance_joint(s, &p, c);
        }
        let mut drivers = HashSet::new();
        for (k, d) in s.drivers.iter().enumerate() {
            let p = format!("drivers[{k}]");
            self.unique(&mut drivers, &format!("{p}.name"), &d.name);
            match &d.target {
                DriverTarget::BodyCoordinate { body, .. } => {
                    if !matches!(s.resolve(body), Some(BodyRef::Body(_))) {
                        self.push(format!("{p}.target.body"), body, "no body of this name");
                    }
                }
                DriverTarget::JointAngle { joint } => {
                    if !s.revolute_joints.iter().any(|j| &j.name == joint) {
                        self.push(
                            format!("{p}.target.joint"),
                            joint,
                            "no revolute joint of this name",
                        );
                    }
                }
            }
            self.law(&format!("{p}.law"), &d.law);
        }
        self.solver(&s.solver);
        self.run(s);
    }

    fn pair(
        &mut self,
        s: &Scene,
        p: &str,
        (bkey, body, point): (&str, &str, [f64; 2]),
        (okey, other, other_point): (&str, &str, [f64; 2]),
    ) {
        self.body_name(s, &format!("{p}.{bkey}"), body);
        self.body_name(s, &format!("{p}.{okey}"), other);
        if body == other {
            self.push(
                format!("{p}.{okey}"),
                other,
                format!("same body as `{bkey}`"),
            );
        }
        self.vector(&format!("{p}.point"), point);
        self.vector(&format!("{p}.other_point"), other_point);
    }

    fn law(&mut self, p: &str, law: &TimeLaw) {
        match law {
            TimeLaw::Constant { value } => {
                self.number(&format!("{p}.value"), *value, false);
            }
            TimeLaw::Ramp { value, rate } => {
                self.number(&format!("{p}.value"), *value, false);
                self.number(&format!("{p}.rate"), *rate, false);
            }
            TimeLaw::Harmonic {
                offset,
                amplitude,
                rpm,
                omega,
            } => {
                self.number(&format!("{p}.offset"), *offset, false);
                self.number(&format!("{p}.amplitude"), *amplitude, false);
                match (rpm, omega) {
                    (Some(r), None) => {
                        self.number(&format!("{p}.rpm"), *r, true);
                    }
                    (None, Some(w)) => {
                        self.number(&format!("{p}.omega"), *w, true);
                    }
                    (None, None) => self.push(p, "{}", "give `rpm` or `omega`"),
                    (Some(r), Some(w)) => self.push(
                        p,
                        (r, w),
                        "give `rpm` or `omega`, not both (rpm, omega shown)",
                    ),
                }
            }
        }
    }

    fn clearance_joint(&mut self, s: &Scene, p: &str, c: &ClearanceJoint) {
        self.body_name(s, &format!("{p}.bearing_body"), &c.bearing_body);
        self.body_name(s, &format!("{p}.pin_body"), &c.pin_body);
        if c.bearing_body == c.pin_body {
            self.push(
                format!("{p}.pin_body"),
                &c.pin_body,
                "same body as the bearing",
            );
        }
        self.vector(&format!("{p}.bearing_point"), c.bearing_point);
        self.vector(&format!("{p}.pin_point"), c.pin_point);
        let radius_ok = self.number(&format!("{p}.bearing_radius"), c.bearing_radius, true);
        if self.number(&format!("{p}.clearance"), c.clearance, true)
            && radius_ok
            && c.clearance >= c.bearing_radius
        {
            self.push(
                format!("{p}.clearance"),
                c.clearance,
                format!(
                    "must be smaller than bearing_radius ({} m): the pin radius is their difference",
                    c.bearing_radius
                ),
            );
        }
        for (side, m) in [("bearing", c.bearing_material), ("pin", c.pin_material)] {
            let q = format!("{p}.{side}_material");
            self.number(&format!("{q}.youngs_modulus"), m.youngs_modulus, true);
            let nu = m.poisson_ratio;
            if self.number(&format!("{q}.poisson_ratio"), nu, false) && !(-1.0 < nu && nu < 0.5) {
                self.push(format!("{q}.poisson_ratio"), nu, "must lie in (-1, 0.5)");
            }
        }
        let q = format!("{p}.normal_law");
        match c.normal_law {
            NormalLaw::HertzLankaraniNikravesh(d)
            | NormalLaw::HuntCrossley(d)
            | NormalLaw::Flores(d) => {
                self.number(&format!("{q}.exponent"), d.exponent, true);
                let e = d.restitution;
                if self.number(&format!("{q}.restitution"), e, true) && e > 1.0 {
                    self.push(format!("{q}.restitution"), e, "must lie in (0, 1]");
                }
                self.number(
                    &format!("{q}.impact_velocity_floor"),
                    d.impact_velocity_floor,
                    true,
                );
            }
            NormalLaw::Hertz(e) => {
                self.number(&format!("{q}.exponent"), e.exponent, true);
            }
        }
        let q = format!("{p}.friction");
        match c.friction {
            FrictionLaw::Ambrosio {
                coefficient,
                v0,
                v1,
            } => {
                self.friction_coefficient(&q, coefficient);
                let ok0 = self.number(&format!("{q}.v0"), v0, true);
                if self.number(&format!("{q}.v1"), v1, true) && ok0 && v1 <= v0 {
                    self.push(format!("{q}.v1"), v1, format!("must exceed v0 ({v0} m/s)"));
                }
            }
            FrictionLaw::Coulomb { coefficient } => self.friction_coefficient(&q, coefficient),
            FrictionLaw::None => {}
        }
        if let Some(w) = &c.wear {
            let q = format!("{p}.wear");
            self.number(&format!("{q}.k_d"), w.k_d, true);
            if let Some(h) = w.hardness {
                self.number(&format!("{q}.hardness"), h, true);
            }
            self.number(&format!("{q}.width"), w.width, true);
            if !(8..=MAX_WEAR_CELLS).contains(&w.cells) {
                self.push(
                    format!("{q}.cells"),
                    w.cells,
                    format!("must lie in 8..={MAX_WEAR_CELLS}"),
                );
            }
        }
    }

    fn friction_coefficient(&mut self, q: &str, cf: f64) {
        if self.number(&format!("{q}.coefficient"), cf, false) && cf < 0.0 {
            self.push(format!("{q}.coefficient"), cf, "must not be negative");
        }
    }

    fn solver(&mut self, s: &Solver) {
        if self.number("solver.rtol", s.rtol, true) && s.rtol >= 1.0 {
            self.push("solver.rtol", s.rtol, "must be below 1");
        }
        if let Some(a) = s.atol_position {
            self.number("solver.atol_position", a, true);
        }
        if let Some(a) = s.atol_angle {
            self.number("solver.atol_angle", a, true);
        }
        self.number("solver.atol_velocity", s.atol_velocity, true);
        self.number("solver.output_interval", s.output_interval, true);
        self.number("solver.baumgarte_alpha", s.baumgarte_alpha, false);
        self.number("solver.baumgarte_beta", s.baumgarte_beta, false);
        if s.max_steps == Some(0) {
            self.push("solver.max_steps", 0, "must be at least 1");
        }
        if let Some(t) = s.max_wall_time {
            self.number("solver.max_wall_time", t, true);
        }
    }

    fn run(&mut self, s: &Scene) {
        let r = &s.run;
        if let Some(t) = r.period {
            self.number("run.period", t, true);
        }
        if (r.cycles > 0 || r.wear_stages > 0) && s.cycle_period().is_none() {
            self.push(
                "run.period",
                "none",
                "no driver has a periodic law (harmonic, or a ramp on an angle); give run.period",
            );
        }
        if r.wear_stages > 0 && r.cycles_per_stage == 0 {
            self.push(
                "run.cycles_per_stage",
                0,
                "must be positive when wear_stages > 0",
            );
        }
        self.number("run.amplification", r.amplification, true);
        let f = r.max_clearance_change;
        if self.number("run.max_clearance_change", f, true) && f > 1.0 {
            self.push("run.max_clearance_change", f, "must lie in (0, 1]");
        }
        self.number("run.max_slope_change", r.max_slope_change, true);
        self.number("run.max_curvature_change", r.max_curvature_change, true);
        if r.max_substeps == 0 {
            self.push("run.max_substeps", 0, "must be at least 1");
        }
        if let Some(name) = &r.response_body
            && !matches!(s.resolve(name), Some(BodyRef::Body(_)))
        {
            self.push("run.response_body", name, "no body of this name");
        }
        if self.number("run.transient_window", r.transient_window, false)
            && r.transient_window < 0.0
        {
            self.push(
                "run.transient_window",
                r.transient_window,
                "must not be negative",
            );
        }
    }
}

/// Parse and validate scene text; `extends` may name built-in scenes only.
pub fn load_str(text: &str, origin: &str) -> Result<Scene, SceneError> {
    let scene = parse(text, origin, None)?;
    scene.validate(origin)?;
    Ok(scene)
}

/// Read, parse and validate a scene file; `extends` may also name a file relative to it.
pub fn load_path(path: &Path) -> Result<Scene, SceneError> {
    let text = read(path)?;
    let origin = path.display().to_string();
    let scene = parse(&text, &origin, path.parent())?;
    scene.validate(&origin)?;
    Ok(scene)
}

fn read(path: &Path) -> Result<String, SceneError> {
    std::fs::read_to_string(path).map_err(|source| SceneError::Io {
        path: path.to_path_buf(),
        source,
    })
}

fn toml_err(origin: &str) -> impl Fn(toml::de::Error) -> SceneError + '_ {
    move |source| SceneError::Toml {
        origin: origin.to_string(),
        source,
    }
}

/// Parse without validating, following `extends`.
fn parse(text: &str, origin: &str, dir: Option<&Path>) -> Result<Scene, SceneError> {
    let table: toml::Table = toml::from_str(text).map_err(toml_err(origin))?;
    if !table.contains_key("extends") {
        // Deserialize from the text itself so type errors keep their line and column.
        return toml::from_str(text).map_err(toml_err(origin));
    }
    let merged = resolve_extends(table, origin, dir, 0)?;
    // The merged table has no line numbers: keep the field path of a type error, and find
    // its line in the extending file when the field is written there.
    serde_path_to_error::deserialize(toml::Value::Table(merged.clone())).map_err(|e| {
        let path = e.path().to_string();
        SceneError::Merged {
            origin: origin.to_string(),
            line: line_of(text, &merged, &path),
            path,
            source: Box::new(e.into_inner()),
        }
    })
}

/// 1-based line of `path`'s last key in `text`, searched after the `name = "…"` line of the
/// innermost named array element on the path (the merged index differs from the file's).
fn line_of(text: &str, merged: &toml::Table, path: &str) -> Option<usize> {
    let mut table = Some(merged);
    let mut name = None;
    let mut key = "";
    for segment in path.split('.') {
        let (k, index) = match segment.split_once('[') {
            Some((k, rest)) => (k, rest.trim_end_matches(']').parse::<usize>().ok()),
            None => (segment, None),
        };
        key = k;
        let value = table.and_then(|t| t.get(k));
        let value = match (value, index) {
            (Some(toml::Value::Array(a)), Some(i)) => a.get(i),
            (v, _) => v,
        };
        if let Some(n) = value
            .and_then(|v| v.get("name"))
            .and_then(toml::Value::as_str)
        {
            name = Some(n);
        }
        table = value.and_then(toml::Value::as_table);
    }
    let lines: Vec<&str> = text.lines().collect();
    let header = |l: &str| l.trim_start().starts_with('[');
    // The section the key is written in: the named element's, a `[table]`'s, or the top.
    let start = match (name, path.rsplit_once('.')) {
        (Some(n), _) => lines
            .iter()
            .position(|l| l.trim_start().starts_with("name") && l.contains(&format!("\"{n}\"")))?,
        (None, Some((section, _))) => {
            lines
                .iter()
                .position(|l| l.trim() == format!("[{section}]"))?
                + 1
        }
        (None, None) => 0,
    };
    let end = (start..lines.len())
        .find(|&k| k > start && header(lines[k]))
        .unwrap_or(lines.len());
    let assigns = |l: &str| {
        l.split(['{', ',']).any(|part| {
            part.trim_start()
                .strip_prefix(key)
                .is_some_and(|rest| rest.trim_start().starts_with('='))
        })
    };
    (start..end).find(|&k| assigns(lines[k])).map(|k| k + 1)
}

/// `table` with its `extends` chain merged in, as raw TOML (deserialized once, at the end).
fn resolve_extends(
    mut table: toml::Table,
    origin: &str,
    dir: Option<&Path>,
    depth: usize,
) -> Result<toml::Table, SceneError> {
    let Some(target) = table.remove("extends") else {
        return Ok(table);
    };
    let fail = |reason: &str| SceneError::Extends {
        origin: origin.to_string(),
        target: target.to_string(),
        reason: reason.to_string(),
    };
    let name = target.as_str().ok_or_else(|| fail("must be a string"))?;
    if depth >= MAX_EXTENDS_DEPTH {
        return Err(fail("too many nested `extends` (a cycle?)"));
    }
    let (text, base_origin, base_dir) = if let Some(text) = crate::scenes::source(name) {
        (text.to_string(), name.to_string(), None)
    } else if let Some(path) = dir.map(|d| d.join(name)).filter(|p| p.is_file()) {
        let parent = path.parent().map(Path::to_path_buf);
        (read(&path)?, path.display().to_string(), parent)
    } else {
        return Err(fail("no built-in scene or file of this name"));
    };
    let base: toml::Table = toml::from_str(&text).map_err(toml_err(&base_origin))?;
    let mut base = resolve_extends(base, &base_origin, base_dir.as_deref(), depth + 1)?;
    merge(&mut base, table, "", origin)?;
    Ok(base)
}

/// Merge `patch` into `base`: tables key by key, arrays of named tables by `name`. An empty
/// array replaces (so `drivers = []` removes the base's), and so does a table whose `law` or
/// `kind` tag differs from the base's (a different law has different keys). `path` is the
/// field path of `base`, for errors.
fn merge(
    base: &mut toml::Table,
    patch: toml::Table,
    path: &str,
    origin: &str,
) -> Result<(), SceneError> {
    for (key, value) in patch {
        let here = if path.is_empty() {
            key.clone()
        } else {
            format!("{path}.{key}")
        };
        match (base.get_mut(&key), value) {
            (Some(toml::Value::Table(b)), toml::Value::Table(p)) if same_tag(b, &p) => {
                merge(b, p, &here, origin)?;
            }
            (Some(toml::Value::Array(b)), toml::Value::Array(p))
                if !p.is_empty() && all_named(b) && all_named(&p) =>
            {
                merge_named(b, p, &here, origin)?;
            }
            (_, value) => {
                base.insert(key, value);
            }
        }
    }
    Ok(())
}

/// Whether `patch` keeps `base`'s `law`/`kind` tag (or gives none).
fn same_tag(base: &toml::Table, patch: &toml::Table) -> bool {
    ["law", "kind"]
        .iter()
        .all(|tag| patch.get(*tag).is_none_or(|t| base.get(*tag) == Some(t)))
}

/// Merge a patch array of named tables into `base` by name (linear: names are indexed); a
/// name given twice in the patch is an error, not a silent double merge.
fn merge_named(
    base: &mut Vec<toml::Value>,
    patch: Vec<toml::Value>,
    path: &str,
    origin: &str,
) -> Result<(), SceneError> {
    let mut index: HashMap<String, usize> = HashMap::with_capacity(base.len());
    for (k, v) in base.iter().enumerate() {
        if let Some(name) = v.get("name").and_then(toml::Value::as_str) {
            index.entry(name.to_string()).or_insert(k);
        }
    }
    let mut seen = HashSet::with_capacity(patch.len());
    for (k, item) in patch.into_iter().enumerate() {
        let toml::Value::Table(item) = item else {
            continue;
        };
        let name = item
            .get("name")
            .and_then(toml::Value::as_str)
            .unwrap_or_default()
            .to_string();
        if !seen.insert(name.clone()) {
            return Err(SceneError::Invalid {
                origin: origin.to_string(),
                issues: vec![Issue {
                    path: format!("{path}[{k}].name"),
                    value: format!("{name:?}"),
                    reason: "duplicate name in this patch (each element may be patched once)"
                        .into(),
                }],
            });
        }
        match index.get(&name).copied() {
            Some(i) => {
                if let Some(toml::Value::Table(e)) = base.get_mut(i) {
                    merge(e, item, &format!("{path}[{i}]"), origin)?;
                }
            }
            None => {
                index.insert(name, base.len());
                base.push(toml::Value::Table(item));
            }
        }
    }
    Ok(())
}

fn all_named(items: &[toml::Value]) -> bool {
    items.iter().all(|v| {
        v.as_table()
            .is_some_and(|t| t.get("name").is_some_and(|n| n.is_str()))
    })
}

/// Scene text with its `extends` chain merged in, as a TOML table, neither deserialized nor
/// validated: the form sweeps and the Python bindings edit before [`from_table`]. `dir` is the
/// folder file `extends` are relative to (`None`: built-in scenes only).
pub fn merged_table(
    text: &str,
    origin: &str,
    dir: Option<&Path>,
) -> Result<toml::Table, SceneError> {
    let table: toml::Table = toml::from_str(text).map_err(toml_err(origin))?;
    resolve_extends(table, origin, dir, 0)
}

/// Deserialize and validate a scene table (e.g. from [`merged_table`], edited); a type error
/// or unknown key names its field path.
pub fn from_table(table: toml::Table, origin: &str) -> Result<Scene, SceneError> {
    let scene: Scene =
        serde_path_to_error::deserialize(toml::Value::Table(table)).map_err(|e| {
            SceneError::Field {
                origin: origin.to_string(),
                path: e.path().to_string(),
                source: Box::new(e.into_inner()),
            }
        })?;
    scene.validate(origin)?;
    Ok(scene)
}
