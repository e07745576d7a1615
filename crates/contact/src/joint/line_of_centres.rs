//! The line-of-centres contact: one contact point on the line of centres, Hertz law on the
//! local radii.
//!
//! # Geometry
//! The **bearing** (a hole) is carried by body *i*, the **pin** by body *j*; their centres are
//! body-fixed points `s_i`, `s_j` (body frame), at `r_k^c = r_k + A(θ_k) s_k` in the global frame.
//! With `e = r_j^c − r_i^c`, the normal is `n = e/|e|`, the tangent `t` is `n` turned by +90°
//! and `φ = atan2(n_y, n_x)`. The surfaces are sampled in the contact direction in their own
//! body frames, at `φ − θ_i` (bearing) and `φ − θ_j` (pin), giving the local radii `R_i`, `R_j`,
//! the local clearance `c(φ) = R_i − R_j` and the penetration `δ = |e| − c(φ)`.
//!
//! # Round surfaces
//! The normal force `F_n` of the law acts along the line of centres: `−(F_n n + F_t t)` on the
//! pin at its contact point `r_j^c + R_j n`, the opposite on the bearing at `r_i^c + R_i n`.
//! Each body gets the moment of its force about its own centroid. The two points are `δ n`
//! apart, so the pair of forces has a net moment `−δ F_t` about any point (zero without
//! friction): the pair is otherwise in balance. The damping rate is the material normal
//! velocity `v_n = (v_j^Q − v_i^Q)·n = dδ/dt`.
//!
//! # Worn (non-round) surfaces
//! The local radii in the contact direction give the penetration and the conformal Hertz
//! stiffness (effective radius `R = R_i R_j/(R_i − R_j)`). Since they depend on `φ` and the body
//! angles, so do `δ` and `K`, and a force along the line of centres would not be conservative:
//! orbiting pins would pump energy in. The force is instead the gradient of the stored energy
//! `V = K W(δ)` (module `general`): `−F_n m` on the pin centre with
//! `m = n − ((R_i' − R_j')/|e|) t`, torques `+F_n R_j'` on the pin and `−F_n R_i'` on the
//! bearing, a small `∇K` term; damping and the onset velocity use `δ̇ = ∇δ·q̇`, friction acts
//! along the contact tangent (perpendicular to `m`) under the load `F_n |m|`. For round
//! surfaces this is the force above; the round kernel is kept because it is cheaper.
//!
//! The model stays a line-of-centres model: it describes the contact while the profile is
//! smooth and shallow against the clearance (`|R_i' − R_j'|/|e|` small, the pin able to follow
//! the worn dent). Callers should check these at the contacts (the diagnostics report slopes
//! and curvatures); [`super::ClearanceJoint::outline_overlap`] measures the true overlap of the two
//! outlines for comparison.
//!
//! Which sliding velocity drives friction is a choice ([`SlidingVelocity`]): the material
//! points' (physical, default) or the paper's `δ φ̇`.

use nalgebra::{Matrix2, SMatrix, Vector2, Vector3};

use super::kinematics::{kinematics_from, perp};
use super::model::{ContactKernel, ContactModel, ModelState, ShapeLimits, ValidityMeasure, Visit};
use super::pair::ContactPair;
use super::types::{
    BodyState, ContactForces, ContactJacobian, Geometry, JointKinematics, JointState,
    SlidingVelocity,
};
use crate::diagnostics::ContactDiagnostics;
use crate::friction::{FrictionForce, FrictionLaw};
use crate::normal::{NormalForce, NormalLaw};
use crate::surface::SurfaceProfile;

mod general;

type Row = SMatrix<f64, 1, 12>;
type Rows2 = SMatrix<f64, 2, 12>;

/// Column of `θ_i` in [`ContactJacobian`].
const COL_THETA_I: usize = 2;
/// Column of `θ_j` in [`ContactJacobian`].
const COL_THETA_J: usize = 5;
/// First velocity column of the bearing body (`ẋ_i`).
const COL_VEL_I: usize = 6;
/// First velocity column of the pin body (`ẋ_j`).
const COL_VEL_J: usize = 9;

/// The line-of-centres contact model (this module).
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, serde::Serialize, serde::Deserialize)]
pub struct LineOfCentres;

impl ContactModel for LineOfCentres {
    /// Reads the outlines directly: no tables, no workspace.
    type Tables = ();
    type Workspace = ();

    fn name(&self) -> &'static str {
        "line-of-centres"
    }

    fn tables<B: SurfaceProfile, P: SurfaceProfile, N, F>(&self, _: &ContactPair<B, P, N, F>) {}

    fn validity_measures(&self) -> &'static [ValidityMeasure] {
        &[
            ValidityMeasure::SlopeRatio,
            ValidityMeasure::Conformity,
            ValidityMeasure::UnloadedPenetration,
            ValidityMeasure::OverlapError,
            ValidityMeasure::MissedContacts,
        ]
    }

    /// The slope limit of the validity checks, 0.3. The curvature is not limited: the wear of
    /// one or a few chaotic cycles carries cell-scale curvature that passes the conformity
    /// limit at sub-micrometre depths, long before a pin whose contact spans tens of cells
    /// could feel it; conformity is measured at the contacts instead.
    fn shape_limits(&self) -> Option<ShapeLimits> {
        Some(ShapeLimits {
            slope: 0.3,
            curvature: f64::INFINITY,
        })
    }
}

impl<B: SurfaceProfile, P: SurfaceProfile, N: NormalLaw, F: FrictionLaw> ContactKernel<B, P, N, F>
    for LineOfCentres
{
    fn forces(
        &self,
        pair: &ContactPair<B, P, N, F>,
        _: ModelState<'_, Self>,
        at: JointState,
        _: Visit,
    ) -> ContactForces {
        pair.line_forces(at)
    }

    fn forces_and_jacobian(
        &self,
        pair: &ContactPair<B, P, N, F>,
        _: ModelState<'_, Self>,
        at: JointState,
    ) -> (ContactForces, ContactJacobian) {
        pair.line_forces_and_jacobian(at)
    }

    fn penetration(
        &self,
        pair: &ContactPair<B, P, N, F>,
        _: ModelState<'_, Self>,
        at: JointState,
    ) -> f64 {
        pair.geometry(at.bearing, at.pin).penetration
    }
}

impl<B: SurfaceProfile, P: SurfaceProfile, N: NormalLaw, F: FrictionLaw> ContactPair<B, P, N, F> {
    /// Both surfaces round and friction on the material sliding: the cheaper round-surface
    /// kernel gives the same forces as the general one.
    #[inline]
    fn uses_round_kernel(&self) -> bool {
        self.friction_sliding == SlidingVelocity::Material
            && self.bearing_profile.is_round()
            && self.pin_profile.is_round()
    }

    /// The line-of-centres forces (see the module docs).
    #[inline]
    fn line_forces(&self, at: JointState) -> ContactForces {
        let (bearing_body, pin_body) = (at.bearing, at.pin);
        let geometry = self.geometry(bearing_body, pin_body);
        let kin = kinematics_from(&geometry, bearing_body, pin_body);
        if kin.penetration < 0.0 {
            return free_forces(&kin, bearing_body, pin_body);
        }
        if !self.uses_round_kernel() {
            return self.general_values(&geometry, &kin, at).forces;
        }
        let stiffness = self.stiffness(kin.bearing.radius, kin.pin.radius);
        let onset = at.onset_velocity.unwrap_or(kin.normal_velocity);
        let (normal, friction) = self.laws(stiffness, &kin, onset);
        assemble(&kin, bearing_body, pin_body, &normal, friction.force)
    }

    /// The line-of-centres forces and their exact partials.
    fn line_forces_and_jacobian(&self, at: JointState) -> (ContactForces, ContactJacobian) {
        let (bearing_body, pin_body) = (at.bearing, at.pin);
        let geometry = self.geometry(bearing_body, pin_body);
        let kin = kinematics_from(&geometry, bearing_body, pin_body);
        if kin.penetration < 0.0 {
            return (
                free_forces(&kin, bearing_body, pin_body),
                ContactJacobian::zeros(),
            );
        }
        if !self.uses_round_kernel() {
            return self.general_forces_and_jacobian(&geometry, &kin, at);
        }
        let onset = at.onset_velocity.unwrap_or(kin.normal_velocity);
        let (n, t) = (kin.normal, kin.tangent);
        let p = PositionPartials::new(&geometry);
        let (d_rho, d_phi) = (p.d_rho, p.d_phi);
        let (d_bearing_radius, d_pin_radius) = (p.d_bearing_radius, p.d_pin_radius);
        let d_penetration = d_rho - d_bearing_radius + d_pin_radius;

        let (stiffness, d_stiffness) = self.stiffness_partials(&kin, &p);

        // Arms from the centroids to the contact points, and the relative velocity.
        let arms = ArmPartials::new(&geometry, &kin, bearing_body, pin_body, &p);
        let (bearing_arm, pin_arm) = (arms.bearing_arm, arms.pin_arm);
        let (d_bearing_arm, d_pin_arm, d_rel_vel) =
            (arms.d_bearing_arm, arms.d_pin_arm, arms.d_relative_velocity);
        let d_normal_velocity: Row = n.transpose() * d_rel_vel + d_phi * kin.tangential_velocity;
        let d_tangential_velocity: Row = t.transpose() * d_rel_vel - d_phi * kin.normal_velocity;

        let (normal, friction) = self.laws(stiffness, &kin, onset);
        let d_normal_force = d_penetration * normal.d_penetration
            + d_normal_velocity * normal.d_velocity
            + d_stiffness * normal.d_stiffness;
        let d_friction_force =
            d_tangential_velocity * friction.d_velocity + d_normal_force * friction.d_normal_force;

        // Force on the pin, −(F_n n + F_t t), and its moments.
        let pin_force = -(n * normal.force + t * friction.force);
        let d_pin_force: Rows2 = -(n * d_normal_force
            + t * d_friction_force
            + (t * normal.force - n * friction.force) * d_phi);
        let d_pin_moment = moment_partials(&pin_arm, &d_pin_arm, &pin_force, &d_pin_force);
        let d_bearing_moment =
            moment_partials(&bearing_arm, &d_bearing_arm, &-pin_force, &-d_pin_force);

        let mut jacobian = ContactJacobian::zeros();
        jacobian.fixed_rows_mut::<2>(0).copy_from(&-d_pin_force);
        jacobian.set_row(2, &d_bearing_moment);
        jacobian.fixed_rows_mut::<2>(3).copy_from(&d_pin_force);
        jacobian.set_row(5, &d_pin_moment);

        let forces = assemble(&kin, bearing_body, pin_body, &normal, friction.force);
        (forces, jacobian)
    }

    /// The normal law at the contact's stiffness, penetration and rate, and the friction law
    /// under the normal force it gives.
    #[inline]
    fn laws(
        &self,
        stiffness: f64,
        kin: &JointKinematics,
        onset: f64,
    ) -> (NormalForce, FrictionForce) {
        let normal =
            self.normal_law
                .evaluate(stiffness, kin.penetration, kin.normal_velocity, onset);
        let friction = self
            .friction_law
            .evaluate(kin.tangential_velocity, normal.force);
        (normal, friction)
    }

    /// Stiffness `K` through the effective radius, and its partials.
    #[inline]
    fn stiffness_partials(&self, kin: &JointKinematics, p: &PositionPartials) -> (f64, Row) {
        let (r_i, r_j) = (kin.bearing.radius, kin.pin.radius);
        let clearance = r_i - r_j;
        let effective_radius = r_i * r_j / clearance;
        let stiffness = self.modulus_factor * effective_radius.sqrt();
        let d_effective_radius = (p.d_pin_radius * (r_i * r_i) - p.d_bearing_radius * (r_j * r_j))
            / (clearance * clearance);
        let d_stiffness = d_effective_radius * (0.5 * stiffness / effective_radius);
        (stiffness, d_stiffness)
    }
}

/// What a contact state loads and dissipates, for [`ContactDiagnostics`].
#[derive(Clone, Copy, Default)]
struct Loads {
    normal_velocity: f64,
    tangential_velocity: f64,
    geometric_sliding_velocity: f64,
    normal_force: f64,
    elastic_force: f64,
    friction_force: f64,
    elastic_energy: f64,
    damping_power: f64,
    friction_power: f64,
}

fn diagnostics(
    kin: &JointKinematics,
    bearing_body: &BodyState,
    pin_body: &BodyState,
    loads: &Loads,
) -> ContactDiagnostics {
    let wrap = crate::surface::wrap_angle;
    ContactDiagnostics {
        in_contact: kin.penetration >= 0.0,
        penetration: kin.penetration,
        eccentricity: kin.eccentricity_norm,
        contact_angle: kin.contact_angle,
        bearing_angle: wrap(kin.contact_angle - bearing_body.theta),
        pin_angle: wrap(kin.contact_angle - pin_body.theta),
        bearing_radius: kin.bearing.radius,
        pin_radius: kin.pin.radius,
        normal_velocity: loads.normal_velocity,
        tangential_velocity: loads.tangential_velocity,
        geometric_sliding_velocity: loads.geometric_sliding_velocity,
        normal_force: loads.normal_force,
        elastic_force: loads.elastic_force,
        friction_force: loads.friction_force,
        contact_point: [kin.bearing_point.x, kin.bearing_point.y],
        elastic_energy: loads.elastic_energy,
        damping_power: loads.damping_power,
        friction_power: loads.friction_power,
        bearing_slope: kin.bearing.slope,
        pin_slope: kin.pin.slope,
        bearing_curvature: kin.bearing.curvature,
        pin_curvature: kin.pin.curvature,
        ..ContactDiagnostics::default()
    }
}

fn free_forces(
    kin: &JointKinematics,
    bearing_body: &BodyState,
    pin_body: &BodyState,
) -> ContactForces {
    let loads = Loads {
        normal_velocity: kin.normal_velocity,
        tangential_velocity: kin.tangential_velocity,
        ..Loads::default()
    };
    ContactForces {
        bearing: Vector3::zeros(),
        pin: Vector3::zeros(),
        diagnostics: diagnostics(kin, bearing_body, pin_body, &loads),
    }
}

/// Forces of the round-surface kernel: `−(F_n n + F_t t)` on the pin at its contact point.
fn assemble(
    kin: &JointKinematics,
    bearing_body: &BodyState,
    pin_body: &BodyState,
    normal: &NormalForce,
    friction_force: f64,
) -> ContactForces {
    let pin_force = -(kin.normal * normal.force + kin.tangent * friction_force);
    let pin_moment = cross(&(kin.pin_point - pin_body.position()), &pin_force);
    let bearing_moment = cross(&(kin.bearing_point - bearing_body.position()), &-pin_force);
    let loads = Loads {
        normal_velocity: kin.normal_velocity,
        tangential_velocity: kin.tangential_velocity,
        geometric_sliding_velocity: kin.penetration * kin.contact_angle_rate(),
        normal_force: normal.force,
        elastic_force: normal.elastic,
        friction_force,
        elastic_energy: normal.potential,
        damping_power: (normal.force - normal.elastic) * kin.normal_velocity,
        friction_power: friction_force * kin.tangential_velocity,
    };
    ContactForces {
        bearing: Vector3::new(-pin_force.x, -pin_force.y, bearing_moment),
        pin: Vector3::new(pin_force.x, pin_force.y, pin_moment),
        diagnostics: diagnostics(kin, bearing_body, pin_body, &loads),
    }
}

/// Partials of the positional quantities with respect to the twelve coordinates.
struct PositionPartials {
    /// `∂|e|`.
    d_rho: Row,
    /// `∂φ`.
    d_phi: Row,
    /// `∂R_i` through the body-frame angle `φ − θ_i`.
    d_bearing_radius: Row,
    /// `∂R_j` through `φ − θ_j`.
    d_pin_radius: Row,
}

impl PositionPartials {
    #[inline]
    fn new(geometry: &Geometry) -> Self {
        let n = geometry.normal;
        let t = perp(&n);
        let mut d_ecc = Rows2::zeros();
        d_ecc[(0, 0)] = -1.0;
        d_ecc[(1, 1)] = -1.0;
        d_ecc.set_column(COL_THETA_I, &-perp(&geometry.bearing_centre_arm));
        d_ecc[(0, 3)] = 1.0;
        d_ecc[(1, 4)] = 1.0;
        d_ecc.set_column(COL_THETA_J, &perp(&geometry.pin_centre_arm));
        let d_rho: Row = n.transpose() * d_ecc;
        let d_phi: Row = t.transpose() * d_ecc / geometry.eccentricity_norm;
        let mut d_bearing_radius = d_phi * geometry.bearing.slope;
        d_bearing_radius[COL_THETA_I] -= geometry.bearing.slope;
        let mut d_pin_radius = d_phi * geometry.pin.slope;
        d_pin_radius[COL_THETA_J] -= geometry.pin.slope;
        Self {
            d_rho,
            d_phi,
            d_bearing_radius,
            d_pin_radius,
        }
    }
}

/// The arms from the centroids to the contact points `r^c + R n` and the material relative
/// velocity there, with their partials.
struct ArmPartials {
    bearing_arm: Vector2<f64>,
    pin_arm: Vector2<f64>,
    d_bearing_arm: Rows2,
    d_pin_arm: Rows2,
    d_relative_velocity: Rows2,
}

impl ArmPartials {
    #[inline]
    fn new(
        geometry: &Geometry,
        kin: &JointKinematics,
        bearing_body: &BodyState,
        pin_body: &BodyState,
        p: &PositionPartials,
    ) -> Self {
        let (n, t) = (kin.normal, kin.tangent);
        let bearing_arm = kin.bearing_point - bearing_body.position();
        let pin_arm = kin.pin_point - pin_body.position();
        let d_bearing_arm = arm_partials(
            &geometry.bearing_centre_arm,
            COL_THETA_I,
            &n,
            &t,
            kin.bearing.radius,
            &p.d_bearing_radius,
            &p.d_phi,
        );
        let d_pin_arm = arm_partials(
            &geometry.pin_centre_arm,
            COL_THETA_J,
            &n,
            &t,
            kin.pin.radius,
            &p.d_pin_radius,
            &p.d_phi,
        );
        let mut d_rel_vel = rotate_columns(&d_pin_arm) * pin_body.omega
            - rotate_columns(&d_bearing_arm) * bearing_body.omega;
        d_rel_vel[(0, COL_VEL_I)] -= 1.0;
        d_rel_vel[(1, COL_VEL_I + 1)] -= 1.0;
        d_rel_vel.set_column(COL_VEL_I + 2, &-perp(&bearing_arm));
        d_rel_vel[(0, COL_VEL_J)] += 1.0;
        d_rel_vel[(1, COL_VEL_J + 1)] += 1.0;
        d_rel_vel.set_column(COL_VEL_J + 2, &perp(&pin_arm));
        Self {
            bearing_arm,
            pin_arm,
            d_bearing_arm,
            d_pin_arm,
            d_relative_velocity: d_rel_vel,
        }
    }
}

/// z component of `a × b`.
#[inline]
fn cross(a: &Vector2<f64>, b: &Vector2<f64>) -> f64 {
    a.x * b.y - a.y * b.x
}

/// Every column turned by +90°.
#[inline]
fn rotate_columns(d: &Rows2) -> Rows2 {
    Matrix2::new(0.0, -1.0, 1.0, 0.0) * d
}

/// Partials of a contact arm `A(θ) s + R n` (centroid to contact point).
#[inline]
fn arm_partials(
    centre_arm: &Vector2<f64>,
    theta_column: usize,
    n: &Vector2<f64>,
    t: &Vector2<f64>,
    radius: f64,
    d_radius: &Row,
    d_phi: &Row,
) -> Rows2 {
    // dn = t dφ.
    let mut d_arm: Rows2 = n * d_radius + t * (d_phi * radius);
    let turned = perp(centre_arm);
    d_arm[(0, theta_column)] += turned.x;
    d_arm[(1, theta_column)] += turned.y;
    d_arm
}

/// Partials of the moment `b × f`.
#[inline]
fn moment_partials(
    arm: &Vector2<f64>,
    d_arm: &Rows2,
    force: &Vector2<f64>,
    d_force: &Rows2,
) -> Row {
    d_arm.row(0) * force.y - d_arm.row(1) * force.x + d_force.row(1) * arm.x
        - d_force.row(0) * arm.y
}
