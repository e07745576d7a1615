//! The figures of a sweep: every metric against every varied input (`scatter.png`, one panel
//! each; a metric's noise, when the sweep keeps it too, as bars of ± one noise on the metric's
//! points rather than as panels of its own), and for random sweeps the histograms of inputs
//! and metrics, noises left out (`histograms.png`). Failed samples and missing metrics are
//! left out of the panels.

use std::path::{Path, PathBuf};

use output::files::OutputError;
use output::plot::{DrawResult, FONT, padded_range, render};
use plotters::coord::Shift;
use plotters::prelude::*;

use crate::{Mode, Row, Status, Sweep};

const BLUE: RGBColor = RGBColor(0, 114, 178);
const PANEL: (u32, u32) = (520, 400);

/// Grid of `n` panels: columns, rows.
fn grid(n: usize, columns: usize) -> (usize, usize) {
    let c = columns.clamp(1, n.max(1));
    (c, n.div_ceil(c).max(1))
}

/// Short axis label: from a joint's name on (`A.clearance_limit.cycles`), else the last two
/// path segments (`mechanism.b50_cycles`).
fn short(name: &str) -> String {
    let parts: Vec<&str> = name.split('.').collect();
    let from = parts
        .iter()
        .position(|p| *p == "joints")
        .map_or(parts.len().saturating_sub(2), |k| k + 1);
    parts[from.min(parts.len().saturating_sub(1))..].join(".")
}

/// The metric whose noise `name` is, if the sweep keeps it: a metric whose last path segment
/// holds `_noise` (`…clearance_limit.cycles_noise`, `…bearing_peak_depth_noise_m`) is the noise
/// of the same name without it (`…cycles`, `…bearing_peak_depth_m`).
fn noise_of(name: &str, metrics: &[String]) -> Option<usize> {
    let (path, last) = name.rsplit_once('.').map_or(("", name), |(p, l)| (p, l));
    let at = last.find("_noise")?;
    let base_last = format!("{}{}", &last[..at], &last[at + "_noise".len()..]);
    let base = if path.is_empty() {
        base_last
    } else {
        format!("{path}.{base_last}")
    };
    metrics.iter().position(|m| *m == base)
}

/// Per metric, the metric it is the noise of ([`noise_of`]), if any: such a metric is drawn as
/// its metric's error bars, not as a panel or histogram of its own.
fn noise_pairs(metrics: &[String]) -> Vec<Option<usize>> {
    metrics.iter().map(|m| noise_of(m, metrics)).collect()
}

/// The scatter figure's file name.
pub const SCATTER_FILE: &str = "scatter.png";
/// The histograms' file name (random sweeps).
pub const HISTOGRAMS_FILE: &str = "histograms.png";

/// Draw the figures of `rows` into `out`; returns the files written.
pub fn draw(sweep: &Sweep, rows: &[Row], out: &Path) -> Result<Vec<PathBuf>, OutputError> {
    let ok: Vec<&Row> = rows
        .iter()
        .filter(|r| r.written_status() == Status::Ok)
        .collect();
    let mut files = Vec::new();
    let ni = sweep.inputs.len();
    let noise_metrics = noise_pairs(&sweep.metrics);
    let panels: Vec<(usize, Option<usize>)> = (0..sweep.metrics.len())
        .filter(|m| noise_metrics[*m].is_none())
        .map(|m| (m, noise_metrics.iter().position(|n| *n == Some(m))))
        .collect();
    let (cols, nrows) = (ni, panels.len());
    let path = out.join(SCATTER_FILE);
    let size = (PANEL.0 * cols as u32, PANEL.1 * nrows as u32 + 40);
    let title = format!(
        "Sweep {}: {} of {} samples ran (scene {})",
        sweep.name,
        ok.len(),
        rows.len(),
        sweep.scene_name
    );
    render(&path, size, |root| {
        let (top, body) = root.split_vertically(40);
        top.titled(&title, (FONT, 22))?;
        for (k, area) in body.split_evenly((nrows, cols)).iter().enumerate() {
            let ((m, noise), i) = (panels[k / cols], k % cols);
            let points: Vec<(f64, f64)> = ok
                .iter()
                .filter_map(|r| Some((r.inputs[i], r.metrics[m]?)))
                .collect();
            // ± one noise where the sample has it (finite and positive).
            let bars: Vec<(f64, f64, f64)> = noise.map_or_else(Vec::new, |n| {
                ok.iter()
                    .filter_map(|r| {
                        let (v, e) = (r.metrics[m]?, r.metrics[n]?);
                        (e.is_finite() && e > 0.0).then_some((r.inputs[i], v - e, v + e))
                    })
                    .collect()
            });
            let mut chart = ChartBuilder::on(area)
                .margin(10)
                .x_label_area_size(45)
                .y_label_area_size(75)
                .build_cartesian_2d(
                    padded_range(points.iter().map(|p| p.0)),
                    padded_range(
                        points
                            .iter()
                            .map(|p| p.1)
                            .chain(bars.iter().flat_map(|b| [b.1, b.2])),
                    ),
                )?;
            chart
                .configure_mesh()
                .x_desc(short(&sweep.inputs[i].name))
                .y_desc(if noise.is_some() {
                    format!("{} (± noise)", short(&sweep.metrics[m]))
                } else {
                    short(&sweep.metrics[m])
                })
                .x_labels(5)
                .x_label_formatter(&|v| format!("{v:.3e}"))
                .y_label_formatter(&|v| format!("{v:.3e}"))
                .label_style((FONT, 13))
                .axis_desc_style((FONT, 14))
                .light_line_style(RGBColor(235, 235, 235))
                .draw()?;
            chart
                .draw_series(bars.iter().map(|b| {
                    PathElement::new(vec![(b.0, b.1), (b.0, b.2)], BLUE.stroke_width(2))
                }))?;
            chart.draw_series(points.iter().map(|p| Circle::new(*p, 4, BLUE.filled())))?;
        }
        Ok(())
    })?;
    files.push(path);

    if matches!(sweep.mode, Mode::Random { .. }) {
        let columns = histogram_columns(sweep, &noise_metrics, &ok);
        let (c, r) = grid(columns.len(), 3);
        let path = out.join(HISTOGRAMS_FILE);
        let title = format!(
            "Sweep {}: histograms of {} samples that ran",
            sweep.name,
            ok.len()
        );
        render(
            &path,
            (PANEL.0 * c as u32, PANEL.1 * r as u32 + 40),
            |root| {
                let (top, body) = root.split_vertically(40);
                top.titled(&title, (FONT, 22))?;
                for (area, (name, values)) in body.split_evenly((r, c)).iter().zip(&columns) {
                    histogram(area, name, values)?;
                }
                Ok(())
            },
        )?;
        files.push(path);
    }
    Ok(files)
}

/// The histograms' columns: every input, and every metric that is not another's noise (a
/// noise is the error bar of its metric's points, not a distribution of interest);
/// `noise_metrics[m]`: the metric that metric `m` is the noise of ([`noise_of`]).
fn histogram_columns(
    sweep: &Sweep,
    noise_metrics: &[Option<usize>],
    ok: &[&Row],
) -> Vec<(String, Vec<f64>)> {
    let inputs = sweep
        .inputs
        .iter()
        .enumerate()
        .map(|(i, input)| (input.name.clone(), ok.iter().map(|r| r.inputs[i]).collect()));
    let metrics = sweep
        .metrics
        .iter()
        .enumerate()
        .filter(|(m, _)| noise_metrics[*m].is_none())
        .map(|(m, name)| {
            (
                name.clone(),
                ok.iter().filter_map(|r| r.metrics[m]).collect(),
            )
        });
    inputs.chain(metrics).collect()
}

fn histogram(
    area: &DrawingArea<BitMapBackend<'_>, Shift>,
    name: &str,
    values: &[f64],
) -> DrawResult {
    let finite: Vec<f64> = values.iter().copied().filter(|v| v.is_finite()).collect();
    let bins = ((finite.len() as f64).sqrt().ceil() as usize).clamp(1, 30);
    let (lo, hi) = finite
        .iter()
        .fold((f64::INFINITY, f64::NEG_INFINITY), |(a, b), v| {
            (a.min(*v), b.max(*v))
        });
    let (lo, hi) = if lo > hi {
        (0.0, 1.0)
    } else if hi > lo {
        (lo, hi)
    } else {
        (
            lo - 0.5 * lo.abs().max(1e-300),
            hi + 0.5 * hi.abs().max(1e-300),
        )
    };
    let width = (hi - lo) / bins as f64;
    let mut counts = vec![0u32; bins];
    for v in &finite {
        let k = (((v - lo) / width) as usize).min(bins - 1);
        counts[k] += 1;
    }
    let top = counts.iter().copied().max().unwrap_or(0).max(1);
    let mut chart = ChartBuilder::on(area)
        .margin(10)
        .x_label_area_size(45)
        .y_label_area_size(50)
        .build_cartesian_2d(lo..hi, 0u32..top + 1)?;
    chart
        .configure_mesh()
        .x_desc(short(name))
        .y_desc("samples")
        .x_labels(5)
        .x_label_formatter(&|v| format!("{v:.3e}"))
        .label_style((FONT, 13))
        .axis_desc_style((FONT, 14))
        .light_line_style(RGBColor(235, 235, 235))
        .draw()?;
    chart.draw_series(counts.iter().enumerate().map(|(k, c)| {
        let x0 = lo + width * k as f64;
        Rectangle::new([(x0, 0), (x0 + width, *c)], BLUE.mix(0.7).filled())
    }))?;
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::{histogram_columns, noise_of, noise_pairs};
    use crate::{Row, Status, Sweep};

    #[test]
    fn histograms_leave_a_kept_noise_out() {
        let sweep = Sweep::from_str(
            r#"
scene = "lgres"
metrics = ["wear.joints.A.bearing_peak_depth_m", "wear.joints.A.bearing_peak_depth_noise_m"]
[[vary]]
path = "run.cycles"
values = [1, 2]
"#,
            "h",
        )
        .expect("a valid sweep");
        let row = Row {
            sample: 0,
            inputs: vec![1.0],
            metrics: vec![Some(3.6e-4), Some(5e-6)],
            status: Status::Ok,
            error: String::new(),
            wall_time_s: 1.0,
        };
        let names: Vec<String> = histogram_columns(&sweep, &noise_pairs(&sweep.metrics), &[&row])
            .into_iter()
            .map(|(name, _)| name)
            .collect();
        assert_eq!(names, ["run.cycles", "wear.joints.A.bearing_peak_depth_m"]);
    }

    #[test]
    fn a_noise_metric_finds_the_metric_it_is_the_noise_of() {
        let metrics: Vec<String> = [
            "wear.joints.A.clearance_limit.cycles",
            "wear.joints.A.clearance_limit.cycles_noise",
            "wear.joints.B.bearing_peak_depth_m",
            "wear.joints.B.bearing_peak_depth_noise_m",
            "wear.joints.A.bearing_peak_depth_noise_m",
            "noise",
        ]
        .map(String::from)
        .to_vec();
        assert_eq!(noise_of(&metrics[1], &metrics), Some(0));
        assert_eq!(noise_of(&metrics[3], &metrics), Some(2));
        // Its metric not kept by the sweep: a panel of its own.
        assert_eq!(noise_of(&metrics[4], &metrics), None);
        // Not a noise, or a segment that only looks like one.
        assert_eq!(noise_of(&metrics[0], &metrics), None);
        assert_eq!(noise_of(&metrics[5], &metrics), None);
        assert_eq!(noise_of("wear.noise_total.x", &metrics), None);
    }
}
