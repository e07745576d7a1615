//! The analytic Jacobian against central finite differences on many random states.
//!
//! Tolerance: an entry passes when `|J − J_fd| ≤ 1e-5 |J| + 1e-7 · max|row of J|`.
//! Central differences with steps `h` carry a truncation error `~ h² f'''/6`; the steps below are
//! at most 1e-3 of the penetration (and of the distance to the friction ramp's corners), giving a
//! relative error below ~1e-7, and a round-off error `~ ulp(|e|) / h ≈ 1e-7` relative. The
//! absolute part (relative to the row's largest entry) covers entries that vanish analytically
//! but pick up that round-off. The tests print the worst ratio seen (observed ≤ 0.45, near δ = 0). Dropping
//! any one term of the Jacobian (a profile slope in `∂R/∂θ`, `∂K/∂q`, the rotation of `n` in
//! `∂v_n/∂q`, one arm component) was checked to fail by 1.5–700× the tolerance.

mod common;

use common::{
    BEARING_RADIUS, CLEARANCE, WavyProfile, central_difference, generalized_forces, random_state,
    state_vector, worn_joint,
};
use contact::{
    BodyState, ClearanceJoint, ContactJacobian, FrictionLaw, FrictionLawKind, NormalLaw,
    NormalLawKind, SlidingVelocity, SurfaceProfile,
};
use rand::{Rng, SeedableRng};
use rand_chacha::ChaCha8Rng;

const RELATIVE_TOLERANCE: f64 = 1e-5;
const ROW_ABSOLUTE_TOLERANCE: f64 = 1e-7;

#[derive(Clone, Copy, Debug)]
enum Regime {
    /// δ of micrometres, sliding faster than v_1.
    DeepSliding,
    /// δ of 1e-8..1e-7 m.
    NearTouch,
    /// |v_t| inside the friction ramp (v_0, v_1).
    FrictionRamp,
    /// |v_t| below v_0 (no friction).
    Sticking,
}

fn finite_difference_jacobian<B, P, N, F>(
    joint: &ClearanceJoint<B, P, N, F>,
    z: &[f64; 12],
    onset: f64,
    steps: &[f64; 12],
) -> ContactJacobian
where
    B: SurfaceProfile,
    P: SurfaceProfile,
    N: NormalLaw,
    F: FrictionLaw,
{
    let mut jacobian = ContactJacobian::zeros();
    for col in 0..12 {
        let column =
            central_difference(z, col, steps[col], |z| generalized_forces(joint, z, onset));
        for (row, value) in column.into_iter().enumerate() {
            jacobian[(row, col)] = value;
        }
    }
    jacobian
}

/// Largest violation of the tolerance (≤ 1 passes).
fn worst_ratio(analytic: &ContactJacobian, numeric: &ContactJacobian) -> (f64, usize, usize) {
    let mut worst = (0.0, 0, 0);
    for row in 0..6 {
        let row_scale = analytic.row(row).amax();
        for col in 0..12 {
            let a = analytic[(row, col)];
            let allowed = RELATIVE_TOLERANCE * a.abs() + ROW_ABSOLUTE_TOLERANCE * row_scale;
            let ratio = (a - numeric[(row, col)]).abs() / allowed.max(f64::MIN_POSITIVE);
            if ratio > worst.0 {
                worst = (ratio, row, col);
            }
        }
    }
    worst
}

/// Checks `samples` random states of `regime`; the normal velocity is drawn from
/// `[−max_separation_ratio · δ̇⁻, δ̇⁻]`, which the caller picks to stay clear of the clamp.
fn check_regime<B, P, N, F>(
    joint: &ClearanceJoint<B, P, N, F>,
    regime: Regime,
    seed: u64,
    samples: usize,
    max_separation_ratio: f64,
) where
    B: SurfaceProfile,
    P: SurfaceProfile,
    N: NormalLaw,
    F: FrictionLaw,
{
    let mut rng = ChaCha8Rng::seed_from_u64(seed);
    let mut worst_seen: f64 = 0.0;
    let mut checked = 0;
    while checked < samples {
        let sign = if rng.random_bool(0.5) { 1.0 } else { -1.0 };
        let (penetration, tangential) = match regime {
            Regime::DeepSliding => (
                rng.random_range(1e-6..2e-5),
                sign * rng.random_range(0.002..0.3),
            ),
            Regime::NearTouch => (
                rng.random_range(1e-8..1e-7),
                sign * rng.random_range(0.002..0.3),
            ),
            Regime::FrictionRamp => (
                rng.random_range(1e-6..2e-5),
                sign * rng.random_range(1.2e-4..9.8e-4),
            ),
            Regime::Sticking => (
                rng.random_range(1e-6..2e-5),
                sign * rng.random_range(0.0..9.8e-5),
            ),
        };
        let onset: f64 = rng.random_range(0.01..0.5);
        let normal_velocity = rng.random_range(-max_separation_ratio * onset..onset);
        let (bearing, pin) =
            random_state(joint, &mut rng, penetration, normal_velocity, tangential);
        let z = state_vector(&bearing, &pin);
        let (forces, analytic) = joint.forces_and_jacobian(&bearing, &pin, Some(onset));
        assert!(
            forces.diagnostics.normal_force > 0.0,
            "{regime:?}: sample not in contact"
        );

        // Steps: ≤ 1e-3 δ in position (arms ≤ 0.1 m, so 1e-3 δ / 0.1 in angle), and ≤ 1e-3 of
        // the distance from v_t to the ramp corners in velocity.
        let sliding = joint.friction_sliding().of(&forces.diagnostics);
        let distance_to_corner = [1e-4, 1e-3]
            .iter()
            .map(|corner| (sliding.abs() - corner).abs())
            .fold(f64::INFINITY, f64::min)
            .max(1e-12);
        let hq = (1e-3 * penetration).min(1e-9);
        let hv = (1e-3 * distance_to_corner).min(1e-7);
        let steps = [
            hq,
            hq,
            10.0 * hq,
            hq,
            hq,
            10.0 * hq,
            hv,
            hv,
            10.0 * hv,
            hv,
            hv,
            10.0 * hv,
        ];
        let numeric = finite_difference_jacobian(joint, &z, onset, &steps);
        let (ratio, row, col) = worst_ratio(&analytic, &numeric);
        assert!(
            ratio <= 1.0,
            "{regime:?} sample {checked}: entry ({row}, {col}) analytic {:e} vs FD {:e} \
             (ratio to tolerance {ratio:.2}); δ = {penetration:e}, v_t = {tangential:e}",
            analytic[(row, col)],
            numeric[(row, col)],
        );
        worst_seen = worst_seen.max(ratio);
        checked += 1;
    }
    eprintln!("{regime:?}: worst |J − J_fd| / tolerance over {samples} samples = {worst_seen:.3}");
}

/// Deep sliding, near touch, inside the friction ramp and below the stick velocity, each from
/// its own seed. 1 + χ v_n/δ̇⁻ ≥ 0.28 with χ = 0.1425 (L–N at c_e = 0.9): away from the clamp.
#[test]
fn jacobian_matches_finite_differences_in_every_regime() {
    for (regime, seed, samples) in [
        (Regime::DeepSliding, 1, 300),
        (Regime::NearTouch, 2, 300),
        (Regime::FrictionRamp, 3, 300),
        (Regime::Sticking, 4, 100),
    ] {
        check_regime(&worn_joint(), regime, seed, samples, 5.0);
    }
}

#[test]
fn jacobian_matches_finite_differences_with_the_papers_sliding_velocity() {
    // Friction driven by δ φ̇ instead of the material sliding (SlidingVelocity::Paper).
    let joint = worn_joint().with_friction_sliding(SlidingVelocity::Paper);
    check_regime(&joint, Regime::DeepSliding, 5, 200, 5.0);
}

#[test]
fn jacobian_matches_finite_differences_on_steep_profiles() {
    // Slopes |R_i' − R_j'|/|e| up to about 1 (the model's validity limit is far below).
    let joint = worn_joint();
    let bearing = WavyProfile {
        base: BEARING_RADIUS,
        modes: [(2.0, 1.2e-4, -0.6e-4), (3.0, 0.0, 0.8e-4)],
    };
    let pin = WavyProfile {
        base: BEARING_RADIUS - CLEARANCE - 2e-4,
        modes: [(1.0, -0.5e-4, 1e-4), (4.0, 2e-5, 0.0)],
    };
    let steep = joint.with_profiles(bearing, pin).expect("valid profiles");
    check_regime(&steep, Regime::DeepSliding, 6, 200, 5.0);
}

#[test]
fn jacobian_matches_for_every_runtime_law() {
    use contact::{Coulomb, Flores, Hertz, HuntCrossley};
    let normals = [
        NormalLawKind::HuntCrossley(HuntCrossley::new(0.8).expect("valid")),
        NormalLawKind::Flores(Flores::new(0.5).expect("valid")),
        NormalLawKind::Hertz(Hertz::new(1.0).expect("valid")),
    ];
    let frictions = [
        FrictionLawKind::Coulomb(Coulomb::new(0.3).expect("valid")),
        FrictionLawKind::None,
    ];
    let base = worn_joint();
    for (k, normal) in normals.iter().enumerate() {
        for (m, friction) in frictions.iter().enumerate() {
            let joint = common::off_centre_joint(
                *base.bearing_profile(),
                *base.pin_profile(),
                *normal,
                *friction,
            );
            // χ ≤ 1.6 (Flores at c_e = 0.5): 1 + χ v_n/δ̇⁻ ≥ 0.2.
            check_regime(
                &joint,
                Regime::DeepSliding,
                10 + (3 * k + m) as u64,
                50,
                0.5,
            );
        }
    }
}

#[test]
fn free_joint_has_zero_forces_and_jacobian() {
    let joint = worn_joint();
    let bearing = BodyState::new([0.0, 0.0, 0.3], [0.1, 0.0, 1.0]);
    let mut pin = BodyState::new([0.07, -0.045, -0.2], [0.0, 0.2, -1.0]);
    // Shift the pin body so that the centres are 0.1 mm apart: inside the 0.5 mm clearance.
    let kin = joint.kinematics(&bearing, &pin);
    pin.x -= kin.eccentricity.x - 1e-4;
    pin.y -= kin.eccentricity.y;
    assert!(joint.penetration(&bearing, &pin) < 0.0);
    let (forces, jacobian) = joint.forces_and_jacobian(&bearing, &pin, Some(0.1));
    assert_eq!(forces.bearing, nalgebra::Vector3::zeros());
    assert_eq!(forces.pin, nalgebra::Vector3::zeros());
    assert_eq!(jacobian, ContactJacobian::zeros());
    assert!(!forces.diagnostics.in_contact);
}
