//! Input robustness: non-finite metrics are never `ok` (neither run nor resumed), and a value
//! written into an integer scene field must be a whole number in the field's range.

use sweep::{Mode, Row, Sampler, Status, Sweep, SweepError};

mod common;
use common::{fresh_dir, refusal, resume};

/// One sample, one metric (a quick slider-crank run).
const ONE: &str = r#"
scene = "slider-crank"
metrics = ["response.joints.rod-slider.max_penetration_m"]
[run]
cycles = 1
[[vary]]
path = "clearance_joints.rod-slider.clearance"
name = "clearance"
values = [5e-4, 4e-4]
"#;

/// The message of the refusal of `text`, which must be a bad value named by its field.
fn field_error(text: &str) -> String {
    match refusal(text) {
        e @ SweepError::Field { .. } => {
            assert!(e.is_bad_input());
            e.to_string()
        }
        e => panic!("expected a field error, got {e}"),
    }
}

/// `text` is refused naming a field, in a message containing every one of `needles`.
fn refused_naming(text: &str, needles: &[&str]) {
    let e = field_error(text);
    assert!(needles.iter().all(|n| e.contains(n)), "{e}");
}

/// A grid sweep of slider-crank varying `path` over `values` (no `[run]`: it would override).
fn grid(path: &str, values: &str) -> String {
    format!(
        "scene = \"slider-crank\"\nmetrics = [\"response.dissipated_per_cycle_j\"]\n\
         [[vary]]\npath = \"{path}\"\nvalues = {values}\n"
    )
}

/// The rows file of `sweep` written by hand (as an older version or an editor would), each row
/// `(sample, metric cell, status)`.
fn write_csv(sweep: &Sweep, out: &std::path::Path, rows: &[(usize, &str, &str)]) {
    std::fs::create_dir_all(out).unwrap();
    let mut text = sweep::table::header(sweep).join(",");
    text.push('\n');
    for (k, metric, status) in rows {
        let input = sweep::table::number(sweep.input_values(*k)[0]);
        text.push_str(&format!("{k},{input},{metric},{status},,0.100\n"));
    }
    std::fs::write(sweep::rows_path(out), text).unwrap();
}

/// The (metric, status) cells of each row of a one-input, one-metric rows file.
fn cells(csv: &str) -> Vec<(&str, &str)> {
    csv.lines()
        .skip(1)
        .map(|l| {
            let c: Vec<&str> = l.split(',').collect();
            (c[2], c[3])
        })
        .collect()
}

#[test]
fn resume_runs_again_an_ok_row_whose_metric_is_not_finite() {
    let s = Sweep::from_str(ONE, "one").unwrap();
    let out = fresh_dir("resume-nan");
    write_csv(&s, &out, &[(0, "NaN", "ok"), (1, "inf", "ok")]);
    let (todo, kept) = sweep::pending(&s, &out, true).unwrap();
    assert_eq!(todo, vec![0, 1], "kept {kept:?}");
    assert!(kept.is_empty(), "{kept:?}");
    // A finite ok row and a failed row are done; only the NaN one runs again.
    write_csv(&s, &out, &[(0, "-inf", "ok"), (1, "2.5e-5", "ok")]);
    let (rows, ran) = resume(&s, &out);
    assert_eq!(ran, vec![0]);
    assert_eq!(rows.len(), 2);
    assert_eq!(rows[0].status, Status::Ok, "{}", rows[0].error);
    assert!(rows[0].metrics[0].is_some_and(f64::is_finite));
    assert_eq!(rows[1].metrics, vec![Some(2.5e-5)]);
    let csv = std::fs::read_to_string(sweep::rows_path(&out)).unwrap();
    assert!(
        !csv.to_lowercase().contains("nan") && !csv.contains("inf"),
        "{csv}"
    );
    let got = cells(&csv);
    assert_eq!(got.len(), 2, "{csv}");
    assert!(
        got[0].0.parse::<f64>().is_ok_and(f64::is_finite) && got[0].1 == "ok",
        "{csv}"
    );
    assert_eq!(got[1], ("2.5e-5", "ok"), "{csv}");
    std::fs::remove_dir_all(&out).unwrap();
}

#[test]
fn an_ok_row_with_a_non_finite_metric_is_written_as_failed() {
    let s = Sweep::from_str(ONE, "one").unwrap();
    let out = fresh_dir("write-nan");
    let row = |sample: usize, metric: f64| Row {
        sample,
        inputs: s.input_values(sample),
        metrics: vec![Some(metric)],
        status: Status::Ok,
        error: String::new(),
        wall_time_s: 0.5,
    };
    sweep::write_outputs(&s, &[row(0, f64::NAN), row(1, f64::INFINITY)], &out).unwrap();
    let csv = std::fs::read_to_string(sweep::rows_path(&out)).unwrap();
    // The metric cells hold no NaN or infinity, and no row is `ok`; the message names both.
    assert_eq!(cells(&csv), vec![("", "failed"), ("", "failed")], "{csv}");
    assert!(csv.contains("(NaN)") && csv.contains("(inf)"), "{csv}");
    let lines: Vec<&str> = csv.lines().skip(1).collect();
    assert_eq!(lines.len(), 2, "{csv}");
    for line in lines {
        assert!(
            line.contains(",failed,")
                && line
                    .contains("metric response.joints.rod-slider.max_penetration_m is not finite"),
            "{csv}"
        );
    }
    // Read back, the rows are failed ones: resuming keeps them and runs nothing.
    let (todo, kept) = sweep::pending(&s, &out, true).unwrap();
    assert!(todo.is_empty());
    assert!(kept.iter().all(|r| r.status == Status::Failed));
    std::fs::remove_dir_all(&out).unwrap();
}

#[test]
fn a_fraction_in_an_integer_field_is_refused_up_front() {
    refused_naming(
        &grid("run.cycles", "[1, 2.5]"),
        &[
            "vary[0].values[1]",
            "run.cycles = 2.5: must be a whole number",
        ],
    );
    // Integer fields the base scene leaves to their defaults are integers too.
    refused_naming(
        &grid("run.cycles_per_stage", "[2.5]"),
        &["run.cycles_per_stage = 2.5: must be a whole number"],
    );
    refused_naming(
        &grid("run.wear_stages", "[0.5]"),
        &["run.wear_stages = 0.5"],
    );
    // A distribution draws fractions: refused on an integer field.
    refused_naming(
        &grid("run.cycles", "[1]")
            .replace(
                "values = [1]",
                "distribution = \"uniform\"\nlow = 1\nhigh = 3",
            )
            .replace("metrics", "samples = 2\nseed = 1\nmetrics"),
        &["vary[0].distribution", "run.cycles"],
    );
}

#[test]
fn a_value_beyond_the_integer_type_is_refused_up_front() {
    refused_naming(
        &grid("run.cycles", "[5e9]"),
        &["run.cycles = 5e9", "0 to 4294967295"],
    );
    refused_naming(
        &grid("run.cycles", "[-1]"),
        &["run.cycles = -1", "0 to 4294967295"],
    );
    // usize: a value beyond i64 (what TOML holds) must be refused, not saturated to 9.2e18 cells.
    let text = r#"
scene = "lgres"
metrics = ["response.dissipated_per_cycle_j"]
[[vary]]
path = "clearance_joints.A.wear.cells"
values = [1e19]
"#;
    let e = field_error(text);
    assert!(
        e.contains("clearance_joints.A.wear.cells = 1e19") && e.contains("range"),
        "{e}"
    );
    assert!(!e.contains("18446744073709552000"), "{e}");
}

#[test]
fn whole_values_reach_integer_fields_exactly() {
    let s = Sweep::from_str(&grid("run.cycles_per_stage", "[2, 3]"), "k").unwrap();
    assert_eq!(s.input_values(1), vec![3.0]);
    assert_eq!(s.scene(1).unwrap().run.cycles_per_stage, 3);
    let s = Sweep::from_str(&grid("run.cycles", "[1, 3]"), "c").unwrap();
    assert_eq!(s.scene(1).unwrap().run.cycles, 3);
    // A float field whose base value is written as an integer (`inertia = 1`) is not rounded:
    // the field's type decides, not how the base scene happens to spell its value.
    let dir = fresh_dir("float-field");
    std::fs::create_dir_all(&dir).unwrap();
    let scene = lgres::scenes::source("slider-crank").unwrap().replacen(
        "inertia = 1.0e-4",
        "inertia = 1",
        1,
    );
    assert!(scene.contains("inertia = 1\n"));
    std::fs::write(dir.join("scene.toml"), scene).unwrap();
    let text =
        grid("bodies.crank.inertia", "[1.5e-4, 2]").replace("\"slider-crank\"", "\"scene.toml\"");
    std::fs::write(dir.join("f.toml"), text).unwrap();
    let s = Sweep::from_path(&dir.join("f.toml")).unwrap();
    assert_eq!(s.input_values(0), vec![1.5e-4]);
    assert_eq!(s.scene(0).unwrap().bodies[0].inertia, 1.5e-4);
    std::fs::remove_dir_all(&dir).unwrap();
}

#[test]
fn a_random_draw_into_an_integer_field_is_a_failed_sample() {
    // A sweep built from a valid grid, then switched to draws (as a caller could).
    let mut s = Sweep::from_str(&grid("run.cycles", "[1]"), "d").unwrap();
    s.inputs[0].sampler = Sampler::Uniform {
        low: 1.0,
        high: 3.0,
    };
    s.mode = Mode::Random {
        samples: 3,
        seed: 1,
    };
    let v = s.input_values(0)[0];
    assert!(v.fract() != 0.0, "{v}");
    let e = s.scene(0).unwrap_err().to_string();
    assert_eq!(
        e,
        format!(
            "run.cycles = {}: must be a whole number",
            sweep::table::number(v)
        )
    );
    let row = s.run_sample(0);
    assert_eq!(row.status, Status::Failed);
    assert_eq!(row.error, e);
    assert_eq!(row.inputs, vec![v]);
    s.inputs[0].sampler = Sampler::Normal {
        mean: 1e19,
        sd: 1.0,
    };
    let e = s.scene(0).unwrap_err().to_string();
    assert!(
        e.starts_with("run.cycles = 1e19: ") && e.contains("range"),
        "{e}"
    );
}
