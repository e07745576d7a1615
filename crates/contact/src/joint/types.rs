//! The values a clearance joint's evaluation takes and gives: the bodies' states, a joint
//! surface, the joint's kinematics and geometry at one state, the outlines' overlap, and the
//! forces.

use nalgebra::{SMatrix, Vector2, Vector3};

use crate::diagnostics::ContactDiagnostics;
use crate::material::Material;
use crate::surface::RadiusSample;

/// Partials of the six generalized forces with respect to the twelve body coordinates.
///
/// Rows: `[bearing F_x, F_y, M, pin F_x, F_y, M]`.
/// Columns: `[x_i, y_i, θ_i, x_j, y_j, θ_j, ẋ_i, ẏ_i, θ̇_i, ẋ_j, ẏ_j, θ̇_j]`
/// (i = bearing body, j = pin body; positions then velocities).
pub type ContactJacobian = SMatrix<f64, 6, 12>;

/// Planar rigid-body state: centroid position, angle and their rates.
#[derive(Clone, Copy, Debug, Default, PartialEq, serde::Serialize, serde::Deserialize)]
pub struct BodyState {
    /// Centroid x (m).
    pub x: f64,
    /// Centroid y (m).
    pub y: f64,
    /// Angle (rad).
    pub theta: f64,
    /// Centroid velocity ẋ (m/s).
    pub vx: f64,
    /// Centroid velocity ẏ (m/s).
    pub vy: f64,
    /// Angular velocity θ̇ (rad/s).
    pub omega: f64,
}

impl BodyState {
    /// State from position `(x, y, θ)` and velocity `(ẋ, ẏ, θ̇)`.
    pub fn new(position: [f64; 3], velocity: [f64; 3]) -> Self {
        Self {
            x: position[0],
            y: position[1],
            theta: position[2],
            vx: velocity[0],
            vy: velocity[1],
            omega: velocity[2],
        }
    }

    /// `[x, y, θ, ẋ, ẏ, θ̇]`: the order of a body's columns in [`ContactJacobian`].
    pub(crate) fn coordinates(&self) -> [f64; 6] {
        [self.x, self.y, self.theta, self.vx, self.vy, self.omega]
    }

    /// A body at rest at `(x, y, θ)`.
    pub fn at_rest(x: f64, y: f64, theta: f64) -> Self {
        Self::new([x, y, theta], [0.0; 3])
    }

    pub(super) fn position(&self) -> Vector2<f64> {
        Vector2::new(self.x, self.y)
    }

    pub(super) fn velocity(&self) -> Vector2<f64> {
        Vector2::new(self.vx, self.vy)
    }

    /// A body-fixed vector turned into the global frame.
    pub(super) fn rotate(&self, local: &Vector2<f64>) -> Vector2<f64> {
        let (s, c) = self.theta.sin_cos();
        Vector2::new(c * local.x - s * local.y, s * local.x + c * local.y)
    }
}

/// The state a contact model is evaluated at: both bodies, and the onset velocity `δ̇⁻` of the
/// current contact (`None`: it has just begun, and the current normal velocity counts; see
/// [`crate::ImpactMemory`]).
#[derive(Clone, Copy, Debug)]
pub struct JointState<'a> {
    /// The bearing's body.
    pub bearing: &'a BodyState,
    /// The pin's body.
    pub pin: &'a BodyState,
    /// `δ̇⁻` of the current contact (m/s).
    pub onset_velocity: Option<f64>,
}

impl<'a> JointState<'a> {
    /// The state of the bearing's and the pin's bodies, with the current contact's `δ̇⁻`.
    pub fn new(bearing: &'a BodyState, pin: &'a BodyState, onset_velocity: Option<f64>) -> Self {
        Self {
            bearing,
            pin,
            onset_velocity,
        }
    }
}

/// One side of a joint: where its centre sits on its body, its shape and its material.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct JointSurface<S> {
    /// Centre of the bearing hole or pin in the carrying body's frame, relative to its centroid (m).
    pub centre: [f64; 2],
    /// Radius as a function of the body-frame angle.
    pub profile: S,
    /// Material.
    pub material: Material,
}

/// Everything the kinematics of a joint gives at one state (global frame).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct JointKinematics {
    /// Eccentricity `e = r_j^c − r_i^c` (m).
    pub eccentricity: Vector2<f64>,
    /// `|e|` (m).
    pub eccentricity_norm: f64,
    /// Normal `n = e/|e|` (taken as the x axis when `|e| = 0`).
    pub normal: Vector2<f64>,
    /// Tangent `t`: `n` turned by +90°.
    pub tangent: Vector2<f64>,
    /// Contact angle `φ = atan2(n_y, n_x)` (rad).
    pub contact_angle: f64,
    /// Bearing radius and slope at body-frame angle `φ − θ_i`.
    pub bearing: RadiusSample,
    /// Pin radius and slope at body-frame angle `φ − θ_j`.
    pub pin: RadiusSample,
    /// Penetration `δ = |e| − (R_i − R_j)` (m).
    pub penetration: f64,
    /// Bearing contact point `r_i^c + R_i n` (m).
    pub bearing_point: Vector2<f64>,
    /// Pin contact point `r_j^c + R_j n` (m).
    pub pin_point: Vector2<f64>,
    /// Velocity of the bearing body's material point at its contact point (m/s).
    pub bearing_point_velocity: Vector2<f64>,
    /// Velocity of the pin body's material point at its contact point (m/s).
    pub pin_point_velocity: Vector2<f64>,
    /// Rate of the eccentricity `ė` (velocity of the pin centre relative to the bearing
    /// centre, m/s).
    pub eccentricity_rate: Vector2<f64>,
    /// Normal relative velocity `v_n = (v_j^Q − v_i^Q)·n` (m/s), positive when approaching.
    pub normal_velocity: f64,
    /// Tangential relative velocity `v_t = (v_j^Q − v_i^Q)·t` (m/s).
    pub tangential_velocity: f64,
}

/// Where the pin's outline reaches deepest into (or nearest to) the bearing's.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct OutlineOverlap {
    /// Largest radial overlap of the outlines (m; negative: apart).
    pub depth: f64,
    /// Global direction of the deepest pin point from the bearing centre (rad).
    pub angle: f64,
}

/// Generalized contact forces on both bodies and what was seen on the way.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct ContactForces {
    /// `(F_x, F_y, M)` on the bearing body (N, N, N·m; moment about its centroid).
    pub bearing: Vector3<f64>,
    /// `(F_x, F_y, M)` on the pin body (N, N, N·m; moment about its centroid).
    pub pin: Vector3<f64>,
    /// Contact state for wear and recording.
    pub diagnostics: ContactDiagnostics,
}

/// The positional part of the kinematics, shared by the event function and the kernel.
#[derive(Clone, Copy)]
pub(super) struct Geometry {
    /// Bearing-centre arm `A(θ_i) s_i` from the bearing body's centroid.
    pub(super) bearing_centre_arm: Vector2<f64>,
    /// Pin-centre arm `A(θ_j) s_j` from the pin body's centroid.
    pub(super) pin_centre_arm: Vector2<f64>,
    pub(super) eccentricity: Vector2<f64>,
    pub(super) eccentricity_norm: f64,
    pub(super) normal: Vector2<f64>,
    pub(super) contact_angle: f64,
    pub(super) bearing: RadiusSample,
    pub(super) pin: RadiusSample,
    pub(super) penetration: f64,
}

impl JointKinematics {
    /// Rate of the contact direction, `φ̇ = t·ė/|e|` (rad/s; 0 for concentric centres).
    pub fn contact_angle_rate(&self) -> f64 {
        if self.eccentricity_norm > 0.0 {
            self.tangent.dot(&self.eccentricity_rate) / self.eccentricity_norm
        } else {
            0.0
        }
    }

    /// Relative velocity of the pin's material point on the bearing's at the contact (m/s).
    pub fn relative_velocity(&self) -> Vector2<f64> {
        self.pin_point_velocity - self.bearing_point_velocity
    }
}

/// Which relative velocity of the contact counts as sliding (for friction, and for wear).
///
/// The physical choice is the velocity of the pin's **material** point on the bearing's
/// (docs/model.md §1): it includes the pin spinning in its bearing, so it is of the order of
/// `ω_rel R`. The paper (Sec. 2.1) differentiates the **geometric** contact point
/// `r^c + R n` instead, which gives `δ φ̇`: the spin drops out and the sliding speed shrinks by
/// about `δ/|e|`. This is why the paper's wear depths are ~30× smaller than the material
/// choice gives with the same wear coefficient; the option lets a scene reproduce the paper.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, serde::Serialize, serde::Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum SlidingVelocity {
    /// `(v_j^Q − v_i^Q)·t` of the material points (physical; the default).
    #[default]
    Material,
    /// `δ φ̇`, the derivative of the geometric contact point (the paper's).
    Paper,
}

impl SlidingVelocity {
    /// The sliding velocity this choice reads from a contact's diagnostics (m/s).
    pub fn of(self, diagnostics: &ContactDiagnostics) -> f64 {
        match self {
            Self::Material => diagnostics.tangential_velocity,
            Self::Paper => diagnostics.geometric_sliding_velocity,
        }
    }
}
