//! What a contact model is evaluated on: the two outlines on their bodies, their materials,
//! the normal and friction laws and which sliding the friction sees — everything of a
//! clearance joint but its contact model ([`super::ContactModel`]).

use nalgebra::Vector2;

use super::types::{JointSurface, SlidingVelocity};
use crate::error::{ContactError, finite, positive};
use crate::material::Material;
use crate::surface::SurfaceProfile;

/// Angles at which a joint's profiles are checked on construction.
const VALIDATION_SAMPLES: usize = 64;

/// A bearing on body *i* and a pin on body *j* with their materials and laws: what a
/// [`super::ContactModel`] evaluates. A [`super::ClearanceJoint`] is a pair and a model.
#[derive(Clone, Debug, PartialEq)]
pub struct ContactPair<B, P, N, F> {
    pub(super) bearing_centre: Vector2<f64>,
    pub(super) pin_centre: Vector2<f64>,
    pub(super) bearing_profile: B,
    pub(super) pin_profile: P,
    pub(super) bearing_material: Material,
    pub(super) pin_material: Material,
    /// `4/(3(ε_i + ε_j))`: the stiffness is this times `√R`.
    pub(super) modulus_factor: f64,
    pub(super) normal_law: N,
    pub(super) friction_law: F,
    /// Which sliding velocity the friction law sees.
    pub(super) friction_sliding: SlidingVelocity,
}

impl<B: SurfaceProfile, P: SurfaceProfile, N, F> ContactPair<B, P, N, F> {
    /// A pair, validated: finite centres, and profiles that are finite, positive and leave a
    /// positive clearance in every direction (checked on 64 angles per surface: the smallest
    /// bearing radius must exceed the largest pin radius).
    pub(super) fn new(
        bearing: JointSurface<B>,
        pin: JointSurface<P>,
        normal_law: N,
        friction_law: F,
    ) -> Result<Self, ContactError> {
        for (parameter, value) in [
            ("bearing centre x", bearing.centre[0]),
            ("bearing centre y", bearing.centre[1]),
            ("pin centre x", pin.centre[0]),
            ("pin centre y", pin.centre[1]),
        ] {
            finite(parameter, value)?;
        }
        validate_profiles(&bearing.profile, &pin.profile)?;
        let compliance = bearing.material.compliance() + pin.material.compliance();
        Ok(Self {
            bearing_centre: Vector2::from(bearing.centre),
            pin_centre: Vector2::from(pin.centre),
            bearing_profile: bearing.profile,
            pin_profile: pin.profile,
            bearing_material: bearing.material,
            pin_material: pin.material,
            modulus_factor: 4.0 / (3.0 * compliance),
            normal_law,
            friction_law,
            friction_sliding: SlidingVelocity::Material,
        })
    }

    /// The same pair with new surface profiles (e.g. after a wear stage), validated again.
    pub(super) fn with_profiles<B2: SurfaceProfile, P2: SurfaceProfile>(
        self,
        bearing_profile: B2,
        pin_profile: P2,
    ) -> Result<ContactPair<B2, P2, N, F>, ContactError> {
        validate_profiles(&bearing_profile, &pin_profile)?;
        Ok(ContactPair {
            bearing_centre: self.bearing_centre,
            pin_centre: self.pin_centre,
            bearing_profile,
            pin_profile,
            bearing_material: self.bearing_material,
            pin_material: self.pin_material,
            modulus_factor: self.modulus_factor,
            normal_law: self.normal_law,
            friction_law: self.friction_law,
            friction_sliding: self.friction_sliding,
        })
    }

    /// The bearing centre in its body's frame (m).
    pub fn bearing_centre(&self) -> [f64; 2] {
        [self.bearing_centre.x, self.bearing_centre.y]
    }

    /// The pin centre in its body's frame (m).
    pub fn pin_centre(&self) -> [f64; 2] {
        [self.pin_centre.x, self.pin_centre.y]
    }

    /// The bearing's profile.
    pub fn bearing_profile(&self) -> &B {
        &self.bearing_profile
    }

    /// The pin's profile.
    pub fn pin_profile(&self) -> &P {
        &self.pin_profile
    }

    /// The bearing and pin materials.
    pub fn materials(&self) -> (Material, Material) {
        (self.bearing_material, self.pin_material)
    }

    /// The normal law.
    pub fn normal_law(&self) -> &N {
        &self.normal_law
    }

    /// The friction law.
    pub fn friction_law(&self) -> &F {
        &self.friction_law
    }

    /// Hertz stiffness `K = 4/(3(ε_i + ε_j)) √(R_i R_j/(R_i − R_j))` for local radii (N/m^1.5).
    pub fn stiffness(&self, bearing_radius: f64, pin_radius: f64) -> f64 {
        let effective_radius = bearing_radius * pin_radius / (bearing_radius - pin_radius);
        self.modulus_factor * effective_radius.sqrt()
    }

    /// Which sliding velocity the friction law sees.
    pub fn friction_sliding(&self) -> SlidingVelocity {
        self.friction_sliding
    }
}

fn validate_profiles<B: SurfaceProfile, P: SurfaceProfile>(
    bearing: &B,
    pin: &P,
) -> Result<(), ContactError> {
    let mut smallest_bearing = (f64::INFINITY, 0.0);
    let mut largest_pin = (f64::NEG_INFINITY, 0.0);
    for k in 0..VALIDATION_SAMPLES {
        let angle = std::f64::consts::TAU * k as f64 / VALIDATION_SAMPLES as f64;
        let b = bearing.sample(angle);
        let p = pin.sample(angle);
        finite("bearing radius", b.radius)?;
        finite("bearing radius slope", b.slope)?;
        finite("pin radius", p.radius)?;
        finite("pin radius slope", p.slope)?;
        positive("pin radius", p.radius)?;
        if b.radius < smallest_bearing.0 {
            smallest_bearing = (b.radius, angle);
        }
        if p.radius > largest_pin.0 {
            largest_pin = (p.radius, angle);
        }
    }
    if smallest_bearing.0 > largest_pin.0 {
        Ok(())
    } else {
        Err(ContactError::NonPositiveClearance {
            bearing_radius: smallest_bearing.0,
            pin_radius: largest_pin.0,
            angle: smallest_bearing.1,
        })
    }
}
