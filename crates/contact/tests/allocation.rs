//! A joint's evaluations allocate nothing: its forces, their Jacobian and its event function,
//! with the workspace the joint made ready and with an empty one, for every built-in model on
//! worn outlines, along a walk in and out of contact.

mod common;

use alloc_count::{CountingAllocator, allocations_of};
use common::foundation::{random_contact, worn};
use common::lgres_laws;
use contact::{
    BodyState, ContactModel, ContactModelKind, Foundation, LineOfCentres, LinearSpring, Quadrature,
    ThinGap,
};
use rand::{Rng, SeedableRng};
use rand_chacha::ChaCha8Rng;

#[global_allocator]
static GLOBAL: CountingAllocator = CountingAllocator;

#[test]
fn evaluations_on_worn_outlines_do_not_allocate() {
    let steel = common::steel();
    let foundation = Foundation::calibrated(&steel, &steel);
    let models: [ContactModelKind; 5] = [
        foundation.into(),
        foundation
            .with_quadrature(Quadrature::Trapezoid)
            .expect("even cells")
            .into(),
        LineOfCentres.into(),
        LinearSpring::new(1e8).expect("positive").into(),
        ThinGap::new(foundation).into(),
    ];
    let (normal, friction) = lgres_laws(0.9);
    for model in models {
        let joint = worn(normal, friction).with_model(model);
        let mut rng = ChaCha8Rng::seed_from_u64(3);
        // States in contact (up to 30 µm deep) and just apart, each nudged as a step's Newton
        // iterations would, so that the foundation's memory is both renewed and read.
        let states: Vec<(BodyState, BodyState)> = (0..40)
            .flat_map(|k| {
                let overlap = if k % 4 == 0 { -2e-7..0.0 } else { 2e-6..3e-5 };
                let (bearing, pin) =
                    random_contact(&joint, &mut rng, 0.2, 250f64.to_radians(), 0.8, overlap);
                let nudge = rng.random_range(-1e-8..1e-8);
                let moved = BodyState::new(
                    [pin.x + nudge, pin.y - nudge, pin.theta + 10.0 * nudge],
                    [pin.vx, pin.vy, pin.omega],
                );
                [(bearing, pin), (bearing, moved)]
            })
            .collect();
        let mut workspace = joint.workspace();
        let mut in_contact = 0;
        let count = allocations_of(|| {
            for (bearing, pin) in &states {
                let depth = joint.penetration_in(&mut workspace, bearing, pin);
                let forces = joint.forces_in(&mut workspace, bearing, pin, Some(0.1));
                let (with_jacobian, _) =
                    joint.forces_and_jacobian_in(&mut workspace, bearing, pin, Some(0.1));
                // Without a workspace: an empty one.
                let plain = joint.forces(bearing, pin, None);
                let (_, jacobian) = joint.forces_and_jacobian(bearing, pin, None);
                in_contact += usize::from(depth > 0.0 && forces.diagnostics.in_contact);
                assert_eq!(forces.pin, with_jacobian.pin);
                assert!(
                    plain
                        .pin
                        .iter()
                        .chain(jacobian.iter())
                        .all(|f| f.is_finite())
                );
            }
        });
        assert!(
            in_contact > 40,
            "{}: {in_contact} states in contact",
            model.name()
        );
        assert_eq!(count, 0, "{}: {count} allocations", model.name());
    }
}
