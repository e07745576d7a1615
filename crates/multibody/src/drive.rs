//! Prescribed motions for driving constraints: a value and its exact first and second time
//! derivatives, since the acceleration equation needs `Φ_tt` exactly.

/// A function of time that a driving constraint imposes on a coordinate or joint.
///
/// Implement it for any motion law; the derivatives must be exact (not finite differences),
/// because they enter the velocity and acceleration equations and the energy audit directly.
/// `Send`, like force elements, so a system can move to a worker thread.
pub trait DriveFunction: Send {
    /// f(t)
    fn value(&self, t: f64) -> f64;
    /// df/dt
    fn velocity(&self, t: f64) -> f64;
    /// d²f/dt²
    fn acceleration(&self, t: f64) -> f64;
}

/// `f(t) = value`: holds a coordinate or joint fixed.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Constant(pub f64);

impl DriveFunction for Constant {
    fn value(&self, _t: f64) -> f64 {
        self.0
    }
    fn velocity(&self, _t: f64) -> f64 {
        0.0
    }
    fn acceleration(&self, _t: f64) -> f64 {
        0.0
    }
}

/// `f(t) = initial + rate·t`: constant-speed motion (e.g. a crank turning at fixed rate).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Ramp {
    /// Value at `t = 0` (m or rad).
    pub initial: f64,
    /// Rate (m/s or rad/s).
    pub rate: f64,
}

impl Ramp {
    /// `f(t) = initial + rate·t`.
    pub fn new(initial: f64, rate: f64) -> Self {
        Self { initial, rate }
    }
}

impl DriveFunction for Ramp {
    fn value(&self, t: f64) -> f64 {
        self.initial + self.rate * t
    }
    fn velocity(&self, _t: f64) -> f64 {
        self.rate
    }
    fn acceleration(&self, _t: f64) -> f64 {
        0.0
    }
}

/// `f(t) = offset + amplitude·(1 − cos ωt)`: starts at `offset` with zero velocity, as the
/// LGRES slide-rod drive does.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Harmonic {
    /// Value at `t = 0` (m or rad).
    pub offset: f64,
    /// Half the stroke (m or rad): the value swings between `offset` and `offset + 2·amplitude`.
    pub amplitude: f64,
    /// Angular frequency ω (rad/s).
    pub omega: f64,
}

impl DriveFunction for Harmonic {
    fn value(&self, t: f64) -> f64 {
        self.offset + self.amplitude * (1.0 - (self.omega * t).cos())
    }
    fn velocity(&self, t: f64) -> f64 {
        self.amplitude * self.omega * (self.omega * t).sin()
    }
    fn acceleration(&self, t: f64) -> f64 {
        self.amplitude * self.omega * self.omega * (self.omega * t).cos()
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn check_derivatives(f: &dyn DriveFunction) {
        let h = 1e-6;
        for t in [0.0, 0.3, 1.7] {
            let v = (f.value(t + h) - f.value(t - h)) / (2.0 * h);
            let a = (f.velocity(t + h) - f.velocity(t - h)) / (2.0 * h);
            assert!((v - f.velocity(t)).abs() < 1e-6, "velocity at {t}");
            assert!((a - f.acceleration(t)).abs() < 1e-6, "acceleration at {t}");
        }
    }

    #[test]
    fn shipped_drives_have_consistent_derivatives() {
        check_derivatives(&Constant(2.0));
        check_derivatives(&Ramp {
            initial: 0.5,
            rate: -3.0,
        });
        check_derivatives(&Harmonic {
            offset: 0.895,
            amplitude: 0.09,
            omega: 4.0,
        });
    }
}
