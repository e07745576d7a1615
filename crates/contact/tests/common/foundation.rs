//! Fixtures of the foundation tests: grooved and counted profiles, joints on them, and random
//! contact states.

use super::{BEARING_RADIUS, CLEARANCE, off_centre_joint, steel};
use contact::{
    BodyState, ClearanceJoint, ContactModelKind, Foundation, FrictionLaw, Hertz, NormalLaw,
    RadiusSample, SurfaceProfile,
};
use rand::Rng;
use rand_chacha::ChaCha8Rng;

/// A surface with a smooth Gaussian groove (bearing, `sign = +1`) or flat (pin, `sign = −1`):
/// `R(α) = R₀ + sign · h · exp(−(α − α₀)²/(2σ²))` (α wrapped to the nearest copy of α₀).
#[derive(Clone, Copy, Debug)]
pub struct Groove {
    pub base: f64,
    pub sign: f64,
    pub depth: f64,
    pub centre: f64,
    pub sigma: f64,
}

impl SurfaceProfile for Groove {
    fn sample(&self, angle: f64) -> RadiusSample {
        let tau = std::f64::consts::TAU;
        let x = (angle - self.centre + std::f64::consts::PI).rem_euclid(tau) - std::f64::consts::PI;
        let s2 = self.sigma * self.sigma;
        let bump = self.sign * self.depth * (-x * x / (2.0 * s2)).exp();
        RadiusSample {
            radius: self.base + bump,
            slope: -bump * x / s2,
            curvature: bump * (x * x / s2 - 1.0) / s2,
        }
    }

    fn radius_bounds(&self) -> Option<(f64, f64)> {
        let moved = self.base + self.sign * self.depth;
        Some((self.base.min(moved), self.base.max(moved)))
    }

    /// The Gaussian's steepest slope, `h e^{-1/2}/σ` (its step at ±π, below 1e-20 m for these
    /// grooves, is within the memory's rounding allowance).
    fn slope_bound(&self) -> Option<f64> {
        Some(self.depth / self.sigma * (-0.5f64).exp())
    }
}

/// A profile that counts its samples (the costly part of a node), to see nodes skipped.
#[derive(Clone, Debug)]
pub struct Counted<S> {
    pub inner: S,
    pub samples: std::rc::Rc<std::cell::Cell<usize>>,
}

impl<S: SurfaceProfile> SurfaceProfile for Counted<S> {
    fn sample(&self, angle: f64) -> RadiusSample {
        self.samples.set(self.samples.get() + 1);
        self.inner.sample(angle)
    }
    fn radius_bounds(&self) -> Option<(f64, f64)> {
        self.inner.radius_bounds()
    }
    fn slope_bound(&self) -> Option<f64> {
        self.inner.slope_bound()
    }
}

pub fn hertz() -> Hertz {
    Hertz::new(1.5).expect("valid exponent")
}

pub fn foundation<B: SurfaceProfile, P: SurfaceProfile, N: NormalLaw, F: FrictionLaw>(
    joint: ClearanceJoint<B, P, N, F>,
) -> ClearanceJoint<B, P, N, F> {
    joint.with_model(ContactModelKind::Foundation(Foundation::calibrated(
        &steel(),
        &steel(),
    )))
}

/// A worn joint A: a 1.2 mm groove in the bearing at 250° and a 0.8 mm flat on the pin at 70°,
/// off-centroid centres.
pub fn worn<N: NormalLaw, F: FrictionLaw>(
    normal: N,
    friction: F,
) -> ClearanceJoint<Groove, Groove, N, F> {
    let bearing = Groove {
        base: BEARING_RADIUS,
        sign: 1.0,
        depth: 1.2e-3,
        centre: 250f64.to_radians(),
        sigma: 0.35,
    };
    let pin = Groove {
        base: BEARING_RADIUS - CLEARANCE,
        sign: -1.0,
        depth: 0.8e-3,
        centre: 70f64.to_radians(),
        sigma: 0.25,
    };
    foundation(off_centre_joint(bearing, pin, normal, friction))
}

/// Pin placed so that its centre is `|e|` from the bearing centre along global angle `phi`,
/// with `|e|` found by bisection so that the deepest overlap is `target` (m).
pub fn place<B, P, N, F>(
    joint: &ClearanceJoint<B, P, N, F>,
    bearing: BodyState,
    pin_theta: f64,
    phi: f64,
    target: f64,
) -> BodyState
where
    B: SurfaceProfile,
    P: SurfaceProfile,
    N: NormalLaw,
    F: FrictionLaw,
{
    let joint_centres = |e: f64| {
        // Bearing centre in the global frame, then the pin body's centroid from its centre.
        let (s, c) = bearing.theta.sin_cos();
        let bc = [0.04, -0.02];
        let centre = [
            bearing.x + c * bc[0] - s * bc[1],
            bearing.y + s * bc[0] + c * bc[1],
        ];
        let (s, c) = pin_theta.sin_cos();
        let pc = [-0.03, 0.025];
        let arm = [c * pc[0] - s * pc[1], s * pc[0] + c * pc[1]];
        BodyState::at_rest(
            centre[0] + e * phi.cos() - arm[0],
            centre[1] + e * phi.sin() - arm[1],
            pin_theta,
        )
    };
    let (mut lo, mut hi) = (0.0, 5e-3);
    for _ in 0..200 {
        let mid = 0.5 * (lo + hi);
        if joint.penetration(&bearing, &joint_centres(mid)) < target {
            lo = mid;
        } else {
            hi = mid;
        }
    }
    joint_centres(0.5 * (lo + hi))
}

/// `state` moving like `moving` (its position kept).
pub fn with_velocity(state: BodyState, moving: BodyState) -> BodyState {
    BodyState::new(
        [state.x, state.y, state.theta],
        [moving.vx, moving.vy, moving.omega],
    )
}

/// A bearing anywhere (moving at up to `speed`, see [`random_body`]) and a pin overlapping it by
/// a depth drawn from `overlap` (m), in a direction within ±`spread` rad of `offset` from the
/// bearing's frame, turned anyhow, and moving at up to `speed` too (at rest for `speed = 0`).
pub fn random_contact<B, P, N, F>(
    joint: &ClearanceJoint<B, P, N, F>,
    rng: &mut ChaCha8Rng,
    speed: f64,
    offset: f64,
    spread: f64,
    overlap: std::ops::Range<f64>,
) -> (BodyState, BodyState)
where
    B: SurfaceProfile,
    P: SurfaceProfile,
    N: NormalLaw,
    F: FrictionLaw,
{
    let bearing = random_body(rng, speed);
    let phi = bearing.theta + offset + rng.random_range(-spread..spread);
    let pin = place(
        joint,
        bearing,
        rng.random_range(-3.0..3.0),
        phi,
        rng.random_range(overlap),
    );
    if speed > 0.0 {
        (bearing, with_velocity(pin, random_body(rng, speed)))
    } else {
        (bearing, pin)
    }
}

/// A body anywhere within 0.1 m and ±3 rad, moving at up to `speed` m/s and `10 speed` rad/s
/// (at rest for `speed = 0`).
pub fn random_body(rng: &mut ChaCha8Rng, speed: f64) -> BodyState {
    let spin = 10.0 * speed;
    let mut rate = |limit: f64| {
        if limit > 0.0 {
            rng.random_range(-limit..limit)
        } else {
            0.0
        }
    };
    let velocity = [rate(speed), rate(speed), rate(spin)];
    BodyState::new(super::symmetric(rng, [0.1, 0.1, 3.0]), velocity)
}

/// The force on the pin of a linear layer over a round pin offset by `e` in a round bearing, by
/// an independent quadrature: the exact overlap along rays from the bearing centre,
/// `d(θ) = e cos θ + √(R_j² − e² sin² θ) − R`, integrated with the measure `R_j dα` of the pin's
/// own outline (α the pin point's polar angle, `dθ/dα` from the same closed form).
pub fn quadrature_force(line_modulus: f64, e: f64, bearing_radius: f64, pin_radius: f64) -> f64 {
    let n = 400_000;
    let mut force = 0.0;
    for k in 0..n {
        let alpha = -std::f64::consts::PI + (k as f64 + 0.5) * std::f64::consts::TAU / n as f64;
        let p = [e + pin_radius * alpha.cos(), pin_radius * alpha.sin()];
        let rho = p[0].hypot(p[1]);
        let d = rho - bearing_radius;
        if d > 0.0 {
            // Radial direction's x component (the resultant is along x by symmetry).
            force +=
                line_modulus * d * (p[0] / rho) * pin_radius * std::f64::consts::TAU / n as f64;
        }
    }
    force
}
