//! Output writers leave complete files only; every figure renders a PNG of the asked size.

use std::f64::consts::TAU;
use std::path::{Path, PathBuf};

use lgres::io::output::{self, AtomicFile, Column, CsvWriter};
use lgres::io::plot::{self, Figure, Series, WornJoint};

fn temp_dir(tag: &str) -> PathBuf {
    let dir = std::env::temp_dir().join(format!("lgres-{tag}-{}", std::process::id()));
    let _ = std::fs::remove_dir_all(&dir);
    std::fs::create_dir_all(&dir).unwrap();
    dir
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

    output::write_csv(&path, &[(cols[0], &[0.0, 1.0]), (cols[1], &[2.0, 3.0])]).unwrap();
    assert_eq!(std::fs::read_to_string(&path).unwrap().lines().count(), 3);
    assert!(output::write_csv(&path, &[(cols[0], &[0.0, 1.0]), (cols[1], &[2.0])]).is_err());
    assert_eq!(only_file(&dir.join("sub")), ["series.csv"]);
    std::fs::remove_dir_all(&dir).unwrap();
}

#[test]
fn abandoned_file_leaves_nothing_and_old_file_survives() {
    let dir = temp_dir("atomic");
    let path = dir.join("summary.json");
    output::write_json(&path, &serde_json::json!({"peak_force_N": 1.0})).unwrap();
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
            let a = plot::cell_angle_deg(k, n).to_radians();
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
    let joint = WornJoint {
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
