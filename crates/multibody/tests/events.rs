//! A non-smooth force law switched at located events: a free body dropped on a spring floor.

use multibody::{
    AbsoluteTolerances, Body, ForceElement, ForcePartials, Gravity, Integrator, Model, OutputTimes,
    SimulationOptions, System,
};

/// A spring-damper floor at `y = 0` acting on body 0 only while in contact. Contact begins
/// and ends at the located crossings of `y = 0`; between them the law is smooth, so the
/// integrator never steps across the switch.
struct Floor {
    stiffness: f64,
    damping: f64,
    in_contact: bool,
    impacts: Vec<f64>,
    steps: usize,
}

impl ForceElement for Floor {
    fn name(&self) -> &str {
        "floor"
    }
    fn add_forces(&self, _t: f64, q: &[f64], qd: &[f64], forces: &mut [f64]) {
        if self.in_contact {
            forces[1] += -self.stiffness * q[1] - self.damping * qd[1];
        }
    }
    fn add_partials(&self, _t: f64, _q: &[f64], _qd: &[f64], partials: &mut ForcePartials<'_>) {
        if self.in_contact {
            partials.add_dq(1, 1, -self.stiffness);
            partials.add_dqd(1, 1, -self.damping);
        }
    }
    fn on_accepted_step(&mut self, _t0: f64, _t: f64, _q: &[f64], _qd: &[f64]) {
        self.steps += 1;
    }
    fn event_count(&self) -> usize {
        1
    }
    fn event_functions(&self, _t: f64, q: &[f64], _qd: &[f64], values: &mut [f64]) {
        values[0] = q[1];
    }
    fn on_event(&mut self, _index: usize, t: f64, _q: &[f64], qd: &[f64]) {
        // Decide by the direction of motion, so a restart exactly on y = 0 cannot flip it back.
        let entering = qd[1] < 0.0;
        if entering && !self.in_contact {
            self.impacts.push(t);
        }
        self.in_contact = entering;
    }
}

fn drop_on_floor(integrator: Integrator, damping: f64) -> (System, multibody::SimulationResult) {
    let mut model = Model::new();
    model
        .add_body(Body::new("ball", 1.0, 0.1, [0.0, 1.0, 0.0]))
        .expect("valid");
    let gravity = Gravity::new(&model, [0.0, -9.81]);
    let mut system = System::new(model).expect("valid");
    system.add_element(Box::new(gravity));
    system.add_element(Box::new(Floor {
        stiffness: 1e5,
        damping,
        in_contact: false,
        impacts: Vec::new(),
        steps: 0,
    }));
    let (q, qd) = system.initial_guess();
    let start = system
        .assemble(0.0, &q, &qd)
        .expect("no constraints to violate");
    let mut options = SimulationOptions::until(1.5);
    options.integrator = integrator;
    options.rtol = 1e-9;
    options.atol = AbsoluteTolerances::uniform(1e-11);
    options.output = OutputTimes::Every(1e-3);
    let result = system
        .simulate(&start, &options, &mut ())
        .expect("integrates");
    (system, result)
}

#[test]
fn elastic_bounce_returns_to_the_drop_height() {
    // Free fall from 1 m hits y = 0 at t = √(2/g) = 0.4515 s; the undamped floor returns all
    // the energy, so the ball rises back to 1 m at ~0.903 s (+ the short contact).
    for integrator in [
        Integrator::Bdf,
        Integrator::Esdirk34,
        Integrator::Radau5,
        Integrator::Tsit45,
    ] {
        let (system, result) = drop_on_floor(integrator, 0.0);
        let floor = system
            .element::<Floor>(multibody::ElementId(1))
            .expect("floor");
        let first = (2.0_f64 / 9.81).sqrt();
        assert!(!floor.impacts.is_empty(), "{integrator:?}: no impact");
        // Event location is as accurate as the state (rtol 1e-9).
        assert!(
            (floor.impacts[0] - first).abs() < 1e-7,
            "{integrator:?}: {:?}",
            floor.impacts
        );
        let apex = (0..result.trajectory.len())
            .filter(|&i| result.trajectory.times[i] > first + 0.1)
            .map(|i| result.trajectory.q(i)[1])
            .fold(f64::NEG_INFINITY, f64::max);
        // Output every 1 ms resolves the apex to ½ g (0.5 ms)² ≈ 1.2e-6 m.
        assert!((apex - 1.0).abs() < 1e-5, "{integrator:?}: apex {apex}");
        assert_eq!(floor.steps, result.statistics.steps, "{integrator:?}");
        let energy = result.energy.expect("audited");
        assert!(
            energy.relative_residual() < 1e-6,
            "{integrator:?}: {energy:?}"
        );
    }
}

#[test]
fn damped_bounce_balances_the_dissipated_energy() {
    let (_, result) = drop_on_floor(Integrator::Bdf, 50.0);
    let energy = result.energy.expect("audited");
    let floor_work = energy
        .element_work
        .iter()
        .find(|(name, _)| name == "floor")
        .map(|(_, w)| *w)
        .expect("floor work");
    // The floor takes energy out; the balance ΔT = W_gravity + W_floor closes to the
    // integration accuracy, because steps land on the switches and the floor's power is
    // integrated by 3-point Gauss on each step.
    assert!(floor_work < -0.1, "{energy:?}");
    assert!(energy.relative_residual() < 1e-6, "{energy:?}");
    assert!(result.statistics.events >= 2);
}

/// Records the floor force at each output frame through `Frame::element`.
struct FloorForce {
    peak: f64,
    frames: usize,
}

impl multibody::Observer for FloorForce {
    fn output(&mut self, frame: &multibody::Frame<'_>) {
        self.frames += 1;
        if let Some(floor) = frame.element::<Floor>(multibody::ElementId(1)) {
            let mut forces = [0.0; 3];
            floor.add_forces(frame.t, frame.q, frame.qd, &mut forces);
            self.peak = self.peak.max(forces[1]);
        }
    }
}

#[test]
fn observer_reads_custom_outputs_from_the_elements() {
    let mut model = Model::new();
    model
        .add_body(Body::new("ball", 1.0, 0.1, [0.0, 1.0, 0.0]))
        .expect("valid");
    let mut system = System::new(model).expect("valid");
    system.add_element(Box::new(Gravity::for_system(&system, [0.0, -9.81])));
    system.add_element(Box::new(Floor {
        stiffness: 1e5,
        damping: 0.0,
        in_contact: false,
        impacts: Vec::new(),
        steps: 0,
    }));
    let (q, qd) = system.initial_guess();
    let start = system.assemble(0.0, &q, &qd).expect("assembles");
    let mut options = SimulationOptions::until(0.6);
    options.output = OutputTimes::Every(1e-4);
    options.record_trajectory = false;
    let mut observer = FloorForce {
        peak: 0.0,
        frames: 0,
    };
    let result = system
        .simulate(&start, &options, &mut observer)
        .expect("integrates");
    assert_eq!(observer.frames, 6001);
    assert!(result.trajectory.is_empty());
    // Undamped linear floor, energy m g (h + y) = ½ k y² at the deepest point:
    // F = m g + √((m g)² + 2 k m g h) = 1410.56 N. The peak is stationary, and frames every
    // 0.1 ms sample the ~10 ms contact to ~1e-4 of it.
    let weight: f64 = 9.81;
    let expected = weight + (weight * weight + 2.0 * 1e5 * weight * 1.0).sqrt();
    assert!(
        (observer.peak - expected).abs() < 5e-4 * expected,
        "{} vs {expected}",
        observer.peak
    );
}
