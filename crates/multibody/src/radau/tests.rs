//! Radau IIA against closed-form solutions: order, stiff decay, roots, dense output.

use super::*;

const LIMITS: RadauLimits = RadauLimits {
    min_step: 1e-14,
    max_error_test_failures: 40,
    max_nonlinear_failures: usize::MAX,
};

/// `x'' = −x`: `x = cos t`, `v = −sin t`.
fn oscillator(y: &[f64], _p: &[f64], _t: f64, dy: &mut [f64]) {
    dy[0] = y[1];
    dy[1] = -y[0];
}

fn oscillator_jacobian(_y: &[f64], _t: f64, j: &mut DMatrix<f64>) {
    j.fill(0.0);
    j[(0, 1)] = 1.0;
    j[(1, 0)] = -1.0;
}

const STIFFNESS: f64 = 1e6;

/// Radau on the oscillator from `x = 1, ẋ = 0` at `t0`, with one absolute tolerance.
fn oscillator_radau(t0: f64, rtol: f64, atol: f64) -> Radau5<'static> {
    Radau5::new(
        &oscillator,
        &oscillator_jacobian,
        None,
        t0,
        &[1.0, 0.0],
        rtol,
        &[atol, atol],
        LIMITS,
    )
}

/// Prothero–Robinson: `y' = −k (y − cos t) − sin t`, smooth solution `cos t`.
fn prothero_robinson(y: &[f64], _p: &[f64], t: f64, dy: &mut [f64]) {
    dy[0] = -STIFFNESS * (y[0] - t.cos()) - t.sin();
}

fn prothero_robinson_jacobian(_y: &[f64], _t: f64, j: &mut DMatrix<f64>) {
    j[(0, 0)] = -STIFFNESS;
}

impl Radau5<'_> {
    /// One step of exactly `h`, without error test (for the order of the method).
    fn step_fixed(&mut self, h: f64) {
        if !self.jacobian_usable {
            (self.jacobian_of)(self.y.as_slice(), self.t, &mut self.jacobian);
            self.jacobian_usable = true;
        }
        if self.factors.as_ref().is_none_or(|f| f.h != h) {
            self.factorize(h);
        }
        assert!(matches!(self.newton(h), Newton::Converged(_)));
        self.accept(h, h, false);
    }
}

/// Integrates to `t_end` with the adaptive controller, landing on `t_end` exactly.
fn run_to(radau: &mut Radau5<'_>, t_end: f64) {
    radau.set_stop_time(t_end).expect("after the start");
    while radau.step().expect("steps") != RadauStop::StopTime {}
    assert_eq!(radau.t(), t_end);
}

#[test]
fn fixed_steps_converge_with_order_five() {
    let errors: Vec<f64> = [0.2, 0.1, 0.05]
        .iter()
        .map(|&h| {
            let mut radau = oscillator_radau(0.0, 1e-13, 1e-13);
            for _ in 0..(2.0_f64 / h).round() as usize {
                radau.step_fixed(h);
            }
            let t = radau.t();
            (radau.y()[0] - t.cos()).hypot(radau.y()[1] + t.sin())
        })
        .collect();
    // Measured: 8.9e-8, 2.8e-9, 8.7e-11 (slopes 5.00, 5.00).
    for pair in errors.windows(2) {
        let slope = (pair[0] / pair[1]).log2();
        assert!((4.7..5.3).contains(&slope), "{errors:?}");
    }
}

#[test]
fn adaptive_error_follows_the_tolerance() {
    let mut previous = f64::INFINITY;
    for rtol in [1e-4, 1e-6, 1e-8, 1e-10] {
        let mut radau = oscillator_radau(0.0, rtol, rtol);
        run_to(&mut radau, 10.0);
        let error = (radau.y()[0] - 10f64.cos()).hypot(radau.y()[1] + 10f64.sin());
        // Global error over ~1.6 periods within a few tolerances, and falling with it
        // (measured 3.6e-5, 9.3e-7, 1.9e-8, 4.0e-10 in 23, 45, 96, 205 steps).
        assert!(
            error < 20.0 * rtol && error < previous,
            "rtol {rtol:e}: {error:e}"
        );
        previous = error;
    }
}

#[test]
fn stiff_problem_takes_large_accurate_steps() {
    // Start off the smooth solution: the transient (time constant 1e-6 s) must be damped
    // by large steps (L-stability, R(∞) = 0), not followed.
    let mut radau = Radau5::new(
        &prothero_robinson,
        &prothero_robinson_jacobian,
        None,
        0.0,
        &[2.0],
        1e-6,
        &[1e-8],
        LIMITS,
    );
    for _ in 0..3 {
        radau.step_fixed(0.1);
    }
    let error = (radau.y()[0] - 0.3f64.cos()).abs();
    // Measured 1.2e-11.
    assert!(error < 1e-9, "after three steps of 0.1 s: {error:e}");

    let mut radau = Radau5::new(
        &prothero_robinson,
        &prothero_robinson_jacobian,
        None,
        0.0,
        &[1.0],
        1e-6,
        &[1e-8],
        LIMITS,
    );
    run_to(&mut radau, 10.0);
    let error = (radau.y()[0] - 10f64.cos()).abs();
    let steps = radau.statistics().steps;
    // Explicit stability would need h < 3e-6 s, i.e. over 3 million steps; measured 9
    // steps, error 2.0e-6 (the internal tolerance is RADAU5's 0.1 rtol^(2/3) = 1e-5).
    assert!(steps < 30, "{steps} steps");
    assert!(error < 1e-5, "{error:e}");
}

#[test]
fn roots_are_located_on_the_dense_output() {
    // x = cos t crosses zero at π/2 and 3π/2.
    let position = |y: &[f64], _p: &[f64], _t: f64, g: &mut [f64]| g[0] = y[0];
    let mut radau = Radau5::new(
        &oscillator,
        &oscillator_jacobian,
        Some((&position, 1)),
        0.0,
        &[1.0, 0.0],
        1e-8,
        &[1e-10, 1e-10],
        LIMITS,
    );
    radau.set_stop_time(6.0).expect("after the start");
    let mut roots = Vec::new();
    loop {
        match radau.step().expect("steps") {
            RadauStop::Root(t, 0) => {
                roots.push(t);
                radau.move_back(t).expect("within the step");
                let (t, y, dy) = radau.derivative_mut();
                oscillator(y, &[], t, dy);
            }
            RadauStop::StopTime => break,
            _ => {}
        }
    }
    let expected = [
        std::f64::consts::FRAC_PI_2,
        3.0 * std::f64::consts::FRAC_PI_2,
    ];
    assert_eq!(roots.len(), 2, "{roots:?}");
    for (t, exact) in roots.iter().zip(expected) {
        // Measured −1.9e-9 and −2.8e-9: the state's own error at rtol 1e-8.
        assert!((t - exact).abs() < 1e-8, "{t} vs {exact}");
    }
    // The restarts at the roots keep the solution on track.
    let error = (radau.y()[0] - 6f64.cos()).hypot(radau.y()[1] + 6f64.sin());
    assert!(error < 1e-7, "{error:e}");
}

#[test]
fn dense_output_is_accurate_between_steps() {
    let mut radau = oscillator_radau(0.0, 1e-8, 1e-10);
    radau.set_stop_time(5.0).expect("after the start");
    let mut worst_inside: f64 = 0.0;
    let mut worst_end: f64 = 0.0;
    let mut y = [0.0; 2];
    loop {
        let t0 = radau.t();
        let stop = radau.step().expect("steps");
        let t1 = radau.t();
        for k in 1..10 {
            let t = t0 + (t1 - t0) * k as f64 / 10.0;
            radau.interpolate(t, &mut y).expect("inside the step");
            worst_inside = worst_inside.max((y[0] - t.cos()).hypot(y[1] + t.sin()));
        }
        worst_end = worst_end.max((radau.y()[0] - t1.cos()).hypot(radau.y()[1] + t1.sin()));
        if stop == RadauStop::StopTime {
            break;
        }
    }
    // The collocation polynomial is of order 3 inside a step, the step ends of order 5:
    // measured 7.3e-8 inside against 2.6e-9 at the ends (rtol 1e-8).
    assert!(
        worst_inside < 5e-7,
        "inside {worst_inside:e}, ends {worst_end:e}"
    );
    assert!(radau.interpolate(-1.0, &mut y).is_err());
}

#[test]
fn stop_time_in_the_past_is_refused() {
    let mut radau = oscillator_radau(1.0, 1e-6, 1e-8);
    assert!(radau.set_stop_time(0.5).is_err());
    assert!(radau.set_stop_time(1.0).is_err());
}
