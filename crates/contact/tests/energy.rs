//! Energy laws of the contact on worn (non-round) surfaces.
//!
//! - The elastic force is the negative gradient of the stored energy `V` the kernel reports,
//!   in all six position coordinates, rotations included (central differences, steps 1e-3 of
//!   the penetration; truncation and round-off both below 1e-6 relative).
//! - The books close: the power of the generalized forces equals `−dV/dt − P_damping −
//!   P_friction` at every state (dV/dt by central differences along the motion).
//! - On round surfaces the general kernel reproduces the round one.
//!
//! The line-of-centres force that these replace fails the first check by orders of magnitude
//! (measured on the LGRES joint A's worn profiles: a closed loop did −13…+8 J of work).

mod common;

use common::{
    BEARING_RADIUS, CLEARANCE, WavyProfile, energy_gradient_error, generalized_forces,
    random_state, state_vector, states_from, worn_joint,
};
use contact::{CircularProfile, ClearanceJoint, Frictionless, Hertz, RadiusSample, SurfaceProfile};
use rand::{Rng, SeedableRng};
use rand_chacha::ChaCha8Rng;

/// Profiles with slopes `|R_i' − R_j'|/|e|` up to about 0.5.
fn steep_profiles() -> (WavyProfile, WavyProfile) {
    (
        WavyProfile {
            base: BEARING_RADIUS,
            modes: [(2.0, 6e-5, -3e-5), (3.0, 0.0, 4e-5)],
        },
        WavyProfile {
            base: BEARING_RADIUS - CLEARANCE - 1e-4,
            modes: [(1.0, -3e-5, 5e-5), (4.0, 1e-5, 0.0)],
        },
    )
}

fn elastic_joint() -> ClearanceJoint<WavyProfile, WavyProfile, Hertz, Frictionless> {
    let (bearing, pin) = steep_profiles();
    common::off_centre_joint(bearing, pin, Hertz::default(), Frictionless)
}

fn stored_energy<
    B: SurfaceProfile,
    P: SurfaceProfile,
    N: contact::NormalLaw,
    F: contact::FrictionLaw,
>(
    joint: &ClearanceJoint<B, P, N, F>,
    z: &[f64; 12],
) -> f64 {
    let (bearing, pin) = states_from(z);
    joint
        .forces(&bearing, &pin, Some(1.0))
        .diagnostics
        .elastic_energy
}

#[test]
fn worn_elastic_force_is_minus_the_gradient_of_the_stored_energy() {
    let joint = elastic_joint();
    let mut rng = ChaCha8Rng::seed_from_u64(21);
    let mut worst: f64 = 0.0;
    let mut largest_slope_ratio: f64 = 0.0;
    for _ in 0..200 {
        let penetration = rng.random_range(2e-6..3e-5);
        let (bearing, pin) = random_state(&joint, &mut rng, penetration, 0.0, 0.0);
        let z = state_vector(&bearing, &pin);
        let d = joint.forces(&bearing, &pin, None).diagnostics;
        largest_slope_ratio =
            largest_slope_ratio.max((d.bearing_slope - d.pin_slope).abs() / d.eccentricity);
        let forces = generalized_forces(&joint, &z, 1.0);
        // Angles are multiplied by arms of at most 0.1 m.
        let step = |k: usize| if k % 3 == 2 { 1e-2 } else { 1e-3 } * penetration;
        let energy = |z: &[f64; 12]| stored_energy(&joint, z);
        let error = energy_gradient_error(&z, &forces, step, energy, 1e-6, "worn state");
        worst = worst.max(error);
    }
    eprintln!(
        "largest |Q + ∇V| / max|Q| = {worst:.2e} over 200 states with |c'|/|e| up to \
         {largest_slope_ratio:.2}"
    );
    assert!(
        largest_slope_ratio > 0.2,
        "the states must exercise the slope terms"
    );
}

#[test]
fn worn_contact_power_balance_closes() {
    // Damped law and friction: Σ Q·q̇ = −dV/dt − P_damping − P_friction.
    let joint = worn_joint();
    let mut rng = ChaCha8Rng::seed_from_u64(22);
    let mut worst: f64 = 0.0;
    for _ in 0..200 {
        let penetration = rng.random_range(2e-6..3e-5);
        let normal_velocity = rng.random_range(-0.3..0.3);
        let tangential_velocity = rng.random_range(-0.3..0.3);
        let (bearing, pin) = random_state(
            &joint,
            &mut rng,
            penetration,
            normal_velocity,
            tangential_velocity,
        );
        let onset = 0.5;
        let z = state_vector(&bearing, &pin);
        let forces = generalized_forces(&joint, &z, onset);
        let power: f64 = (0..6).map(|k| forces[k] * z[k + 6]).sum();
        let d = joint.forces(&bearing, &pin, Some(onset)).diagnostics;
        // dV/dt along the motion, by central differences in time.
        let h = 1e-3 * penetration / z[6..].iter().map(|v| v.abs()).fold(1e-3, f64::max);
        let (mut plus, mut minus) = (z, z);
        for k in 0..6 {
            plus[k] += h * z[k + 6];
            minus[k] -= h * z[k + 6];
        }
        let energy_rate =
            (stored_energy(&joint, &plus) - stored_energy(&joint, &minus)) / (2.0 * h);
        let balance = power + energy_rate + d.damping_power + d.friction_power;
        let scale = power
            .abs()
            .max(energy_rate.abs())
            .max(d.damping_power.abs());
        worst = worst.max(balance.abs() / scale);
        assert!(
            balance.abs() <= 1e-5 * scale,
            "power {power:e}, dV/dt {energy_rate:e}, damping {:e}, friction {:e}",
            d.damping_power,
            d.friction_power
        );
        assert!(
            d.damping_power >= 0.0,
            "damping must dissipate: {:e}",
            d.damping_power
        );
        assert!(
            d.friction_power >= 0.0,
            "friction must dissipate: {:e}",
            d.friction_power
        );
    }
    eprintln!("largest power-balance residual / scale = {worst:.2e} over 200 states");
}

/// A round surface that does not say so, to force the general kernel.
#[derive(Clone, Copy)]
struct UndeclaredRound(CircularProfile);

impl SurfaceProfile for UndeclaredRound {
    fn sample(&self, angle: f64) -> RadiusSample {
        self.0.sample(angle)
    }
}

#[test]
fn general_kernel_on_round_surfaces_matches_the_round_kernel() {
    let round = common::round_joint(
        [0.04, -0.02],
        [-0.03, 0.025],
        contact::LankaraniNikravesh::new(0.9).expect("valid"),
        contact::Ambrosio::new(0.15, 1e-4, 1e-3).expect("valid"),
    );
    let general = round
        .clone()
        .with_profiles(
            UndeclaredRound(*round.bearing_profile()),
            UndeclaredRound(*round.pin_profile()),
        )
        .expect("valid profiles");
    let mut rng = ChaCha8Rng::seed_from_u64(23);
    for _ in 0..100 {
        let penetration = rng.random_range(1e-7..3e-5);
        let (bearing, pin) = random_state(&round, &mut rng, penetration, 0.1, 0.05);
        let (fa, ja) = round.forces_and_jacobian(&bearing, &pin, Some(0.3));
        let (fb, jb) = general.forces_and_jacobian(&bearing, &pin, Some(0.3));
        let force_scale = fa.pin.amax().max(fa.bearing.amax());
        assert!((fa.pin - fb.pin).amax() <= 1e-12 * force_scale);
        assert!((fa.bearing - fb.bearing).amax() <= 1e-12 * force_scale);
        assert!((ja - jb).amax() <= 1e-10 * ja.amax());
        let (da, db) = (fa.diagnostics, fb.diagnostics);
        assert!((da.normal_force - db.normal_force).abs() <= 1e-12 * da.normal_force);
        assert!((da.damping_power - db.damping_power).abs() <= 1e-9 * da.damping_power.abs());
    }
}
