//! A NaN or infinity in a sample's summary is a failed metric, not a missing value: serde_json
//! would make it `null`, which reads as "no number here" and left the row `ok`.

use serde::Serialize;
use sweep::Sweep;

const ONE: &str = r#"
scene = "slider-crank"
metrics = ["response.energy_residual_j", "response.numerics"]
[[vary]]
path = "clearance_joints.rod-slider.clearance"
values = [4e-4]
"#;

#[derive(Serialize)]
struct Summary {
    response: Response,
}

#[derive(Serialize)]
struct Response {
    energy_residual_j: f64,
    numerics: Option<f64>,
}

#[test]
fn a_non_finite_metric_in_the_summary_is_a_sample_error_not_a_missing_value() {
    let s = Sweep::from_str(ONE, "m").unwrap();
    let summary = |e: f64| Summary {
        response: Response {
            energy_residual_j: e,
            numerics: None,
        },
    };
    assert_eq!(
        s.metrics_of_summary(&summary(1.5)).unwrap(),
        vec![Some(1.5), None]
    );
    for (v, shown) in [(f64::NAN, "NaN"), (f64::INFINITY, "inf")] {
        let e = s.metrics_of_summary(&summary(v)).unwrap_err().to_string();
        assert_eq!(
            e,
            format!("metric response.energy_residual_j is not finite ({shown})")
        );
    }
    // The tree the metrics are read from keeps the non-finite number apart from a null.
    let tree = sweep::path::summary_value(&summary(f64::NEG_INFINITY)).unwrap();
    let got = sweep::path::number(&tree, "response.energy_residual_j").unwrap();
    assert_eq!(got, Some(f64::NEG_INFINITY));
    assert_eq!(sweep::path::number(&tree, "response.numerics"), Ok(None));
}

#[derive(Serialize)]
#[serde(tag = "kind", rename_all = "kebab-case")]
enum Law {
    Ramp { rate: f64 },
    Fixed,
}

#[derive(Serialize)]
enum Shape {
    Circle(f64),
    Pair(f64, f64),
    Box { w: f64 },
    Empty,
}

#[derive(Serialize)]
struct Rich {
    law: Law,
    fixed: Law,
    shapes: Vec<Shape>,
    by_index: std::collections::BTreeMap<u32, (String, Option<f64>)>,
    unit: (),
    flag: bool,
    small: f32,
    big: u64,
    negative: i8,
    letter: char,
}

#[test]
fn finite_summaries_read_the_numbers_their_json_holds() {
    let rich = Rich {
        law: Law::Ramp { rate: 523.5988 },
        fixed: Law::Fixed,
        shapes: vec![
            Shape::Circle(0.5),
            Shape::Pair(1.0, 2.0),
            Shape::Box { w: 3.0 },
            Shape::Empty,
        ],
        by_index: [(1, ("a".to_string(), Some(1e-9))), (2, ("b".into(), None))]
            .into_iter()
            .collect(),
        unit: (),
        flag: true,
        small: 0.25,
        big: u64::MAX,
        negative: -3,
        letter: 'x',
    };
    // Every number the JSON holds (objects by key, arrays by index), read from the tree by its
    // path, is the JSON's: serde_json is the independent reader here.
    let json = serde_json::to_value(&rich).unwrap();
    let tree = sweep::path::summary_value(&rich).unwrap();
    let mut leaves = Vec::new();
    numbers("", &json, &mut leaves);
    assert_eq!(leaves.len(), 12, "{leaves:?}");
    for (path, expected) in leaves {
        assert_eq!(sweep::path::number(&tree, &path), Ok(expected), "{path}");
    }
    assert!(sweep::path::number(&tree, "letter").is_err());
}

/// Every number, boolean and null below `value`, with its dotted path, as `number` reads it.
fn numbers(path: &str, value: &serde_json::Value, out: &mut Vec<(String, Option<f64>)>) {
    let join = |key: &str| {
        if path.is_empty() {
            key.to_string()
        } else {
            format!("{path}.{key}")
        }
    };
    match value {
        serde_json::Value::Object(m) => m.iter().for_each(|(k, v)| numbers(&join(k), v, out)),
        serde_json::Value::Array(a) => a
            .iter()
            .enumerate()
            .for_each(|(k, v)| numbers(&join(&k.to_string()), v, out)),
        serde_json::Value::Number(n) => out.push((path.to_string(), n.as_f64())),
        serde_json::Value::Bool(b) => out.push((path.to_string(), Some(f64::from(u8::from(*b))))),
        serde_json::Value::Null => out.push((path.to_string(), None)),
        serde_json::Value::String(_) => {}
    }
}

/// A row stored `ok` with a NaN metric (an older version's file, or an edited one) is failed
/// wherever it is shown: in its cell, in the page's count and out of the figures.
#[test]
fn an_ok_row_with_a_nan_metric_counts_as_failed_on_the_page() {
    let s = Sweep::from_str(ONE, "m").unwrap();
    let row = |sample: usize, metric: f64| sweep::Row {
        sample,
        inputs: vec![4e-4],
        metrics: vec![Some(metric), None],
        status: sweep::Status::Ok,
        error: String::new(),
        wall_time_s: 0.0,
    };
    let rows = [row(0, 1.5), row(1, f64::NAN)];
    assert_eq!(rows[1].written_status(), sweep::Status::Failed);
    let out = std::env::temp_dir().join(format!("sweep-nan-page-{}", std::process::id()));
    std::fs::create_dir_all(&out).unwrap();
    let page = sweep::page::write_page(&s, &rows, &[], None, &out).unwrap();
    let html = std::fs::read_to_string(page).unwrap();
    assert!(html.contains("1 of 2 rows ran, 1 failed"), "{html}");
    std::fs::remove_dir_all(&out).unwrap();
}
