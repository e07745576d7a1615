//! The clearance force element, as the multibody system calls it, allocates nothing: its
//! forces (the right-hand side), their Jacobian and its event function, on worn surfaces, with
//! the elastic foundation and with the line of centres, along a walk in and out of contact.

use std::f64::consts::TAU;

use alloc_count::{CountingAllocator, allocations_of};
use clearance::WornClearanceForce;
use contact::{
    Ambrosio, BodyState, ClearanceJoint, ContactModelKind, Foundation, FrictionLawKind,
    JointSurface, LankaraniNikravesh, LineOfCentres, Material, NormalLawKind,
};
use multibody::{Baumgarte, Body, BodyId, Equations, ForceElement, Model, System};
use nalgebra::DMatrix;
use wear::{Side, WornProfile};

#[global_allocator]
static GLOBAL: CountingAllocator = CountingAllocator;

const BEARING_RADIUS: f64 = 0.05;
const CLEARANCE: f64 = 5e-4;

/// A surface of 360 cells with a smooth dent of depth `depth` (m) centred at `centre` (rad).
fn dented(side: Side, radius: f64, depth: f64, centre: f64) -> WornProfile {
    let cells = 360;
    let depths = (0..cells)
        .map(|k| {
            let angle = (k as f64 + 0.5) * TAU / cells as f64;
            let off = (angle - centre + TAU / 2.0).rem_euclid(TAU) - TAU / 2.0;
            depth * (-(off / 0.4).powi(2)).exp()
        })
        .collect();
    WornProfile::from_depths(side, radius, depths).expect("valid depths")
}

/// A worn joint with contact model `model`: a 100 µm dent in the bearing at 250° (where the
/// pin is placed) and a 40 µm one on the pin.
fn worn_joint(model: ContactModelKind) -> ClearanceJoint<WornProfile, WornProfile> {
    let steel = Material::new(200e9, 0.3).expect("valid material");
    ClearanceJoint::new(
        JointSurface {
            centre: [0.0, 0.0],
            profile: dented(Side::Bearing, BEARING_RADIUS, 1e-4, 250f64.to_radians()),
            material: steel,
        },
        JointSurface {
            centre: [0.0, 0.0],
            profile: dented(Side::Pin, BEARING_RADIUS - CLEARANCE, 4e-5, 1.0),
            material: steel,
        },
        NormalLawKind::LankaraniNikravesh(LankaraniNikravesh::new(0.9).expect("valid")),
        FrictionLawKind::Ambrosio(Ambrosio::new(0.15, 1e-4, 1e-3).expect("valid")),
    )
    .expect("valid joint")
    .with_model(model)
}

/// The pin body's position at global angle `phi` from the bearing centre, `depth` (m) into the
/// bearing by the model's event function (found by bisection).
fn placed(joint: &ClearanceJoint<WornProfile, WornProfile>, phi: f64, depth: f64) -> [f64; 2] {
    let ground = BodyState::at_rest(0.0, 0.0, 0.0);
    let at = |e: f64| BodyState::at_rest(e * phi.cos(), e * phi.sin(), 0.3);
    let (mut lo, mut hi) = (0.0, 10.0 * CLEARANCE);
    for _ in 0..100 {
        let mid = 0.5 * (lo + hi);
        if joint.penetration(&ground, &at(mid)) < depth {
            lo = mid;
        } else {
            hi = mid;
        }
    }
    let e = 0.5 * (lo + hi);
    [e * phi.cos(), e * phi.sin()]
}

#[test]
fn the_worn_clearance_force_does_not_allocate() {
    let steel = Material::new(200e9, 0.3).expect("valid material");
    let models: [ContactModelKind; 2] = [
        Foundation::calibrated(&steel, &steel).into(),
        LineOfCentres.into(),
    ];
    for model in models {
        let joint = worn_joint(model);
        // States 30 µm deep to 0.2 µm apart around the dent, each also moved by a Newton-sized
        // 10 nm: the foundation's overlap memory is renewed and read.
        let states: Vec<[f64; 6]> = (0..24)
            .flat_map(|k| {
                let phi = (240.0 + k as f64).to_radians();
                let depth = 3e-5 - 1.3e-6 * k as f64;
                let [x, y] = placed(&joint, phi, depth);
                [
                    [x, y, 0.3, -0.05, 0.02, 1.0],
                    [x + 1e-8, y - 1e-8, 0.3 + 1e-7, -0.05, 0.02, 1.0],
                ]
            })
            .collect();
        let mut body_model = Model::new();
        body_model
            .add_body(Body::new("pin", 10.0, 0.02, [0.0, 0.0, 0.3]))
            .expect("valid body");
        let mut system = System::new(body_model).expect("valid model");
        let id = system.add_element(Box::new(WornClearanceForce::new(
            "worn",
            None,
            Some(BodyId(0)),
            joint,
        )));
        let mut evaluator = system.evaluator(Baumgarte::default());
        let elements = system.elements();
        let element = system
            .element::<WornClearanceForce>(id)
            .expect("the element");
        let mut dx = [0.0; 6];
        let mut jacobian = DMatrix::zeros(6, 6);
        let mut event = [0.0];
        let mut in_contact = 0;
        let allocations = allocations_of(|| {
            for (k, x) in states.iter().enumerate() {
                let t = 1e-4 * k as f64;
                evaluator.rhs(elements, t, x, &mut dx).expect("regular");
                evaluator
                    .jacobian(elements, t, x, &mut jacobian)
                    .expect("regular");
                element.event_functions(t, &x[..3], &x[3..], &mut event);
                in_contact += usize::from(event[0] > 0.0);
            }
        });
        assert!(in_contact > 30, "{model:?}: {in_contact} states in contact");
        assert!(jacobian.iter().any(|v| *v != 0.0), "{model:?}: loaded");
        assert_eq!(allocations, 0, "{model:?}: {allocations} allocations");
    }
}
