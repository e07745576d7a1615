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
    let size = angle.abs();
    if !(size < 2.0 * TAU) || size == TAU {
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
    // 2^52: from here on every f64 is an integer (and NaN and infinities fail the test).
    if !(x.abs() < 4_503_599_627_370_496.0) {
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

/// `atan(j/64)` for `j = 0..=64` (rounded to nearest).
const ATAN_64THS: [f64; 65] = [
    0.0,
    0.015623728620476831,
    0.031239833430268277,
    0.046840712915969654,
    0.06241880999595735,
    0.0779666338315423,
    0.09347678115858947,
    0.10894195698986579,
    0.12435499454676144,
    0.13970887428916365,
    0.15499674192394097,
    0.1702119252854744,
    0.18534794999569476,
    0.2003985538258785,
    0.21535769969773805,
    0.23021958727684372,
    0.24497866312686414,
    0.2596296294082575,
    0.2741674511196588,
    0.2885873618940774,
    0.3028848683749714,
    0.31705575320914703,
    0.3310960767041321,
    0.34500217720710513,
    0.35877067027057225,
    0.3723984466767542,
    0.38588266939807375,
    0.39922076957525254,
    0.4124104415973873,
    0.42544963737004227,
    0.43833655985795783,
    0.4510696559885235,
    0.4636476090008061,
    0.4760693303227612,
    0.48833395105640554,
    0.5004408131472942,
    0.5123894603107377,
    0.5241796287829132,
    0.5358112379604637,
    0.5472843809874369,
    0.5585993153435624,
    0.5697564534829784,
    0.5807563535676704,
    0.5915997103351114,
    0.6022873461349642,
    0.6128202021652414,
    0.6231993299340659,
    0.6334258829691446,
    0.6435011087932844,
    0.6534263411807619,
    0.6632029927060933,
    0.6728325475937632,
    0.6823165548747481,
    0.6916566218531999,
    0.7008544078844502,
    0.7099116184635249,
    0.7188299996216245,
    0.7276113326265107,
    0.7362574289814281,
    0.7447701257160751,
    0.7531512809621944,
    0.7614027698055784,
    0.7695264804056583,
    0.7775243103733478,
    0.7853981633974483,
];

/// `y.atan2(x)` to within 2 ulp of the exact angle, in about a quarter of libm's instructions.
///
/// The foundation contact takes the ray angle of every node it computes (hundreds per
/// evaluation on worn surfaces), where libm's correctly rounded `atan2` was a fifth of a
/// worn cycle. `atan(t)` for `t = min/max(|x|, |y|)` is `atan(c) + atan((t − c)/(1 + tc))`
/// with `c` the nearest 64th, whose arctangent is tabulated, and `|(t − c)/(1 + tc)| ≤ 1/128`,
/// where five terms of the series leave less than 1e-24; `t − c` is exact (Sterbenz). Zero,
/// infinite and NaN arguments take libm's `atan2`, so the special values are its own.
#[inline]
pub fn ray_angle(y: f64, x: f64) -> f64 {
    let (ax, ay) = (x.abs(), y.abs());
    let (small, big) = if ay > ax { (ax, ay) } else { (ay, ax) };
    if !(big < f64::INFINITY && small > 0.0) {
        return y.atan2(x);
    }
    let t = small / big;
    let j = (t * 64.0 + 0.5) as usize;
    let c = j as f64 / 64.0;
    let z = (t - c) / (1.0 + t * c);
    let z2 = z * z;
    let series = z - z * z2 * (1.0 / 3.0 - z2 * (1.0 / 5.0 - z2 * (1.0 / 7.0 - z2 / 9.0)));
    let mut angle = ATAN_64THS[j] + series;
    if ay > ax {
        angle = std::f64::consts::FRAC_PI_2 - angle;
    }
    if x < 0.0 {
        angle = std::f64::consts::PI - angle;
    }
    angle.copysign(y)
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

    /// The ray angle agrees with libm's `atan2` to 2 ulp in every octant and at the octants'
    /// edges, and takes its special values from it.
    #[test]
    fn ray_angle_matches_atan2() {
        use super::ray_angle;
        let ulps = |a: f64, b: f64| (a - b).abs() / f64::EPSILON / b.abs().max(f64::MIN_POSITIVE);
        let mut worst: f64 = 0.0;
        let mut state = 0x2545_f491_4f6c_dd1d_u64;
        let mut next = || {
            // xorshift64*: reproducible uniform numbers without a dependency.
            state ^= state >> 12;
            state ^= state << 25;
            state ^= state >> 27;
            (state.wrapping_mul(0x2545_f491_4f6c_dd1d) >> 11) as f64 / (1u64 << 53) as f64
        };
        for _ in 0..400_000 {
            let angle = (next() - 0.5) * 2.0 * std::f64::consts::PI;
            let radius = 1e-3 * (1.0 + 1e3 * next());
            let (y, x) = (radius * angle.sin(), radius * angle.cos());
            worst = worst.max(ulps(ray_angle(y, x), y.atan2(x)));
        }
        for k in 0..=64 {
            for (y, x) in [(k as f64, 64.0), (64.0, k as f64), (-(k as f64), -64.0)] {
                let near = [y, y.next_up(), y.next_down()];
                for y in near {
                    worst = worst.max(ulps(ray_angle(y, x), y.atan2(x)));
                }
            }
        }
        assert!(worst <= 2.0, "{worst} ulp");
        for (y, x) in [
            (0.0, 1.0),
            (-0.0, 1.0),
            (0.0, -1.0),
            (-0.0, -1.0),
            (1.0, 0.0),
            (-1.0, -0.0),
            (0.0, 0.0),
            (f64::INFINITY, 1.0),
            (1.0, f64::NEG_INFINITY),
            (1e-320, 1.0),
        ] {
            assert_eq!(ray_angle(y, x).to_bits(), y.atan2(x).to_bits(), "{y} {x}");
        }
        assert!(ray_angle(f64::NAN, 1.0).is_nan());
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
