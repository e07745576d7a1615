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
    // The JSON form keeps the non-finite number apart from a null.
    let json = sweep::path::summary_json(&summary(f64::NEG_INFINITY)).unwrap();
    let got = sweep::path::number(&json, "response.energy_residual_j").unwrap();
    assert_eq!(got, Some(f64::NEG_INFINITY));
    assert_eq!(sweep::path::number(&json, "response.numerics"), Ok(None));
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
fn finite_summaries_are_the_json_serde_json_makes() {
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
    assert_eq!(
        sweep::path::summary_json(&rich).unwrap(),
        serde_json::to_value(&rich).unwrap()
    );
}
