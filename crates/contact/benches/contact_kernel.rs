//! The contact kernel's cost for a joint in contact (LGRES joint A, sliding, mid-impact).

use std::hint::black_box;
use std::time::Instant;

use contact::{
    Ambrosio, BodyState, CircularProfile, ClearanceJoint, FrictionLawKind, JointSurface,
    LankaraniNikravesh, Material, NormalLawKind, RadiusSample, SurfaceProfile,
};

/// A worn-looking (non-round) surface: a 10 µm dent, so the general kernel runs.
#[derive(Clone, Copy)]
struct Dented(f64);

impl SurfaceProfile for Dented {
    fn sample(&self, angle: f64) -> RadiusSample {
        let (s, c) = (2.0 * angle).sin_cos();
        RadiusSample {
            radius: self.0 + 5e-6 * (1.0 + c),
            slope: -1e-5 * s,
            curvature: -2e-5 * c,
        }
    }
}
use criterion::{Criterion, criterion_group, criterion_main};

fn joint_a<N, F>(normal: N, friction: F) -> ClearanceJoint<CircularProfile, CircularProfile, N, F>
where
    N: contact::NormalLaw,
    F: contact::FrictionLaw,
{
    let steel = Material::new(200e9, 0.3).expect("valid material");
    ClearanceJoint::new(
        JointSurface {
            centre: [0.56, 0.0],
            profile: CircularProfile::new(0.05),
            material: steel,
        },
        JointSurface {
            centre: [0.645, 0.0],
            profile: CircularProfile::new(0.0495),
            material: steel,
        },
        normal,
        friction,
    )
    .expect("valid joint")
    .with_model(contact::LineOfCentres)
}

/// Bearing on rod 2 and pin on rod 3 of LGRES joint A, the pin 10 µm into the wall at 30°,
/// approaching at 0.05 m/s and sliding at 0.2 m/s.
fn states<N, F>(
    joint: &ClearanceJoint<CircularProfile, CircularProfile, N, F>,
) -> (BodyState, BodyState)
where
    N: contact::NormalLaw,
    F: contact::FrictionLaw,
{
    let bearing = BodyState::new([0.799, 0.297, -0.5], [0.1, -0.2, 1.5]);
    let (s, c) = (-0.5f64).sin_cos();
    let bearing_centre = [0.799 + 0.56 * c, 0.297 + 0.56 * s];
    let (sp, cp) = 0.02f64.sin_cos();
    let offset = 5e-4 + 1e-5;
    let pin_centre = [
        bearing_centre[0] + offset * (30f64.to_radians()).cos(),
        bearing_centre[1] + offset * (30f64.to_radians()).sin(),
    ];
    let mut pin = BodyState::new(
        [pin_centre[0] - 0.645 * cp, pin_centre[1] - 0.645 * sp, 0.02],
        [0.05, 0.1, -2.0],
    );
    let kin = joint.kinematics(&bearing, &pin);
    let (dn, dt) = (0.05 - kin.normal_velocity, 0.2 - kin.tangential_velocity);
    pin.vx += dn * kin.normal.x + dt * kin.tangent.x;
    pin.vy += dn * kin.normal.y + dt * kin.tangent.y;
    (bearing, pin)
}

fn bench(c: &mut Criterion) {
    let laws = (
        LankaraniNikravesh::new(0.9).expect("valid"),
        Ambrosio::new(0.15, 1e-4, 1e-3).expect("valid"),
    );
    let static_joint = joint_a(laws.0, laws.1);
    let dynamic_joint = joint_a(
        NormalLawKind::LankaraniNikravesh(laws.0),
        FrictionLawKind::Ambrosio(laws.1),
    );
    let (bearing, pin) = states(&static_joint);
    assert!(
        static_joint
            .forces(&bearing, &pin, Some(0.1))
            .diagnostics
            .normal_force
            > 0.0
    );

    c.bench_function("force", |b| {
        b.iter(|| static_joint.forces(black_box(&bearing), black_box(&pin), black_box(Some(0.1))))
    });
    c.bench_function("force (serde enum dispatch)", |b| {
        b.iter(|| dynamic_joint.forces(black_box(&bearing), black_box(&pin), black_box(Some(0.1))))
    });
    c.bench_function("force + jacobian", |b| {
        b.iter(|| {
            static_joint.forces_and_jacobian(
                black_box(&bearing),
                black_box(&pin),
                black_box(Some(0.1)),
            )
        })
    });
    // The same contact on worn (non-round) surfaces: the energy-consistent general kernel.
    let worn = static_joint
        .clone()
        .with_profiles(Dented(0.05), Dented(0.0495 - 1e-5))
        .expect("valid profiles");
    c.bench_function("force (worn surfaces)", |b| {
        b.iter(|| worn.forces(black_box(&bearing), black_box(&pin), black_box(Some(0.1))))
    });
    c.bench_function("force + jacobian (worn surfaces)", |b| {
        b.iter(|| {
            worn.forces_and_jacobian(black_box(&bearing), black_box(&pin), black_box(Some(0.1)))
        })
    });
    c.bench_function("penetration", |b| {
        b.iter(|| static_joint.penetration(black_box(&bearing), black_box(&pin)))
    });

    // Criterion's line above is a mean-based estimate; the project quotes medians, which are
    // robust to the noise of a shared machine, so measure them here as well.
    let force = median_ns_per_call(|| {
        black_box(static_joint.forces(black_box(&bearing), black_box(&pin), Some(0.1)));
    });
    let with_jacobian = median_ns_per_call(|| {
        black_box(static_joint.forces_and_jacobian(
            black_box(&bearing),
            black_box(&pin),
            Some(0.1),
        ));
    });
    let worn_force = median_ns_per_call(|| {
        black_box(worn.forces(black_box(&bearing), black_box(&pin), Some(0.1)));
    });
    let worn_jacobian = median_ns_per_call(|| {
        black_box(worn.forces_and_jacobian(black_box(&bearing), black_box(&pin), Some(0.1)));
    });
    println!(
        "median force: {force:.1} ns/eval; median force + jacobian: {with_jacobian:.1} ns/eval"
    );
    println!(
        "worn surfaces: median force {worn_force:.1} ns/eval; force + jacobian \
         {worn_jacobian:.1} ns/eval"
    );
}

/// Median over 101 batches of 10 000 calls of the time per call (ns).
fn median_ns_per_call(mut call: impl FnMut()) -> f64 {
    const BATCH: u32 = 10_000;
    let mut per_call: Vec<f64> = (0..101)
        .map(|_| {
            let start = Instant::now();
            for _ in 0..BATCH {
                call();
            }
            start.elapsed().as_secs_f64() * 1e9 / f64::from(BATCH)
        })
        .collect();
    per_call.sort_by(f64::total_cmp);
    per_call[per_call.len() / 2]
}

criterion_group!(benches, bench);
criterion_main!(benches);
