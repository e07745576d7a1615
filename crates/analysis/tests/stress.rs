//! The stress battery runs and reports every case's outcome (tiny durations).

use analysis::stress::{self, Outcome};

#[test]
fn battery_reports_each_case_and_expected_errors_by_name() {
    let base = lgres::scenes::builtin(lgres::scenes::DEFAULT).unwrap();
    let all = stress::cases(&base, 0.01);
    let pick = [
        "baseline",
        "clearance 0",
        "v0 = v1",
        "worn to 2x clearance",
        "1000 cycles",
    ];
    let chosen: Vec<_> = all
        .into_iter()
        .filter(|c| pick.contains(&c.name.as_str()))
        .collect();
    assert_eq!(chosen.len(), pick.len());
    let mut seen = Vec::new();
    let results = stress::run_cases(&chosen, true, &mut |c, r| {
        if r.is_some() {
            seen.push(c.name.clone());
        }
    });
    assert_eq!(seen.len(), pick.len());
    let by = |name: &str| results.iter().find(|r| r.name == name).unwrap();

    for name in ["baseline", "worn to 2x clearance"] {
        let r = by(name);
        assert_eq!(
            r.outcome,
            Outcome::Completed,
            "{name}: {}",
            r.outcome.detail()
        );
        assert!(r.steps > 0 && r.smallest_step_s > 0.0);
        assert!(r.drift_position.is_finite() && r.energy_residual_j.is_finite());
        assert_eq!(r.peak_normal_force_n.len(), 2);
    }
    // Tolerances scale with the nominal clearance: 2e-4 × 0.5 mm.
    assert!((by("baseline").atol_position_m - 1e-7).abs() < 1e-15);

    for (name, field) in [
        ("clearance 0", ".clearance"),
        ("v0 = v1", "friction.slip_velocity"),
    ] {
        match &by(name).outcome {
            Outcome::ExpectedError { error, message } => {
                assert_eq!(error, "SceneError::Invalid");
                assert!(message.contains(field), "{name}: {message}");
            }
            other => panic!("{name}: expected a named validation error, got {other:?}"),
        }
    }
    assert!(matches!(by("1000 cycles").outcome, Outcome::Skipped { .. }));

    let md = stress::markdown(&results);
    let csv = stress::csv(&results);
    for name in pick {
        assert!(md.contains(&format!("| {name} |")), "{md}");
        assert!(csv.contains(&format!("\"{name}\"")), "{csv}");
    }
    assert!(md.contains("expected error") && md.contains("SceneError::Invalid"));
    assert_eq!(csv.lines().count(), pick.len() + 1);
}

#[test]
fn tiny_clearance_gets_a_clearance_scaled_position_tolerance() {
    let base = lgres::scenes::builtin(lgres::scenes::DEFAULT).unwrap();
    let case = stress::cases(&base, 0.005)
        .into_iter()
        .find(|c| c.name == "clearance 1 µm")
        .unwrap();
    let r = stress::run_case(&case);
    assert_eq!(r.outcome, Outcome::Completed, "{}", r.outcome.detail());
    assert!((r.atol_position_m - 2e-10).abs() < 1e-18);
}
