//! Cost of one right-hand side and one Jacobian (exact vs forward differences) on a four-bar
//! under gravity (`n = 9`) and on an LGRES-sized mechanism (`n = 15`, `m = 11`, two two-body
//! penalty elements standing in for the clearance joints A and B):
//! `cargo bench -p multibody --bench evaluation`. Medians are printed after criterion's lines.

mod common;
#[path = "../tests/common/lgres_scene.rs"]
mod lgres_scene;

use common::bench_median;
use criterion::{Criterion, criterion_group, criterion_main};
use lgres_scene::Lgres;
use multibody::{
    Anchor, Baumgarte, Body, BodyId, Equations, ForceElement, ForcePartials, Gravity, Model, System,
};
use nalgebra::DMatrix;

fn four_bar() -> System {
    let mut model = Model::new();
    let guess = [
        ("crank", 0.2, [0.07, 0.07, 0.785]),
        ("coupler", 0.5, [0.35, 0.25, 0.1]),
        ("rocker", 0.4, [0.5, 0.15, 1.8]),
    ];
    let ids: Vec<_> = guess
        .iter()
        .map(|(name, length, pose)| {
            model
                .add_body(Body::new(*name, 1.0, length * length / 12.0, *pose))
                .expect("valid body")
        })
        .collect();
    let joints = [
        (Anchor::ground(0.0, 0.0), Anchor::on(ids[0], -0.1, 0.0)),
        (Anchor::on(ids[0], 0.1, 0.0), Anchor::on(ids[1], -0.25, 0.0)),
        (Anchor::on(ids[1], 0.25, 0.0), Anchor::on(ids[2], 0.2, 0.0)),
        (Anchor::ground(0.45, 0.0), Anchor::on(ids[2], -0.2, 0.0)),
    ];
    for (k, (i, j)) in joints.into_iter().enumerate() {
        model
            .add_revolute(format!("J{k}"), i, j)
            .expect("valid joint");
    }
    let gravity = Gravity::new(&model, [0.0, -9.81]);
    let mut system = System::new(model).expect("valid model");
    system.add_element(Box::new(gravity));
    system
}

/// A linear spring-damper between a point on body `a` and a point on body `b` (a bushing):
/// `F_b = −k d − c ḋ` with `d` the separation of the points, `F_a = −F_b`. Its 6×12 Jacobian
/// goes through `add_pair` like a clearance joint's.
struct Bushing {
    bodies: [BodyId; 2],
    points: [[f64; 2]; 2],
    stiffness: f64,
    damping: f64,
}

/// Per body: lever arm `a = A(θ)s` and angular velocity.
type Arms = [([f64; 2], f64); 2];

impl Bushing {
    fn arms(&self, q: &[f64], qd: &[f64]) -> Arms {
        [0, 1].map(|s| {
            let k = 3 * self.bodies[s].0;
            let (sin, cos) = q[k + 2].sin_cos();
            let p = self.points[s];
            (
                [cos * p[0] - sin * p[1], sin * p[0] + cos * p[1]],
                qd[k + 2],
            )
        })
    }

    /// Force on body b.
    fn force(&self, q: &[f64], qd: &[f64], arms: &Arms) -> [f64; 2] {
        let [ka, kb] = self.bodies.map(|b| 3 * b.0);
        let [(aa, wa), (ab, wb)] = *arms;
        let d = [
            q[kb] + ab[0] - q[ka] - aa[0],
            q[kb + 1] + ab[1] - q[ka + 1] - aa[1],
        ];
        let v = [
            qd[kb] - wb * ab[1] - qd[ka] + wa * aa[1],
            qd[kb + 1] + wb * ab[0] - qd[ka + 1] - wa * aa[0],
        ];
        [0, 1].map(|i| -self.stiffness * d[i] - self.damping * v[i])
    }
}

fn cross(a: [f64; 2], f: [f64; 2]) -> f64 {
    a[0] * f[1] - a[1] * f[0]
}

impl ForceElement for Bushing {
    fn name(&self) -> &str {
        "bushing"
    }

    fn add_forces(&self, _t: f64, q: &[f64], qd: &[f64], forces: &mut [f64]) {
        let arms = self.arms(q, qd);
        let fb = self.force(q, qd, &arms);
        for (s, f) in [[-fb[0], -fb[1]], fb].into_iter().enumerate() {
            let k = 3 * self.bodies[s].0;
            forces[k] += f[0];
            forces[k + 1] += f[1];
            forces[k + 2] += cross(arms[s].0, f);
        }
    }

    fn add_partials(&self, _t: f64, q: &[f64], qd: &[f64], partials: &mut ForcePartials<'_>) {
        let arms = self.arms(q, qd);
        let fb = self.force(q, qd, &arms);
        let perp = |a: [f64; 2]| [-a[1], a[0]];
        let [(aa, wa), (ab, wb)] = arms;
        // ∂d and ∂ḋ per column (q_a, q_b, q̇_a, q̇_b).
        let mut dd = [[0.0; 2]; 12];
        let mut dv = [[0.0; 2]; 12];
        dd[0] = [-1.0, 0.0];
        dd[1] = [0.0, -1.0];
        dd[2] = perp(aa).map(|x| -x);
        dd[3] = [1.0, 0.0];
        dd[4] = [0.0, 1.0];
        dd[5] = perp(ab);
        dv[2] = aa.map(|x| wa * x);
        dv[5] = ab.map(|x| -wb * x);
        dv[6..12].copy_from_slice(&dd[..6]);
        let mut jacobian = [[0.0; 12]; 6];
        for c in 0..12 {
            let dfb = [0, 1].map(|i| -self.stiffness * dd[c][i] - self.damping * dv[c][i]);
            let dfa = dfb.map(|x| -x);
            jacobian[0][c] = dfa[0];
            jacobian[1][c] = dfa[1];
            jacobian[2][c] = cross(aa, dfa);
            jacobian[3][c] = dfb[0];
            jacobian[4][c] = dfb[1];
            jacobian[5][c] = cross(ab, dfb);
        }
        // The lever arms turn with their bodies.
        jacobian[2][2] += cross(perp(aa), fb.map(|x| -x));
        jacobian[5][5] += cross(perp(ab), fb);
        partials.add_pair(self.bodies.map(Some), &jacobian);
    }
}

/// The LGRES mechanism read from `crates/lgres/scenes/lgres.toml` (bodies, ideal joints O1, C,
/// O3, D, the slide rod's guide and drive): 15 coordinates, 11 constraints; the clearance joints
/// A and B are bushings.
fn lgres_sized() -> System {
    let Lgres {
        model,
        clearance_joints,
        gravity,
        ..
    } = Lgres::load(60.0);
    let gravity = Gravity::new(&model, gravity);
    let mut system = System::new(model).expect("valid model");
    system.add_element(Box::new(gravity));
    for joint in clearance_joints {
        let body = |anchor: Anchor| anchor.body.expect("A and B join two bodies");
        system.add_element(Box::new(Bushing {
            bodies: [body(joint.bearing), body(joint.pin)],
            points: [joint.bearing.point, joint.pin.point],
            stiffness: 1e8,
            damping: 1e4,
        }));
    }
    assert_eq!(
        (system.coordinate_count(), system.constraint_count()),
        (15, 11)
    );
    system
}

/// RHS, exact and finite-difference Jacobian of `system` at the state assembled at `t`, with
/// the last velocity set to `spin` (the four-bar's assembled velocities are zero).
fn bench_system(c: &mut Criterion, label: &str, system: &System, t: f64, spin: f64) {
    let (q, qd) = system.initial_guess();
    let state = system.assemble(t, &q, &qd).expect("assembles");
    let mut y: Vec<f64> = state.q.iter().chain(&state.qd).copied().collect();
    let size = y.len();
    y[size - 1] += spin;
    let mut dy = vec![0.0; size];
    let mut jacobian = DMatrix::zeros(size, size);
    let mut evaluator = system.evaluator(Baumgarte::default());
    let elements = system.elements();

    // The exact Jacobian (bushings included) agrees with forward differences.
    let mut reference = DMatrix::zeros(size, size);
    evaluator
        .jacobian(elements, t, &y, &mut jacobian)
        .expect("regular");
    evaluator
        .finite_difference_jacobian(elements, t, &y, &mut reference)
        .expect("regular");
    let scale = reference.amax().max(1.0);
    assert!(
        (&jacobian - &reference).amax() < 1e-4 * scale,
        "{label}: exact Jacobian differs from forward differences"
    );

    let mut group = c.benchmark_group(label);
    let medians = [
        bench_median(
            &mut group,
            label,
            "rhs",
            100,
            || (),
            |()| evaluator.rhs(elements, t, &y, &mut dy),
        ),
        bench_median(
            &mut group,
            label,
            "exact jacobian",
            100,
            || (),
            |()| evaluator.jacobian(elements, t, &y, &mut jacobian),
        ),
        bench_median(
            &mut group,
            label,
            "finite-difference jacobian",
            100,
            || (),
            |()| evaluator.finite_difference_jacobian(elements, t, &y, &mut jacobian),
        ),
    ];
    group.finish();
    if let [Some(rhs), Some(exact), Some(fd)] = medians {
        println!(
            "{label}: median exact Jacobian = {:.1} RHS; forward differences = {:.1} RHS",
            exact.as_secs_f64() / rhs.as_secs_f64(),
            fd.as_secs_f64() / rhs.as_secs_f64()
        );
    }
}

fn evaluation(c: &mut Criterion) {
    bench_system(c, "four-bar", &four_bar(), 0.0, 1.0);
    bench_system(c, "lgres-sized", &lgres_sized(), 0.25, 0.0);
}

criterion_group!(benches, evaluation);
criterion_main!(benches);
