//! Normal and friction laws: closed forms, the clamp, the onset floor, validation, serde.

mod common;

use contact::{
    Ambrosio, CircularProfile, ClearanceJoint, ContactDiagnostics, ContactError, Coulomb, Flores,
    FrictionLaw, FrictionLawKind, Frictionless, Hertz, HuntCrossley, ImpactMemory, JointSurface,
    LankaraniNikravesh, Material, NormalLaw, NormalLawKind,
};
use proptest::prelude::*;

const K: f64 = 3.0e11;

#[test]
fn hertz_force_matches_closed_form() {
    // K from the conformal formula with joint A's numbers, then F = K δ^1.5.
    let joint = common::round_joint([0.0; 2], [0.0; 2], Hertz::default(), Frictionless);
    let (ri, rj): (f64, f64) = (0.05, 0.0495);
    let epsilon = (1.0 - 0.3f64.powi(2)) / 200e9;
    let expected_k = 4.0 / (3.0 * 2.0 * epsilon) * (ri * rj / (ri - rj)).sqrt();
    let k = joint.stiffness(ri, rj);
    approx::assert_relative_eq!(k, expected_k, max_relative = 1e-14);
    approx::assert_relative_eq!(k, 3.2598e11, max_relative = 1e-4);
    for delta in [1e-7, 3e-6, 2e-5] {
        let f = Hertz::default().evaluate(k, delta, 0.3, 0.1);
        approx::assert_relative_eq!(f.force, expected_k * delta.powf(1.5), max_relative = 1e-14);
        approx::assert_relative_eq!(
            f.d_penetration,
            1.5 * expected_k * delta.sqrt(),
            max_relative = 1e-14
        );
        assert_eq!(f.d_velocity, 0.0);
    }
    // Through the joint: pin pushed 10 µm into the bearing along −y.
    let bearing = contact::BodyState::at_rest(0.0, 0.0, 0.0);
    let pin = contact::BodyState::at_rest(0.0, -(5e-4 + 1e-5), 0.0);
    let forces = joint.forces(&bearing, &pin, None);
    let expected = expected_k * 1e-5f64.powf(1.5);
    approx::assert_relative_eq!(forces.pin.y, expected, max_relative = 1e-9);
    approx::assert_relative_eq!(forces.bearing.y, -expected, max_relative = 1e-9);
    approx::assert_relative_eq!(
        forces.diagnostics.normal_force,
        expected,
        max_relative = 1e-9
    );
}

#[test]
fn damped_laws_match_their_damping_coefficients() {
    let (ce, delta, vel, onset): (f64, f64, f64, f64) = (0.8, 1e-5, 0.05, 0.2);
    let elastic = K * delta.powf(1.5);
    let cases: [(&dyn NormalLaw, f64); 3] = [
        (
            &LankaraniNikravesh::new(ce).unwrap(),
            3.0 * K * (1.0 - ce * ce) / (4.0 * onset),
        ),
        (
            &HuntCrossley::new(ce).unwrap(),
            3.0 * K * (1.0 - ce) / (2.0 * onset),
        ),
        (
            &Flores::new(ce).unwrap(),
            8.0 * K * (1.0 - ce) / (5.0 * ce * onset),
        ),
    ];
    for (law, damping) in cases {
        let f = law.evaluate(K, delta, vel, onset);
        approx::assert_relative_eq!(
            f.force,
            elastic + damping * delta.powf(1.5) * vel,
            max_relative = 1e-13
        );
        approx::assert_relative_eq!(
            f.d_velocity,
            damping * delta.powf(1.5),
            max_relative = 1e-13
        );
        approx::assert_relative_eq!(f.d_stiffness, f.force / K, max_relative = 1e-13);
    }
}

#[test]
fn near_zero_onset_velocity_is_floored() {
    // A pin settling with δ̇⁻ = 0 (or a tiny 1e-9 m/s) must see the damping of δ̇⁻ = 1e-4 m/s,
    // not an unbounded one.
    let law = LankaraniNikravesh::new(0.9).unwrap();
    let floored = law.evaluate(K, 1e-6, 1e-5, 1e-4);
    for onset in [0.0, 1e-9, -1e-9, f64::NAN] {
        let f = law.evaluate(K, 1e-6, 1e-5, onset);
        assert!(f.force.is_finite() && f.d_velocity.is_finite());
        assert_eq!(f, floored, "onset {onset}");
    }
    // Here the damping term is χ δ̇/δ̇⁻ = 0.1425 · 0.1 of the elastic one.
    approx::assert_relative_eq!(
        floored.force,
        K * 1e-9 * (1.0 + 0.1425 * 0.1),
        max_relative = 1e-12
    );
    // A larger floor is configurable and lowers the damping.
    let soft = law.with_onset_velocity_floor(1e-2).unwrap();
    assert!(soft.evaluate(K, 1e-6, 1e-5, 0.0).force < floored.force);
    // An onset above the floor is used as is.
    assert!(law.evaluate(K, 1e-6, 1e-5, 0.5).force < floored.force);
}

#[test]
fn force_clamps_to_zero_when_separating_fast() {
    let law = LankaraniNikravesh::new(0.9).unwrap();
    // χ = 0.1425: adhesive below δ̇ = −δ̇⁻/χ ≈ −7.02 δ̇⁻.
    let f = law.evaluate(K, 1e-5, -8.0 * 0.1, 0.1);
    assert_eq!(f.force, 0.0);
    assert_eq!(
        (f.d_penetration, f.d_velocity, f.d_stiffness),
        (0.0, 0.0, 0.0)
    );
    // The elastic part and its potential are still reported (energy books).
    approx::assert_relative_eq!(f.elastic, K * 1e-5f64.powf(1.5), max_relative = 1e-12);
    approx::assert_relative_eq!(f.potential, f.elastic * 1e-5 / 2.5, max_relative = 1e-12);
    let f = law.evaluate(K, 1e-5, -6.0 * 0.1, 0.1);
    assert!(f.force > 0.0);
}

proptest! {
    #[test]
    fn normal_force_is_never_negative(
        ce in 0.05f64..=1.0,
        delta in -1e-4f64..1e-4,
        vel in -10.0f64..10.0,
        onset in -1.0f64..1.0,
        exponent in 1.0f64..2.5,
    ) {
        let laws = [
            NormalLawKind::LankaraniNikravesh(LankaraniNikravesh::new(ce).unwrap().with_exponent(exponent).unwrap()),
            NormalLawKind::HuntCrossley(HuntCrossley::new(ce).unwrap()),
            NormalLawKind::Flores(Flores::new(ce).unwrap()),
            NormalLawKind::Hertz(Hertz::new(exponent).unwrap()),
        ];
        for law in laws {
            let f = law.evaluate(K, delta, vel, onset);
            prop_assert!(f.force >= 0.0 && f.force.is_finite(), "{law:?}: {f:?}");
            if f.force == 0.0 {
                prop_assert_eq!((f.d_penetration, f.d_velocity, f.d_stiffness), (0.0, 0.0, 0.0));
            }
            // The conservative part: F_e = ∂V/∂δ, both ≥ 0, and zero out of contact.
            prop_assert!(f.elastic >= 0.0 && f.potential >= 0.0);
            if delta > 0.0 {
                let n = match law { NormalLawKind::Hertz(_) | NormalLawKind::LankaraniNikravesh(_) => exponent, _ => 1.5 };
                prop_assert!((f.potential - f.elastic * delta / (n + 1.0)).abs() <= 1e-12 * f.potential);
            } else {
                prop_assert_eq!((f.elastic, f.potential), (0.0, 0.0));
            }
            if delta <= 0.0 {
                prop_assert_eq!(f.force, 0.0);
            }
            // The per-node hysteresis factor is the force at K = δ = 1, bit for bit.
            let unit = law.evaluate(1.0, 1.0, vel, onset);
            let (factor, d_factor) = law.hysteresis(vel, onset);
            prop_assert_eq!((factor.to_bits(), d_factor.to_bits()), (unit.force.to_bits(), unit.d_velocity.to_bits()), "{:?}", law);
        }
    }
}

#[test]
fn ambrosio_friction_is_zero_below_v0_and_continuous_across_the_ramp() {
    let law = Ambrosio::new(0.15, 1e-4, 1e-3).unwrap();
    let fn_ = 1000.0;
    for v in [0.0, 1e-5, 9.99e-5, 1e-4, -1e-4, -5e-5] {
        assert_eq!(law.evaluate(v, fn_).force, 0.0, "v_t = {v}");
    }
    // Continuity: sweep through the corners with a fine step; the force may change at most by
    // its slope times the step (c_f F_n / (v_1 − v_0) · dv).
    let dv = 1e-8;
    let bound = 0.15 * fn_ / 9e-4 * dv * (1.0 + 1e-9);
    let mut previous = law.evaluate(-2e-3, fn_).force;
    let mut v = -2e-3 + dv;
    while v < 2e-3 {
        let f = law.evaluate(v, fn_).force;
        assert!(
            (f - previous).abs() <= bound,
            "jump at v_t = {v}: {previous} → {f}"
        );
        previous = f;
        v += dv;
    }
    // Mid-ramp and full slip values; odd in v_t; opposes sliding through F = −F_t t on the pin.
    approx::assert_relative_eq!(
        law.evaluate(5.5e-4, fn_).force,
        0.15 * 0.5 * fn_,
        max_relative = 1e-12
    );
    assert_eq!(law.evaluate(0.1, fn_).force, 0.15 * fn_);
    assert_eq!(law.evaluate(-0.1, fn_).force, -0.15 * fn_);
    // Partials inside the ramp.
    let f = law.evaluate(-5.5e-4, fn_);
    approx::assert_relative_eq!(f.d_velocity, 0.15 * fn_ / 9e-4, max_relative = 1e-12);
    approx::assert_relative_eq!(f.d_normal_force, -0.15 * 0.5, max_relative = 1e-12);
}

#[test]
fn coulomb_and_none() {
    let law = Coulomb::new(0.2).unwrap();
    assert_eq!(law.evaluate(1e-9, 10.0).force, 2.0);
    assert_eq!(law.evaluate(-3.0, 10.0).force, -2.0);
    assert_eq!(law.evaluate(0.0, 10.0).force, 0.0);
    assert_eq!(FrictionLawKind::None.evaluate(1.0, 10.0).force, 0.0);
}

fn assert_names(result: Result<impl std::fmt::Debug, ContactError>, parameter: &str, value: &str) {
    let err = result.expect_err("must be rejected");
    let message = err.to_string();
    assert!(
        message.contains(parameter),
        "{message:?} should name {parameter}"
    );
    assert!(message.contains(value), "{message:?} should show {value}");
}

#[test]
fn invalid_parameters_are_rejected_with_their_name() {
    assert_names(LankaraniNikravesh::new(0.0), "restitution", "0");
    assert_names(HuntCrossley::new(1.2), "restitution", "1.2");
    assert_names(Flores::new(-0.5), "restitution", "-0.5");
    assert_names(Flores::new(f64::NAN), "restitution", "NaN");
    assert_names(
        LankaraniNikravesh::new(0.9).unwrap().with_exponent(0.5),
        "exponent",
        "0.5",
    );
    assert_names(
        LankaraniNikravesh::new(0.9)
            .unwrap()
            .with_onset_velocity_floor(0.0),
        "onset_velocity_floor",
        "0",
    );
    assert_names(Hertz::new(f64::INFINITY), "exponent", "inf");
    assert_names(Ambrosio::new(0.15, 1e-3, 1e-3), "slip_velocity", "0.001");
    assert_names(Ambrosio::new(0.15, 1e-3, 1e-4), "slip_velocity", "0.0001");
    assert_names(Ambrosio::new(-0.1, 1e-4, 1e-3), "coefficient", "-0.1");
    assert_names(Coulomb::new(f64::NAN), "coefficient", "NaN");
    assert_names(Material::new(0.0, 0.3), "youngs_modulus", "0");
    assert_names(Material::new(-2e11, 0.3), "youngs_modulus", "-200000000000");
    assert_names(Material::new(2e11, 0.5), "poisson_ratio", "0.5");
    assert_names(Material::new(2e11, -1.0), "poisson_ratio", "-1");
    assert_names(Material::new(f64::NAN, 0.3), "youngs_modulus", "NaN");

    let steel = common::steel();
    let joint = |bearing_radius: f64, pin_radius: f64, centre: f64| {
        ClearanceJoint::new(
            JointSurface {
                centre: [centre, 0.0],
                profile: CircularProfile::new(bearing_radius),
                material: steel,
            },
            JointSurface {
                centre: [0.0, 0.0],
                profile: CircularProfile::new(pin_radius),
                material: steel,
            },
            Hertz::default(),
            Frictionless,
        )
    };
    assert!(joint(0.05, 0.0495, 0.0).is_ok());
    // Pin larger than bearing (negative clearance) and zero clearance.
    assert!(matches!(
        joint(0.05, 0.051, 0.0),
        Err(ContactError::NonPositiveClearance {
            bearing_radius: 0.05,
            pin_radius: 0.051,
            ..
        })
    ));
    assert_names(joint(0.05, 0.051, 0.0), "clearance", "0.051");
    assert!(joint(0.05, 0.05, 0.0).is_err());
    assert_names(joint(0.05, -0.01, 0.0), "pin radius", "-0.01");
    assert_names(joint(f64::NAN, 0.04, 0.0), "bearing radius", "NaN");
    assert_names(joint(0.05, 0.04, f64::INFINITY), "bearing centre x", "inf");
}

#[test]
fn impact_memory_records_the_crossing_velocity() {
    let free = ContactDiagnostics {
        in_contact: false,
        penetration: -1e-6,
        normal_velocity: 0.10,
        ..Default::default()
    };
    let touching = ContactDiagnostics {
        in_contact: true,
        penetration: 3e-6,
        normal_velocity: 0.06,
        ..Default::default()
    };
    let deeper = ContactDiagnostics {
        in_contact: true,
        penetration: 5e-6,
        normal_velocity: 0.01,
        ..Default::default()
    };
    let mut memory = ImpactMemory::new();
    assert_eq!(memory.onset_velocity(), None);
    memory.update(&free, &free);
    assert_eq!(memory.onset_velocity(), None);
    memory.update(&free, &touching);
    // δ crosses 0 a quarter into the step: 0.10 + 0.25 (0.06 − 0.10) = 0.09.
    approx::assert_relative_eq!(memory.onset_velocity().unwrap(), 0.09, max_relative = 1e-12);
    memory.update(&touching, &deeper);
    approx::assert_relative_eq!(memory.onset_velocity().unwrap(), 0.09, max_relative = 1e-12);
    memory.update(&deeper, &free);
    assert_eq!(memory.onset_velocity(), None);
    // Starting in contact: the current velocity is taken.
    memory.update(&deeper, &deeper);
    assert_eq!(memory.onset_velocity(), Some(0.01));
}

#[test]
fn laws_round_trip_through_serde_and_validate_on_load() {
    let normal: NormalLawKind =
        serde_json::from_str(r#"{"law": "lankarani_nikravesh", "restitution": 0.9}"#).unwrap();
    assert_eq!(
        normal,
        NormalLawKind::LankaraniNikravesh(LankaraniNikravesh::new(0.9).unwrap())
    );
    let text = serde_json::to_string(&normal).unwrap();
    assert_eq!(
        serde_json::from_str::<NormalLawKind>(&text).unwrap(),
        normal
    );
    let flores: NormalLawKind = serde_json::from_str(
        r#"{"law": "flores", "restitution": 0.5, "exponent": 1.0, "onset_velocity_floor": 0.001}"#,
    )
    .unwrap();
    assert_eq!(
        flores,
        NormalLawKind::Flores(
            Flores::new(0.5)
                .unwrap()
                .with_exponent(1.0)
                .unwrap()
                .with_onset_velocity_floor(1e-3)
                .unwrap()
        )
    );
    let hertz: NormalLawKind = serde_json::from_str(r#"{"law": "hertz"}"#).unwrap();
    assert_eq!(hertz, NormalLawKind::Hertz(Hertz::default()));
    let friction: FrictionLawKind = serde_json::from_str(
        r#"{"law": "ambrosio", "coefficient": 0.15, "stick_velocity": 1e-4, "slip_velocity": 1e-3}"#,
    )
    .unwrap();
    assert_eq!(
        friction,
        FrictionLawKind::Ambrosio(Ambrosio::new(0.15, 1e-4, 1e-3).unwrap())
    );
    let none: FrictionLawKind = serde_json::from_str(r#"{"law": "none"}"#).unwrap();
    assert_eq!(none, FrictionLawKind::None);
    let material: Material =
        serde_json::from_str(r#"{"youngs_modulus": 2e11, "poisson_ratio": 0.3}"#).unwrap();
    assert_eq!(material, common::steel());

    // Invalid values are rejected on load, naming the parameter.
    let err =
        serde_json::from_str::<NormalLawKind>(r#"{"law": "hunt_crossley", "restitution": 1.5}"#)
            .unwrap_err();
    assert!(err.to_string().contains("restitution"), "{err}");
    let err = serde_json::from_str::<FrictionLawKind>(
        r#"{"law": "ambrosio", "coefficient": 0.15, "stick_velocity": 1e-3, "slip_velocity": 1e-4}"#,
    )
    .unwrap_err();
    assert!(err.to_string().contains("slip_velocity"), "{err}");
    let err = serde_json::from_str::<Material>(r#"{"youngs_modulus": 2e11, "poisson_ratio": 0.7}"#)
        .unwrap_err();
    assert!(err.to_string().contains("poisson_ratio"), "{err}");
}
