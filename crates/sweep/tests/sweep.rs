//! Sweep files: validation naming fields, deterministic samples, local runs, resume.

use std::path::PathBuf;

use sweep::{LocalOptions, Mode, Status, Sweep, SweepError};

mod common;
use common::{fresh_dir, refusal, resume};

const GRID: &str = r#"
scene = "slider-crank"
metrics = ["response.joints.rod-slider.max_penetration_m", "response.dissipated_per_cycle_j"]
[run]
cycles = 1
[[vary]]
path = "clearance_joints.rod-slider.clearance"
values = [4e-4, -1e-4]
[[vary]]
path = "drivers.crank-speed.law.rate"
values = [400.0, 523.5988]
"#;

const RANDOM: &str = r#"
scene = "slider-crank"
samples = 5
seed = 11
metrics = ["response.joints.rod-slider.max_penetration_m"]
[run]
cycles = 1
[[vary]]
path = "clearance_joints.rod-slider.clearance"
distribution = "uniform"
low = 3e-4
high = 6e-4
[[vary]]
path = "clearance_joints.rod-slider.normal_law.restitution"
distribution = "normal"
mean = 0.8
sd = 0.05
"#;

/// The message of the refusal of `text`, which must name a field (a bad value or type).
fn field_error(text: &str) -> String {
    match refusal(text) {
        e @ (SweepError::Field { .. } | SweepError::Type { .. }) => e.to_string(),
        e => panic!("expected a field error, got {e}"),
    }
}

#[test]
fn bad_files_name_the_field() {
    // (base file, text replaced, replacement, what the message must contain)
    let cases: &[(&str, &str, &str, &[&str])] = &[
        (RANDOM, "low = 3e-4", "lo = 3e-4", &["vary[0]", "lo"]),
        (
            RANDOM,
            "\"uniform\"",
            "\"uniformly\"",
            &["vary[0].distribution", "uniformly"],
        ),
        (RANDOM, "high = 6e-4", "high = 2e-4", &["vary[0].high"]),
        (RANDOM, "seed = 11\n", "", &["seed"]),
        (RANDOM, "sd = 0.05", "sd = -0.05", &["vary[1].sd"]),
        (
            RANDOM,
            "rod-slider.clearance",
            "rod-slider.clearence",
            &["vary[0].path", "clearence"],
        ),
        (
            RANDOM,
            "clearance_joints.rod-slider",
            "clearance_joints.B",
            &["vary[0].path", "names: rod-slider"],
        ),
        (
            RANDOM,
            "\"response.joints",
            "\"respons.joints",
            &["metrics[0]"],
        ),
        (
            GRID,
            "values = [4e-4, -1e-4]",
            "distribution = \"uniform\"\nlow = 1e-4\nhigh = 2e-4",
            &["vary[1].values"],
        ),
        (GRID, "[run]", "samples = 3\n[run]", &["samples"]),
        (RANDOM, "cycles = 1", "cycles = \"one\"", &["run.cycles"]),
        // Draws that could be infinite, refused naming the field that makes them so.
        (
            RANDOM,
            "low = 3e-4\nhigh = 6e-4",
            "low = -1.7e308\nhigh = 1.7e308",
            &[
                "vary[0].high = 1.7e308: high − low overflows (low = -",
                "draws would be infinite",
            ],
        ),
        (
            RANDOM,
            "sd = 0.05",
            "sd = 1e308",
            &["vary[1].sd = 1e308: draws reach mean ± 8.57·sd (mean = 0.8), beyond the largest"],
        ),
        (
            RANDOM,
            "distribution = \"uniform\"\nlow = 3e-4\nhigh = 6e-4",
            "distribution = \"log-normal\"\nmedian = 1e306\nsigma = 1.0",
            &[
                "vary[0].sigma = 1.0: draws reach median·exp(8.57·sigma) (median = 1",
                "beyond the largest number",
            ],
        ),
        // Refused up front, not by every sample.
        (
            RANDOM,
            "cycles = 1",
            "cycles = 1\nwear_tolerance = 2.0",
            &["run.wear_tolerance = 2"],
        ),
    ];
    for (base, from, to, needles) in cases {
        let e = field_error(&base.replace(from, to));
        assert!(needles.iter().all(|n| e.contains(n)), "{e}");
    }
}

#[test]
fn samples_depend_on_seed_and_index_only() {
    let s = Sweep::from_str(RANDOM, "r").unwrap();
    assert_eq!(
        s.mode,
        Mode::Random {
            samples: 5,
            seed: 11
        }
    );
    let again = Sweep::from_plan(&s.plan()).unwrap();
    for k in 0..5 {
        let v = s.input_values(k);
        assert_eq!(v, again.input_values(k));
        assert!((3e-4..6e-4).contains(&v[0]), "{v:?}");
        // A sample's scene is the same rebuilt from the plan (what a Dask worker does).
        assert_eq!(s.scene(k).unwrap(), again.scene(k).unwrap());
    }
    assert_ne!(s.input_values(0), s.input_values(1));
    let other = Sweep::from_str(&RANDOM.replace("seed = 11", "seed = 12"), "r").unwrap();
    assert_ne!(s.input_values(0), other.input_values(0));
    // More samples: the first five are unchanged.
    let more = Sweep::from_str(&RANDOM.replace("samples = 5", "samples = 50"), "r").unwrap();
    assert_eq!(more.input_values(4), s.input_values(4));
}

#[test]
fn distributions_have_their_moments() {
    let text = RANDOM.replace("samples = 5", "samples = 20000").replace(
        "distribution = \"uniform\"\nlow = 3e-4\nhigh = 6e-4",
        "distribution = \"log-normal\"\nmedian = 4e-4\nsigma = 0.5",
    );
    let s = Sweep::from_str(&text, "m").unwrap();
    let v: Vec<Vec<f64>> = (0..20000).map(|k| s.input_values(k)).collect();
    let mut logs: Vec<f64> = v.iter().map(|x| x[0].ln()).collect();
    logs.sort_by(f64::total_cmp);
    let median = logs[10000].exp();
    assert!((median / 4e-4 - 1.0).abs() < 0.02, "{median}");
    let mean_ln = logs.iter().sum::<f64>() / 2e4;
    let sd_ln = (logs.iter().map(|l| (l - mean_ln).powi(2)).sum::<f64>() / 2e4).sqrt();
    assert!((sd_ln - 0.5).abs() < 0.01, "{sd_ln}");
    let mean = v.iter().map(|x| x[1]).sum::<f64>() / 2e4;
    let sd = (v.iter().map(|x| (x[1] - mean).powi(2)).sum::<f64>() / 2e4).sqrt();
    assert!(
        (mean - 0.8).abs() < 0.002 && (sd - 0.05).abs() < 0.002,
        "{mean} {sd}"
    );
}

#[test]
fn grid_runs_every_combination_and_a_bad_sample_is_a_row() {
    let s = Sweep::from_str(GRID, "g").unwrap();
    assert_eq!(s.samples(), 4);
    assert_eq!(s.input_values(1), vec![4e-4, 523.5988]);
    assert_eq!(s.input_values(2), vec![-1e-4, 400.0]);
    let out = fresh_dir("grid");
    let mut seen = 0;
    let rows = sweep::run_local(
        &s,
        &out,
        &LocalOptions {
            jobs: 2,
            resume: false,
        },
        None,
        &mut |_, _, _| seen += 1,
    )
    .unwrap();
    assert_eq!(seen, 4);
    assert_eq!(
        rows.iter().map(|r| r.sample).collect::<Vec<_>>(),
        vec![0, 1, 2, 3]
    );
    assert_eq!(rows[0].status, Status::Ok, "{}", rows[0].error);
    assert!(rows[0].metrics[0].is_some_and(|p| p > 0.0));
    for r in &rows[2..] {
        assert_eq!(r.status, Status::Failed);
        assert!(
            r.error.contains("clearance_joints[0].clearance"),
            "{}",
            r.error
        );
    }
    let csv = std::fs::read_to_string(out.join("samples.csv")).unwrap();
    assert!(csv.starts_with("sample,clearance_joints.rod-slider.clearance,drivers.crank-speed.law.rate,response.joints.rod-slider.max_penetration_m,"), "{csv}");
    assert!(out.join("scatter.png").is_file());
    // The page: the figure embedded byte for byte, a row per sample with its verdict and
    // error, nothing from elsewhere.
    let page = std::fs::read_to_string(out.join("samples.html")).unwrap();
    let scatter = std::fs::read(out.join("scatter.png")).unwrap();
    assert!(page.contains(&output::html::data_uri("image/png", &scatter)));
    let ok = rows.iter().filter(|r| r.status == Status::Ok).count();
    assert_eq!(page.matches("<td class=\"ok\">ok</td>").count(), ok);
    assert_eq!(
        page.matches("<td class=\"bad\">failed</td>").count(),
        4 - ok
    );
    assert!(page.contains(&format!("{ok} of 4 rows ran, {} failed", 4 - ok)));
    for r in &rows {
        assert!(page.contains(&output::html::escape(&r.error)));
    }
    assert!(!page.contains("http://") && !page.contains("https://"));
    std::fs::remove_dir_all(&out).unwrap();
}

/// The CSV without its last column (wall time).
fn without_wall_time(text: &str) -> String {
    text.lines()
        .map(|l| l.rsplit_once(',').map_or(l, |(a, _)| a).to_string())
        .collect::<Vec<_>>()
        .join("\n")
}

#[test]
fn threads_one_by_one_and_resume_give_the_same_file() {
    let s = Sweep::from_str(RANDOM, "r").unwrap();
    let (a, b) = (fresh_dir("a"), fresh_dir("b"));
    let two = sweep::run_local(
        &s,
        &a,
        &LocalOptions {
            jobs: 2,
            resume: false,
        },
        None,
        &mut |_, _, _| {},
    )
    .unwrap();
    assert!(a.join("histograms.png").is_file());
    // One sample at a time, as Dask tasks do, rows through JSON, written by the one writer.
    let mut rows: Vec<_> = (0..5)
        .rev()
        .map(|k| {
            let row = Sweep::from_plan(&s.plan())
                .unwrap()
                .try_run_sample(k)
                .unwrap();
            sweep::Row::from_json(&row.to_json()).unwrap()
        })
        .collect();
    for (x, y) in rows.iter().rev().zip(&two) {
        assert_eq!(
            (x.sample, &x.inputs, &x.metrics, x.status),
            (y.sample, &y.inputs, &y.metrics, y.status)
        );
    }
    sweep::write_outputs(&s, &rows, &b).unwrap();
    let text = |d: &PathBuf| std::fs::read_to_string(d.join("samples.csv")).unwrap();
    assert_eq!(without_wall_time(&text(&a)), without_wall_time(&text(&b)));
    // Resume: keep two rows, run the other three only.
    rows.retain(|r| r.sample % 2 == 1);
    sweep::table::write_rows(&s, &rows, &b.join("samples.csv")).unwrap();
    let (_, mut ran) = resume(&s, &b);
    ran.sort_unstable();
    assert_eq!(ran, vec![0, 2, 4]);
    assert_eq!(without_wall_time(&text(&a)), without_wall_time(&text(&b)));
    // Another sweep's file is not resumed.
    let other = Sweep::from_str(&RANDOM.replace("seed = 11", "seed = 3"), "r").unwrap();
    let e = sweep::pending(&other, &b, true).unwrap_err();
    assert!(matches!(e, SweepError::Resume { .. }), "{e}");
    std::fs::remove_dir_all(&a).unwrap();
    std::fs::remove_dir_all(&b).unwrap();
}

#[test]
fn scene_tables_parse_to_the_scenes_the_command_line_loads() {
    for b in lgres::scenes::BUILTINS {
        let table = scene::merged_table(b.source, b.name, None, lgres::scenes::BUILTINS).unwrap();
        let from_table = scene::from_table(table, b.name).unwrap();
        assert_eq!(
            from_table,
            lgres::scenes::builtin(b.name).unwrap(),
            "{}",
            b.name
        );
    }
}

#[test]
fn paths_address_named_elements() {
    let mut t = scene::merged_table(
        lgres::scenes::source("lgres").unwrap(),
        "lgres",
        None,
        lgres::scenes::BUILTINS,
    )
    .unwrap();
    sweep::path::set(
        &mut t,
        "clearance_joints.B.wear.k_d",
        toml::Value::Float(2e-13),
    )
    .unwrap();
    sweep::path::set(&mut t, "drivers.drive.law.rpm", toml::Value::Float(45.0)).unwrap();
    sweep::path::set(&mut t, "bodies[1].mass", toml::Value::Float(13.0)).unwrap();
    let s = scene::from_table(t.clone(), "x").unwrap();
    assert_eq!(s.clearance_joints[1].wear.as_ref().unwrap().k_d, 2e-13);
    assert_eq!(s.bodies[1].mass, 13.0);
    let e = sweep::path::set(
        &mut t,
        "clearance_joints.C.clearance",
        toml::Value::Float(1.0),
    )
    .unwrap_err();
    assert!(e.contains("names: A, B"), "{e}");
    // The same for an element set whole.
    let e = sweep::path::set(&mut t, "bodies.9", toml::Value::Float(1.0)).unwrap_err();
    assert!(
        e.starts_with("bodies has no element \"9\" (names: rod1, rod2, rod3"),
        "{e}"
    );
    let summary = sweep::path::summary_value(&serde_json::json!({"wear": {"joints": [{"name": "A", "d": 1.5}, {"name": "B", "d": null}]}})).unwrap();
    assert_eq!(
        sweep::path::number(&summary, "wear.joints.A.d"),
        Ok(Some(1.5))
    );
    assert_eq!(sweep::path::number(&summary, "wear.joints[1].d"), Ok(None));
    assert!(sweep::path::number(&summary, "wear.joints.C.d").is_err());
}
