//! A node's and a body's values in the kernel's arithmetic (plain or dual numbers), and the
//! small vector algebra they need.

use crate::joint::dual::Real;

/// The angle of `d`, given a vector `w` at a known angle `w_angle` close to it: `w_angle` plus
/// the small angle from `w` to `d` by its Taylor series where that is within 1/16 rad (its
/// truncation, the `z¹⁷/17` term, is below 1e-20 of the angle; the sum rounds like `atan2`'s
/// result), else `atan2`. The result may differ from `atan2`'s by a multiple of 2π.
#[inline]
pub(in crate::joint) fn angle_near(d: [f64; 2], w: [f64; 2], w_angle: f64) -> f64 {
    let along = w[0] * d[0] + w[1] * d[1];
    let across = w[0] * d[1] - w[1] * d[0];
    if !(along > 0.0 && across.abs() <= along * 0.0625) {
        return d[1].atan2(d[0]);
    }
    let z = across / along;
    let z2 = z * z;
    let series = 1.0
        + z2 * (-1.0 / 3.0
            + z2 * (1.0 / 5.0
                + z2 * (-1.0 / 7.0
                    + z2 * (1.0 / 9.0
                        + z2 * (-1.0 / 11.0 + z2 * (1.0 / 13.0 + z2 * (-1.0 / 15.0)))))));
    w_angle + z * series
}

/// The positional and kinematic values of one node.
#[derive(Clone, Copy)]
pub(in crate::joint) struct Node<T> {
    pub(in crate::joint) cell: usize,
    pub(in crate::joint) alpha: f64,
    /// Overlap `g_k` (m; negative: apart).
    pub(in crate::joint) g: T,
    /// `m_k = n_k − (R_i'/ρ_k) t_k`.
    pub(in crate::joint) m: [T; 2],
    /// `ġ_k`.
    pub(in crate::joint) g_rate: T,
    /// Relative velocity of the pin's material point at `P_k` on the bearing's.
    pub(in crate::joint) relative_velocity: [T; 2],
    /// `P_k` from the pin body's centroid.
    pub(in crate::joint) pin_arm: [T; 2],
    /// `P_k` from the bearing body's centroid.
    pub(in crate::joint) bearing_arm: [T; 2],
    /// `D_k`, whose angle less `θ_i` is where the node meets the bearing.
    pub(in crate::joint) ray: [f64; 2],
    /// `ψ_k − θ_i` (rad, unwrapped) when it was needed for the node (else found from `ray`).
    pub(in crate::joint) bearing_angle: Option<f64>,
    /// The overlap as `ContactPair::overlap_at` gives it (m): `g_k`, or the distance
    /// below the bearing's smallest radius where the node cannot touch.
    pub(in crate::joint) overlap: f64,
    /// Whether the node lies beyond the bearing's smallest radius (`overlap` is `g_k`).
    pub(in crate::joint) beyond: bool,
}

/// One body's position and velocity in the kernel's arithmetic.
#[derive(Clone, Copy)]
pub(in crate::joint) struct Body<T> {
    pub(in crate::joint) position: [T; 2],
    /// The rotation's plain value (rad).
    pub(in crate::joint) theta: f64,
    pub(in crate::joint) theta_sin_cos: (T, T),
    pub(in crate::joint) velocity: [T; 2],
    pub(in crate::joint) omega: T,
}

impl<T: Real> Body<T> {
    pub(in crate::joint) fn new(state: [T; 6]) -> Self {
        Self {
            position: [state[0], state[1]],
            theta: state[2].value(),
            theta_sin_cos: state[2].sin_cos(),
            velocity: [state[3], state[4]],
            omega: state[5],
        }
    }

    /// A body-fixed vector turned into the global frame.
    #[inline]
    pub(in crate::joint) fn rotate(&self, local: [f64; 2]) -> [T; 2] {
        let (s, c) = self.theta_sin_cos;
        [c * local[0] - s * local[1], s * local[0] + c * local[1]]
    }

    /// Velocity of the material point at `arm` from the centroid.
    #[inline]
    pub(in crate::joint) fn point_velocity(&self, arm: &[T; 2]) -> [T; 2] {
        [
            self.velocity[0] - self.omega * arm[1],
            self.velocity[1] + self.omega * arm[0],
        ]
    }
}

/// The point at `pin_arm` from the pin body's centroid, seen from the point at `bearing_arm`
/// from the bearing body's.
#[inline]
pub(in crate::joint) fn offset<T: Real>(
    pin: &Body<T>,
    pin_arm: &[T; 2],
    bearing: &Body<T>,
    bearing_arm: &[T; 2],
) -> [T; 2] {
    [
        pin.position[0] + pin_arm[0] - bearing.position[0] - bearing_arm[0],
        pin.position[1] + pin_arm[1] - bearing.position[1] - bearing_arm[1],
    ]
}

#[inline]
pub(in crate::joint) fn dot<T: Real>(a: &[T; 2], b: &[T; 2]) -> T {
    a[0] * b[0] + a[1] * b[1]
}

#[inline]
pub(in crate::joint) fn cross<T: Real>(a: &[T; 2], b: &[T; 2]) -> T {
    a[0] * b[1] - a[1] * b[0]
}

#[cfg(test)]
mod tests {
    use super::angle_near;
    use rand::{Rng, SeedableRng};
    use std::f64::consts::{PI, TAU};

    /// A node's ray angle from the small-angle series agrees with `atan2` to rounding (modulo
    /// 2π) over random pins and eccentricities up to a tenth of the radius (past 1/16 rad it
    /// is `atan2` itself), and falls back to `atan2` where the node's own direction is far off.
    #[test]
    fn a_rays_angle_near_its_nodes_direction_matches_atan2() {
        let mut rng = rand_chacha::ChaCha8Rng::seed_from_u64(7);
        let mut worst: f64 = 0.0;
        let mut series = 0;
        for _ in 0..100_000 {
            let radius = rng.random_range(0.01..0.2);
            let turn = rng.random_range(-50.0..50.0);
            let w_angle: f64 = turn + rng.random_range(0.0..TAU);
            let w = [radius * w_angle.cos(), radius * w_angle.sin()];
            let (size, direction) = (
                rng.random_range(0.0..0.1 * radius),
                rng.random_range(0.0..TAU),
            );
            let d = [w[0] + size * direction.cos(), w[1] + size * direction.sin()];
            let near = angle_near(d, w, w_angle);
            let exact = d[1].atan2(d[0]);
            let apart = (near - exact + PI).rem_euclid(TAU) - PI;
            // The rounding of an angle of up to 56 rad (8 ulp there is 6e-14), not of the
            // small one.
            worst = worst.max(apart.abs());
            let z = (w[0] * d[1] - w[1] * d[0]) / (w[0] * d[0] + w[1] * d[1]);
            series += usize::from(z.abs() <= 0.0625);
        }
        assert!(worst < 6e-14, "worst {worst:e}");
        assert!(series > 50_000, "the series ran {series} times");
        // Opposite directions: atan2.
        assert_eq!(
            angle_near([-1.0, 1e-3], [1.0, 0.0], 0.0),
            1e-3_f64.atan2(-1.0)
        );
    }
}
