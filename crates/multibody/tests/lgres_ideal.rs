//! The LGRES mechanism of `crates/lgres/scenes/lgres.toml` (docs/model.md §6) with all joints
//! ideal (15 equations, 15 coordinates): assembly from the scene's initial configuration, the
//! swing ranges over one drive period, and dynamics of the fully driven mechanism against its
//! kinematics. The geometry is read from the scene file, so it is the scene's, not a copy.

mod common;

use common::lgres_scene::Lgres;
use common::{assembled, max_abs_diff};
use multibody::{
    AbsoluteTolerances, Formulation, Gravity, OutputTimes, SimulationOptions, SimulationResult,
    System, Trajectory,
};

/// The scene's mechanism with the clearance joints A and B made ideal revolutes, driven at
/// `rpm`; also the scene's body names and poses (x, y in m, θ in degrees).
fn lgres(rpm: f64) -> (System, Vec<String>, Vec<[f64; 3]>) {
    let Lgres {
        mut model,
        names,
        poses,
        clearance_joints,
        gravity,
    } = Lgres::load(rpm);
    for joint in clearance_joints {
        model
            .add_revolute(joint.name, joint.bearing, joint.pin)
            .expect("valid joint");
    }
    let gravity = Gravity::new(&model, gravity);
    let mut system = System::new(model).expect("valid model");
    system.add_element(Box::new(gravity));
    (system, names, poses)
}

/// The assembled start, a run from it with `options`, and the kinematic solution at the run's
/// output times: what the driven-dynamics tests compare.
fn dynamics_and_kinematics(
    system: &mut System,
    options: &SimulationOptions,
) -> (SimulationResult, Trajectory) {
    let start = assembled(system);
    let result = system
        .simulate(&start, options, &mut ())
        .expect("integrates");
    let solution = system
        .kinematics(&result.trajectory.times, &start.q)
        .expect("kinematics");
    (result, solution)
}

#[test]
fn assembles_at_the_reconstructed_configuration() {
    let (system, names, poses) = lgres(60.0);
    assert_eq!(
        (system.coordinate_count(), system.constraint_count()),
        (15, 15)
    );
    let (q, qd) = system.initial_guess();
    let state = system.assemble(0.0, &q, &qd).expect("assembles");
    // The scene's poses are rounded to 5 decimals (m) and 4 (degrees): the assembled
    // configuration must be within that rounding, and the drive starts at rest.
    assert_eq!(poses.len(), 5);
    for (k, (name, [x, y, degrees])) in names.iter().zip(&poses).enumerate() {
        assert!((state.q[3 * k] - x).abs() < 2e-5, "{name} x");
        assert!((state.q[3 * k + 1] - y).abs() < 2e-5, "{name} y");
        assert!(
            (state.q[3 * k + 2].to_degrees() - degrees).abs() < 2e-3,
            "{name} θ"
        );
    }
    assert!(state.qd.iter().all(|v| v.abs() < 1e-12));
}

#[test]
fn one_period_sweeps_the_reported_ranges() {
    let (system, ..) = lgres(60.0);
    let (q, _) = system.initial_guess();
    let times: Vec<f64> = (0..=200).map(|k| k as f64 / 200.0).collect();
    let solution = system
        .kinematics(&times, &q)
        .expect("assembles over the stroke");
    let range = |k: usize| {
        let angles: Vec<f64> = (0..times.len())
            .map(|f| solution.q(f)[3 * k + 2].to_degrees())
            .collect();
        let min = angles.iter().copied().fold(f64::INFINITY, f64::min);
        let max = angles.iter().copied().fold(f64::NEG_INFINITY, f64::max);
        (min, max)
    };
    // docs/model.md §6 states these to 0.1° (rod 3 to 0.01°); 1 s sampled every 5 ms resolves the
    // extremes (at the stroke ends, where the angles are stationary) far better.
    let (min3, max3) = range(2);
    assert!(
        (min3 - 1.17).abs() < 0.01 && (max3 - 51.89).abs() < 0.01,
        "rod 3 {min3}..{max3}"
    );
    let (min4, max4) = range(3);
    assert!(
        (min4 - 80.5).abs() < 0.1 && (max4 - 90.0).abs() < 0.1,
        "rocker {min4}..{max4}"
    );
    let (min2, max2) = range(1);
    assert!(
        (min2 + 28.9).abs() < 0.1 && (max2 - 25.0).abs() < 0.1,
        "rod 2 {min2}..{max2}"
    );
    let (min1, max1) = range(0);
    assert!(
        (min1 + 102.7).abs() < 0.1 && (max1 + 72.0).abs() < 0.1,
        "rod 1 {min1}..{max1}"
    );
    // Back where it started after one period.
    let last = times.len() - 1;
    let closure = max_abs_diff(solution.q(last), solution.q(0));
    assert!(closure < 1e-9, "{closure}");
}

#[test]
fn driven_dynamics_follows_the_kinematics() {
    let (mut system, ..) = lgres(105.0);
    let options = SimulationOptions::until(60.0 / 105.0)
        .with_rtol(1e-8)
        .with_atol(AbsoluteTolerances::uniform(1e-10))
        .with_output(OutputTimes::Every(0.01));
    let (result, solution) = dynamics_and_kinematics(&mut system, &options);
    // With no degree of freedom left, the integrated motion can differ from the constraint
    // solution only by drift, which Baumgarte keeps at the integration tolerance.
    for frame in 0..result.trajectory.len() {
        let dq = max_abs_diff(solution.q(frame), result.trajectory.q(frame));
        assert!(dq < 1e-8, "t = {}: {dq:e}", result.trajectory.times[frame]);
        // The multipliers (joint reactions, drive force) agree to the same relative order.
        let scale = solution
            .lambda(frame)
            .iter()
            .fold(1.0_f64, |a, l| a.max(l.abs()));
        let dl = max_abs_diff(solution.lambda(frame), result.trajectory.lambda(frame));
        assert!(
            dl < 1e-5 * scale,
            "t = {}: λ differs by {dl:e} of {scale}",
            result.trajectory.times[frame]
        );
    }
    let peak = (0..solution.times.len())
        .map(|f| system.kinetic_energy(solution.qd(f)))
        .fold(0.0, f64::max);
    let energy = result.energy.expect("audited");
    // The reconstruction amplifies the slide-rod motion strongly: ~184 J of peak kinetic
    // energy at 105 rpm, in the kinematics as in the dynamics.
    assert!(
        (energy.peak_kinetic - peak).abs() < 1e-3 * peak,
        "{} vs {peak}",
        energy.peak_kinetic
    );
    println!(
        "LGRES ideal, one period at 105 rpm: {:?}, energy {energy:?}",
        result.statistics
    );
    assert!(energy.relative_residual() < 1e-6, "{energy:?}");
}

#[test]
fn both_formulations_follow_the_kinematics_to_a_nanometre() {
    let (mut system, ..) = lgres(60.0);
    let mut options = SimulationOptions::until(1.0);
    options.rtol = 1e-10;
    options.atol = AbsoluteTolerances::uniform(1e-12);
    options.output = OutputTimes::Every(0.01);
    for formulation in [Formulation::Cartesian, Formulation::JointCoordinates] {
        options.formulation = formulation;
        let (result, solution) = dynamics_and_kinematics(&mut system, &options);
        let dq = (0..result.trajectory.len())
            .map(|f| max_abs_diff(solution.q(f), result.trajectory.q(f)))
            .fold(0.0, f64::max);
        println!(
            "{formulation:?}: ideal LGRES vs kinematics over one period, max |Δq| {dq:e} ({} steps)",
            result.statistics.steps
        );
        assert!(dq < 1e-9, "{formulation:?}: {dq:e}");
    }
}
