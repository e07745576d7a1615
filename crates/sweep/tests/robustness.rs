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
        let settings = sweep.settings_id();
        text.push_str(&format!(
            "{k},{input},{metric},{status},,{settings},0.100\n"
        ));
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

/// A slider-crank sweep with `[run]` table `run` varying `path` over `values`, on the base
/// scene `scene` (a built-in name).
fn sweep_with(scene: &str, run: &str, path: &str, values: &str) -> String {
    format!(
        "scene = \"{scene}\"\nmetrics = [\"response.joints.rod-slider.max_penetration_m\"]\n\
         [run]\n{run}\n[[vary]]\npath = \"{path}\"\nvalues = {values}\n"
    )
}

#[test]
fn a_varied_path_the_run_table_sets_is_refused_naming_both() {
    let text = sweep_with("slider-crank", "cycles = 1", "run.cycles", "[2, 3]");
    refused_naming(
        &text,
        &["vary[0].path", "run.cycles", "[run] table's cycles"],
    );
    // Without the table's value the varied one runs.
    let s = Sweep::from_str(
        &sweep_with("slider-crank", "stages = 0", "run.cycles", "[2, 3]"),
        "t",
    )
    .unwrap();
    assert_eq!(s.scene(1).unwrap().run.cycles, 3);
}

#[test]
fn the_trajectories_refusal_names_the_tables_k_once() {
    let text = sweep_with(
        "lgres-paper",
        "cycles = 1\ncycles_per_stage = 2\ntrajectories = 3",
        "clearance_joints.A.clearance",
        "[4e-4]",
    );
    let e = field_error(&text);
    assert!(
        e.contains("K = 2") && e.contains("this table's run.cycles_per_stage"),
        "{e}"
    );
    assert_eq!(e.matches("run.trajectories").count(), 1, "{e}");
}

#[test]
fn control_characters_in_column_names_are_refused() {
    let base = sweep_with(
        "slider-crank",
        "cycles = 1",
        "clearance_joints.rod-slider.clearance",
        "[4e-4]",
    );
    for c in ['\u{1b}', '\u{7}', '\u{0}', '\u{7f}', '\u{9b}', '\t'] {
        // As TOML escapes it.
        let escaped = format!("\\u{:04x}", u32::from(c));
        let named = format!("{base}name = \"x{escaped}y\"\n");
        refused_naming(&named, &["vary[0].name", "control characters"]);
        let metric = base.replace(
            "max_penetration_m\"",
            &format!("max_penetration_m{escaped}\""),
        );
        refused_naming(&metric, &["metrics[0]", "control characters"]);
    }
}

/// The value at `path` of `sweep`'s sample `k` as it runs: in the scene as run
/// ([`sim::scene_as_run`] with the sweep's run options), but `run.cycles_per_stage` in the
/// sample's scene (its `K` sets what a stage stands for; the run's `K` is simulated).
fn value_that_ran(sweep: &Sweep, k: usize, path: &str) -> f64 {
    let scene = sweep.scene(k).unwrap();
    let as_run =
        sim::scene_as_run("t", &scene, &sweep.overrides.run_options()).expect("scene as run");
    let text = if path == "run.cycles_per_stage" {
        scene.to_toml()
    } else {
        as_run.to_toml()
    };
    let table: toml::Table = toml::from_str(&text).unwrap();
    match sweep::path::get(&table, path) {
        Some(toml::Value::Float(x)) => *x,
        Some(toml::Value::Integer(i)) => *i as f64,
        other => panic!("{path}: {other:?}"),
    }
}

/// Fuzzing by kind: every `[run]` field set or not, against every run or solver field it sets
/// varied (and a plain scene field), on a base scene that sets the field too or not. Each
/// sweep is refused naming `vary[0].path`, or every sample's recorded input is the value its
/// run takes. Nothing is simulated.
#[test]
fn varied_paths_and_the_run_table_never_disagree_on_what_ran() {
    let run_fields = [
        "cycles = 1",
        "stages = 0",
        "rtol = 1e-6",
        "cycles_per_stage = 2",
        "trajectories = 1",
        "wear_tolerance = 0.05",
        "max_steps = 100000",
        "max_wall_time = 60.0",
    ];
    let varied = [
        ("run.cycles", "[2, 3]"),
        ("run.wear_stages", "[0, 1]"),
        ("solver.rtol", "[1e-7, 1e-8]"),
        ("run.cycles_per_stage", "[4, 6]"),
        ("run.trajectories", "[1, 2]"),
        ("run.wear_tolerance", "[0.1, 0.2]"),
        ("solver.max_steps", "[200000, 300000]"),
        ("solver.max_wall_time", "[120.0, 240.0]"),
        ("clearance_joints.rod-slider.clearance", "[4e-4, 3e-4]"),
    ];
    let dir = fresh_dir("overlap");
    std::fs::create_dir_all(&dir).unwrap();
    // The base scene sets the run fields too (or not): its values must never win either.
    let based = dir.join("base.toml");
    std::fs::write(
        &based,
        "extends = \"slider-crank\"\n[run]\ncycles = 5\ntrajectories = 2\n\
         adaptive_extrapolation = true\n[solver]\nrtol = 1e-5\n",
    )
    .unwrap();
    let mut counts = std::collections::BTreeMap::<String, usize>::new();
    // Each [run] field alone, all of them, and none.
    let tables: Vec<Vec<&str>> = std::iter::once(Vec::new())
        .chain(run_fields.iter().map(|f| vec![*f]))
        .chain(std::iter::once(run_fields.to_vec()))
        .chain(std::iter::once(vec!["cycles_per_stage = 2", "cycles = 1"]))
        .collect();
    for scene in ["slider-crank", "base.toml"] {
        for run in &tables {
            for (path, values) in varied {
                let text = sweep_with(scene, &run.join("\n"), path, values);
                let file = dir.join("s.toml");
                std::fs::write(&file, &text).unwrap();
                let kind = match Sweep::from_path(&file) {
                    Err(e @ SweepError::Field { .. }) if e.to_string().contains("vary[0].path") => {
                        assert!(e.to_string().contains(path), "{e}");
                        "refused: vary[0].path"
                    }
                    Err(e) => {
                        assert!(e.is_bad_input(), "{text}\n{e}");
                        "refused: another field"
                    }
                    Ok(s) => {
                        for k in 0..s.samples() {
                            assert_eq!(
                                value_that_ran(&s, k, path),
                                s.input_values(k)[0],
                                "sample {k} of\n{text}"
                            );
                        }
                        "accepted: inputs as run"
                    }
                };
                *counts.entry(format!("{kind} ({path})")).or_default() += 1;
            }
        }
    }
    eprintln!("{counts:#?}");
    let _ = std::fs::remove_dir_all(&dir);
    for (path, _) in varied {
        assert!(
            counts.contains_key(&format!("accepted: inputs as run ({path})")),
            "{path} never accepted: {counts:#?}"
        );
    }
    for path in ["run.cycles", "solver.rtol", "run.trajectories"] {
        assert!(
            counts.contains_key(&format!("refused: vary[0].path ({path})")),
            "{path} never refused: {counts:#?}"
        );
    }
}

/// Fuzzing by kind of the resume: a sweep's rows written, then resumed by a sweep whose
/// `[run]` table, varied paths or base scene changed (or not). Every row kept is one the
/// resuming sweep would run the same way: its sample's scene as run and its run options equal.
#[test]
fn resumed_rows_ran_with_what_the_resuming_sweep_runs() {
    let dir = fresh_dir("resume-settings");
    std::fs::create_dir_all(&dir).unwrap();
    let bases = [
        "extends = \"slider-crank\"\n",
        "extends = \"slider-crank\"\n[run]\ncycles = 3\n",
        "extends = \"slider-crank\"\n[solver]\nrtol = 1e-7\n",
    ];
    let runs = [
        "cycles = 1",
        "cycles = 2",
        "cycles = 1\nrtol = 1e-8",
        "stages = 0",
    ];
    let varied = [
        ("clearance_joints.rod-slider.clearance", "[4e-4, 3e-4]"),
        (
            "clearance_joints.rod-slider.normal_law.restitution",
            "[0.8, 0.7]",
        ),
    ];
    let sweep_of = |base: &str, run: &str, (path, values): (&str, &str)| {
        let folder = dir.join("sweep");
        std::fs::create_dir_all(&folder).unwrap();
        std::fs::write(folder.join("base.toml"), base).unwrap();
        let file = folder.join("s.toml");
        std::fs::write(&file, sweep_with("base.toml", run, path, values)).unwrap();
        Sweep::from_path(&file).unwrap()
    };
    let mut cases = Vec::new();
    for base in bases {
        for run in runs {
            for vary in varied {
                cases.push((base, run, vary));
            }
        }
    }
    let mut kinds = std::collections::BTreeMap::<&str, usize>::new();
    let as_run = |s: &Sweep, k: usize| {
        let scene = s.scene(k).unwrap();
        let options = s.overrides.run_options();
        (
            sim::scene_as_run("t", &scene, &options).unwrap().to_toml(),
            format!("{options:?}"),
        )
    };
    for (k, first) in cases.iter().enumerate() {
        // Each case against itself and a few others (all pairs would be slow).
        for second in cases.iter().skip(k % 5).step_by(5) {
            let ran = sweep_of(first.0, first.1, first.2);
            let out = dir.join("out");
            let _ = std::fs::remove_dir_all(&out);
            std::fs::create_dir_all(&out).unwrap();
            let rows: Vec<Row> = (0..ran.samples())
                .map(|k| Row {
                    sample: k,
                    inputs: ran.input_values(k),
                    metrics: vec![Some(1e-6)],
                    status: Status::Ok,
                    error: String::new(),
                    wall_time_s: 0.5,
                })
                .collect();
            sweep::table::write_rows(&ran, &rows, &sweep::rows_path(&out)).unwrap();
            let resuming = sweep_of(second.0, second.1, second.2);
            let kind = match sweep::pending(&resuming, &out, true) {
                Ok((_, kept)) => {
                    for row in &kept {
                        assert_eq!(
                            as_run(&ran, row.sample),
                            as_run(&resuming, row.sample),
                            "sample {} kept from {first:?} resumed as {second:?}",
                            row.sample
                        );
                    }
                    if kept.is_empty() {
                        "accepted: none kept"
                    } else {
                        "accepted: rows kept"
                    }
                }
                Err(e @ SweepError::Resume { .. }) => {
                    let e = e.to_string();
                    if e.contains("other settings") {
                        "refused: settings changed"
                    } else if e.contains("inputs") || e.contains("columns") {
                        "refused: inputs or columns changed"
                    } else {
                        panic!("{e}")
                    }
                }
                Err(e) => panic!("{e}"),
            };
            *kinds.entry(kind).or_default() += 1;
        }
    }
    eprintln!("{kinds:#?}");
    let _ = std::fs::remove_dir_all(&dir);
    for kind in [
        "accepted: rows kept",
        "refused: settings changed",
        "refused: inputs or columns changed",
    ] {
        assert!(kinds.contains_key(kind), "no case of {kind}: {kinds:#?}");
    }
}
