//! Slider-crank and four-bar: kinematic analysis against closed form, dynamics against
//! kinematics, constraint drift.

mod common;

use std::f64::consts::PI;

use common::{FourBar, Replay, SliderCrank, angle_driver, assembled, max_abs_diff, with_gravity};
use multibody::{
    AbsoluteTolerances, ConstraintOwner, DriverId, Model, OutputTimes, Ramp, SimulationOptions,
    System, Trajectory,
};

/// Drives the crank at 2 rad/s through most of a turn; positions must match the closed form
/// to 1e-10 (Newton converges to ~1e-15, so this is tight but not flaky), and velocities must
/// match the closed form differentiated numerically (1e-6, the accuracy of a central
/// difference with step 1e-5).
fn check_fully_driven(
    model: Model,
    positions: impl Fn(f64) -> [f64; 9],
    joint: multibody::JointId,
) {
    let mut model = model;
    angle_driver(
        &mut model,
        joint,
        Box::new(Ramp {
            initial: 0.3,
            rate: 2.0,
        }),
    );
    let system = System::new(model).expect("valid");
    let times: Vec<f64> = (0..=60).map(|k| 0.05 * k as f64).collect();
    let (guess, _) = system.initial_guess();
    let solution = system.kinematics(&times, &guess).expect("kinematics");
    for (frame, &t) in times.iter().enumerate() {
        let phi = 0.3 + 2.0 * t;
        let exact = positions(phi);
        let error = max_abs_diff(solution.q(frame), &exact);
        assert!(error < 1e-10, "t = {t}: position error {error:e}");
        let h = 1e-5;
        let (plus, minus) = (positions(phi + h), positions(phi - h));
        let velocity: Vec<f64> = plus
            .iter()
            .zip(minus)
            .map(|(p, m)| 2.0 * (p - m) / (2.0 * h))
            .collect();
        let error = max_abs_diff(solution.qd(frame), &velocity);
        assert!(error < 1e-6, "t = {t}: velocity error {error:e}");
    }
}

#[test]
fn driven_slider_crank_kinematics_matches_closed_form() {
    let mechanism = SliderCrank::STANDARD;
    let (model, joint) = mechanism.model(0.3);
    check_fully_driven(model, |phi| mechanism.positions(phi), joint);
}

#[test]
fn driven_four_bar_kinematics_matches_closed_form() {
    let mechanism = FourBar::STANDARD;
    let (model, joint) = mechanism.model(0.3);
    check_fully_driven(model, |phi| mechanism.positions(phi), joint);
}

fn tight(t_end: f64) -> SimulationOptions {
    let mut options = SimulationOptions::until(t_end);
    options.rtol = 1e-8;
    options.atol = AbsoluteTolerances::uniform(1e-10);
    options.output = OutputTimes::Every(0.01);
    options
}

/// Runs the free 1-DOF mechanism under gravity, then replays its crank angle (with velocity
/// and acceleration) as a driver in a kinematic analysis: the dependent coordinates, their
/// rates and accelerations must agree, and the driver must do no work (its multiplier ~ 0),
/// since the recorded motion was free.
fn check_dynamics_against_kinematics(build: impl Fn() -> (Model, multibody::JointId)) {
    let (model, _) = build();
    let mut system = with_gravity(model);
    let start = assembled(&system);
    let result = system
        .simulate(&start, &tight(2.0), &mut ())
        .expect("integrates");
    // Constraint drift below 1e-8 at rtol 1e-8 (atol 1e-10).
    assert!(result.drift.position < 1e-8, "{:?}", result.drift);
    let trajectory: &Trajectory = &result.trajectory;
    let samples = (0..trajectory.len())
        .map(|i| {
            (
                trajectory.times[i],
                trajectory.q(i)[2],
                trajectory.qd(i)[2],
                trajectory.qdd(i)[2],
            )
        })
        .collect();

    let (mut model, joint) = build();
    angle_driver(&mut model, joint, Box::new(Replay { samples }));
    let kinematic = with_gravity(model);
    let solution = kinematic
        .kinematics(&trajectory.times, trajectory.q(0))
        .expect("kinematics");
    let driver_row = kinematic
        .constraint_owners()
        .iter()
        .position(|o| *o == ConstraintOwner::Driver(DriverId(0)))
        .expect("driver row");
    // Tolerances: the dynamic state is off the constraints by its drift (<1e-8) and its
    // accelerations carry the Baumgarte terms 2αΦ̇ + β²Φ (~1e-5 at the measured drift), so
    // positions 1e-7, velocities 1e-6, accelerations and the driver torque 1e-4 (in SI, the
    // accelerations are O(10)).
    for frame in 0..trajectory.len() {
        let t = trajectory.times[frame];
        let dq = max_abs_diff(solution.q(frame), trajectory.q(frame));
        let dv = max_abs_diff(solution.qd(frame), trajectory.qd(frame));
        let da = max_abs_diff(solution.qdd(frame), trajectory.qdd(frame));
        assert!(dq < 1e-7, "t = {t}: position {dq:e}");
        assert!(dv < 1e-6, "t = {t}: velocity {dv:e}");
        assert!(da < 1e-4, "t = {t}: acceleration {da:e}");
        let torque = solution.lambda(frame)[driver_row];
        assert!(torque.abs() < 1e-4, "t = {t}: driver torque {torque:e}");
    }
    // The motion must actually be large, or the comparison says little.
    let swing = (0..trajectory.len())
        .map(|i| trajectory.q(i)[2])
        .fold(f64::NEG_INFINITY, f64::max)
        - (0..trajectory.len())
            .map(|i| trajectory.q(i)[2])
            .fold(f64::INFINITY, f64::min);
    assert!(swing > 0.5, "crank swing {swing}");
}

#[test]
fn free_slider_crank_dynamics_agrees_with_kinematics() {
    check_dynamics_against_kinematics(|| SliderCrank::STANDARD.model(PI / 3.0));
}

#[test]
fn free_four_bar_dynamics_agrees_with_kinematics() {
    check_dynamics_against_kinematics(|| FourBar::STANDARD.model(PI / 2.0));
}

#[test]
fn every_integrator_runs_the_free_slider_crank() {
    use multibody::Integrator;
    let reference = {
        let (model, _) = SliderCrank::STANDARD.model(PI / 3.0);
        let mut system = with_gravity(model);
        let start = assembled(&system);
        system
            .simulate(&start, &tight(0.5), &mut ())
            .expect("integrates")
            .final_state
    };
    for integrator in [
        Integrator::TrBdf2,
        Integrator::Esdirk34,
        Integrator::Radau5,
        Integrator::Tsit45,
    ] {
        let (model, _) = SliderCrank::STANDARD.model(PI / 3.0);
        let mut system = with_gravity(model);
        let start = assembled(&system);
        let mut options = tight(0.5);
        options.integrator = integrator;
        let result = system
            .simulate(&start, &options, &mut ())
            .expect("integrates");
        // Same tolerances, different methods: BDF, ESDIRK34 and Tsit45 agree to ~1e-7 m after
        // 0.5 s; second-order TR-BDF2 was measured at 1.2e-6 m. Bound 1e-5 m.
        let error = max_abs_diff(&result.final_state.q, &reference.q);
        assert!(error < 1e-5, "{integrator:?}: {error:e}");
        assert!(result.statistics.steps > 0);
    }
}
