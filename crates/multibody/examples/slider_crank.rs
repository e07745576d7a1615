//! A slider-crank driven by a constant motor torque against a viscous load on the slider,
//! under gravity: integrates several crank turns with BDF and the exact Jacobian, prints the
//! integrator statistics, constraint drift and energy balance, then measures what the exact
//! Jacobian saves against finite differences.
//!
//! `cargo run --release -p multibody --example slider_crank`

use std::time::Instant;

use multibody::{
    Anchor, Baumgarte, Body, BodyId, Equations, ForceElement, ForcePartials, Frame, Gravity,
    JacobianMethod, Model, Observer, RotationLock, SimulationOptions, SimulationResult, System,
};
use nalgebra::DMatrix;

/// A constant torque on one body (no partials: it depends on nothing).
struct Motor {
    body: BodyId,
    torque: f64,
}

impl ForceElement for Motor {
    fn name(&self) -> &str {
        "motor"
    }
    fn add_forces(&self, _t: f64, _q: &[f64], _qd: &[f64], forces: &mut [f64]) {
        forces[3 * self.body.0 + 2] += self.torque;
    }
    fn add_partials(&self, _t: f64, _q: &[f64], _qd: &[f64], _partials: &mut ForcePartials<'_>) {}
}

/// A viscous load `F_x = −c ẋ` on the slider: ∂F/∂ẋ = −c.
struct Load {
    body: BodyId,
    damping: f64,
}

impl ForceElement for Load {
    fn name(&self) -> &str {
        "viscous load"
    }
    fn add_forces(&self, _t: f64, _q: &[f64], qd: &[f64], forces: &mut [f64]) {
        let x = 3 * self.body.0;
        forces[x] -= self.damping * qd[x];
    }
    fn add_partials(&self, _t: f64, _q: &[f64], _qd: &[f64], partials: &mut ForcePartials<'_>) {
        let x = 3 * self.body.0;
        partials.add_dqd(x, x, -self.damping);
    }
}

/// Counts crank turns from the output frames.
#[derive(Default)]
struct Turns {
    crank_angle: f64,
}

impl Observer for Turns {
    fn output(&mut self, frame: &Frame<'_>) {
        self.crank_angle = frame.q[2];
    }
}

fn build() -> Result<System, Box<dyn std::error::Error>> {
    let (r, l) = (0.1, 0.35);
    let mut model = Model::new();
    // Rough guesses; assembly puts the mechanism together.
    let crank = model.add_body(Body::new(
        "crank",
        1.0,
        1.0 * r * r / 12.0,
        [0.05, 0.0, 0.0],
    ))?;
    let rod = model.add_body(Body::new("rod", 2.0, 2.0 * l * l / 12.0, [0.27, 0.01, 0.0]))?;
    let slider = model.add_body(Body::new("slider", 3.0, 0.01, [0.45, 0.0, 0.0]))?;
    model.add_revolute(
        "O",
        Anchor::ground(0.0, 0.0),
        Anchor::on(crank, -r / 2.0, 0.0),
    )?;
    model.add_revolute(
        "A",
        Anchor::on(crank, r / 2.0, 0.0),
        Anchor::on(rod, -l / 2.0, 0.0),
    )?;
    model.add_revolute(
        "B",
        Anchor::on(rod, l / 2.0, 0.0),
        Anchor::on(slider, 0.0, 0.0),
    )?;
    model.add_prismatic(
        "guide",
        Anchor::ground(0.0, 0.0),
        [1.0, 0.0],
        Anchor::on(slider, 0.0, 0.0),
        RotationLock::At(0.0),
    )?;
    let gravity = Gravity::new(&model, [0.0, -9.81]);
    let mut system = System::new(model)?;
    system.add_element(Box::new(gravity));
    system.add_element(Box::new(Motor {
        body: crank,
        torque: 1.5,
    }));
    system.add_element(Box::new(Load {
        body: slider,
        damping: 20.0,
    }));
    Ok(system)
}

fn report(label: &str, result: &SimulationResult) {
    let s = &result.statistics;
    println!("{label}");
    println!(
        "  steps {} (rejected {}, Newton failures {}), RHS evaluations {}, Jacobians {} \
         ({} jac-vec products served from the cache), factorizations {}",
        s.steps,
        s.rejected_steps,
        s.nonlinear_solver_failures,
        s.rhs_evaluations,
        s.jacobian_evaluations,
        s.jacobian_vector_products,
        s.factorizations
    );
    println!(
        "  step size {:.3e} .. {:.3e} s, wall time {:.1} ms",
        s.smallest_step,
        s.largest_step,
        s.wall_time.as_secs_f64() * 1e3
    );
    println!(
        "  constraint drift: max |Φ| = {:.3e}, max |Φ̇| = {:.3e}",
        result.drift.position, result.drift.velocity
    );
}

fn main() -> Result<(), Box<dyn std::error::Error>> {
    let mut system = build()?;
    let (q, qd) = system.initial_guess();
    let start = system.assemble(0.0, &q, &qd)?;
    let options = SimulationOptions::until(4.0);
    let mut turns = Turns::default();
    let result = system.simulate(&start, &options, &mut turns)?;
    println!(
        "slider-crank, {} coordinates, {} constraints, {} s: {:.2} crank turns, final crank speed \
         {:.2} rad/s",
        system.coordinate_count(),
        system.constraint_count(),
        options.t_end,
        (turns.crank_angle - start.q[2]) / std::f64::consts::TAU,
        result.final_state.qd[2]
    );
    report("BDF, rtol 1e-6, exact Jacobian:", &result);
    if let Some(energy) = &result.energy {
        println!(
            "  energy: kinetic {:.6} -> {:.6} J",
            energy.initial_kinetic, energy.final_kinetic
        );
        for (name, work) in energy.element_work.iter().chain(&energy.driver_work) {
            println!("    work of {name}: {work:+.6} J");
        }
        println!(
            "  energy balance residual {:.3e} J ({:.2e} of the largest term)",
            energy.residual,
            energy.relative_residual()
        );
    }

    // What the exact Jacobian saves: the same run with forward differences ...
    let mut fd_options = options.clone();
    fd_options.jacobian = JacobianMethod::FiniteDifference;
    let fd = system.simulate(&start, &fd_options, &mut ())?;
    report("BDF, rtol 1e-6, finite-difference Jacobian:", &fd);
    // The same two runs without the 40 001 output frames and the energy quadrature, so the
    // wall time is the integrator's own.
    for method in [JacobianMethod::Exact, JacobianMethod::FiniteDifference] {
        let mut lean = options.clone();
        lean.jacobian = method;
        lean.output = multibody::OutputTimes::Every(0.01);
        lean.energy_audit = false;
        let run = system.simulate(&start, &lean, &mut ())?;
        println!(
            "  {method:?} Jacobian, output every 10 ms, no audit: {} RHS evaluations, {:.1} ms",
            run.statistics.rhs_evaluations,
            run.statistics.wall_time.as_secs_f64() * 1e3
        );
    }
    // ... and one Jacobian alone, exact against forward differences, at the final state.
    let n = system.coordinate_count();
    let y: Vec<f64> = result
        .final_state
        .q
        .iter()
        .chain(&result.final_state.qd)
        .copied()
        .collect();
    let mut evaluator = system.evaluator(Baumgarte::default());
    let mut jacobian = DMatrix::zeros(2 * n, 2 * n);
    let repeats = 20_000;
    let time = |f: &mut dyn FnMut()| {
        let started = Instant::now();
        for _ in 0..repeats {
            f();
        }
        started.elapsed().as_secs_f64() / repeats as f64 * 1e6
    };
    let elements = system.elements();
    let mut dy = vec![0.0; 2 * n];
    let rhs_us = time(&mut || {
        let _ = evaluator.rhs(elements, 4.0, &y, &mut dy);
    });
    let exact_us = time(&mut || {
        let _ = evaluator.jacobian(elements, 4.0, &y, &mut jacobian);
    });
    let fd_us = time(&mut || {
        let _ = evaluator.finite_difference_jacobian(elements, 4.0, &y, &mut jacobian);
    });
    println!(
        "one RHS {rhs_us:.2} µs; one Jacobian ({size}×{size}): exact {exact_us:.2} µs, forward \
         differences {fd_us:.2} µs ({ratio:.1}× the exact)",
        size = 2 * n,
        ratio = fd_us / exact_us
    );
    Ok(())
}
