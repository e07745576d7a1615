//! The test model of the contact-model interface, `LinearSpring`, checked against laws that can
//! fail: its force against the closed form `k δ`, its Jacobian against central finite
//! differences, and its force against the gradient of its own energy `k δ²/2` (so that an
//! elastic joint on it conserves energy). Off-centre journals make the moments non-trivial.
//!
//! Tolerances: central differences with step `h = 1e-9 m` (1e-6 rad) on a force that is
//! quadratic in the coordinates near `δ ≈ 10 µm` carry a truncation error of order
//! `(h/δ)² ≈ 1e-8` relative and a round-off of order `ulp(|e|)/h ≈ 1e-7` relative; 1e-5 of the
//! row's largest entry leaves room for both.

mod common;

use common::{
    CLEARANCE, central_difference, central_slope, generalized_forces, random_state, round_joint,
    state_vector, states_from,
};
use contact::{
    CircularProfile, ClearanceJoint, ContactModel, Frictionless, Hertz, LinearSpring,
    ValidityMeasure,
};
use rand::SeedableRng;
use rand_chacha::ChaCha8Rng;

const STIFFNESS: f64 = 2e8;
const TOLERANCE: f64 = 1e-5;

fn spring_joint() -> ClearanceJoint<CircularProfile, CircularProfile, Hertz, Frictionless> {
    round_joint(
        [0.01, -0.02],
        [-0.03, 0.015],
        Hertz::default(),
        Frictionless,
    )
    .with_model(LinearSpring::new(STIFFNESS).expect("a positive stiffness"))
}

#[test]
fn the_model_is_asked_not_named() {
    let joint = spring_joint();
    let model = joint.model();
    assert_eq!(model.name(), "linear-spring");
    assert_eq!(model.nodes(), None);
    assert_eq!(model.validity_measures(), &[ValidityMeasure::SlopeRatio]);
    assert!(LinearSpring::new(0.0).is_err());
    assert!(LinearSpring::new(f64::NAN).is_err());
}

#[test]
fn force_is_k_delta_along_the_line_of_centres_and_the_pair_has_no_net_moment() {
    let joint = spring_joint();
    let mut rng = ChaCha8Rng::seed_from_u64(7);
    let mut worst: f64 = 0.0;
    for k in 0..50 {
        let depth = 1e-6 * (1.0 + k as f64);
        let (bearing, pin) = random_state(&joint, &mut rng, depth, 0.1, -0.2);
        let forces = joint.forces(&bearing, &pin, None);
        let kin = joint.kinematics(&bearing, &pin);
        let magnitude = forces.pin.xy().norm();
        worst = worst.max((magnitude - STIFFNESS * kin.penetration).abs() / magnitude);
        // Along −n on the pin, +n on the bearing.
        assert!(forces.pin.xy().dot(&kin.normal) < 0.0);
        assert_eq!(forces.bearing.xy(), -forces.pin.xy());
        // Net moment about the global origin: each body's moment plus its force's moment.
        let net = forces.bearing.z + bearing.x * forces.bearing.y - bearing.y * forces.bearing.x
            + forces.pin.z
            + pin.x * forces.pin.y
            - pin.y * forces.pin.x;
        assert!(
            net.abs() <= 1e-9 * magnitude,
            "net moment {net} N·m at {magnitude} N"
        );
        assert_eq!(forces.diagnostics.damping_power, 0.0);
        assert_eq!(forces.diagnostics.friction_power, 0.0);
    }
    println!("worst relative error of |F| against k δ: {worst:.1e}");
    assert!(worst < 1e-6, "{worst}");
    // Apart: no force.
    let (bearing, pin) = random_state(&joint, &mut rng, -0.1 * CLEARANCE, 0.0, 0.0);
    assert_eq!(joint.forces(&bearing, &pin, None).pin.norm(), 0.0);
}

#[test]
fn jacobian_matches_central_differences_and_force_is_minus_the_energy_gradient() {
    let joint = spring_joint();
    let mut rng = ChaCha8Rng::seed_from_u64(11);
    let (mut worst_jacobian, mut worst_gradient): (f64, f64) = (0.0, 0.0);
    for _ in 0..50 {
        let (bearing, pin) = random_state(&joint, &mut rng, 1e-5, 0.3, 0.7);
        let z = state_vector(&bearing, &pin);
        let (forces, analytic) = joint.forces_and_jacobian(&bearing, &pin, None);
        let scale = forces.pin.norm().max(forces.bearing.norm());
        for col in 0..12 {
            let h = if col % 3 == 2 { 1e-6 } else { 1e-9 };
            let column = central_difference(&z, col, h, |z| generalized_forces(&joint, z, 0.0));
            for (row, numeric) in column.into_iter().enumerate() {
                let row_scale = analytic.row(row).amax().max(f64::MIN_POSITIVE);
                worst_jacobian =
                    worst_jacobian.max((analytic[(row, col)] - numeric).abs() / row_scale);
            }
            // The generalized force of coordinate `col` (positions only) is −∂V/∂q.
            if col < 6 {
                let energy = |z: &[f64; 12]| {
                    let (b, p) = states_from(z);
                    joint.forces(&b, &p, None).diagnostics.elastic_energy
                };
                let gradient = central_slope(&z, col, h, energy);
                let force = [forces.bearing, forces.pin][col / 3][col % 3];
                worst_gradient = worst_gradient.max((force + gradient).abs() / scale);
            }
        }
    }
    println!(
        "worst Jacobian error {worst_jacobian:.1e} of the row's largest entry; worst \
         |Q + ∂V/∂q| {worst_gradient:.1e} of the force"
    );
    assert!(worst_jacobian < TOLERANCE, "{worst_jacobian}");
    assert!(worst_gradient < TOLERANCE, "{worst_gradient}");
}
