//! Invalid parameters give errors naming the parameter and value.

mod common;

use common::*;
use wear::{
    Extrapolation, Side, StagePlan, StageWear, WearError, WearParams, WornJoint, WornProfile,
};

fn name(e: WearError) -> &'static str {
    match e {
        WearError::InvalidParameter { name, .. } => name,
        other => panic!("expected InvalidParameter, got {other:?}"),
    }
}

#[test]
fn wear_params_refuse_negative_nan_or_infinite_values_and_zero_cells() {
    assert_eq!(
        name(WearParams::new(-1e-13, WIDTH, 10).unwrap_err()),
        "wear_coefficient"
    );
    assert_eq!(
        name(WearParams::new(f64::NAN, WIDTH, 10).unwrap_err()),
        "wear_coefficient"
    );
    assert_eq!(
        name(WearParams::new(K_D, 0.0, 10).unwrap_err()),
        "hinge_width"
    );
    assert_eq!(
        name(WearParams::new(K_D, f64::INFINITY, 10).unwrap_err()),
        "hinge_width"
    );
    assert_eq!(
        WearParams::new(K_D, WIDTH, 0).unwrap_err(),
        WearError::ZeroCells
    );
    let e = WearParams::new(K_D, -0.5, 10).unwrap_err();
    assert!(e.to_string().contains("hinge_width = -0.5"), "{e}");
}

#[test]
fn zero_wear_coefficient_means_off() {
    let off = WearParams::new(0.0, WIDTH, 1000).unwrap();
    assert!(
        WornJoint::if_wearing(&off, R_BEARING, R_PIN)
            .unwrap()
            .is_none()
    );
    // Radii are still validated when wear is off.
    assert!(matches!(
        WornJoint::if_wearing(&off, R_PIN, R_BEARING),
        Err(WearError::RadiiInconsistent { .. })
    ));
    // A joint value always means wear on.
    let b = WornProfile::new(Side::Bearing, R_BEARING, 10).unwrap();
    let p = WornProfile::new(Side::Pin, R_PIN, 10).unwrap();
    assert_eq!(
        name(WornJoint::from_profiles(0.0, WIDTH, b.clone(), p.clone()).unwrap_err()),
        "wear_coefficient"
    );
    assert_eq!(
        WornJoint::from_profiles(K_D, WIDTH, p, b).unwrap_err(),
        WearError::WrongSide { name: "bearing" }
    );
}

#[test]
fn worn_joint_refuses_a_pin_not_smaller_than_its_bearing_and_bad_radii() {
    let params = WearParams::new(K_D, WIDTH, 10).unwrap();
    assert_eq!(
        WornJoint::new(&params, 0.05, 0.05).unwrap_err(),
        WearError::RadiiInconsistent {
            pin: 0.05,
            bearing: 0.05
        }
    );
    assert_eq!(
        name(WornJoint::new(&params, 0.05, -0.01).unwrap_err()),
        "pin_radius"
    );
    assert_eq!(
        name(WornJoint::new(&params, f64::NAN, 0.01).unwrap_err()),
        "bearing_radius"
    );
}

#[test]
fn depths_must_be_finite_and_non_negative_and_grids_must_match() {
    let e = WornProfile::from_depths(Side::Pin, R_PIN, vec![0.0, -1e-9]).unwrap_err();
    assert_eq!(
        e,
        WearError::InvalidDepth {
            name: "depth",
            index: 1,
            value: -1e-9
        }
    );
    assert_eq!(
        WornProfile::from_depths(Side::Pin, R_PIN, vec![]).unwrap_err(),
        WearError::ZeroCells
    );
    let j = joint(10);
    let e = StageWear::from_depths(&j, vec![0.0; 9], vec![0.0; 10]).unwrap_err();
    assert_eq!(
        e,
        WearError::GridMismatch {
            name: "bearing wear",
            expected: 10,
            found: 9
        }
    );
    let e = StageWear::from_depths(&j, vec![0.0; 10], vec![f64::NAN; 10]).unwrap_err();
    assert!(matches!(
        e,
        WearError::InvalidDepth {
            name: "pin wear",
            index: 0,
            ..
        }
    ));
}

#[test]
fn apply_refuses_non_positive_amplification_and_a_pin_worn_through_unchanged() {
    let mut j = joint(10);
    let w = StageWear::from_depths(&j, vec![1e-6; 10], vec![1e-6; 10]).unwrap();
    assert_eq!(name(j.apply(&w, 0.0).unwrap_err()), "amplification");
    assert_eq!(name(j.apply(&w, -2.0).unwrap_err()), "amplification");
    let before = j.clone();
    let e = j.apply(&w, 1e6).unwrap_err();
    assert!(matches!(e, WearError::PinWornThrough { .. }), "{e}");
    assert_eq!(j, before, "a refused update leaves the joint untouched");
}

#[test]
fn profiles_deeper_than_their_radius_are_refused() {
    use wear::{Side, WornProfile};
    // A surface loses half the depth from its radius: 0.1 m of depth on a 0.05 m radius leaves
    // none, on either side; 0.099 m leaves 0.5 mm.
    let deep = |side| WornProfile::from_depths(side, 0.05, vec![0.0, 0.1, 0.0, 0.0]).unwrap_err();
    assert!(matches!(deep(Side::Pin), WearError::PinWornThrough { .. }));
    assert!(matches!(
        deep(Side::Bearing),
        WearError::BearingTooDeep { .. }
    ));
    assert!(WornProfile::from_depths(Side::Bearing, 0.05, vec![0.0, 0.099, 0.0, 0.0]).is_ok());
}

#[test]
fn stage_plans_refuse_out_of_range_fractions_counts_and_amplifications() {
    let with = |x| StagePlan::paper(1).with_extrapolation(x);
    let adaptive = |f| {
        with(Extrapolation::Adaptive {
            max_fraction: f,
            max_substeps: 10,
            max_slope_change: f64::INFINITY,
            max_curvature_change: f64::INFINITY,
        })
    };
    for bad in [0.0, -0.1, 1.5, f64::NAN] {
        assert_eq!(name(adaptive(bad).validate().unwrap_err()), "max_fraction");
        assert_eq!(
            name(
                with(Extrapolation::SingleJump { warn_fraction: bad })
                    .validate()
                    .unwrap_err()
            ),
            "warn_fraction"
        );
    }
    assert!(adaptive(1.0).validate().is_ok());
    assert_eq!(
        name(
            with(Extrapolation::Adaptive {
                max_fraction: 0.1,
                max_substeps: 0,
                max_slope_change: f64::INFINITY,
                max_curvature_change: f64::INFINITY,
            })
            .validate()
            .unwrap_err()
        ),
        "max_substeps"
    );
    let controlled = |tolerance, min_fraction, max_fraction, max_runs| {
        with(Extrapolation::Controlled {
            tolerance,
            min_fraction,
            max_fraction,
            max_runs,
        })
        .validate()
    };
    assert!(controlled(0.02, 0.05, 0.5, 10).is_ok());
    for bad in [0.0, -0.1, 1.5, f64::NAN] {
        let err = |plan: Result<(), WearError>| name(plan.unwrap_err());
        assert_eq!(err(controlled(bad, 0.05, 0.5, 10)), "tolerance");
        assert_eq!(err(controlled(0.02, bad, 0.5, 10)), "min_fraction");
    }
    for bad in [0.01, f64::NAN] {
        assert_eq!(
            name(controlled(0.02, 0.05, bad, 10).unwrap_err()),
            "max_fraction"
        );
    }
    assert_eq!(
        name(controlled(0.02, 0.05, 0.5, 0).unwrap_err()),
        "max_runs"
    );
    for bad in [0.0, -20_000.0, f64::INFINITY] {
        let plan = StagePlan::paper(1).with_amplification(bad);
        assert_eq!(name(plan.validate().unwrap_err()), "amplification");
    }
}
