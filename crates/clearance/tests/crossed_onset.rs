//! A contact onset crossed inside a step: a free pin (no gravity) flies across its clearance,
//! hits the bearing head-on and rebounds. A joint whose force is C¹ at onset (Hertz exponent
//! 1.5 here) locates no event, so the integrator steps over the onset and the impact memory
//! interpolates the onset velocity within that step; the rebound must still come out at the
//! law's restitution, as the contact crate's own fine-step drop test gives it (Lankarani–Nikravesh
//! at `c_e = 0.9`: 0.913, its known overshoot), and the pin must leave the bearing with the
//! books of the contact closing the energy lost.

use clearance::RoundClearanceForce;
use contact::{
    CircularProfile, ClearanceJoint, FrictionLawKind, JointSurface, LankaraniNikravesh,
    LinearSpring, Material, NormalLawKind,
};
use multibody::{Body, BodyId, Model, OutputTimes, SimulationOptions, System};

const MASS: f64 = 3.0;
const APPROACH: f64 = 0.1;
const CLEARANCE: f64 = 5e-4;

struct Rebound {
    restitution: f64,
    events: usize,
    lost: f64,
    damped: f64,
}

fn head_on(model: contact::ContactModelKind) -> Rebound {
    let mut bodies = Model::new();
    let body = bodies
        .add_body(Body::new("pin", MASS, 1e-3, [0.0, 0.0, 0.0]))
        .expect("valid body");
    let mut system = System::new(bodies).expect("valid model");
    let steel = Material::new(200e9, 0.3).expect("valid material");
    let radius = 0.02;
    let joint = ClearanceJoint::new(
        JointSurface {
            centre: [0.0, 0.0],
            profile: CircularProfile::new(radius),
            material: steel,
        },
        JointSurface {
            centre: [0.0, 0.0],
            profile: CircularProfile::new(radius - CLEARANCE),
            material: steel,
        },
        NormalLawKind::LankaraniNikravesh(LankaraniNikravesh::new(0.9).expect("valid")),
        FrictionLawKind::None,
    )
    .expect("valid joint")
    .with_model(model);
    let element = system.add_element(Box::new(RoundClearanceForce::new(
        "pin",
        None,
        Some(BodyId(body.0)),
        joint,
    )));
    let (q, mut qd) = system.initial_guess();
    qd[0] = APPROACH;
    let start = system.assemble(0.0, &q, &qd).expect("assembles");
    // The wall is reached at 5 ms; by 8 ms the pin is back in free flight, short of the
    // opposite wall (10 ms away).
    let end = 8e-3;
    let mut options = SimulationOptions::until(end);
    options.output = OutputTimes::At(vec![end]);
    let result = system
        .simulate(&start, &options, &mut ())
        .expect("integrates");
    let probe = system
        .element::<RoundClearanceForce>(element)
        .expect("the element");
    let leaving = result.final_state.qd[0];
    Rebound {
        restitution: -leaving / APPROACH,
        events: result.statistics.events,
        lost: 0.5 * MASS * (APPROACH * APPROACH - leaving * leaving),
        damped: probe.damping_dissipation(),
    }
}

#[test]
fn an_onset_crossed_inside_a_step_rebounds_with_the_laws_restitution() {
    let rebound = head_on(contact::LineOfCentres.into());
    eprintln!(
        "restitution {:.5}, {} events, energy lost {:.4e} J, damping books {:.4e} J",
        rebound.restitution, rebound.events, rebound.lost, rebound.damped
    );
    assert_eq!(rebound.events, 0, "a C¹ onset is crossed, not located");
    // The contact crate's drop test (RK4 at 5e-8 s) gives 0.913 for this law at c_e = 0.9.
    assert!((rebound.restitution - 0.913).abs() < 0.005);
    assert!((rebound.damped - rebound.lost).abs() < 0.01 * rebound.lost);
}

#[test]
fn a_kinked_onset_is_located() {
    let spring = LinearSpring::new(1e8).expect("valid stiffness");
    let rebound = head_on(spring.into());
    assert!(
        rebound.events >= 2,
        "onset and separation: {}",
        rebound.events
    );
    assert!(rebound.restitution > 0.0 && rebound.restitution < 1.0);
}
