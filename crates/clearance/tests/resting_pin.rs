//! A clearance joint in a mechanism, against a closed form: a free body hangs by its pin in a
//! bearing fixed to the ground. Once the impacts have died out the pin rests at the bottom of
//! the bearing, pressed in by its weight: `K δ^1.5 = m g`, with the conformal Hertz stiffness
//! `K = 4/(3(ε_i + ε_j)) √(R_i R_j/(R_i − R_j))`.

use clearance::RoundClearanceForce;
use contact::{
    Ambrosio, CircularProfile, ClearanceJoint, FrictionLawKind, JointSurface, LankaraniNikravesh,
    Material, NormalLawKind,
};
use multibody::{Body, BodyId, Gravity, Model, OutputTimes, SimulationOptions, System};

#[test]
fn a_hanging_pin_settles_to_the_hertz_static_penetration() {
    let (mass, bearing_radius, clearance) = (10.0, 0.05, 5e-4);
    let mut model = Model::new();
    let body = model
        .add_body(Body::new("bob", mass, 0.02, [0.0, 0.0, 0.0]))
        .expect("valid body");
    let gravity = Gravity::new(&model, [0.0, -9.81]);
    let mut system = System::new(model).expect("valid model");
    system.add_element(Box::new(gravity));
    let steel = Material::new(200e9, 0.3).expect("valid material");
    let joint = ClearanceJoint::new(
        JointSurface {
            centre: [0.0, 0.0],
            profile: CircularProfile::new(bearing_radius),
            material: steel,
        },
        JointSurface {
            centre: [0.0, 0.0],
            profile: CircularProfile::new(bearing_radius - clearance),
            material: steel,
        },
        NormalLawKind::LankaraniNikravesh(LankaraniNikravesh::new(0.5).expect("valid")),
        FrictionLawKind::Ambrosio(Ambrosio::new(0.1, 1e-4, 1e-3).expect("valid")),
    )
    .expect("valid joint")
    .with_model(contact::LineOfCentres);
    let stiffness = joint.stiffness(bearing_radius, bearing_radius - clearance);
    let element = system.add_element(Box::new(RoundClearanceForce::new(
        "pin",
        None,
        Some(BodyId(body.0)),
        joint,
    )));
    let (q, qd) = system.initial_guess();
    let start = system.assemble(0.0, &q, &qd).expect("assembles");
    let mut options = SimulationOptions::until(1.0);
    options.output = OutputTimes::At(vec![1.0]);
    options.atol.position = 1e-9;
    system
        .simulate(&start, &options, &mut ())
        .expect("integrates");
    let probe = system
        .element::<RoundClearanceForce>(element)
        .expect("the element");
    let resting = probe.last_diagnostics().expect("accepted steps were seen");
    let expected = (mass * 9.81 / stiffness).powf(2.0 / 3.0);
    eprintln!(
        "static penetration {:.4e} m (Hertz: {expected:.4e} m), force {:.2} N",
        resting.penetration, resting.normal_force
    );
    // Settled: the weight is carried by the contact alone (1e-3: the damped impacts have
    // decayed by orders of magnitude after 1 s).
    assert!((resting.normal_force - mass * 9.81).abs() < 1e-3 * mass * 9.81);
    assert!((resting.penetration - expected).abs() < 1e-3 * expected);
    // At the bottom of the bearing.
    assert!((resting.contact_angle + std::f64::consts::FRAC_PI_2).abs() < 1e-3);
}
