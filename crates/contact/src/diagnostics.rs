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
    /// Penetration rate `δ̇ = ∇δ·q̇` (m/s), positive when penetrating: the rate the damping and
    /// the onset velocity use. For round surfaces it is the material normal velocity
    /// `(v_j^Q − v_i^Q)·n`; on a worn one it also holds the profile sweeping past (see `joint`).
    pub normal_velocity: f64,
    /// Sliding velocity `v_t` of the pin's material point on the bearing's, along the contact
    /// tangent (m/s): the physical sliding speed.
    pub tangential_velocity: f64,
    /// The paper's sliding velocity `δ φ̇` (m/s): the derivative of the geometric contact
    /// point, which leaves out the spin of the pin in the bearing (see [`crate::SlidingVelocity`]).
    /// 0 when the joint is free (nothing slides).
    pub geometric_sliding_velocity: f64,
    /// Normal force magnitude `F_n ≥ 0` (N): the load between the surfaces.
    pub normal_force: f64,
    /// The conservative part of the normal force (N): `K δⁿ` on the line of centres, the
    /// magnitude of the layer's elastic resultant `|Σ G_k m_k|` on the foundation. With
    /// `normal_force` it splits a peak into its elastic and damping parts: a force that is
    /// mostly damping is the rate term of a law, not a load the surfaces carry. Can exceed
    /// `normal_force` while the surfaces separate fast (the damped force clamps at zero).
    #[serde(default)]
    pub elastic_force: f64,
    /// Signed friction force along the contact tangent (N): `c_f c_d F_n sgn(v_t)`.
    pub friction_force: f64,
    /// Global position of the contact point on the bearing surface (m).
    pub contact_point: [f64; 2],
    /// Energy stored in the contact's elastic potential `V = K δⁿ⁺¹/(n+1)` (J; 0 when free).
    pub elastic_energy: f64,
    /// Power the normal force dissipates beyond its elastic part (W, ≥ 0 for a dissipative
    /// law): `(F_n − F_e) δ̇`, plus the stored energy released where the damped force clamps.
    pub damping_power: f64,
    /// Power friction dissipates on the relative sliding of the material points (W):
    /// `F_t v_t`, ≥ 0 whenever the friction opposes the material sliding.
    pub friction_power: f64,
    /// Bearing profile slope `dR_i/dα` in the contact direction (m/rad; 0 for round).
    pub bearing_slope: f64,
    /// Pin profile slope `dR_j/dα` in the contact direction (m/rad; 0 for round).
    pub pin_slope: f64,
    /// Bearing profile curvature `d²R_i/dα²` in the contact direction (m/rad²).
    pub bearing_curvature: f64,
    /// Pin profile curvature `d²R_j/dα²` in the contact direction (m/rad²).
    pub pin_curvature: f64,
    /// Foundation model: nodes of the pin's outline that overlap the bearing (0 for the
    /// line-of-centres model).
    #[serde(default)]
    pub contact_cells: u32,
    /// Foundation model: separate contact zones (runs of overlapping nodes).
    #[serde(default)]
    pub contact_zones: u32,
    /// Foundation model: overlapping nodes across the narrowest contact zone that carries at
    /// least a tenth of the load (0 when free).
    #[serde(default)]
    pub narrowest_zone_cells: u32,
    /// Foundation model: the estimated relative error of the normal load from the grid's
    /// resolution of the contact zones, `Σ share · 0.96/n²` over zones of `n` nodes.
    #[serde(default)]
    pub resolution_error: f64,
    /// Thin-gap model: the terms its overlap neglects (the third-order terms of the pin's
    /// outline read along the bearing's ray, estimated per overlapping node) over the overlap,
    /// summed over the overlapping nodes: the relative error of the overlaps that carry the
    /// load (0 for the other models and when free).
    #[serde(default)]
    pub neglected_terms: f64,
}
