//! The thin-gap contact on worn outlines against laws that can fail: its overlap against the
//! exact overlap of the outlines along the same rays, the force as the exact gradient of its
//! stored energy, the exact Jacobian against finite differences, C¹ forces as a zone edge
//! crosses a node, the force against the exact-outline foundation, and its validity measure.

mod common;

use common::foundation::*;
use common::steel;
use contact::{
    BodyState, ClearanceJoint, ContactModel, ContactModelKind, Foundation, FrictionLaw,
    Frictionless, NormalLaw, SlidingVelocity, SurfaceProfile, ThinGap, ValidityMeasure,
};
use rand::{Rng, SeedableRng};
use rand_chacha::ChaCha8Rng;
use std::f64::consts::TAU;

/// The thin-gap model on the foundation's calibrated layer with `cells` nodes.
fn thin_gap(cells: usize) -> ThinGap {
    ThinGap::new(
        Foundation::calibrated(&steel(), &steel())
            .with_cells(cells)
            .expect("even cells"),
    )
}

/// The bearing of the test's worn joints: a wide groove 0.25 mm deep at 250°.
fn worn_bearing() -> Groove {
    Groove {
        base: common::BEARING_RADIUS,
        sign: 1.0,
        depth: 2.5e-4,
        centre: 250f64.to_radians(),
        sigma: 0.35,
    }
}

/// A joint worn as the LGRES's joints are: a 0.25 mm groove in the bearing at 250° (a
/// 0.5 mm wear depth) and a 0.1 mm flat on the pin at 70°, off-centroid centres, on the thin
/// gap of `cells` nodes. ([`worn`]'s 1.2 mm groove and 0.8 mm flat are beyond the thin gap:
/// `outside_validity_the_measure_says_so`.)
fn worn_thin<N: NormalLaw, F: FrictionLaw>(
    normal: N,
    friction: F,
    cells: usize,
) -> ClearanceJoint<Groove, Groove, N, F> {
    let bearing = worn_bearing();
    let pin = Groove {
        base: common::BEARING_RADIUS - common::CLEARANCE,
        sign: -1.0,
        depth: 1e-4,
        centre: 70f64.to_radians(),
        sigma: 0.5,
    };
    common::off_centre_joint(bearing, pin, normal, friction).with_model(thin_gap(cells))
}

/// The largest neglected terms over random contacts of `joint` (overlaps 5–40 µm at bearing
/// angle 250°), each against the deepest overlap's error there (the exact outlines along the
/// node's rays; both relative to the overlap): `(neglected, error)` at each pose.
fn measure_and_error<B, P, N, F>(joint: &ClearanceJoint<B, P, N, F>, seed: u64) -> Vec<(f64, f64)>
where
    B: SurfaceProfile,
    P: SurfaceProfile,
    N: NormalLaw,
    F: FrictionLaw,
{
    let cells = joint.model().nodes().expect("a layer");
    let (bearing_profile, pin_profile) =
        (joint.pair().bearing_profile(), joint.pair().pin_profile());
    let mut rng = ChaCha8Rng::seed_from_u64(seed);
    (0..30)
        .map(|_| {
            let (bearing, pin) =
                random_contact(joint, &mut rng, 0.0, 250f64.to_radians(), 0.6, 5e-6..4e-5);
            let neglected = joint
                .forces(&bearing, &pin, None)
                .diagnostics
                .neglected_terms;
            let depth = joint.penetration(&bearing, &pin);
            let (eps, turn) = relative_pose(joint, &bearing, &pin);
            let exact = (0..cells)
                .map(|k| {
                    let theta = (k as f64 + 0.5) * TAU / cells as f64;
                    exact_overlap(pin_profile, bearing_profile, eps, turn, theta)
                })
                .fold(f64::NEG_INFINITY, f64::max);
            (neglected, (depth - exact).abs() / exact)
        })
        .collect()
}

/// The measure follows the overlap's error: on the deep groove and flat of [`worn`] (1.2 mm
/// and 0.8 mm) and on a narrow 0.8 mm flat in a clearance of 8 % of the radius it bounds the
/// deepest overlap's error at every pose, by less than four times the largest error.
#[test]
fn the_measure_bounds_the_overlaps_error() {
    let narrow_pin = Groove {
        base: common::BEARING_RADIUS - 4e-3,
        sign: -1.0,
        depth: 8e-4,
        centre: 70f64.to_radians(),
        sigma: 0.05,
    };
    let bearing = worn_bearing();
    let narrow = common::off_centre_joint(bearing, narrow_pin, hertz(), Frictionless)
        .with_model(thin_gap(1000));
    let deep = worn(hertz(), Frictionless).with_model(thin_gap(1000));
    for (name, poses) in [
        ("deep groove", measure_and_error(&deep, 44)),
        ("narrow flat", measure_and_error(&narrow, 45)),
    ] {
        for &(neglected, error) in &poses {
            assert!(neglected >= error, "{name}: {neglected:e} < {error:e}");
        }
        let (neglected, error) = poses.iter().fold((0.0_f64, 0.0_f64), |(n, e), &(pn, pe)| {
            (n.max(pn), e.max(pe))
        });
        eprintln!("{name}: neglected terms up to {neglected:.2e}, overlap error {error:.2e}");
        assert!(
            neglected < 4.0 * error,
            "{name}: {neglected:e} vs {error:e}"
        );
    }
}

#[test]
fn the_model_is_asked_not_named() {
    let model = ContactModelKind::from(thin_gap(1000));
    assert_eq!(model.name(), "thin-gap");
    assert_eq!(model.nodes(), Some(1000));
    assert!(
        model
            .validity_measures()
            .contains(&ValidityMeasure::NeglectedTerms)
    );
}

/// The pin centre from the bearing centre in the bearing's frame, and the pin's turn.
fn relative_pose<B, P, N, F>(
    joint: &ClearanceJoint<B, P, N, F>,
    bearing: &BodyState,
    pin: &BodyState,
) -> ([f64; 2], f64)
where
    B: SurfaceProfile,
    P: SurfaceProfile,
    N: NormalLaw,
    F: FrictionLaw,
{
    let centre = |body: &BodyState, local: [f64; 2]| {
        let (s, c) = body.theta.sin_cos();
        [
            body.x + c * local[0] - s * local[1],
            body.y + s * local[0] + c * local[1],
        ]
    };
    let ci = centre(bearing, joint.pair().bearing_centre());
    let cj = centre(pin, joint.pair().pin_centre());
    let e = [cj[0] - ci[0], cj[1] - ci[1]];
    let (s, c) = bearing.theta.sin_cos();
    (
        [c * e[0] + s * e[1], c * e[1] - s * e[0]],
        pin.theta - bearing.theta,
    )
}

/// The exact overlap of the outlines along the bearing-frame ray `theta`: the pin's outline
/// point on that ray (found by iterating on its polar angle about the pin centre) less the
/// bearing's radius there.
fn exact_overlap(
    pin: &impl SurfaceProfile,
    bearing: &impl SurfaceProfile,
    eps: [f64; 2],
    turn: f64,
    theta: f64,
) -> f64 {
    let mut beta = theta;
    let point = |beta: f64| {
        let r = pin.sample(beta - turn).radius;
        [eps[0] + r * beta.cos(), eps[1] + r * beta.sin()]
    };
    for _ in 0..60 {
        let p = point(beta);
        let off = (theta - p[1].atan2(p[0]) + std::f64::consts::PI).rem_euclid(TAU)
            - std::f64::consts::PI;
        beta += off;
    }
    let p = point(beta);
    p[0].hypot(p[1]) - bearing.sample(theta).radius
}

/// The model's deepest overlap (its event function) against the exact deepest overlap along
/// the same rays, over random contacts on the worn joint: within a few 1e-4 of the overlap,
/// while the first-order film thickness `ε·n + r(θ − Δ) − R_i(θ)`, the same without the
/// chord's `b²/(2r)`, the reading shift's `r' b/r` and the curvature's `r'' b²/(2r²)`, errs by
/// far more. What it neglects is third order: within 1e-5 of the overlap (without the
/// curvature term 3.8e-4; reading the second-order terms at the pin's largest radius instead
/// of its own, 6.5e-5 more).
#[test]
fn the_overlap_matches_the_exact_outlines_to_second_order() {
    let cells = 1000;
    let joint = worn_thin(hertz(), Frictionless, cells);
    let (bearing_profile, pin_profile) =
        (joint.pair().bearing_profile(), joint.pair().pin_profile());
    let mut rng = ChaCha8Rng::seed_from_u64(44);
    let (mut worst, mut worst_first): (f64, f64) = (0.0, 0.0);
    for _ in 0..60 {
        let offset = if rng.random_bool(0.5) { 250f64 } else { 130f64 }.to_radians();
        let (bearing, pin) = random_contact(&joint, &mut rng, 0.0, offset, 0.6, 5e-6..4e-5);
        assert!(
            joint
                .forces(&bearing, &pin, None)
                .diagnostics
                .neglected_terms
                < 1e-3
        );
        let depth = joint.penetration(&bearing, &pin);
        let (eps, turn) = relative_pose(&joint, &bearing, &pin);
        let (mut exact, mut first) = (f64::NEG_INFINITY, f64::NEG_INFINITY);
        for k in 0..cells {
            let theta = (k as f64 + 0.5) * TAU / cells as f64;
            exact = exact.max(exact_overlap(
                pin_profile,
                bearing_profile,
                eps,
                turn,
                theta,
            ));
            let a = eps[0] * theta.cos() + eps[1] * theta.sin();
            first = first.max(
                a + pin_profile.sample(theta - turn).radius - bearing_profile.sample(theta).radius,
            );
        }
        worst = worst.max((depth - exact).abs() / exact);
        worst_first = worst_first.max((first - exact).abs() / exact);
    }
    eprintln!(
        "deepest overlap against the exact outlines: thin gap {worst:.2e}, first order \
         {worst_first:.2e} (relative)"
    );
    assert!(worst < 1e-5, "{worst:e}");
    assert!(worst_first > 1000.0 * worst, "{worst_first:e} vs {worst:e}");
}

#[test]
fn elastic_force_is_the_gradient_of_the_stored_energy() {
    let joint = worn_thin(hertz(), Frictionless, 1000);
    let mut rng = ChaCha8Rng::seed_from_u64(21);
    let mut worst: f64 = 0.0;
    for sample in 0..40 {
        let (bearing, pin) =
            random_contact(&joint, &mut rng, 0.0, 250f64.to_radians(), 0.8, 2e-6..4e-5);
        let z = common::state_vector(&bearing, &pin);
        let forces = joint.forces(&bearing, &pin, None);
        let energy = |z: &[f64; 12]| {
            let (b, p) = common::states_from(z);
            joint.forces(&b, &p, None).diagnostics.elastic_energy
        };
        let q = common::force_vector(&forces);
        let step = |col: usize| if col % 3 == 2 { 1e-9 } else { 1e-10 };
        let case = format!("sample {sample}");
        worst = worst.max(common::energy_gradient_error(
            &z, &q, step, energy, 1e-5, &case,
        ));
    }
    eprintln!("worst |Q + ∇V| / max|Q| over 40 worn states: {worst:.2e}");
}

fn check_jacobian<B, P, N, F>(joint: &ClearanceJoint<B, P, N, F>, seed: u64, phi_offset: f64)
where
    B: SurfaceProfile,
    P: SurfaceProfile,
    N: NormalLaw,
    F: FrictionLaw,
{
    let mut rng = ChaCha8Rng::seed_from_u64(seed);
    let mut worst: f64 = 0.0;
    for sample in 0..30 {
        let (bearing, pin) = random_contact(joint, &mut rng, 0.2, phi_offset, 0.8, 2e-6..3e-5);
        let onset = rng.random_range(0.05..0.5);
        let z = common::state_vector(&bearing, &pin);
        let (forces, analytic) = joint.forces_and_jacobian(&bearing, &pin, Some(onset));
        assert!(forces.diagnostics.in_contact);
        let plain = joint.forces(&bearing, &pin, Some(onset));
        assert_eq!(plain.pin, forces.pin, "the f64 and dual evaluations agree");
        let scale = common::force_vector(&forces)
            .iter()
            .fold(0.0f64, |m, v| m.max(v.abs()));
        for col in 0..12 {
            let h = match col {
                0 | 1 | 3 | 4 => 1e-11,
                2 | 5 => 1e-10,
                _ => 1e-8,
            };
            let column = common::central_difference(&z, col, h, |z| {
                common::generalized_forces(joint, z, onset)
            });
            for (row, numeric) in column.into_iter().enumerate() {
                let column_scale = if col < 6 { scale / 1e-5 } else { scale };
                let error = (analytic[(row, col)] - numeric).abs() / column_scale;
                worst = worst.max(error);
                assert!(
                    error < 2e-4,
                    "sample {sample} ({row}, {col}): analytic {:e} vs FD {numeric:e}",
                    analytic[(row, col)]
                );
            }
        }
    }
    eprintln!("worst Jacobian error (scaled) over 30 states: {worst:.2e}");
}

#[test]
fn jacobian_matches_finite_differences_on_worn_outlines() {
    let (normal, friction) = common::lgres_laws(0.9);
    check_jacobian(&worn_thin(normal, friction, 1000), 7, 250f64.to_radians());
    let paper = worn_thin(normal, friction, 1000).with_friction_sliding(SlidingVelocity::Paper);
    check_jacobian(&paper, 8, 130f64.to_radians());
}

#[test]
fn force_is_smooth_as_a_zone_edge_crosses_a_node() {
    // Press the pin in: nodes enter the arc. The force is C¹, so its stiffness (the exact
    // Jacobian's) changes smoothly: its second difference along the path stays far below the
    // jump a node entering the plain nodal sum would make (its share, ~1/zone width).
    let joint = worn_thin(hertz(), Frictionless, 1000);
    let bearing = BodyState::at_rest(0.0, 0.0, 0.3);
    let pin = place(&joint, bearing, 1.1, 0.3 + 250f64.to_radians(), 5e-6);
    let direction = [
        (0.3 + 250f64.to_radians()).cos(),
        (0.3 + 250f64.to_radians()).sin(),
    ];
    let stiffness: Vec<f64> = (0..400)
        .map(|k| {
            let s = k as f64 * 5e-9;
            let moved = BodyState::at_rest(
                pin.x + s * direction[0],
                pin.y + s * direction[1],
                pin.theta,
            );
            let (_, j) = joint.forces_and_jacobian(&bearing, &moved, None);
            j[(3, 3)] * direction[0] + j[(3, 4)] * direction[1]
        })
        .collect();
    let scale = stiffness.iter().fold(0.0f64, |m, v| m.max(v.abs()));
    let worst = stiffness
        .windows(3)
        .map(|w| (w[0] - 2.0 * w[1] + w[2]).abs() / scale)
        .fold(0.0, f64::max);
    eprintln!("largest second difference of the stiffness: {worst:.2e} of it");
    assert!(worst < 2e-3, "{worst:e}");
}

/// The force on worn outlines against the exact-outline foundation on four times the nodes:
/// the same layer, so the same force to the thin gap's neglected terms and the quadrature.
#[test]
fn the_force_matches_the_exact_outline_foundation() {
    let joint = worn_thin(hertz(), Frictionless, 1000);
    let reference = joint.clone().with_model(
        Foundation::calibrated(&steel(), &steel())
            .with_cells(4000)
            .expect("even"),
    );
    let mut rng = ChaCha8Rng::seed_from_u64(5);
    let mut worst: f64 = 0.0;
    let mut neglected: f64 = 0.0;
    for _ in 0..40 {
        let (bearing, pin) =
            random_contact(&joint, &mut rng, 0.0, 250f64.to_radians(), 0.8, 5e-6..4e-5);
        let thin = joint.forces(&bearing, &pin, None);
        let exact = reference.forces(&bearing, &pin, None);
        let error = (thin.pin - exact.pin).xy().norm() / exact.pin.xy().norm();
        worst = worst.max(error);
        neglected = neglected.max(thin.diagnostics.neglected_terms);
    }
    eprintln!(
        "force against the foundation on 4000 nodes: worst {worst:.2e}; neglected terms ≤ {neglected:.2e}"
    );
    assert!(worst < 2e-4, "{worst:e}");
    assert!(neglected > 0.0 && neglected < 1e-3, "{neglected:e}");
}
