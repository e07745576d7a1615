//! Surface profiles: the radius of a pin or bearing as a function of the body-frame angle.
//!
//! A constant-radius bearing and a worn one (see the `wear` crate) share one contact code path
//! through [`SurfaceProfile`]. The angle is measured in the frame of the body that carries the
//! surface, from that body's local x axis, counter-clockwise: a global contact direction at angle
//! `φ` meets the surface of a body turned by `θ` at body-frame angle `φ − θ`.

/// Radius and slope of a surface at one body-frame angle.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct RadiusSample {
    /// Surface radius at the angle (m).
    pub radius: f64,
    /// Derivative of the radius with respect to the body-frame angle (m/rad). It enters the
    /// exact Jacobian of the contact force, so it must be the true derivative of `radius`.
    pub slope: f64,
}

/// Radius of a circular-ish surface as a smooth, 2π-periodic function of the body-frame angle.
///
/// Implementations must accept any finite angle (not only `[0, 2π)`) and must be continuous,
/// with a continuous slope, everywhere including across 0/2π: a stiff integrator must not see
/// a jump.
pub trait SurfaceProfile {
    /// Radius and slope at body-frame angle `angle` (rad).
    fn sample(&self, angle: f64) -> RadiusSample;
}

/// A perfectly round surface of constant radius: the unworn pin or bearing.
#[derive(Clone, Copy, Debug, PartialEq, serde::Serialize, serde::Deserialize)]
pub struct CircularProfile {
    /// Radius (m).
    pub radius: f64,
}

impl CircularProfile {
    /// A round surface of the given radius (m).
    pub fn new(radius: f64) -> Self {
        Self { radius }
    }
}

impl SurfaceProfile for CircularProfile {
    #[inline]
    fn sample(&self, _angle: f64) -> RadiusSample {
        RadiusSample {
            radius: self.radius,
            slope: 0.0,
        }
    }
}

impl<P: SurfaceProfile + ?Sized> SurfaceProfile for &P {
    #[inline]
    fn sample(&self, angle: f64) -> RadiusSample {
        (**self).sample(angle)
    }
}
