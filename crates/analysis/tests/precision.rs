//! The work–precision sweep on a short window of the default scene: the references agree far
//! below the errors they measure, errors fall with the tolerance, timed runs repeat the
//! measured trajectory bit for bit, and bad settings are named.

use analysis::precision::{
    PrecisionError, PrecisionOptions, PrecisionReport, RowOutcome, run_sweep,
};
use scene::{Integrator, ValidScene};

/// The start-up window only (first impacts at ~0.012 s), two methods, two tolerances.
fn short_sweep() -> PrecisionReport {
    sweep(
        vec![Integrator::Bdf, Integrator::Esdirk34],
        vec![1e-5, 1e-8],
        [(Integrator::Bdf, 1e-11), (Integrator::Esdirk34, 1e-11)],
    )
}

/// The default scene as the bounds below were set on.
fn scene() -> ValidScene {
    let mut scene = lgres::scenes::builtin("lgres")
        .expect("built-in scene")
        .into_scene();
    // The bounds below were set on the Cartesian formulation. In joint coordinates the 1e-11
    // references agree to 2.8e-9 m and BDF at 1e-8 is off by 1.0e-8 m: resolved, but not by
    // the factor 10 asserted here.
    scene.solver.formulation = scene::Formulation::Cartesian;
    // And on the line-of-centres contact: on the foundation the two 1e-11 references agree
    // only to 2e-7 m over this window (not yet understood; docs/convergence.md), which would
    // hide the errors this test checks.
    for joint in &mut scene.clearance_joints {
        joint.contact = scene::ContactSpec::line_of_centres();
    }
    ValidScene::new(scene, "lgres, Cartesian, line of centres").expect("valid scene")
}

fn sweep(
    methods: Vec<Integrator>,
    rtols: Vec<f64>,
    references: [(Integrator, f64); 2],
) -> PrecisionReport {
    let scene = scene();
    let options = PrecisionOptions {
        methods,
        rtols,
        references,
        duration: Some(0.02),
        repeats: 1,
        ..PrecisionOptions::default()
    };
    run_sweep("lgres", &scene, &options, &mut |_| {}).expect("sweep runs")
}

#[test]
fn short_sweep_measures_errors_that_fall_with_the_tolerance_above_the_reference_floor() {
    let report = short_sweep();
    // The references (two methods at 1e-11) agree on the start-up paths to well under a
    // micrometre — the clearance is 0.5 mm — and do not separate.
    let floor = report.reference_agreement.start_up_m();
    assert!(floor < 1e-8, "references disagree by {floor:e} m");
    assert_eq!(report.reference_agreement.separation_s, None);
    assert_eq!(report.rows.len(), 4);
    for method in ["bdf", "esdirk34"] {
        let rows: Vec<_> = report.rows.iter().filter(|r| r.method == method).collect();
        let [loose, tight] = rows.as_slice() else {
            panic!("two rows per method");
        };
        // Never measured against itself.
        assert_ne!(loose.reference, method);
        let (el, et) = (
            loose.errors().expect("completes"),
            tight.errors().expect("completes"),
        );
        // Three decades of tolerance buy at least one decade of start-up accuracy, and the
        // tight run's error is still resolved (ten times the floor).
        assert!(
            et.start_up_m() * 10.0 < el.start_up_m(),
            "{method}: {:e} at 1e-8 vs {:e} at 1e-5",
            et.start_up_m(),
            el.start_up_m()
        );
        assert!(
            et.start_up_m() > 10.0 * floor,
            "{method}: {:e}",
            et.start_up_m()
        );
        assert!(tight.steps > loose.steps);
        // Output frames, the energy audit and wear accumulation only observe the run.
        assert!(loose.timed_runs_identical && tight.timed_runs_identical);
        assert!(tight.wall_s.is_finite() && tight.wall_wear_s.is_finite());
    }
}

#[test]
fn radau_agrees_with_bdf_on_the_clearance_start_up() {
    // BDF at rtol 1e-11 and Radau IIA at 1e-13 (its rtol is RADAU5's, applied internally as
    // 0.1 rtol^(2/3): 2e-10 here) as the two references: their start-up paths must agree
    // about as closely as BDF's and ESDIRK34's at 1e-11 do in the test above (measured
    // 1.8e-9 m). Measured 6.5e-10 m; bound 5e-9 m.
    let report = sweep(
        vec![Integrator::Radau5],
        vec![1e-5, 1e-8],
        [(Integrator::Bdf, 1e-11), (Integrator::Radau5, 1e-13)],
    );
    let floor = report.reference_agreement.start_up_m();
    assert!(floor < 5e-9, "Radau and BDF disagree by {floor:e} m");
    assert_eq!(report.reference_agreement.separation_s, None);
    let [loose, tight] = report.rows.as_slice() else {
        panic!("two rows");
    };
    let (el, et) = (
        loose.errors().expect("completes"),
        tight.errors().expect("completes"),
    );
    // Looser than BDF at the same rtol value (above): measured 1.2e-4 m at 1e-5 and 1.3e-5 m
    // at 1e-8, both far above the floor.
    assert!(
        et.start_up_m() * 5.0 < el.start_up_m() && et.start_up_m() > 10.0 * floor,
        "{:e} at 1e-8 vs {:e} at 1e-5",
        et.start_up_m(),
        el.start_up_m()
    );
}

#[test]
fn report_files_are_written_with_one_line_per_run() {
    let report = short_sweep();
    let csv = report.csv();
    assert_eq!(csv.lines().count(), 1 + report.rows.len());
    let header_columns = csv.lines().next().map_or(0, |h| h.split(',').count());
    for line in csv.lines().skip(1) {
        assert_eq!(line.split(',').count(), header_columns, "{line}");
    }
    let md = report.markdown(Some("precision.png"));
    assert!(md.contains("| bdf | 1e-5 |") && md.contains("| esdirk34 | 1e-8 |"));
    let dir = std::env::temp_dir().join(format!("lgres-precision-{}", std::process::id()));
    let files = report.write(&dir).expect("writes");
    assert_eq!(files.len(), 4);
    for f in &files {
        let size = std::fs::metadata(f).map(|m| m.len()).unwrap_or(0);
        assert!(size > 100, "{} has {size} bytes", f.display());
    }
    let _ = std::fs::remove_dir_all(&dir);
}

#[test]
fn an_explicit_method_over_a_step_budget_fails_and_skips_its_tighter_tolerances() {
    let scene = scene();
    let options = PrecisionOptions {
        methods: vec![Integrator::Tsit45],
        rtols: vec![1e-6, 1e-7],
        references: [(Integrator::Bdf, 1e-9), (Integrator::Esdirk34, 1e-9)],
        duration: Some(0.02),
        repeats: 0,
        max_steps: 50,
        ..PrecisionOptions::default()
    };
    let report = run_sweep("lgres", &scene, &options, &mut |_| {}).expect("sweep runs");
    match &report.rows[0].outcome {
        RowOutcome::Failed { reason } => assert!(reason.contains("50 accepted steps"), "{reason}"),
        other => panic!("expected the budget to stop the run: {other:?}"),
    }
    assert!(matches!(report.rows[1].outcome, RowOutcome::Skipped { .. }));
}

#[test]
fn bad_settings_name_the_option() {
    let scene = lgres::scenes::builtin("lgres").expect("built-in scene");
    let field = |options: PrecisionOptions| match run_sweep("lgres", &scene, &options, &mut |_| {})
    {
        Err(PrecisionError::Options { field, .. }) => field,
        other => panic!(
            "expected an options error, got {:?}",
            other.map(|r| r.rows.len())
        ),
    };
    let same_method = PrecisionOptions {
        references: [(Integrator::Bdf, 1e-12), (Integrator::Bdf, 1e-11)],
        ..PrecisionOptions::default()
    };
    assert_eq!(field(same_method), "references");
    let looser_reference = PrecisionOptions {
        references: [(Integrator::Bdf, 1e-6), (Integrator::Esdirk34, 1e-12)],
        ..PrecisionOptions::default()
    };
    assert_eq!(field(looser_reference), "references");
    let zero_rtol = PrecisionOptions {
        rtols: vec![1e-4, 0.0],
        ..PrecisionOptions::default()
    };
    assert_eq!(field(zero_rtol), "rtols");
    let window_past_end = PrecisionOptions {
        duration: Some(0.01),
        ..PrecisionOptions::default()
    };
    assert_eq!(field(window_past_end), "start_up");
    let ideal = lgres::scenes::builtin("lgres-ideal").expect("built-in scene");
    assert!(matches!(
        run_sweep(
            "lgres-ideal",
            &ideal,
            &PrecisionOptions::default(),
            &mut |_| {}
        ),
        Err(PrecisionError::Unsuitable(_))
    ));
}

#[test]
fn method_names_are_the_scene_files_spelling_and_parse_back() {
    use analysis::precision::{ALL_METHODS, method_by_name, method_name};
    for method in ALL_METHODS {
        let name = method_name(method);
        assert_eq!(
            serde_json::to_value(method).expect("serializes"),
            serde_json::Value::from(name)
        );
        assert_eq!(method_by_name(name), Some(method));
    }
    assert_eq!(method_by_name("rk4"), None);
}
