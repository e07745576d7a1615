//! The exact Jacobian of the right-hand side against central finite differences.

mod common;

use common::{FourBar, SpringDamper, with_gravity_and_spring};
use multibody::{
    Baumgarte, DriveTarget, Equations, ForceElement, ForcePartials, Harmonic, JointId,
};
use nalgebra::DMatrix;

#[test]
fn exact_jacobian_matches_central_differences() {
    let mechanism = FourBar::STANDARD;
    let (model, _) = mechanism.model(0.7);
    // A free four-bar with a spring-damper (nonzero ∂G/∂q and ∂G/∂q̇) on the coupler.
    let system = with_gravity_and_spring(model, SpringDamper::STIFF);
    let (q, qd) = system.initial_guess();
    // A state off the constraint manifold and moving, so every term (Baumgarte, γ, ∂γ) counts.
    let mut y: Vec<f64> = q.iter().chain(&qd).copied().collect();
    let n = q.len();
    for (i, value) in y.iter_mut().enumerate() {
        *value += if i < n {
            1e-3 * (i as f64).sin()
        } else {
            0.8 * (1.3 * i as f64).cos()
        };
    }
    let mut evaluator = system.evaluator(Baumgarte {
        alpha: 20.0,
        beta: 30.0,
    });
    let elements = system.elements();
    let mut exact = DMatrix::zeros(2 * n, 2 * n);
    evaluator
        .jacobian(elements, 0.4, &y, &mut exact)
        .expect("regular");
    let mut plus = vec![0.0; 2 * n];
    let mut minus = vec![0.0; 2 * n];
    let scale = exact.amax();
    for c in 0..2 * n {
        let h = 1e-6;
        let mut shifted = y.clone();
        shifted[c] += h;
        evaluator
            .rhs(elements, 0.4, &shifted, &mut plus)
            .expect("regular");
        shifted[c] -= 2.0 * h;
        evaluator
            .rhs(elements, 0.4, &shifted, &mut minus)
            .expect("regular");
        for r in 0..2 * n {
            let central = (plus[r] - minus[r]) / (2.0 * h);
            // Central differences are accurate to ~h² f''' + ε f / h ≈ 1e-8 relative to the
            // largest entry; 1e-6 of it catches any wrong term (they are O(1) of the scale).
            assert!(
                (central - exact[(r, c)]).abs() < 1e-6 * scale,
                "J[{r},{c}]: exact {} vs central {central} (scale {scale})",
                exact[(r, c)]
            );
        }
    }
}

#[test]
fn exact_jacobian_matches_with_a_moving_driver_and_prismatic_joint() {
    use common::SliderCrank;
    let mechanism = SliderCrank::STANDARD;
    let (mut model, _) = mechanism.model(0.4);
    // Drive the slider along its guide harmonically (Φ_t, Φ_tt ≠ 0, and the slide equation
    // turns with no body, the line equation with none): the Jacobian formula holds for any
    // state, assembled or not.
    model
        .add_driver(
            "slide",
            DriveTarget::JointSlide(JointId(3)),
            Box::new(Harmonic {
                offset: 0.35,
                amplitude: 0.02,
                omega: 5.0,
            }),
        )
        .expect("valid");
    let system = with_gravity_and_spring(model, SpringDamper::SOFT);
    let (q, qd) = system.initial_guess();
    let n = q.len();
    let y: Vec<f64> = q
        .iter()
        .chain(&qd)
        .enumerate()
        .map(|(i, v)| {
            v + if i < n {
                2e-3 * (0.7 * i as f64).cos()
            } else {
                0.5 * (i as f64).sin()
            }
        })
        .collect();
    let mut evaluator = system.evaluator(Baumgarte::default());
    let elements = system.elements();
    let mut exact = DMatrix::zeros(2 * n, 2 * n);
    let mut reference = DMatrix::zeros(2 * n, 2 * n);
    evaluator
        .jacobian(elements, 0.3, &y, &mut exact)
        .expect("regular");
    evaluator
        .finite_difference_jacobian(elements, 0.3, &y, &mut reference)
        .expect("regular");
    // Forward differences: ~1e-8 × scale × (second derivatives); Baumgarte β² = 2500 makes
    // the entries large, so compare relative to the largest entry.
    let error = (&exact - &reference).amax() / exact.amax();
    assert!(error < 1e-5, "relative error {error:e}");
}

/// A spring-damper that forgets its partials: the kind of element `check_partials` exists for.
struct ForgetfulSpring(SpringDamper);

impl ForceElement for ForgetfulSpring {
    fn name(&self) -> &str {
        "forgetful spring"
    }
    fn add_forces(&self, t: f64, q: &[f64], qd: &[f64], forces: &mut [f64]) {
        self.0.add_forces(t, q, qd, forces);
    }
    fn add_partials(&self, _t: f64, _q: &[f64], _qd: &[f64], _partials: &mut ForcePartials<'_>) {}
}

#[test]
fn check_partials_passes_exact_elements_and_catches_a_forgotten_one() {
    let (model, _) = FourBar::STANDARD.model(0.7);
    let mut system = with_gravity_and_spring(model, SpringDamper::STIFF);
    system.add_element(Box::new(ForgetfulSpring(SpringDamper::STIFF)));
    let (q, mut qd) = system.initial_guess();
    for (i, v) in qd.iter_mut().enumerate() {
        *v += 0.5 * (i as f64).cos();
    }
    let report = system
        .check_partials(0.0, &q, &qd, 1e-6, 1e-6)
        .expect("checks");
    let names: Vec<&str> = report.iter().map(|c| c.element.as_str()).collect();
    assert_eq!(names, ["gravity", "spring-damper", "forgetful spring"]);
    // Gravity: constant, so exactly zero both ways. The spring: truncation and round-off of
    // central differences at 1e-6 steps, ~1e-8 of its stiffness.
    assert_eq!(report[0].max_relative_error, 0.0);
    assert!(report[1].max_relative_error < 1e-6, "{:?}", report[1]);
    // The forgetful one is off by its whole stiffness (relative error ~ 1 against a scale of 1).
    let worst = report[2].worst.expect("a disagreement");
    assert!(report[2].max_relative_error > 100.0, "{:?}", report[2]);
    assert_eq!(worst.exact, 0.0);
}
