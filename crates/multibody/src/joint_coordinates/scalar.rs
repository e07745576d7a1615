//! The arithmetic the tree kinematics is written in: plain `f64` for the right-hand side, and a
//! first-order dual number for the exact derivatives of the kinematic terms (`∂J/∂z`,
//! `∂(J̇ż)/∂z`, `∂(J̇ż)/∂ż`) that the Jacobian needs. Forward-mode differentiation of the same
//! code cannot disagree with it, and needs no hand-derived third derivatives of the tree.

use std::ops::{Add, Mul, Neg, Sub};

/// A number the forward kinematics can be evaluated in.
pub(crate) trait Scalar:
    Copy + Add<Output = Self> + Sub<Output = Self> + Mul<Output = Self> + Neg<Output = Self>
{
    /// A constant (zero derivative).
    fn constant(value: f64) -> Self;
    /// `(sin x, cos x)`.
    fn sin_cos(self) -> (Self, Self);
}

impl Scalar for f64 {
    fn constant(value: f64) -> Self {
        value
    }
    fn sin_cos(self) -> (Self, Self) {
        f64::sin_cos(self)
    }
}

/// `v + d ε` with `ε² = 0`: the value and its derivative along one direction.
#[derive(Debug, Clone, Copy, Default, PartialEq)]
pub(crate) struct Dual {
    pub v: f64,
    pub d: f64,
}

impl Add for Dual {
    type Output = Self;
    fn add(self, o: Self) -> Self {
        Self {
            v: self.v + o.v,
            d: self.d + o.d,
        }
    }
}

impl Sub for Dual {
    type Output = Self;
    fn sub(self, o: Self) -> Self {
        Self {
            v: self.v - o.v,
            d: self.d - o.d,
        }
    }
}

impl Mul for Dual {
    type Output = Self;
    fn mul(self, o: Self) -> Self {
        Self {
            v: self.v * o.v,
            d: self.d * o.v + self.v * o.d,
        }
    }
}

impl Neg for Dual {
    type Output = Self;
    fn neg(self) -> Self {
        Self {
            v: -self.v,
            d: -self.d,
        }
    }
}

impl Scalar for Dual {
    fn constant(value: f64) -> Self {
        Self { v: value, d: 0.0 }
    }
    fn sin_cos(self) -> (Self, Self) {
        let (s, c) = self.v.sin_cos();
        (
            Self {
                v: s,
                d: c * self.d,
            },
            Self {
                v: c,
                d: -s * self.d,
            },
        )
    }
}

/// A planar vector.
pub(crate) type V2<T> = [T; 2];

pub(crate) fn add<T: Scalar>(a: V2<T>, b: V2<T>) -> V2<T> {
    [a[0] + b[0], a[1] + b[1]]
}

pub(crate) fn sub<T: Scalar>(a: V2<T>, b: V2<T>) -> V2<T> {
    [a[0] - b[0], a[1] - b[1]]
}

pub(crate) fn scale<T: Scalar>(k: T, a: V2<T>) -> V2<T> {
    [k * a[0], k * a[1]]
}

/// `a` turned +90° (`k × a`).
pub(crate) fn perp<T: Scalar>(a: V2<T>) -> V2<T> {
    [-a[1], a[0]]
}

/// `R(θ) s` for a constant body-frame vector `s`.
pub(crate) fn rotate<T: Scalar>(theta: T, s: [f64; 2]) -> V2<T> {
    let (sin, cos) = theta.sin_cos();
    let (x, y) = (T::constant(s[0]), T::constant(s[1]));
    [cos * x - sin * y, sin * x + cos * y]
}

pub(crate) fn lift<T: Scalar>(a: [f64; 2]) -> V2<T> {
    [T::constant(a[0]), T::constant(a[1])]
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn dual_numbers_differentiate_products_and_rotations() {
        // d/dx [x² sin x] at x = 0.7.
        let x = Dual { v: 0.7, d: 1.0 };
        let (s, _) = x.sin_cos();
        let f = x * x * s;
        let exact = 2.0 * 0.7 * 0.7_f64.sin() + 0.49 * 0.7_f64.cos();
        assert!((f.d - exact).abs() < 1e-15);
        let r = rotate(x, [0.3, -0.2]);
        let h = 1e-7;
        let numeric =
            (rotate(0.7 + h, [0.3, -0.2])[0] - rotate(0.7 - h, [0.3, -0.2])[0]) / (2.0 * h);
        assert!((r[0].d - numeric).abs() < 1e-9);
    }
}
