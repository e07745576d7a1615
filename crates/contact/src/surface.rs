//! Surface profiles: the radius of a pin or bearing as a function of the body-frame angle.
//!
//! A constant-radius bearing and a worn one (see the `wear` crate) share one contact code path
//! through [`SurfaceProfile`]. The angle is measured in the frame of the body that carries the
//! surface, from that body's local x axis, counter-clockwise: a global contact direction at angle
//! `φ` meets the surface of a body turned by `θ` at body-frame angle `φ − θ`.

use std::f64::consts::TAU;

/// `angle.rem_euclid(2π)`, bit for bit, cheaply for `|angle| < 4π`.
///
/// `f64::rem_euclid` calls `fmod`, a software routine of ~100 instructions on the baseline
/// x86-64 target, and the contact kernels wrap an angle per node. Below `4π` the remainder is
/// one exact subtraction (Sterbenz), so this gives `fmod`'s result, sign of zero included;
/// other angles take `rem_euclid` itself.
#[inline]
pub fn wrap_angle(angle: f64) -> f64 {
    // The common cases first (the same results as below, −0.0 included): a ray angle less a
    // body angle, or an angle already wrapped.
    if (0.0..TAU).contains(&angle) {
        return angle;
    }
    if angle < 0.0 && angle > -TAU {
        return angle + TAU;
    }
    let size = angle.abs();
    if size.is_nan() || size >= 2.0 * TAU || size == TAU {
        return angle.rem_euclid(TAU);
    }
    let remainder = if size > TAU {
        angle - TAU.copysign(angle)
    } else {
        angle
    };
    if remainder < 0.0 {
        remainder + TAU
    } else {
        remainder
    }
}

/// `x.floor()`, bit for bit, without the call to a software `floor` that the baseline x86-64
/// target (no SSE4.1 `roundsd`) makes: the spline and sector lookups floor once per node.
#[inline]
pub fn floor(x: f64) -> f64 {
    // 2^52: from here on every f64 is an integer.
    if x.is_nan() || x.abs() >= 4_503_599_627_370_496.0 {
        return x.floor();
    }
    let truncated = x as i64 as f64;
    if truncated == x {
        // An integer is its own floor, −0.0 included.
        x
    } else if truncated > x {
        truncated - 1.0
    } else {
        truncated
    }
}

/// Radius and slope of a surface at one body-frame angle.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct RadiusSample {
    /// Surface radius at the angle (m).
    pub radius: f64,
    /// Derivative of the radius with respect to the body-frame angle (m/rad). It enters the
    /// exact Jacobian of the contact force, so it must be the true derivative of `radius`.
    pub slope: f64,
    /// Second derivative of the radius with respect to the angle (m/rad²). On a non-round
    /// surface the energy-consistent contact force contains the slope, so its exact Jacobian
    /// needs this; it must be the true derivative of `slope`.
    pub curvature: f64,
}

/// Radius of a circular-ish surface as a smooth, 2π-periodic function of the body-frame angle.
///
/// Implementations must accept any finite angle (not only `[0, 2π)`) and must be continuous,
/// with a continuous slope and curvature, everywhere including across 0/2π: a stiff integrator
/// must not see a jump.
pub trait SurfaceProfile {
    /// Radius, slope and curvature at body-frame angle `angle` (rad).
    fn sample(&self, angle: f64) -> RadiusSample;

    /// Whether the radius is constant at every angle. A joint whose two surfaces are round takes
    /// the cheaper round-surface code path; `false` (the default) is always correct.
    fn is_round(&self) -> bool {
        false
    }

    /// The smallest and largest radius over the whole surface, or bounds on them (the first no
    /// larger than the true smallest, the second no smaller than the true largest). `None`
    /// (the default): unknown, and the foundation contact then visits every node of the pin.
    fn radius_bounds(&self) -> Option<(f64, f64)> {
        None
    }

    /// Bounds on the radius over the body-frame angles `[start, end]` (`end ≥ start`, any
    /// finite angles, the range may wrap): the foundation contact skips the parts of the
    /// outlines that cannot touch with them. The default is the whole surface's bounds.
    fn radius_bounds_between(&self, _start: f64, _end: f64) -> Option<(f64, f64)> {
        self.radius_bounds()
    }

    /// A bound on the slope `|dR/dθ|` over the whole surface (m/rad), or `None` (the default)
    /// when unknown. With it on the bearing, the foundation contact reuses an earlier
    /// evaluation's overlaps to skip the nodes that cannot have reached the bearing since (the
    /// results are the same bit for bit, only cheaper).
    fn slope_bound(&self) -> Option<f64> {
        None
    }
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
            curvature: 0.0,
        }
    }

    fn is_round(&self) -> bool {
        true
    }

    fn radius_bounds(&self) -> Option<(f64, f64)> {
        Some((self.radius, self.radius))
    }

    fn slope_bound(&self) -> Option<f64> {
        Some(0.0)
    }
}

impl<P: SurfaceProfile + ?Sized> SurfaceProfile for &P {
    #[inline]
    fn sample(&self, angle: f64) -> RadiusSample {
        (**self).sample(angle)
    }

    fn is_round(&self) -> bool {
        (**self).is_round()
    }

    fn radius_bounds(&self) -> Option<(f64, f64)> {
        (**self).radius_bounds()
    }

    fn radius_bounds_between(&self, start: f64, end: f64) -> Option<(f64, f64)> {
        (**self).radius_bounds_between(start, end)
    }

    fn slope_bound(&self) -> Option<f64> {
        (**self).slope_bound()
    }
}

#[cfg(test)]
mod tests {
    use super::{floor, wrap_angle};
    use proptest::prelude::*;
    use std::f64::consts::TAU;

    #[test]
    fn wrap_and_floor_match_std_at_the_edges() {
        let edges = [
            0.0,
            -0.0,
            TAU,
            -TAU,
            2.0 * TAU,
            -2.0 * TAU,
            TAU.next_up(),
            TAU.next_down(),
            (-TAU).next_up(),
            (-TAU).next_down(),
            (2.0 * TAU).next_down(),
            (-2.0 * TAU).next_up(),
            1e-300,
            -1e-300,
            0.5,
            -0.5,
            -1.0,
            4_503_599_627_370_495.5,
            -4_503_599_627_370_495.5,
            1e17,
            -1e17,
            f64::INFINITY,
            f64::NEG_INFINITY,
        ];
        for x in edges {
            assert_eq!(wrap_angle(x).to_bits(), x.rem_euclid(TAU).to_bits(), "{x}");
            assert_eq!(floor(x).to_bits(), x.floor().to_bits(), "{x}");
        }
        assert!(wrap_angle(f64::NAN).is_nan() && floor(f64::NAN).is_nan());
    }

    proptest! {
        #[test]
        fn wrap_and_floor_match_std(x in -30.0..30.0f64, scale in -20i32..20) {
            let x = x * 2f64.powi(scale);
            prop_assert_eq!(wrap_angle(x).to_bits(), x.rem_euclid(TAU).to_bits());
            prop_assert_eq!(floor(x).to_bits(), x.floor().to_bits());
        }
    }
}
