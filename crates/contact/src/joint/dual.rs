//! A scalar that is either a plain `f64` or a forward-mode dual number over the twelve body
//! coordinates of a joint, so one kernel gives the forces (with `f64`) and their exact
//! 6×12 Jacobian (with [`Dual`]) from the same lines of code.
//!
//! Only what the foundation and thin-gap kernels need is here: the four operations, `sqrt`,
//! `sin_cos`, `atan2`, [`Real::chain`] to apply a function whose value and derivative the
//! caller already knows (a surface profile's radius and slope, a contact law and its
//! partials), a body's coordinates as the variables ([`body_variables`]) and the Jacobian
//! gathered from the forces' partials ([`jacobian`]).

use std::ops::{Add, Div, Mul, Neg, Sub};

use crate::joint::types::{BodyState, ContactJacobian};

/// Number of independent variables: `[x_i, y_i, θ_i, x_j, y_j, θ_j]` then their rates.
pub(crate) const VARIABLES: usize = 12;

/// The arithmetic the foundation kernel is written in.
pub(crate) trait Real:
    Copy
    + Add<Output = Self>
    + Sub<Output = Self>
    + Mul<Output = Self>
    + Div<Output = Self>
    + Neg<Output = Self>
    + Add<f64, Output = Self>
    + Sub<f64, Output = Self>
    + Mul<f64, Output = Self>
    + Div<f64, Output = Self>
{
    /// Whether this is the plain `f64` (no partials): then computing a value costs no more
    /// than testing whether it is needed.
    const PLAIN: bool;
    /// A constant.
    fn constant(value: f64) -> Self;
    /// The value (the derivatives dropped).
    fn value(self) -> f64;
    fn sqrt(self) -> Self;
    fn sin_cos(self) -> (Self, Self);
    /// `atan2(self, x)`.
    fn atan2(self, x: Self) -> Self;
    /// `f(self)` for a function with value `f` and derivative `df` at `self.value()`.
    fn chain(self, f: f64, df: f64) -> Self;
    /// `f(self, other)` for a function with value `f` and partials `df_self`, `df_other`.
    fn chain2(self, other: Self, f: f64, df_self: f64, df_other: f64) -> Self;
}

impl Real for f64 {
    const PLAIN: bool = true;
    #[inline]
    fn constant(value: f64) -> Self {
        value
    }
    #[inline]
    fn value(self) -> f64 {
        self
    }
    #[inline]
    fn sqrt(self) -> Self {
        f64::sqrt(self)
    }
    #[inline]
    fn sin_cos(self) -> (Self, Self) {
        f64::sin_cos(self)
    }
    #[inline]
    fn atan2(self, x: Self) -> Self {
        f64::atan2(self, x)
    }
    #[inline]
    fn chain(self, f: f64, _df: f64) -> Self {
        f
    }
    #[inline]
    fn chain2(self, _other: Self, f: f64, _df_self: f64, _df_other: f64) -> Self {
        f
    }
}

/// A value and its partials with respect to the [`VARIABLES`] body coordinates.
#[derive(Clone, Copy, Debug, PartialEq)]
pub(crate) struct Dual {
    pub(crate) value: f64,
    pub(crate) partials: [f64; VARIABLES],
}

impl Dual {
    /// Independent variable number `index` at `value`.
    pub(crate) fn variable(value: f64, index: usize) -> Self {
        let mut partials = [0.0; VARIABLES];
        partials[index] = 1.0;
        Self { value, partials }
    }

    #[inline]
    fn map(self, value: f64, scale: f64) -> Self {
        let mut partials = self.partials;
        for p in &mut partials {
            *p *= scale;
        }
        Self { value, partials }
    }

    #[inline]
    fn combine(self, a: f64, other: Self, b: f64, value: f64) -> Self {
        let mut partials = [0.0; VARIABLES];
        for (k, p) in partials.iter_mut().enumerate() {
            *p = a * self.partials[k] + b * other.partials[k];
        }
        Self { value, partials }
    }
}

impl Add for Dual {
    type Output = Self;
    #[inline]
    fn add(self, o: Self) -> Self {
        self.combine(1.0, o, 1.0, self.value + o.value)
    }
}

impl Sub for Dual {
    type Output = Self;
    #[inline]
    fn sub(self, o: Self) -> Self {
        self.combine(1.0, o, -1.0, self.value - o.value)
    }
}

impl Mul for Dual {
    type Output = Self;
    #[inline]
    fn mul(self, o: Self) -> Self {
        self.combine(o.value, o, self.value, self.value * o.value)
    }
}

impl Div for Dual {
    type Output = Self;
    #[inline]
    fn div(self, o: Self) -> Self {
        let q = self.value / o.value;
        self.combine(1.0 / o.value, o, -q / o.value, q)
    }
}

impl Neg for Dual {
    type Output = Self;
    #[inline]
    fn neg(self) -> Self {
        self.map(-self.value, -1.0)
    }
}

impl Add<f64> for Dual {
    type Output = Self;
    #[inline]
    fn add(self, c: f64) -> Self {
        Self {
            value: self.value + c,
            partials: self.partials,
        }
    }
}

impl Sub<f64> for Dual {
    type Output = Self;
    #[inline]
    fn sub(self, c: f64) -> Self {
        self + (-c)
    }
}

impl Mul<f64> for Dual {
    type Output = Self;
    #[inline]
    fn mul(self, c: f64) -> Self {
        self.map(self.value * c, c)
    }
}

impl Div<f64> for Dual {
    type Output = Self;
    #[inline]
    fn div(self, c: f64) -> Self {
        self.map(self.value / c, 1.0 / c)
    }
}

impl Real for Dual {
    const PLAIN: bool = false;
    #[inline]
    fn constant(value: f64) -> Self {
        Self {
            value,
            partials: [0.0; VARIABLES],
        }
    }
    #[inline]
    fn value(self) -> f64 {
        self.value
    }
    #[inline]
    fn sqrt(self) -> Self {
        let r = self.value.sqrt();
        self.map(r, 0.5 / r)
    }
    #[inline]
    fn sin_cos(self) -> (Self, Self) {
        let (s, c) = self.value.sin_cos();
        (self.map(s, c), self.map(c, -s))
    }
    #[inline]
    fn atan2(self, x: Self) -> Self {
        // d atan2(y, x) = (x dy − y dx)/(x² + y²).
        let r2 = x.value * x.value + self.value * self.value;
        self.combine(x.value / r2, x, -self.value / r2, self.value.atan2(x.value))
    }
    #[inline]
    fn chain(self, f: f64, df: f64) -> Self {
        self.map(f, df)
    }
    #[inline]
    fn chain2(self, other: Self, f: f64, df_self: f64, df_other: f64) -> Self {
        self.combine(df_self, other, df_other, f)
    }
}

/// A body's coordinates as the independent variables of a joint's Jacobian: the bearing's
/// (`offset` 0) and the pin's (`offset` 3) positions are columns `offset..offset + 3`, their
/// rates six columns further on.
pub(crate) fn body_variables(state: &BodyState, offset: usize) -> [Dual; 6] {
    let values = state.coordinates();
    std::array::from_fn(|k| {
        let column = if k < 3 {
            offset + k
        } else {
            6 + offset + k - 3
        };
        Dual::variable(values[k], column)
    })
}

/// The Jacobian whose rows are the partials of the bearing's and then the pin's generalized
/// forces.
pub(crate) fn jacobian(bearing: &[Dual; 3], pin: &[Dual; 3]) -> ContactJacobian {
    let mut jacobian = ContactJacobian::zeros();
    for (row, value) in bearing.iter().chain(pin).enumerate() {
        for (column, partial) in value.partials.iter().enumerate() {
            jacobian[(row, column)] = *partial;
        }
    }
    jacobian
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Every operation against a central difference of its f64 version.
    #[test]
    fn partials_match_central_differences() {
        let f = |x: [f64; 2]| -> f64 {
            let (a, b) = (x[0], x[1]);
            let (s, c) = (a * b).sin_cos();
            (a / b + (a * a + 1.0).sqrt() - s * c * 3.0).atan2(b - 0.3 * a) * 2.0 - 1.0
        };
        let g = |x: [Dual; 2]| -> Dual {
            let (a, b) = (x[0], x[1]);
            let (s, c) = (a * b).sin_cos();
            (a / b + (a * a + 1.0).sqrt() - s * c * 3.0).atan2(b - a * 0.3) * 2.0 - 1.0
        };
        let x = [0.7, 1.3];
        let d = g([Dual::variable(x[0], 0), Dual::variable(x[1], 1)]);
        assert_eq!(d.value, f(x));
        for k in 0..2 {
            let h = 1e-6;
            let (mut up, mut down) = (x, x);
            up[k] += h;
            down[k] -= h;
            let fd = (f(up) - f(down)) / (2.0 * h);
            assert!(
                (d.partials[k] - fd).abs() < 1e-8,
                "{k}: {} vs {fd}",
                d.partials[k]
            );
        }
    }
}
