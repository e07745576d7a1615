//! The stress battery never reports a case `ok` with a non-finite number: a measured NaN or
//! infinity makes the case FAILED with the quantity named, and a quantity not measured (the
//! energy books of a case run without the audit) is left empty, not written as NaN.

use analysis::stress::{self, CaseResult, Outcome, SurfaceSetup};

fn result(outcome: Outcome) -> CaseResult {
    CaseResult {
        name: "long".into(),
        description: "energy audit off".into(),
        duration_s: 10.0,
        outcome,
        steps: 100,
        rejected_steps: 3,
        newton_failures: 0,
        smallest_step_s: 1e-6,
        events: 4,
        drift_position: 1e-7,
        energy_residual_j: f64::NAN,
        energy_relative_residual: f64::NAN,
        peak_normal_force_n: vec![("A".into(), 1.5e4)],
        wear_depth_m: Vec::new(),
        wear_volume_ratio: Vec::new(),
        atol_position_m: 1e-7,
        wall_time_s: 1.0,
    }
}

/// The battery's case `name` on the default scene, `duration` s long.
fn default_case(name: &str, duration: f64) -> stress::StressCase {
    let base = lgres::scenes::builtin(lgres::scenes::DEFAULT).unwrap();
    stress::cases(&base, duration)
        .into_iter()
        .find(|c| c.name == name)
        .unwrap()
}

/// The `ok` rows of the CSV.
fn ok_rows(csv: &str) -> Vec<&str> {
    csv.lines().filter(|l| l.contains(",ok,")).collect()
}

#[test]
fn a_wear_case_whose_volume_ratio_is_nan_is_a_named_failure() {
    // 1 ms: the pin has not dropped into the clearance yet, so no wear and no Archard volume:
    // the grid/Archard volume ratio is 0/0.
    let case = default_case("wear, 10 cells", 1e-3);
    assert_eq!(case.surfaces, SurfaceSetup::WearOn);
    let r = stress::run_case(&case);
    assert!(
        r.wear_volume_ratio.iter().any(|(_, v)| !v.is_finite()),
        "the case should measure a NaN ratio: {:?}",
        r.wear_volume_ratio
    );
    match &r.outcome {
        Outcome::Failed { error, message } => {
            assert_eq!(error, "NonFinite");
            assert!(
                message.contains("wear_volume_ratio") && message.contains("NaN"),
                "{message}"
            );
        }
        other => panic!("expected a NonFinite failure, got {other:?}"),
    }
    let csv = stress::csv(&[r]);
    assert!(ok_rows(&csv).is_empty(), "{csv}");
    assert!(csv.contains("FAILED"), "{csv}");
}

#[test]
fn an_ok_case_finishes_with_every_measured_number_finite() {
    let case = default_case("baseline", 5e-3);
    let r = stress::run_case(&case);
    assert_eq!(r.outcome, Outcome::Completed, "{}", r.outcome.detail());
    for x in [
        r.smallest_step_s,
        r.drift_position,
        r.energy_residual_j,
        r.energy_relative_residual,
        r.atol_position_m,
    ] {
        assert!(x.is_finite(), "{r:?}");
    }
    let csv = stress::csv(&[r]);
    let rows = ok_rows(&csv);
    assert_eq!(rows.len(), 1, "{csv}");
    assert!(!rows[0].to_lowercase().contains("nan"), "{csv}");
}

#[test]
fn the_csv_writes_no_nan_in_an_ok_row() {
    // The long case runs without the energy audit: its residuals are not measured (NaN in
    // the struct). The CSV leaves them empty rather than print `ok` next to `NaN`.
    let csv = stress::csv(&[result(Outcome::Completed)]);
    let rows = ok_rows(&csv);
    assert_eq!(rows.len(), 1, "{csv}");
    assert!(!rows[0].to_lowercase().contains("nan"), "{csv}");
    let header: Vec<&str> = csv.lines().next().unwrap().split(',').collect();
    let cells: Vec<&str> = rows[0].split(',').collect();
    let at = |name: &str| cells[header.iter().position(|h| *h == name).unwrap()];
    assert_eq!(at("energy_residual_j"), "");
    assert_eq!(at("energy_relative_residual"), "");
    assert_eq!(at("drift_position"), "0.0000001");
    // A failed case keeps a measured infinity visible.
    let mut failed = result(Outcome::Failed {
        error: "NonFinite".into(),
        message: "drift_position = inf is not finite".into(),
    });
    failed.drift_position = f64::INFINITY;
    let csv = stress::csv(&[failed]);
    assert!(csv.contains(",inf,"), "{csv}");
}
