//! A linear spring on the line of centres: the test model of the [`ContactModel`] interface.
//!
//! The pin's centre is pushed back along the line of centres by `F = k δ` while the
//! penetration `δ = |e| − c` is positive (`c` the local clearance in the contact direction),
//! applied at the two journal centres so that the pair of forces has no net moment. It stores
//! `V = k δ²/2`, has no damping and no friction (the joint's normal and friction laws are not
//! used), and is exact on round surfaces: its Jacobian holds the local clearance fixed, which
//! is exact only where the profiles are round. It exists to show, and to test, that a model is
//! one module implementing [`ContactModel`] plus its scene value (docs/architecture.md): it
//! uses only the public API of [`ContactPair`], as a model written outside this crate would.
//! It is no model of a real joint: a linear penalty law has neither Hertz's stiffening nor the
//! conformal contact of a worn bearing.

use nalgebra::{Matrix2, Vector2};

use super::model::{ContactKernel, ContactModel, ModelState, ValidityMeasure, Visit};
use super::pair::ContactPair;
use super::types::{BodyState, ContactForces, ContactJacobian, JointKinematics, JointState};
use crate::diagnostics::ContactDiagnostics;
use crate::error::{ContactError, positive};
use crate::friction::FrictionLaw;
use crate::normal::NormalLaw;
use crate::surface::SurfaceProfile;

/// The linear-spring contact model: stiffness `k` (N/m).
#[derive(Clone, Copy, Debug, PartialEq, serde::Serialize, serde::Deserialize)]
pub struct LinearSpring {
    stiffness: f64,
}

impl LinearSpring {
    /// A spring of stiffness `k` (N/m, finite and > 0).
    pub fn new(stiffness: f64) -> Result<Self, ContactError> {
        positive("stiffness", stiffness)?;
        Ok(Self { stiffness })
    }

    /// The stiffness `k` (N/m).
    pub fn stiffness(&self) -> f64 {
        self.stiffness
    }

    /// The forces at the given states and, when asked for, their partials into `jacobian`
    /// (left zero apart): the right-hand side computes no partials.
    fn evaluate<B: SurfaceProfile, P: SurfaceProfile, N: NormalLaw, F: FrictionLaw>(
        &self,
        pair: &ContactPair<B, P, N, F>,
        at: JointState,
        jacobian: Option<&mut ContactJacobian>,
    ) -> ContactForces {
        let (bearing_body, pin_body) = (at.bearing, at.pin);
        let kin = pair.kinematics(bearing_body, pin_body);
        let arm = |body: &BodyState, centre: [f64; 2]| {
            let (s, c) = body.theta.sin_cos();
            Vector2::new(c * centre[0] - s * centre[1], s * centre[0] + c * centre[1])
        };
        let bearing_arm = arm(bearing_body, pair.bearing_centre());
        let pin_arm = arm(pin_body, pair.pin_centre());
        let depth = kin.penetration;
        let mut diagnostics = ContactDiagnostics {
            in_contact: depth >= 0.0,
            penetration: depth,
            eccentricity: kin.eccentricity_norm,
            contact_angle: kin.contact_angle,
            bearing_radius: kin.bearing.radius,
            pin_radius: kin.pin.radius,
            normal_velocity: kin.normal_velocity,
            tangential_velocity: kin.tangential_velocity,
            contact_point: [kin.bearing_point.x, kin.bearing_point.y],
            ..ContactDiagnostics::default()
        };
        if depth < 0.0 {
            return ContactForces {
                diagnostics,
                ..ContactForces::default()
            };
        }
        let n = kin.normal;
        let magnitude = self.stiffness * depth;
        let pin_force = -n * magnitude;
        diagnostics.normal_force = magnitude;
        diagnostics.elastic_force = magnitude;
        diagnostics.elastic_energy = 0.5 * self.stiffness * depth * depth;
        if let Some(jacobian) = jacobian {
            self.partials(&kin, bearing_arm, pin_arm, pin_force, jacobian);
        }
        ContactForces {
            bearing: nalgebra::Vector3::new(
                -pin_force.x,
                -pin_force.y,
                cross(&bearing_arm, &-pin_force),
            ),
            pin: nalgebra::Vector3::new(pin_force.x, pin_force.y, cross(&pin_arm, &pin_force)),
            diagnostics,
        }
    }

    /// The partials of the forces on both bodies into `jacobian` ([`ContactJacobian`]'s
    /// layout), in contact at `kin`, the pin's force `pin_force`.
    fn partials(
        &self,
        kin: &JointKinematics,
        bearing_arm: Vector2<f64>,
        pin_arm: Vector2<f64>,
        pin_force: Vector2<f64>,
        jacobian: &mut ContactJacobian,
    ) {
        let (n, depth) = (kin.normal, kin.penetration);
        // F = −k (e − c n) with the local clearance c held fixed:
        // ∂F/∂e = −k (I − (c/|e|)(I − n nᵀ)).
        let clearance = kin.eccentricity_norm - depth;
        let d_force_d_e = -self.stiffness
            * (Matrix2::identity()
                - (Matrix2::identity() - n * n.transpose()) * (clearance / kin.eccentricity_norm));
        // Columns of ∂e/∂q: x_i, y_i, θ_i, x_j, y_j, θ_j.
        let d_e = [
            Vector2::new(-1.0, 0.0),
            Vector2::new(0.0, -1.0),
            -perp(&bearing_arm),
            Vector2::new(1.0, 0.0),
            Vector2::new(0.0, 1.0),
            perp(&pin_arm),
        ];
        for (column, d) in d_e.iter().enumerate() {
            let d_pin_force = d_force_d_e * d;
            // The arms turn with their own body's angle only.
            let d_pin_arm = if column == 5 {
                perp(&pin_arm)
            } else {
                Vector2::zeros()
            };
            let d_bearing_arm = if column == 2 {
                perp(&bearing_arm)
            } else {
                Vector2::zeros()
            };
            jacobian[(0, column)] = -d_pin_force.x;
            jacobian[(1, column)] = -d_pin_force.y;
            jacobian[(2, column)] =
                cross(&d_bearing_arm, &-pin_force) + cross(&bearing_arm, &-d_pin_force);
            jacobian[(3, column)] = d_pin_force.x;
            jacobian[(4, column)] = d_pin_force.y;
            jacobian[(5, column)] = cross(&d_pin_arm, &pin_force) + cross(&pin_arm, &d_pin_force);
        }
    }
}

impl ContactModel for LinearSpring {
    /// Reads the outlines directly: no tables, no workspace.
    type Tables = ();
    type Workspace = ();

    fn name(&self) -> &'static str {
        "linear-spring"
    }

    fn tables<B: SurfaceProfile, P: SurfaceProfile, N, F>(&self, _: &ContactPair<B, P, N, F>) {}

    /// Exact on round surfaces only: judged by the profile slope at its contacts.
    fn validity_measures(&self) -> &'static [ValidityMeasure] {
        &[ValidityMeasure::SlopeRatio]
    }
}

impl<B: SurfaceProfile, P: SurfaceProfile, N: NormalLaw, F: FrictionLaw> ContactKernel<B, P, N, F>
    for LinearSpring
{
    fn forces(
        &self,
        pair: &ContactPair<B, P, N, F>,
        _: ModelState<'_, Self>,
        at: JointState,
        _: Visit,
    ) -> ContactForces {
        self.evaluate(pair, at, None)
    }

    fn forces_and_jacobian(
        &self,
        pair: &ContactPair<B, P, N, F>,
        _: ModelState<'_, Self>,
        at: JointState,
    ) -> (ContactForces, ContactJacobian) {
        let mut jacobian = ContactJacobian::zeros();
        let forces = self.evaluate(pair, at, Some(&mut jacobian));
        (forces, jacobian)
    }

    fn penetration(
        &self,
        pair: &ContactPair<B, P, N, F>,
        _: ModelState<'_, Self>,
        at: JointState,
    ) -> f64 {
        pair.kinematics(at.bearing, at.pin).penetration
    }
}

/// `v` turned by +90°.
fn perp(v: &Vector2<f64>) -> Vector2<f64> {
    Vector2::new(-v.y, v.x)
}

/// z component of `a × b`.
fn cross(a: &Vector2<f64>, b: &Vector2<f64>) -> f64 {
    a.x * b.y - a.y * b.x
}
