//! The two formulations of the equations of motion (`solver.formulation = "cartesian"` and
//! `"joint"`) on the default LGRES: over the start-up window, before the chaotic paths separate
//! (docs/model.md §8), the journal-centre paths and the first impacts at A and B must agree.

use multibody::{Frame, Observer, OutputTimes};
use scene::{Formulation, Scene};
use sim::build::{JointHandle, Surfaces, build};
use sim::simulation_options;

/// Journal-centre paths (eccentricity vectors) and normal forces at every output frame.
#[derive(Default)]
struct Startup {
    joints: Vec<JointHandle>,
    times: Vec<f64>,
    paths: Vec<Vec<[f64; 2]>>,
    forces: Vec<Vec<f64>>,
}

impl Observer for Startup {
    fn output(&mut self, frame: &Frame<'_>) {
        self.times.push(frame.t);
        for (k, joint) in self.joints.iter().enumerate() {
            let probe = joint.probe(frame.elements).expect("clearance joint");
            let d = probe.contact(frame.q, frame.qd).diagnostics;
            let (s, c) = d.contact_angle.sin_cos();
            self.paths[k].push([d.eccentricity * c, d.eccentricity * s]);
            self.forces[k].push(d.normal_force);
        }
    }
}

/// The default scene to `t_end` at `rtol` (absolute tolerances scaled with it, as in the
/// work–precision report), output every `dt`.
fn startup(formulation: Formulation, rtol: f64, t_end: f64, dt: f64) -> Startup {
    let mut scene: Scene = lgres::scenes::builtin("lgres")
        .expect("built-in scene")
        .into_scene();
    let factor = rtol / scene.solver.rtol;
    let tolerances = scene.tolerances();
    scene.solver.rtol = rtol;
    scene.solver.atol_position = Some(tolerances.position * factor);
    scene.solver.atol_angle = Some(tolerances.angle * factor);
    scene.solver.atol_velocity = tolerances.velocity * factor;
    scene.solver.formulation = formulation;
    let scene = scene::ValidScene::new(scene, "the default scene at rtol").expect("valid");
    let mut built = build(&scene, Surfaces::default()).expect("builds");
    let (q, qd) = built.system.initial_guess();
    let state = built.system.assemble(0.0, &q, &qd).expect("assembles");
    let options = simulation_options(&scene, t_end, OutputTimes::Every(dt), false);
    let joints = built.joints.clone();
    let mut record = Startup {
        paths: vec![Vec::new(); joints.len()],
        forces: vec![Vec::new(); joints.len()],
        joints,
        ..Startup::default()
    };
    built
        .system
        .simulate(&state, &options, &mut record)
        .expect("integrates");
    record
}

/// Largest force and its time among frames up to `t_max`.
fn peak(record: &Startup, joint: usize, t_max: f64) -> (f64, f64) {
    record
        .times
        .iter()
        .zip(&record.forces[joint])
        .filter(|(t, _)| **t <= t_max)
        .fold(
            (0.0, 0.0),
            |best, (t, f)| if *f > best.0 { (*f, *t) } else { best },
        )
}

/// The largest distance between joint `k`'s journal-centre paths in `a` and `b` over the
/// start-up window (t ≤ 0.02 s), m; `a` and `b` share their output times.
fn startup_difference(a: &Startup, b: &Startup, k: usize) -> f64 {
    a.paths[k]
        .iter()
        .zip(&b.paths[k])
        .zip(&a.times)
        .filter(|(_, t)| **t <= 0.02)
        .map(|((p, q), _)| (p[0] - q[0]).hypot(p[1] - q[1]))
        .fold(0.0, f64::max)
}

/// At a tight tolerance the start-up window (t ≤ 0.02 s: the first impacts at A and B) is
/// resolved by both formulations to well below the clearance; the paths may differ by the
/// integration error only. Bound: 1e-6 m (0.2 % of the 0.5 mm clearance; at rtol 1e-10 the
/// work–precision report's references agree to ~1e-10 m over this window, so a formulation
/// error of consequence, e.g. a missing Coriolis term, would be far above it).
#[test]
fn startup_paths_and_first_impacts_agree() {
    let (rtol, t_end, dt) = (1e-10, 0.025, 2e-6);
    let cartesian = startup(Formulation::Cartesian, rtol, t_end, dt);
    let joint = startup(Formulation::JointCoordinates, rtol, t_end, dt);
    assert_eq!(cartesian.times, joint.times);
    for (k, name) in ["A", "B"].into_iter().enumerate() {
        let difference = startup_difference(&cartesian, &joint, k);
        let (fc, tc) = peak(&cartesian, k, t_end);
        let (fj, tj) = peak(&joint, k, t_end);
        let relative = (fc - fj).abs() / fc;
        eprintln!(
            "joint {name}: start-up path difference {difference:.3e} m (t ≤ 0.02 s); first impact \
             cartesian {fc:.1} N at {tc:.5} s, joint {fj:.1} N at {tj:.5} s ({relative:.2e} relative)"
        );
        assert!(difference < 1e-6, "{name}: {difference:e} m");
        // Peaks sampled every 2 µs on identical frames: 1 % as the issue asks.
        assert!(relative < 0.01, "{name}: {fc} N vs {fj} N");
        assert!((tc - tj).abs() <= 2.0 * dt, "{name}: {tc} s vs {tj} s");
    }
    // At the default tolerance (rtol 1e-6) the same comparison is reported, not asserted: there
    // the integration error itself (~3e-5 m at start-up, docs/precision) sets the difference.
    let (coarse_c, coarse_j) = (
        startup(Formulation::Cartesian, 1e-6, t_end, dt),
        startup(Formulation::JointCoordinates, 1e-6, t_end, dt),
    );
    for (k, name) in ["A", "B"].into_iter().enumerate() {
        let difference = startup_difference(&coarse_c, &coarse_j, k);
        let ((fc, tc), (fj, tj)) = (peak(&coarse_c, k, t_end), peak(&coarse_j, k, t_end));
        eprintln!(
            "rtol 1e-6, joint {name}: path difference {difference:.3e} m; first impact cartesian \
             {fc:.1} N at {tc:.5} s, joint {fj:.1} N at {tj:.5} s"
        );
    }
    // The impacts the issue names: about 30 kN at A near 0.013 s, 46 kN at B near 0.018 s.
    let (fa, ta) = peak(&joint, 0, t_end);
    let (fb, tb) = peak(&joint, 1, t_end);
    assert!(
        (fa - 30e3).abs() < 5e3 && (ta - 0.013).abs() < 2e-3,
        "A: {fa} N at {ta} s"
    );
    assert!(
        (fb - 46e3).abs() < 5e3 && (tb - 0.018).abs() < 2e-3,
        "B: {fb} N at {tb} s"
    );
}
