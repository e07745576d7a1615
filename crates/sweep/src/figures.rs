//! The figures of a sweep: every metric against every varied input (`scatter.png`, one panel
//! each), and for random sweeps the histograms of inputs and metrics (`histograms.png`).
//! Failed samples and missing metrics are left out of the panels.

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
    let (ni, nm) = (sweep.inputs.len(), sweep.metrics.len());
    let (cols, nrows) = (ni, nm);
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
            let (m, i) = (k / cols, k % cols);
            let points: Vec<(f64, f64)> = ok
                .iter()
                .filter_map(|r| Some((r.inputs[i], r.metrics[m]?)))
                .collect();
            let mut chart = ChartBuilder::on(area)
                .margin(10)
                .x_label_area_size(45)
                .y_label_area_size(75)
                .build_cartesian_2d(
                    padded_range(points.iter().map(|p| p.0)),
                    padded_range(points.iter().map(|p| p.1)),
                )?;
            chart
                .configure_mesh()
                .x_desc(short(&sweep.inputs[i].name))
                .y_desc(short(&sweep.metrics[m]))
                .x_labels(5)
                .x_label_formatter(&|v| format!("{v:.3e}"))
                .y_label_formatter(&|v| format!("{v:.3e}"))
                .label_style((FONT, 13))
                .axis_desc_style((FONT, 14))
                .light_line_style(RGBColor(235, 235, 235))
                .draw()?;
            chart.draw_series(points.iter().map(|p| Circle::new(*p, 4, BLUE.filled())))?;
        }
        Ok(())
    })?;
    files.push(path);

    if matches!(sweep.mode, Mode::Random { .. }) {
        let mut columns: Vec<(String, Vec<f64>)> = Vec::new();
        for (i, input) in sweep.inputs.iter().enumerate() {
            columns.push((input.name.clone(), ok.iter().map(|r| r.inputs[i]).collect()));
        }
        for (m, metric) in sweep.metrics.iter().enumerate() {
            columns.push((
                metric.clone(),
                ok.iter().filter_map(|r| r.metrics[m]).collect(),
            ));
        }
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
