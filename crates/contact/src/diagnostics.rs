//! What a contact evaluation reports besides forces: the inputs of wear accumulation and plots.

/// The state of one clearance joint at one instant, as computed by the force kernel.
///
/// `wear` accumulates Archard wear from these fields (normal force, sliding speed, the
/// eccentricity and local radii for the contact arc, and the body-frame contact angles that
/// pick the grid cells); recorders plot them.
#[derive(Clone, Copy, Debug, Default, PartialEq, serde::Serialize, serde::Deserialize)]
pub struct ContactDiagnostics {
    /// Whether the pin touches the bearing (`penetration ≥ 0`).
    pub in_contact: bool,
    /// Penetration `δ = |e| − c(θ, t)` (m); negative when the joint is free.
    pub penetration: f64,
    /// Eccentricity magnitude `|e|` (m): distance between pin and bearing centres.
    pub eccentricity: f64,
    /// Global angle of the contact normal `n = e/|e|` (rad, in `(−π, π]`).
    pub contact_angle: f64,
    /// Contact direction in the bearing body's frame, `φ − θ_bearing` (rad, wrapped to `[0, 2π)`).
    pub bearing_angle: f64,
    /// Contact direction in the pin body's frame, `φ − θ_pin` (rad, wrapped to `[0, 2π)`).
    pub pin_angle: f64,
    /// Local (possibly worn) bearing radius in the contact direction (m).
    pub bearing_radius: f64,
    /// Local (possibly worn) pin radius in the contact direction (m).
    pub pin_radius: f64,
    /// Normal relative velocity `v_n = dδ/dt` (m/s), positive when penetrating. It is the
    /// material-point velocity `(v_j^Q − v_i^Q)·n`: exactly `dδ/dt` for round surfaces; on a worn
    /// one it leaves out the profile sweeping past the contact direction (see `joint`).
    pub normal_velocity: f64,
    /// Tangential relative velocity `v_t` of the pin on the bearing (m/s).
    pub tangential_velocity: f64,
    /// Normal force magnitude `F_n ≥ 0` (N).
    pub normal_force: f64,
    /// Signed friction force along the tangent `t` (N): `c_f c_d F_n sgn(v_t)`.
    pub friction_force: f64,
    /// Global position of the contact point on the bearing surface (m).
    pub contact_point: [f64; 2],
}
