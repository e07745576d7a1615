//! Shared test fixtures: the LGRES joint-A parameters, a worn-looking profile, and a small
//! fixed-step RK4 integrator of two free bodies coupled only by a joint.
#![allow(dead_code)]

pub mod foundation;

use contact::{
    Ambrosio, BodyState, CircularProfile, ClearanceJoint, ContactForces, FrictionLaw, ImpactMemory,
    JointSurface, LankaraniNikravesh, Material, NormalLaw, RadiusSample, SurfaceProfile,
};
use rand::Rng;
use rand_chacha::ChaCha8Rng;

/// LGRES joint A: bearing radius 0.05 m, clearance 0.5 mm.
pub const BEARING_RADIUS: f64 = 0.05;
pub const CLEARANCE: f64 = 5e-4;

pub fn steel() -> Material {
    Material::new(200e9, 0.3).expect("valid steel")
}

/// A smooth non-circular profile `R(α) = R₀ + Σ a_k cos(kα) + b_k sin(kα)`, like a worn surface.
#[derive(Clone, Copy, Debug)]
pub struct WavyProfile {
    pub base: f64,
    pub modes: [(f64, f64, f64); 2],
}

impl SurfaceProfile for WavyProfile {
    fn sample(&self, angle: f64) -> RadiusSample {
        let mut radius = self.base;
        let mut slope = 0.0;
        let mut curvature = 0.0;
        for (k, a, b) in self.modes {
            let (s, c) = (k * angle).sin_cos();
            radius += a * c + b * s;
            slope += k * (-a * s + b * c);
            curvature -= k * k * (a * c + b * s);
        }
        RadiusSample {
            radius,
            slope,
            curvature,
        }
    }
}

/// Joint A with round surfaces; the bearing and pin centres sit at the given body-fixed points.
pub fn round_joint<N: NormalLaw, F: FrictionLaw>(
    bearing_centre: [f64; 2],
    pin_centre: [f64; 2],
    normal: N,
    friction: F,
) -> ClearanceJoint<CircularProfile, CircularProfile, N, F> {
    ClearanceJoint::new(
        JointSurface {
            centre: bearing_centre,
            profile: CircularProfile::new(BEARING_RADIUS),
            material: steel(),
        },
        JointSurface {
            centre: pin_centre,
            profile: CircularProfile::new(BEARING_RADIUS - CLEARANCE),
            material: steel(),
        },
        normal,
        friction,
    )
    .expect("valid joint")
    .with_model(contact::LineOfCentres)
}

pub fn lgres_laws(restitution: f64) -> (LankaraniNikravesh, Ambrosio) {
    (
        LankaraniNikravesh::new(restitution).expect("valid restitution"),
        Ambrosio::new(0.15, 1e-4, 1e-3).expect("valid friction"),
    )
}

/// Mass and centroidal inertia of a free body.
#[derive(Clone, Copy, Debug)]
pub struct Inertia {
    pub mass: f64,
    pub inertia: f64,
}

impl Inertia {
    pub fn kinetic_energy(&self, s: &BodyState) -> f64 {
        0.5 * self.mass * (s.vx * s.vx + s.vy * s.vy) + 0.5 * self.inertia * s.omega * s.omega
    }
}

fn derivative(
    state: &[BodyState; 2],
    forces: &[[f64; 3]; 2],
    inertia: &[Inertia; 2],
) -> [[f64; 6]; 2] {
    let mut out = [[0.0; 6]; 2];
    for k in 0..2 {
        let s = &state[k];
        let f = &forces[k];
        out[k] = [
            s.vx,
            s.vy,
            s.omega,
            f[0] / inertia[k].mass,
            f[1] / inertia[k].mass,
            f[2] / inertia[k].inertia,
        ];
    }
    out
}

fn advance(state: &[BodyState; 2], rate: &[[f64; 6]; 2], h: f64) -> [BodyState; 2] {
    let mut out = *state;
    for k in 0..2 {
        let s = &mut out[k];
        let r = &rate[k];
        s.x += h * r[0];
        s.y += h * r[1];
        s.theta += h * r[2];
        s.vx += h * r[3];
        s.vy += h * r[4];
        s.omega += h * r[5];
    }
    out
}

/// Summary of one simulated impact.
#[derive(Clone, Copy, Debug, Default)]
pub struct ImpactRecord {
    /// Normal velocity at the onset (m/s).
    pub onset_velocity: f64,
    /// Normal velocity after separation (m/s, negative when separating).
    pub separation_velocity: f64,
    pub peak_force: f64,
    pub peak_penetration: f64,
    /// Bodies when they separate.
    pub final_state: [BodyState; 2],
}

impl ImpactRecord {
    pub fn restitution(&self) -> f64 {
        -self.separation_velocity / self.onset_velocity
    }
}

/// Integrates two free bodies (bearing first) with RK4 at step `h` until the first contact ends
/// (or `max_steps` pass). The onset velocity is tracked with [`ImpactMemory`] on accepted steps.
pub fn simulate_impact<B, P, N, F>(
    joint: &ClearanceJoint<B, P, N, F>,
    mut state: [BodyState; 2],
    inertia: [Inertia; 2],
    h: f64,
    max_steps: usize,
) -> Option<ImpactRecord>
where
    B: SurfaceProfile,
    P: SurfaceProfile,
    N: NormalLaw,
    F: FrictionLaw,
{
    let mut memory = ImpactMemory::new();
    let mut record = ImpactRecord::default();
    let mut previous = joint.forces(&state[0], &state[1], None).diagnostics;
    let mut touched = false;
    let rates = |s: &[BodyState; 2], onset: Option<f64>| {
        let f = joint.forces(&s[0], &s[1], onset);
        derivative(s, &[f.bearing.into(), f.pin.into()], &inertia)
    };
    for _ in 0..max_steps {
        let onset = memory.onset_velocity();
        let k1 = rates(&state, onset);
        let k2 = rates(&advance(&state, &k1, 0.5 * h), onset);
        let k3 = rates(&advance(&state, &k2, 0.5 * h), onset);
        let k4 = rates(&advance(&state, &k3, h), onset);
        for k in 0..2 {
            let s = &mut state[k];
            let mut r = [0.0; 6];
            for m in 0..6 {
                r[m] = (k1[k][m] + 2.0 * k2[k][m] + 2.0 * k3[k][m] + k4[k][m]) / 6.0;
            }
            *s = advance(&[*s, *s], &[r, r], h)[0];
        }
        let current = joint
            .forces(&state[0], &state[1], memory.onset_velocity())
            .diagnostics;
        memory.update(&previous, &current);
        if current.in_contact && !touched {
            touched = true;
            record.onset_velocity = memory.onset_velocity().unwrap_or(current.normal_velocity);
        }
        if touched {
            record.peak_force = record.peak_force.max(current.normal_force);
            record.peak_penetration = record.peak_penetration.max(current.penetration);
            if !current.in_contact {
                record.separation_velocity = current.normal_velocity;
                record.final_state = state;
                return Some(record);
            }
        }
        previous = current;
    }
    None
}

/// Three draws, from `(−a, a)` for each limit `a` in turn.
pub fn symmetric(rng: &mut ChaCha8Rng, limits: [f64; 3]) -> [f64; 3] {
    limits.map(|a| rng.random_range(-a..a))
}

/// `(f(z + h e_col) − f(z − h e_col))/(2h)` for each component of `f`: its central difference
/// along coordinate `col` of the state vector `z`.
pub fn central_difference<const R: usize>(
    z: &[f64; 12],
    col: usize,
    h: f64,
    f: impl Fn(&[f64; 12]) -> [f64; R],
) -> [f64; R] {
    let (mut plus, mut minus) = (*z, *z);
    plus[col] += h;
    minus[col] -= h;
    let (fp, fm) = (f(&plus), f(&minus));
    std::array::from_fn(|k| (fp[k] - fm[k]) / (2.0 * h))
}

/// [`central_difference`] of a scalar, e.g. the stored energy.
pub fn central_slope(z: &[f64; 12], col: usize, h: f64, f: impl Fn(&[f64; 12]) -> f64) -> f64 {
    central_difference(z, col, h, |z| [f(z)])[0]
}

/// `|Q_k + ∂V/∂q_k| / max|Q|` at each position coordinate `k` of `z`, with the generalized
/// forces `forces` and `∂V/∂q_k` the [`central_slope`] of the stored energy `energy` with step
/// `step(k)`: each asserted below `tolerance` (a failure names `case`), the largest returned.
pub fn energy_gradient_error(
    z: &[f64; 12],
    forces: &[f64; 6],
    step: impl Fn(usize) -> f64,
    energy: impl Fn(&[f64; 12]) -> f64,
    tolerance: f64,
    case: &str,
) -> f64 {
    let scale = forces.iter().fold(0.0f64, |m, v| m.max(v.abs()));
    let mut worst: f64 = 0.0;
    for (k, force) in forces.iter().enumerate() {
        let gradient = central_slope(z, k, step(k), &energy);
        let error = (force + gradient).abs() / scale;
        worst = worst.max(error);
        assert!(
            error < tolerance,
            "{case}, coordinate {k}: Q = {force:e}, −∂V/∂q = {:e}",
            -gradient
        );
    }
    worst
}

pub fn state_vector(bearing: &BodyState, pin: &BodyState) -> [f64; 12] {
    [
        bearing.x,
        bearing.y,
        bearing.theta,
        pin.x,
        pin.y,
        pin.theta,
        bearing.vx,
        bearing.vy,
        bearing.omega,
        pin.vx,
        pin.vy,
        pin.omega,
    ]
}

pub fn states_from(z: &[f64; 12]) -> (BodyState, BodyState) {
    (
        BodyState::new([z[0], z[1], z[2]], [z[6], z[7], z[8]]),
        BodyState::new([z[3], z[4], z[5]], [z[9], z[10], z[11]]),
    )
}

pub fn generalized_forces<B, P, N, F>(
    joint: &ClearanceJoint<B, P, N, F>,
    z: &[f64; 12],
    onset: f64,
) -> [f64; 6]
where
    B: SurfaceProfile,
    P: SurfaceProfile,
    N: NormalLaw,
    F: FrictionLaw,
{
    let (bearing, pin) = states_from(z);
    force_vector(&joint.forces(&bearing, &pin, Some(onset)))
}

/// The generalized forces on the bearing's coordinates, then on the pin's.
pub fn force_vector(f: &ContactForces) -> [f64; 6] {
    [
        f.bearing.x,
        f.bearing.y,
        f.bearing.z,
        f.pin.x,
        f.pin.y,
        f.pin.z,
    ]
}

/// Places the pin body so that the joint penetrates by `target` along a random direction, then
/// sets the pin's velocity so that `v_n` and `v_t` take the requested values.
pub fn random_state<B, P, N, F>(
    joint: &ClearanceJoint<B, P, N, F>,
    rng: &mut ChaCha8Rng,
    target_penetration: f64,
    normal_velocity: f64,
    tangential_velocity: f64,
) -> (BodyState, BodyState)
where
    B: SurfaceProfile,
    P: SurfaceProfile,
    N: NormalLaw,
    F: FrictionLaw,
{
    let bearing = BodyState::new(
        symmetric(rng, [0.1, 0.1, 3.0]),
        symmetric(rng, [0.2, 0.2, 2.0]),
    );
    let mut pin = BodyState::new(
        [bearing.x, bearing.y, rng.random_range(-3.0..3.0)],
        symmetric(rng, [0.2, 0.2, 2.0]),
    );
    // Fixed-point iteration on the pin position: δ depends on the direction through the radii.
    let phi: f64 = rng.random_range(-3.1..3.1);
    for _ in 0..50 {
        let kin = joint.kinematics(&bearing, &pin);
        let correction = target_penetration - kin.penetration;
        let direction = if kin.eccentricity_norm > 1e-6 {
            kin.normal
        } else {
            nalgebra::Vector2::new(phi.cos(), phi.sin())
        };
        pin.x += correction * direction.x;
        pin.y += correction * direction.y;
    }
    // The rates the kernel sees (δ̇ along ∇δ, v_t along the contact tangent) are linear in the
    // pin's velocity and close to its components along n and t: iterate the correction.
    for _ in 0..30 {
        let kin = joint.kinematics(&bearing, &pin);
        let d = joint.forces(&bearing, &pin, Some(1.0)).diagnostics;
        let dn = normal_velocity - d.normal_velocity;
        let dt = tangential_velocity - d.tangential_velocity;
        pin.vx += dn * kin.normal.x + dt * kin.tangent.x;
        pin.vy += dn * kin.normal.y + dt * kin.tangent.y;
    }
    (bearing, pin)
}

/// Joint A with smooth non-circular (worn-looking) surfaces and off-centroid centres.
pub fn worn_joint() -> ClearanceJoint<WavyProfile, WavyProfile, LankaraniNikravesh, Ambrosio> {
    let bearing = WavyProfile {
        base: BEARING_RADIUS,
        modes: [(2.0, 2e-5, -1e-5), (3.0, 0.0, 1.5e-5)],
    };
    let pin = WavyProfile {
        base: BEARING_RADIUS - CLEARANCE,
        modes: [(1.0, -1e-5, 2e-5), (4.0, 5e-6, 0.0)],
    };
    off_centre_joint(
        bearing,
        pin,
        LankaraniNikravesh::new(0.9).expect("valid"),
        Ambrosio::new(0.15, 1e-4, 1e-3).expect("valid"),
    )
}

/// A joint of steel surfaces `bearing` and `pin` whose centres sit off the bodies' centroids.
pub fn off_centre_joint<B: SurfaceProfile, P: SurfaceProfile, N: NormalLaw, F: FrictionLaw>(
    bearing: B,
    pin: P,
    normal: N,
    friction: F,
) -> ClearanceJoint<B, P, N, F> {
    ClearanceJoint::new(
        JointSurface {
            centre: [0.04, -0.02],
            profile: bearing,
            material: steel(),
        },
        JointSurface {
            centre: [-0.03, 0.025],
            profile: pin,
            material: steel(),
        },
        normal,
        friction,
    )
    .expect("valid joint")
    .with_model(contact::LineOfCentres)
}
