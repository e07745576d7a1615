//! A pinned rigid body: period, energy, reaction; a double pendulum's energy drift.

mod common;

use std::f64::consts::PI;

use common::{G, assembled, bar, max_abs_diff, pendulum, pin, with_gravity};
use multibody::{
    AbsoluteTolerances, Anchor, BodyId, ConstraintOwner, ForceElement, ForcePartials, Gravity,
    JointId, Model, OutputTimes, SimulationOptions, System,
};

fn tight(t_end: f64) -> SimulationOptions {
    let mut options = SimulationOptions::until(t_end);
    options.rtol = 1e-8;
    options.atol = AbsoluteTolerances::uniform(1e-10);
    options
}

/// Times at which `signal` crosses zero upwards, by linear interpolation between frames.
fn upward_crossings(times: &[f64], signal: impl Fn(usize) -> f64) -> Vec<f64> {
    (1..times.len())
        .filter(|&i| signal(i - 1) < 0.0 && signal(i) >= 0.0)
        .map(|i| {
            let (a, b) = (signal(i - 1), signal(i));
            times[i - 1] + (times[i] - times[i - 1]) * (-a / (b - a))
        })
        .collect()
}

#[test]
fn small_angle_period_and_energy() {
    let (mass, length, amplitude) = (2.0, 1.0, 0.01);
    let mut system = with_gravity(pendulum(mass, length, -PI / 2.0 + amplitude));
    let start = assembled(&system);
    let result = system
        .simulate(&start, &tight(5.0), &mut ())
        .expect("integrates");
    // Physical pendulum: ω₀² = m g (L/2) / (m L²/3). A 0.01 rad amplitude lengthens the period
    // by θ₀²/16 ≈ 6e-6; crossing times interpolated linearly between 1e-4 s frames are good to
    // ~1e-7 s. So 2e-5 relative tests the dynamics, not the measurement.
    let omega0 = (3.0 * G / (2.0 * length)).sqrt();
    let expected = 2.0 * PI / omega0 * (1.0 + amplitude * amplitude / 16.0);
    let trajectory = &result.trajectory;
    let crossings = upward_crossings(&trajectory.times, |i| trajectory.q(i)[2] + PI / 2.0);
    assert!(crossings.len() >= 3, "{crossings:?}");
    let period = (crossings[crossings.len() - 1] - crossings[0]) / (crossings.len() - 1) as f64;
    assert!(
        (period - expected).abs() / expected < 2e-5,
        "period {period} vs {expected}"
    );
    // Energy: at rtol 1e-8 the balance closes to ~1e-9 of the energy exchanged.
    let energy = result.energy.expect("audited");
    assert!(energy.relative_residual() < 1e-6, "{energy:?}");
    assert!(result.drift.position < 1e-8, "{:?}", result.drift);
}

#[test]
fn hanging_body_reaction_equals_weight() {
    let mass = 3.5;
    let mut system = with_gravity(pendulum(mass, 0.8, -PI / 2.0));
    let start = assembled(&system);
    let mut options = SimulationOptions::until(0.5);
    options.output = OutputTimes::Every(0.1);
    let result = system
        .simulate(&start, &options, &mut ())
        .expect("integrates");
    for frame in 0..result.trajectory.len() {
        let reaction = system
            .reaction(
                ConstraintOwner::Joint(JointId(0)),
                BodyId(0),
                result.trajectory.times[frame],
                result.trajectory.q(frame),
                result.trajectory.lambda(frame),
            )
            .expect("lengths match");
        // Statics: the pin holds the weight exactly; the body stays at rest, so only the
        // integrator's roundoff can show (1e-9 N of 34 N).
        assert!(reaction[0].abs() < 1e-9, "{reaction:?}");
        assert!((reaction[1] - mass * G).abs() < 1e-9, "{reaction:?}");
        assert!(reaction[2].abs() < 1e-9, "{reaction:?}");
    }
}

#[test]
fn double_pendulum_energy_drift_is_bounded() {
    let length = 1.0;
    let mut model = Model::new();
    // Both links released horizontal: a chaotic, energetic motion.
    let first = bar(&mut model, "upper", 1.0, length, [0.5, 0.0, 0.0]);
    let second = bar(&mut model, "lower", 1.0, length, [1.5, 0.0, 0.0]);
    let (upper_end, lower_end) = (
        Anchor::on(first, -0.5 * length, 0.0),
        Anchor::on(first, 0.5 * length, 0.0),
    );
    pin(&mut model, "O", Anchor::ground(0.0, 0.0), upper_end);
    pin(
        &mut model,
        "A",
        lower_end,
        Anchor::on(second, -0.5 * length, 0.0),
    );
    let gravity = Gravity::new(&model, [0.0, -G]);
    let mut system = System::new(model).expect("valid");
    system.add_element(Box::new(gravity));
    let start = assembled(&system);
    let mut options = tight(10.0);
    options.output = OutputTimes::Every(1e-2);
    let result = system
        .simulate(&start, &options, &mut ())
        .expect("integrates");
    let energy = result.energy.expect("audited");
    // About 10 J change hands between kinetic and potential energy; at rtol 1e-8 over 10 s of
    // chaotic motion the balance was measured to close to 2.7e-5 J (relative 2.8e-6); the
    // bound 1e-5 leaves a margin of ~4. Drift measured 1.8e-8 m.
    println!(
        "double pendulum, 10 s: energy residual {:.3e} J (relative {:.3e}), drift {:?}, {} steps",
        energy.residual,
        energy.relative_residual(),
        result.drift,
        result.statistics.steps
    );
    assert!(energy.relative_residual() < 1e-5, "{energy:?}");
    assert!(result.drift.position < 1e-7, "{:?}", result.drift);
}

/// Counts accepted steps and records when the rod passes the bottom (event θ + π/2 = 0).
struct BottomPassage {
    steps: usize,
    passages: Vec<f64>,
}

impl ForceElement for BottomPassage {
    fn name(&self) -> &str {
        "bottom passage"
    }
    fn add_forces(&self, _t: f64, _q: &[f64], _qd: &[f64], _forces: &mut [f64]) {}
    fn add_partials(&self, _t: f64, _q: &[f64], _qd: &[f64], _partials: &mut ForcePartials<'_>) {}
    fn on_accepted_step(&mut self, _t0: f64, _t: f64, _q: &[f64], _qd: &[f64]) {
        self.steps += 1;
    }
    fn event_count(&self) -> usize {
        1
    }
    fn event_functions(&self, _t: f64, q: &[f64], _qd: &[f64], values: &mut [f64]) {
        values[0] = q[2] + PI / 2.0;
    }
    fn on_event(&mut self, _index: usize, t: f64, _q: &[f64], _qd: &[f64]) {
        self.passages.push(t);
    }
}

#[test]
fn events_land_on_the_bottom_passage_and_hooks_see_every_step() {
    let (length, amplitude) = (1.0, 0.01);
    let mut system = with_gravity(pendulum(1.0, length, -PI / 2.0 + amplitude));
    let id = system.add_element(Box::new(BottomPassage {
        steps: 0,
        passages: Vec::new(),
    }));
    let start = assembled(&system);
    let result = system
        .simulate(&start, &tight(3.0), &mut ())
        .expect("integrates");
    let element = system.element::<BottomPassage>(id).expect("element back");
    assert_eq!(element.steps, result.statistics.steps);
    // Released at rest, the rod first passes the bottom after a quarter period, then every
    // half period. Root finding is good to the integrator's accuracy (~1e-8 here).
    let omega0 = (3.0 * G / (2.0 * length)).sqrt();
    let period = 2.0 * PI / omega0 * (1.0 + amplitude * amplitude / 16.0);
    assert!(element.passages.len() >= 4, "{:?}", element.passages);
    for (k, t) in element.passages.iter().enumerate() {
        let expected = period * (0.25 + 0.5 * k as f64);
        assert!(
            (t - expected).abs() < 1e-6,
            "passage {k}: {t} vs {expected}"
        );
    }
    assert_eq!(result.events.len(), element.passages.len());
}

#[test]
fn max_step_bounds_every_step_without_changing_the_answer() {
    let run = |max_step: Option<f64>| {
        let mut system = with_gravity(pendulum(1.0, 1.0, -PI / 2.0 + 1.0));
        let start = assembled(&system);
        let mut options = tight(2.0);
        options.max_step = max_step;
        system
            .simulate(&start, &options, &mut ())
            .expect("integrates")
    };
    let free = run(None);
    let bounded = run(Some(2e-3));
    assert!(free.statistics.largest_step > 2e-3, "{:?}", free.statistics);
    assert!(
        bounded.statistics.largest_step <= 2e-3 * (1.0 + 1e-9),
        "{:?}",
        bounded.statistics
    );
    assert!(bounded.statistics.steps >= 1000);
    // Both at rtol 1e-8: the final states agree to ~1e-7.
    let difference = max_abs_diff(&free.final_state.q, &bounded.final_state.q);
    assert!(difference < 1e-6, "{difference:e}");
    assert_eq!(bounded.final_state.t, 2.0);
}

#[test]
fn max_steps_stops_the_run_with_a_named_error_at_the_budget() {
    let mut system = with_gravity(pendulum(1.0, 1.0, -PI / 2.0 + 1.0));
    let start = assembled(&system);
    let mut options = tight(2.0);
    let full = system
        .simulate(&start, &options, &mut ())
        .expect("integrates");
    assert!(full.statistics.steps > 20, "{:?}", full.statistics);
    options.max_steps = Some(20);
    match system.simulate(&start, &options, &mut ()) {
        Err(multibody::SimulationError::StepLimit { t, steps }) => {
            assert_eq!(steps, 20);
            assert!(t > 0.0 && t < 2.0, "stopped at t = {t}");
        }
        other => panic!("expected the step budget to stop the run, got {other:?}"),
    }
    // A budget the run does not reach changes nothing.
    options.max_steps = Some(full.statistics.steps + 1000);
    let within = system
        .simulate(&start, &options, &mut ())
        .expect("integrates");
    assert_eq!(within.final_state.q, full.final_state.q);
}

#[test]
fn max_wall_time_stops_the_run_with_a_named_error() {
    let mut system = with_gravity(pendulum(1.0, 1.0, -PI / 2.0 + 1.0));
    let start = assembled(&system);
    let mut options = tight(2.0);
    // A spent budget stops the run before its first step (deterministic, no timing).
    options.max_wall_time = Some(std::time::Duration::ZERO);
    match system.simulate(&start, &options, &mut ()) {
        Err(e @ multibody::SimulationError::WallTimeLimit { steps: 0, .. }) => {
            assert!(e.to_string().contains("max_wall_time"), "{e}");
        }
        other => panic!("expected the wall-time budget to stop the run, got {other:?}"),
    }
    options.max_wall_time = Some(std::time::Duration::from_secs(3600));
    assert!(system.simulate(&start, &options, &mut ()).is_ok());
}
