//! Joint kinematics: normal velocity as the rate of penetration, and worn profiles sampled in
//! each body's own frame.

mod common;

use common::{BEARING_RADIUS, CLEARANCE, WavyProfile, steel};
use contact::{BodyState, ClearanceJoint, Frictionless, Hertz, JointSurface, NormalLaw};

#[test]
fn normal_velocity_is_the_rate_of_penetration_for_round_surfaces() {
    let joint = common::round_joint([0.03, -0.02], [-0.01, 0.04], Hertz::default(), Frictionless);
    let bearing = BodyState::new([0.1, 0.2, 0.4], [0.3, -0.1, 2.0]);
    let mut pin = BodyState::new([0.0, 0.0, -0.7], [-0.2, 0.25, -3.0]);
    let kin = joint.kinematics(&bearing, &pin);
    pin.x += 3e-4 - kin.eccentricity.x;
    pin.y += 2e-4 - kin.eccentricity.y;
    let kin = joint.kinematics(&bearing, &pin);
    let moved = |s: &BodyState, h: f64| {
        BodyState::new(
            [s.x + h * s.vx, s.y + h * s.vy, s.theta + h * s.omega],
            [s.vx, s.vy, s.omega],
        )
    };
    let h = 1e-7;
    let rate = (joint.penetration(&moved(&bearing, h), &moved(&pin, h))
        - joint.penetration(&moved(&bearing, -h), &moved(&pin, -h)))
        / (2.0 * h);
    approx::assert_relative_eq!(kin.normal_velocity, rate, max_relative = 1e-6);
    // And v_t is the relative velocity of the material points along t.
    let relative = kin.pin_point_velocity - kin.bearing_point_velocity;
    approx::assert_relative_eq!(
        kin.tangential_velocity,
        relative.dot(&kin.tangent),
        max_relative = 1e-12
    );
}

#[test]
fn worn_profiles_are_sampled_in_their_own_body_frames() {
    // Bearing worn open by 20 µm around its body-frame angle 0, pin round.
    let bearing_profile = WavyProfile {
        base: BEARING_RADIUS,
        modes: [(1.0, 2e-5, 0.0), (0.0, 0.0, 0.0)],
    };
    let pin_profile = WavyProfile {
        base: BEARING_RADIUS - CLEARANCE,
        modes: [(0.0, 0.0, 0.0); 2],
    };
    let joint = ClearanceJoint::new(
        JointSurface {
            centre: [0.0, 0.0],
            profile: bearing_profile,
            material: steel(),
        },
        JointSurface {
            centre: [0.0, 0.0],
            profile: pin_profile,
            material: steel(),
        },
        Hertz::default(),
        Frictionless,
    )
    .expect("valid joint")
    .with_model(contact::LineOfCentres);
    let theta_i: f64 = 0.5;
    let phi: f64 = -2.0;
    let bearing = BodyState::at_rest(0.0, 0.0, theta_i);
    let depth = CLEARANCE + 3e-5;
    let pin = BodyState::at_rest(depth * phi.cos(), depth * phi.sin(), 1.2);
    let local_bearing_radius = BEARING_RADIUS + 2e-5 * (phi - theta_i).cos();
    let expected_penetration = depth - (local_bearing_radius - (BEARING_RADIUS - CLEARANCE));
    let forces = joint.forces(&bearing, &pin, None);
    let d = forces.diagnostics;
    approx::assert_relative_eq!(d.penetration, expected_penetration, max_relative = 1e-9);
    approx::assert_relative_eq!(d.bearing_radius, local_bearing_radius, max_relative = 1e-14);
    approx::assert_relative_eq!(d.contact_angle, phi, max_relative = 1e-12);
    approx::assert_relative_eq!(
        d.bearing_angle,
        (phi - theta_i).rem_euclid(std::f64::consts::TAU),
        max_relative = 1e-12
    );
    approx::assert_relative_eq!(
        d.pin_angle,
        (phi - 1.2).rem_euclid(std::f64::consts::TAU),
        max_relative = 1e-12
    );
    // Stiffness from the local radii.
    let k = joint.stiffness(local_bearing_radius, BEARING_RADIUS - CLEARANCE);
    let law_force = Hertz::default()
        .evaluate(k, expected_penetration, 0.0, 0.0)
        .force;
    // The reported load is |F_n m|, m = n − (R_i'/|e|) t on this worn bearing.
    let slope_ratio = -2e-5 * (phi - theta_i).sin() / depth;
    let expected_force = law_force * (1.0 + slope_ratio * slope_ratio).sqrt();
    approx::assert_relative_eq!(d.normal_force, expected_force, max_relative = 1e-8);
    approx::assert_relative_eq!(
        d.bearing_slope,
        -2e-5 * (phi - theta_i).sin(),
        max_relative = 1e-12
    );
    // Contact point on the bearing surface, in the contact direction.
    approx::assert_relative_eq!(
        d.contact_point[0],
        local_bearing_radius * phi.cos(),
        max_relative = 1e-12
    );
    approx::assert_relative_eq!(
        d.contact_point[1],
        local_bearing_radius * phi.sin(),
        max_relative = 1e-12
    );
}

#[test]
fn outline_overlap_equals_penetration_on_round_surfaces_and_sees_a_dent_wall() {
    use contact::{Frictionless, Hertz};
    let joint = common::round_joint([0.0, 0.0], [0.0, 0.0], Hertz::default(), Frictionless);
    let bearing = BodyState::at_rest(0.0, 0.0, 0.3);
    let pin = BodyState::at_rest(0.0, -(CLEARANCE + 2e-5), -0.7);
    let overlap = joint.outline_overlap(&bearing, &pin, 3600);
    // Sampling error of a round pin: R (1 − cos(π/N)) ≈ 1.9e-8 m at N = 3600.
    approx::assert_abs_diff_eq!(overlap.depth, 2e-5, epsilon = 2e-8);
    approx::assert_abs_diff_eq!(overlap.angle, -std::f64::consts::FRAC_PI_2, epsilon = 2e-3);
    // A bearing with ridges every 60° (radius 50 µm smaller at 0°, larger at ±30°): a pin
    // pushed towards −30° sits 10 µm short of the groove there, while its outline overlaps the
    // ridges at 0° and −60° by tens of µm, which the line of centres does not see.
    let bumpy = common::WavyProfile {
        base: BEARING_RADIUS,
        modes: [(6.0, -5e-5, 0.0), (1.0, 0.0, 0.0)],
    };
    let pin_profile = *joint.pin_profile();
    let worn = joint
        .with_profiles(bumpy, pin_profile)
        .expect("valid profiles");
    let bearing = BodyState::at_rest(0.0, 0.0, 0.0);
    let direction = -std::f64::consts::FRAC_PI_6;
    let rho = CLEARANCE + 5e-5 - 1e-5;
    let pin = BodyState::at_rest(rho * direction.cos(), rho * direction.sin(), 0.0);
    let line_of_centres = worn.penetration(&bearing, &pin);
    let overlap = worn.outline_overlap(&bearing, &pin, 3600);
    approx::assert_abs_diff_eq!(line_of_centres, -1e-5, epsilon = 1e-9);
    assert!(overlap.depth > 1.5e-5, "{overlap:?}");
    // Deepest on a ridge flank (the ridges at 0° and −60° are symmetric about −30°).
    assert!((overlap.angle - direction).abs() > 0.25, "{overlap:?}");
}
