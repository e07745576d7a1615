//! Output writers leave complete files only; every figure renders a PNG of the asked size.

mod common;

use std::f64::consts::TAU;
use std::path::{Path, PathBuf};

use output::files::{self, AtomicFile, Cell, Column, CsvWriter};
use output::plot::{self, DEFAULT_SIZE, Figure, Series, WornOutlines};

fn temp_dir(tag: &str) -> PathBuf {
    common::temp_dir("output", tag)
}

/// Width and height from a PNG's IHDR chunk.
fn png_size(path: &Path) -> (u32, u32) {
    let bytes = std::fs::read(path).unwrap();
    assert!(bytes.len() > 1000, "{} is nearly empty", path.display());
    assert_eq!(&bytes[1..4], b"PNG");
    let be = |k: usize| u32::from_be_bytes(bytes[k..k + 4].try_into().unwrap());
    (be(16), be(20))
}

fn only_file(dir: &Path) -> Vec<String> {
    let mut names: Vec<String> = std::fs::read_dir(dir)
        .unwrap()
        .map(|e| e.unwrap().file_name().to_string_lossy().into_owned())
        .collect();
    names.sort();
    names
}

#[test]
fn csv_has_units_and_appears_only_when_finished() {
    let dir = temp_dir("csv");
    let path = dir.join("sub/series.csv");
    let cols = [
        Column {
            name: "t",
            unit: "s",
        },
        Column {
            name: "y3",
            unit: "m",
        },
    ];
    let mut w = CsvWriter::create(&path, &cols).unwrap();
    w.row(&[0.0, 1.5]).unwrap();
    assert!(w.row(&[1.0]).is_err());
    assert!(!path.exists(), "visible before finish");
    w.finish().unwrap();
    let text = std::fs::read_to_string(&path).unwrap();
    assert_eq!(text.lines().next(), Some("t [s],y3 [m]"));
    assert_eq!(text.lines().count(), 2);

    // Labels and counts next to numbers (numbers as `row` writes them); one cell per column.
    let mut w = CsvWriter::create(&path, &cols).unwrap();
    w.record(&[Cell::Text("joint, A"), Cell::Number(2.5e-6)])
        .unwrap();
    w.record(&[Cell::Count(3), Cell::Number(0.0)]).unwrap();
    assert!(w.record(&[Cell::Count(3)]).is_err());
    w.finish().unwrap();
    let text = std::fs::read_to_string(&path).unwrap();
    assert_eq!(
        text.lines().collect::<Vec<_>>(),
        ["t [s],y3 [m]", "\"joint, A\",2.5e-6", "3,0e0"]
    );

    files::write_csv(&path, &[(cols[0], &[0.0, 1.0]), (cols[1], &[2.0, 3.0])]).unwrap();
    assert_eq!(std::fs::read_to_string(&path).unwrap().lines().count(), 3);
    assert!(files::write_csv(&path, &[(cols[0], &[0.0, 1.0]), (cols[1], &[2.0])]).is_err());
    assert_eq!(only_file(&dir.join("sub")), ["series.csv"]);
    std::fs::remove_dir_all(&dir).unwrap();
}

#[test]
fn abandoned_file_leaves_nothing_and_old_file_survives() {
    let dir = temp_dir("atomic");
    let path = dir.join("summary.json");
    files::write_json(&path, &serde_json::json!({"peak_force_N": 1.0})).unwrap();
    {
        use std::io::Write;
        let mut f = AtomicFile::create(&path).unwrap();
        f.write_all(b"{\"half").unwrap();
        // Dropped without commit: an error or interruption part-way.
    }
    let v: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(&path).unwrap()).unwrap();
    assert_eq!(v["peak_force_N"], 1.0);
    assert_eq!(only_file(&dir), ["summary.json"]);
    std::fs::remove_dir_all(&dir).unwrap();
}

#[test]
fn every_plot_renders_a_png_of_the_right_size() {
    let dir = temp_dir("plot");
    let t: Vec<f64> = (0..=1000).map(|k| f64::from(k) * 1e-3).collect();
    let y: Vec<f64> = t.iter().map(|t| 0.1 * (TAU * t).sin()).collect();
    let z: Vec<f64> = t.iter().map(|t| 0.08 * (TAU * t).cos()).collect();
    let fig = Figure {
        title: "Rod 3 centroid",
        x_label: "t (s)",
        y_label: "displacement (m)",
        size: (800, 500),
    };
    let lines = dir.join("lines.png");
    plot::line_chart(
        &lines,
        &fig,
        &[
            Series {
                label: "clearance",
                x: &t,
                y: &y,
            },
            Series {
                label: "ideal",
                x: &t,
                y: &z,
            },
        ],
    )
    .unwrap();
    assert_eq!(png_size(&lines), (800, 500));

    let n = 1000;
    let bearing: Vec<f64> = (0..n)
        .map(|k| {
            let a = sim::surfaces::cell_angle_deg(k, n).to_radians();
            1e-4 * (-(a - 2.3).powi(2) / 0.1).exp()
        })
        .collect();
    let pin: Vec<f64> = bearing.iter().rev().map(|h| 0.5 * h).collect();
    let depth = dir.join("depth.png");
    plot::wear_depth(
        &depth,
        "Wear at A",
        (700, 400),
        &[("bearing", &bearing), ("pin", &pin)],
    )
    .unwrap();
    assert_eq!(png_size(&depth), (700, 400));

    let outline = dir.join("outline.png");
    let joint = WornOutlines {
        bearing_radius: 0.05,
        pin_radius: 0.0495,
        bearing_wear: &bearing,
        pin_wear: &pin,
        exaggeration: 50.0,
    };
    plot::worn_outline(&outline, "Worn joint A", (800, 600), &joint).unwrap();
    assert_eq!(png_size(&outline), (800, 600));

    let (ex, ey): (Vec<f64>, Vec<f64>) = t
        .iter()
        .map(|t| {
            let r = 5e-4 * (1.0 - (-20.0 * t).exp());
            (r * (9.0 * t).cos(), r * (9.0 * t).sin())
        })
        .unzip();
    let path = dir.join("journal.png");
    plot::journal_path(&path, "Journal centre at A", (640, 480), &ex, &ey, 5e-4).unwrap();
    assert_eq!(png_size(&path), (640, 480));

    let cycles = [0.0, 1e5, 4e5, 1e6, 1.5e6, 2e6];
    let bearing = [0.0, 2e-6, 6e-6, 1.2e-5, 1.6e-5, 2e-5];
    let pin = bearing.map(|h| 1.5 * h);
    let clearance: Vec<f64> = bearing
        .iter()
        .zip(&pin)
        .map(|(b, p)| 5e-4 + (b + p) / 2.0)
        .collect();
    let path = dir.join("life.png");
    let curve = output::life_plot::LifeCurve {
        cycles: &cycles,
        bearing_depth: &bearing,
        pin_depth: &pin,
        max_clearance: &clearance,
        noise: [
            &bearing.map(|h| 0.05 * h),
            &pin.map(|h| 0.05 * h),
            &[1e-6; 6],
        ],
        stage_boundaries: &[1e6],
        limit: Some((5.2e-4, Some(1.7e6))),
    };
    output::life_plot::life_curve(&path, "Wear of joint A over its life", (900, 700), &curve)
        .unwrap();
    assert_eq!(png_size(&path), (900, 700));

    // Empty data still gives a readable (empty) chart rather than an error or a panic.
    let empty = dir.join("empty.png");
    plot::line_chart(
        &empty,
        &fig,
        &[Series {
            label: "none",
            x: &[],
            y: &[],
        }],
    )
    .unwrap();
    assert_eq!(png_size(&empty), (800, 500));

    let names = only_file(&dir);
    assert!(
        names.iter().all(|n| !n.starts_with('.')),
        "temp files left: {names:?}"
    );
    if std::env::var_os("LGRES_KEEP_PLOTS").is_none() {
        std::fs::remove_dir_all(&dir).unwrap();
    }
}

/// Rows of a CSV file without its header, split at commas (no quoted cells here).
fn csv_rows(path: &Path) -> (String, Vec<Vec<String>>) {
    let text = std::fs::read_to_string(path).unwrap();
    let mut lines = text.lines();
    let header = lines.next().unwrap().to_string();
    let rows = lines
        .map(|l| l.split(',').map(str::to_string).collect())
        .collect();
    (header, rows)
}

/// A short worn run (the slider-crank with wear on its clearance joint: 1 response cycle, two
/// stages of K = 2 cycles) writes the life curve of its joint: one row at 0 cycles with the
/// unworn values and one per sub-step, cycles increasing to the total the stages applied, and
/// its figure; the clearance limit is reached where the rows straddle it.
#[test]
fn short_worn_run_writes_the_life_curve_and_its_figure() {
    let text = common::worn_slider_crank("", 1, 2, "clearance_limit = 0.000505\n");
    let scene = scene::load_str(&text, "life", lgres::scenes::BUILTINS).unwrap();
    let outcome = sim::run_scene("life", &scene, &Default::default(), &mut ()).unwrap();
    let dir = temp_dir("life");
    let files = output::write_run(&outcome, &dir).unwrap();
    // Every file the run lists exists, and the folder holds nothing it does not list.
    let mut listed: Vec<String> = files
        .iter()
        .map(|f| f.file_name().unwrap().to_string_lossy().into_owned())
        .collect();
    listed.sort();
    assert_eq!(listed, only_file(&dir));
    for name in ["wear_life.csv", "wear_life_rod-slider.png"] {
        assert!(
            listed.iter().any(|n| n == name),
            "{name} not listed: {listed:?}"
        );
    }
    assert_eq!(
        png_size(&dir.join("wear_life_rod-slider.png")),
        DEFAULT_SIZE
    );

    let wear = outcome.summary.wear.as_ref().expect("stages ran");
    let (header, rows) = csv_rows(&dir.join("wear_life.csv"));
    assert_eq!(
        header,
        "joint [-],stage [1],substep [1],cycles [1],bearing_peak_depth [m],pin_peak_depth [m],\
         worn_volume [m^3],max_local_clearance [m],wear_stiffness [1]"
    );
    let substeps: usize = wear.substeps_per_stage.iter().sum();
    assert!(substeps >= 2, "{substeps} sub-steps");
    assert_eq!(rows.len(), substeps + 1);
    let number = |row: &[String], k: usize| row[k].parse::<f64>().unwrap();
    let first = &rows[0];
    assert_eq!(first[..4], ["rod-slider", "0", "0", "0e0"]);
    for k in 4..7 {
        assert_eq!(number(first, k), 0.0, "unworn column {k}");
    }
    let c0 = scene.clearance_joints[0].clearance;
    assert!((number(first, 7) - c0).abs() < 1e-15, "{first:?}");
    // The start applied no update; every sub-step reports a finite, non-negative aλ.
    assert_eq!(number(first, 8), 0.0);
    assert!(
        rows[1..]
            .iter()
            .all(|r| number(r, 8).is_finite() && number(r, 8) >= 0.0),
        "{rows:?}"
    );
    // Stages and sub-steps count from 1 in order; cycles and wear grow.
    let mut expected = (1, 1);
    for pair in rows.windows(2) {
        let (a, b) = (&pair[0], &pair[1]);
        assert!(
            number(b, 3) > number(a, 3),
            "cycles not increasing: {a:?} then {b:?}"
        );
        for k in 6..8 {
            assert!(number(b, k) >= number(a, k), "column {k}: {a:?} then {b:?}");
        }
        let at: (usize, usize) = (b[1].parse().unwrap(), b[2].parse().unwrap());
        if at.0 != expected.0 {
            expected = (expected.0 + 1, 1);
        }
        assert_eq!(at, expected, "{b:?}");
        expected.1 += 1;
    }
    // Each stage adds the cycles it applied: all of its K x amplification, or what it applied
    // before the validity limits; the last row is the run's total.
    let mut before = 0.0;
    for stage in 1..=wear.stages as usize {
        let end = rows
            .iter()
            .filter(|r| r[1] == stage.to_string())
            .map(|r| number(r, 3))
            .next_back()
            .unwrap_or(before);
        let applied =
            wear.cycles_applied_at_limits[stage - 1].unwrap_or(wear.cycles_represented_per_stage);
        assert!(
            (end - before - applied).abs() <= 1e-9 * applied,
            "stage {stage}: {} cycles, expected {applied}",
            end - before
        );
        before = end;
    }
    assert_eq!(number(rows.last().unwrap(), 3), wear.cycles_applied);
    // The last row is the summary's final state.
    let joint = &wear.joints[0];
    let last = rows.last().unwrap();
    assert_eq!(number(last, 4), joint.bearing_peak_depth_m);
    assert_eq!(number(last, 5), joint.pin_peak_depth_m);
    assert_eq!(number(last, 7), joint.max_local_clearance_m);

    // The limit, c0 + 5 µm, lies between two rows: the summary interpolates between them.
    let limit = joint
        .clearance_limit
        .as_ref()
        .expect("run.clearance_limit is set");
    assert_eq!(limit.limit_m, 0.000505);
    let k = rows
        .iter()
        .position(|r| number(r, 7) >= 0.000505)
        .expect("this run wears more than 5 µm");
    assert!(k > 0);
    let (x0, y0, x1, y1) = (
        number(&rows[k - 1], 3),
        number(&rows[k - 1], 7),
        number(&rows[k], 3),
        number(&rows[k], 7),
    );
    let by_hand = x0 + (0.000505 - y0) * (x1 - x0) / (y1 - y0);
    let cycles = limit.cycles.expect("reached");
    assert!(
        (cycles - by_hand).abs() <= 1e-9 * by_hand,
        "{cycles} vs {by_hand}"
    );
    assert!(limit.message.starts_with("reached after"), "{limit:?}");
    let json = std::fs::read_to_string(dir.join("summary.json")).unwrap();
    let summary: serde_json::Value = serde_json::from_str(&json).unwrap();
    let reported = &summary["wear"]["joints"][0]["clearance_limit"];
    assert_eq!(reported["cycles"].as_f64(), Some(cycles));

    // Out of reach: null and the words; without a limit: no entry at all.
    let far = scene
        .clone()
        .edit("far", |far| {
            far.run.clearance_limit = Some(0.01);
            far.run.wear_stages = 1;
            // A stage of 40 000 cycles that ends early at the line-of-centres contact's
            // validity limits: the curve ends at exactly the cycles the stage applied.
            far.run.amplification = 20_000.0;
            for joint in &mut far.clearance_joints {
                joint.contact = scene::ContactSpec::line_of_centres();
            }
        })
        .unwrap();
    let outcome = sim::run_scene("far", &far, &Default::default(), &mut ()).unwrap();
    let wear = outcome.summary.wear.as_ref().unwrap();
    let applied = wear.cycles_applied_at_limits[0].expect("ends at the validity limits");
    let life = &outcome.wear[0].life;
    assert_eq!(life.last().unwrap().cycles, applied);
    assert_eq!(wear.cycles_applied, applied);
    let joint = &wear.joints[0];
    let limit = joint.clearance_limit.as_ref().unwrap();
    assert_eq!(limit.cycles, None);
    assert_eq!(limit.message, "not reached within the run");
    let value = serde_json::to_value(&outcome.summary).unwrap();
    assert!(value["wear"]["joints"][0]["clearance_limit"]["cycles"].is_null());
    let none = far
        .edit("none", |none| {
            none.run.clearance_limit = None;
            none.run.wear_stages = 0;
        })
        .unwrap();
    let outcome = sim::run_scene("none", &none, &Default::default(), &mut ()).unwrap();
    let files = output::write_run(&outcome, &dir.join("none")).unwrap();
    assert!(
        files
            .iter()
            .all(|f| !f.to_string_lossy().contains("wear_life")),
        "a run without stages writes no life curve: {files:?}"
    );
    std::fs::remove_dir_all(&dir).unwrap();
}
