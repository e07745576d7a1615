//! The kinematics of the line of centres at one state ([`ContactPair::kinematics`]): the
//! eccentricity, the contact direction, the local radii there, the penetration and the contact
//! points' velocities. The line-of-centres models are built on it, and the joint reports it.

use nalgebra::Vector2;

use super::pair::ContactPair;
use super::types::{BodyState, Geometry, JointKinematics};
use crate::surface::SurfaceProfile;

impl<B: SurfaceProfile, P: SurfaceProfile, N, F> ContactPair<B, P, N, F> {
    /// Full kinematics of the line of centres at the given states.
    pub fn kinematics(&self, bearing_body: &BodyState, pin_body: &BodyState) -> JointKinematics {
        let geometry = self.geometry(bearing_body, pin_body);
        kinematics_from(&geometry, bearing_body, pin_body)
    }

    /// The positional part of the kinematics: what the event function needs.
    pub(super) fn geometry(&self, bearing_body: &BodyState, pin_body: &BodyState) -> Geometry {
        let bearing_centre_arm = bearing_body.rotate(&self.bearing_centre);
        let pin_centre_arm = pin_body.rotate(&self.pin_centre);
        let eccentricity =
            pin_body.position() + pin_centre_arm - bearing_body.position() - bearing_centre_arm;
        let eccentricity_norm = eccentricity.norm();
        let normal = if eccentricity_norm > 0.0 {
            eccentricity / eccentricity_norm
        } else {
            Vector2::x()
        };
        let contact_angle = normal.y.atan2(normal.x);
        let bearing = self
            .bearing_profile
            .sample(contact_angle - bearing_body.theta);
        let pin = self.pin_profile.sample(contact_angle - pin_body.theta);
        Geometry {
            bearing_centre_arm,
            pin_centre_arm,
            eccentricity,
            eccentricity_norm,
            normal,
            contact_angle,
            bearing,
            pin,
            penetration: eccentricity_norm - (bearing.radius - pin.radius),
        }
    }
}

/// The full kinematics from the positional part and the bodies' velocities.
pub(super) fn kinematics_from(
    geometry: &Geometry,
    bearing_body: &BodyState,
    pin_body: &BodyState,
) -> JointKinematics {
    let n = geometry.normal;
    let t = perp(&n);
    let bearing_point =
        bearing_body.position() + geometry.bearing_centre_arm + n * geometry.bearing.radius;
    let pin_point = pin_body.position() + geometry.pin_centre_arm + n * geometry.pin.radius;
    let bearing_point_velocity = bearing_body.velocity()
        + perp(&(bearing_point - bearing_body.position())) * bearing_body.omega;
    let pin_point_velocity =
        pin_body.velocity() + perp(&(pin_point - pin_body.position())) * pin_body.omega;
    let relative_velocity = pin_point_velocity - bearing_point_velocity;
    let eccentricity_rate = pin_body.velocity() + perp(&geometry.pin_centre_arm) * pin_body.omega
        - bearing_body.velocity()
        - perp(&geometry.bearing_centre_arm) * bearing_body.omega;
    JointKinematics {
        eccentricity: geometry.eccentricity,
        eccentricity_norm: geometry.eccentricity_norm,
        normal: n,
        tangent: t,
        contact_angle: geometry.contact_angle,
        bearing: geometry.bearing,
        pin: geometry.pin,
        penetration: geometry.penetration,
        bearing_point,
        pin_point,
        bearing_point_velocity,
        pin_point_velocity,
        eccentricity_rate,
        normal_velocity: relative_velocity.dot(&n),
        tangential_velocity: relative_velocity.dot(&t),
    }
}

/// `v` turned by +90°.
#[inline]
pub(super) fn perp(v: &Vector2<f64>) -> Vector2<f64> {
    Vector2::new(-v.y, v.x)
}
