//! Bad input gives a clear error naming the culprit, never a panic.

mod common;

use std::f64::consts::PI;

use common::{FourBar, SliderCrank, pendulum, with_gravity};
use multibody::{
    Anchor, AssemblyError, Body, BodyId, Constant, DriveTarget, JointId, KinematicsError, Model,
    ModelError, OutputTimes, RotationLock, SimulationError, SimulationOptions, System,
};

#[test]
fn invalid_mass_and_inertia_name_the_body() {
    let mut model = Model::new();
    for (mass, inertia) in [
        (0.0, 1.0),
        (-1.0, 1.0),
        (f64::NAN, 1.0),
        (1.0, 0.0),
        (1.0, -2.0),
        (1.0, f64::INFINITY),
    ] {
        let error = model
            .add_body(Body::new("link 7", mass, inertia, [0.0; 3]))
            .expect_err("must be rejected");
        assert!(error.to_string().contains("link 7"), "{error}");
        assert!(matches!(
            error,
            ModelError::InvalidMass { .. } | ModelError::InvalidInertia { .. }
        ));
    }
    let error = model
        .add_body(Body::new("drifter", 1.0, 1.0, [0.0, f64::NAN, 0.0]))
        .expect_err("non-finite pose");
    assert!(matches!(error, ModelError::NonFiniteBodyState { .. }));
}

#[test]
fn a_named_body_needs_its_mass_and_inertia() {
    let mut model = Model::new();
    let error = model
        .add_body(Body::named("rod").with_inertia(0.1))
        .expect_err("mass never given");
    assert!(matches!(error, ModelError::InvalidMass { .. }), "{error}");
    let error = model
        .add_body(Body::named("rod").with_mass(1.0))
        .expect_err("inertia never given");
    assert!(
        matches!(error, ModelError::InvalidInertia { .. }),
        "{error}"
    );
    let body = Body::named("rod")
        .with_mass(2.0)
        .with_inertia(0.1)
        .with_pose([0.5, 0.0, 0.3]);
    assert_eq!(body, Body::new("rod", 2.0, 0.1, [0.5, 0.0, 0.3]));
    assert!(model.add_body(body).is_ok());
}

#[test]
fn joints_and_drivers_must_refer_to_existing_items() {
    let mut model = Model::new();
    let body = model
        .add_body(Body::new("b", 1.0, 1.0, [0.0; 3]))
        .expect("valid");
    let error = model
        .add_revolute(
            "hinge",
            Anchor::on(body, 0.0, 0.0),
            Anchor::on(BodyId(4), 0.0, 0.0),
        )
        .expect_err("missing body");
    assert_eq!(
        error,
        ModelError::MissingBody {
            owner: "joint",
            name: "hinge".into(),
            index: 4,
            count: 1
        }
    );
    assert!(error.to_string().contains("hinge") && error.to_string().contains("#4"));
    let error = model
        .add_revolute(
            "self",
            Anchor::on(body, 0.0, 0.0),
            Anchor::on(body, 1.0, 0.0),
        )
        .expect_err("same body");
    assert!(matches!(error, ModelError::DegenerateJoint { .. }));
    // A slot along `axis` from the ground origin, and a motor on the angle of `joint`.
    let add_slot = |model: &mut Model, axis| {
        model.add_prismatic(
            "slot",
            Anchor::ground(0.0, 0.0),
            axis,
            Anchor::on(body, 0.0, 0.0),
            RotationLock::Free,
        )
    };
    let add_motor = |model: &mut Model, joint| {
        model.add_driver(
            "motor",
            DriveTarget::JointAngle(joint),
            Box::new(Constant(0.0)),
        )
    };
    let error = add_slot(&mut model, [0.0, 0.0]).expect_err("zero axis");
    assert!(matches!(error, ModelError::ZeroAxis { .. }));
    let error = add_motor(&mut model, JointId(2)).expect_err("missing joint");
    assert!(matches!(error, ModelError::MissingJoint { index: 2, .. }));
    let slot = add_slot(&mut model, [1.0, 0.0]).expect("valid");
    let error = add_motor(&mut model, slot).expect_err("angle of a prismatic joint");
    assert!(
        matches!(error, ModelError::WrongJointKind { .. }),
        "{error}"
    );
    assert!(matches!(System::new(Model::new()), Err(ModelError::Empty)));
}

#[test]
fn redundant_joint_is_named_as_rank_deficient() {
    // The slider's guide already holds y = 0; driving y again adds an equation but no
    // independent constraint (9 equations, rank 8).
    let (mut model, _) = SliderCrank::STANDARD.model(0.5);
    model
        .add_driver(
            "second pin",
            DriveTarget::Coordinate(BodyId(2), multibody::Coordinate::Y),
            Box::new(Constant(0.0)),
        )
        .expect("valid as data");
    let system = System::new(model).expect("valid");
    let (q, qd) = system.initial_guess();
    let error = system.assemble(0.0, &q, &qd).expect_err("rank deficient");
    match &error {
        AssemblyError::RankDeficient { dependent, .. } => {
            assert!(dependent.contains("second pin"), "{error}")
        }
        other => panic!("unexpected {other}"),
    }
}

#[test]
fn overconstrained_mechanism_is_rejected() {
    let mut model = pendulum(1.0, 1.0, -PI / 2.0);
    for (k, target) in [multibody::Coordinate::X, multibody::Coordinate::Y]
        .into_iter()
        .enumerate()
    {
        model
            .add_driver(
                format!("lock {k}"),
                DriveTarget::Coordinate(BodyId(0), target),
                Box::new(Constant(0.0)),
            )
            .expect("valid as data");
    }
    model
        .add_driver(
            "lock angle",
            DriveTarget::JointAngle(JointId(0)),
            Box::new(Constant(0.0)),
        )
        .expect("valid as data");
    let system = System::new(model).expect("valid");
    let (q, qd) = system.initial_guess();
    assert!(matches!(
        system.assemble(0.0, &q, &qd),
        Err(AssemblyError::Overconstrained {
            equations: 5,
            coordinates: 3
        })
    ));
}

#[test]
fn unassemblable_four_bar_reports_residual_and_constraints() {
    // The coupler and rocker together are shorter than the distance they must bridge.
    let mechanism = FourBar {
        a: 0.2,
        b: 0.1,
        c: 0.1,
        d: 0.9,
    };
    // Impossible lengths, started from the standard mechanism's configuration.
    let (model, _) = mechanism.model_at(&FourBar::STANDARD.positions(0.3));
    let system = System::new(model).expect("valid");
    let (q, qd) = system.initial_guess();
    let error = system
        .assemble(0.0, &q, &qd)
        .expect_err("cannot close the loop");
    let message = error.to_string();
    match error {
        AssemblyError::NotConverged { residual, .. } => {
            assert!(residual > 1e-3, "{message}");
            assert!(message.contains("revolute"), "{message}");
        }
        // Newton may also end on a singular (stretched-out) configuration: also a clear error.
        AssemblyError::RankDeficient { .. } => {}
        other => panic!("unexpected {other}"),
    }
}

#[test]
fn kinematics_needs_a_fully_driven_mechanism() {
    let (model, _) = SliderCrank::STANDARD.model(0.2);
    let system = System::new(model).expect("valid");
    let (q, _) = system.initial_guess();
    assert!(matches!(
        system.kinematics(&[0.0], &q),
        Err(KinematicsError::NotFullyDriven {
            coordinates: 9,
            equations: 8
        })
    ));
}

#[test]
fn bad_options_and_state_lengths_are_errors() {
    let mut system = with_gravity(pendulum(1.0, 1.0, -PI / 4.0));
    let (q, qd) = system.initial_guess();
    assert!(matches!(
        system.assemble(0.0, &q[..2], &qd),
        Err(AssemblyError::WrongLength {
            expected: 3,
            actual: 2
        })
    ));
    let start = system.assemble(0.0, &q, &qd).expect("assembles");
    let mut options = SimulationOptions::until(-1.0);
    assert!(matches!(
        system.simulate(&start, &options, &mut ()),
        Err(SimulationError::InvalidOptions(_))
    ));
    options.t_end = 1.0;
    options.rtol = 0.0;
    assert!(matches!(
        system.simulate(&start, &options, &mut ()),
        Err(SimulationError::InvalidOptions(_))
    ));
    options.rtol = 1e-6;
    options.output = OutputTimes::Every(0.0);
    assert!(matches!(
        system.simulate(&start, &options, &mut ()),
        Err(SimulationError::InvalidOptions(_))
    ));
    // The elements are back after a failed run.
    assert_eq!(system.elements().len(), 1);
}

#[test]
fn driving_through_a_singular_position_is_an_error_not_a_panic() {
    // With crank = rod, at φ = 90° the rod folds onto the crank and the slider reaches the
    // pivot: Φ_q loses rank there (a bifurcation point).
    let mechanism = SliderCrank { r: 0.2, l: 0.2 };
    let (mut model, joint) = mechanism.model(0.5);
    model
        .add_driver(
            "motor",
            DriveTarget::JointAngle(joint),
            Box::new(multibody::Ramp {
                initial: 0.5,
                rate: 1.0,
            }),
        )
        .expect("valid");
    let mut system = with_gravity(model);
    let singular_time = PI / 2.0 - 0.5;
    let (q, qd) = system.initial_guess();
    let error = system
        .kinematics(&[0.0, 0.5, 1.0, singular_time], &q)
        .expect_err("singular position");
    assert!(
        matches!(
            error,
            KinematicsError::Assembly(AssemblyError::RankDeficient { .. })
        ),
        "{error}"
    );
    let start = system
        .assemble(0.0, &q, &qd)
        .expect("assembles away from the singularity");
    let mut options = SimulationOptions::until(2.0);
    options.output = OutputTimes::At(vec![singular_time]);
    // The output frame at the singular time needs q̈ and λ there, which do not exist.
    let outcome = system.simulate(&start, &options, &mut ());
    assert!(
        matches!(
            outcome,
            Err(SimulationError::Evaluation {
                error: multibody::EvaluationError::Singular { .. },
                ..
            })
        ),
        "{outcome:?}"
    );
    assert_eq!(
        system.elements().len(),
        1,
        "elements back after the failure"
    );
}
