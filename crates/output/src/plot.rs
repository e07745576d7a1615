//! Figures as PNG, written atomically (see [`crate::files`]).
//!
//! Text uses the DejaVu Sans font embedded in the binary, so figures render the same on a
//! machine without system fonts.

use std::error::Error;
use std::f64::consts::TAU;
use std::ops::Range;
use std::path::Path;
use std::sync::Once;

use plotters::coord::{CoordTranslate, Shift};
use plotters::prelude::*;
use plotters::style::{FontStyle, register_font};

use crate::files::{OutputError, write_via_temp};
use sim::surfaces::cell_angle_deg;

/// Default figure size, pixels.
pub const DEFAULT_SIZE: (u32, u32) = (1000, 650);

/// Colour-blind-safe series colours (Okabe–Ito), cycled.
const COLOURS: [RGBColor; 7] = [
    RGBColor(0, 114, 178),
    RGBColor(213, 94, 0),
    RGBColor(0, 158, 115),
    RGBColor(204, 121, 167),
    RGBColor(230, 159, 0),
    RGBColor(86, 180, 233),
    RGBColor(0, 0, 0),
];

pub(crate) fn colour(k: usize) -> RGBColor {
    COLOURS[k % COLOURS.len()]
}

/// The compiled-in font family every figure uses (registered by [`render`]).
pub const FONT: &str = "sans-serif";

/// Registers the compiled-in fonts under [`FONT`] (once per process).
pub(crate) fn register_fonts() {
    static ONCE: Once = Once::new();
    ONCE.call_once(|| {
        // The fonts are compiled in and valid; should registration fail anyway, plotters
        // reports the missing font as a drawing error, which is where it is handled.
        let _ = register_font(FONT, FontStyle::Normal, dejavu::sans::regular());
        let _ = register_font(FONT, FontStyle::Bold, dejavu::sans::bold());
    });
}

/// Title, axis labels (with units) and size of a figure.
#[derive(Debug, Clone, Copy)]
pub struct Figure<'a> {
    /// Caption above the plot.
    pub title: &'a str,
    /// Horizontal axis label with unit, e.g. `t (s)`.
    pub x_label: &'a str,
    /// Vertical axis label with unit.
    pub y_label: &'a str,
    /// Width and height, pixels.
    pub size: (u32, u32),
}

/// One curve: legend label and points.
#[derive(Debug, Clone, Copy)]
pub struct Series<'a> {
    /// Legend entry.
    pub label: &'a str,
    /// Abscissae.
    pub x: &'a [f64],
    /// Ordinates (same length as `x`; extra values of either are ignored).
    pub y: &'a [f64],
}

/// What a drawing closure returns: plotters' errors, boxed.
pub type DrawResult = Result<(), Box<dyn Error>>;

/// A legend key: a 24-pixel stroke in `style`.
pub(crate) fn key(style: ShapeStyle) -> impl Fn((i32, i32)) -> PathElement<(i32, i32)> {
    move |(x, y)| PathElement::new(vec![(x, y), (x + 24, y)], style)
}

/// Draws `chart`'s legend: its labels at `font` pixels in a bordered, nearly opaque white box
/// at `position`.
pub(crate) fn draw_legend<'a, CT: CoordTranslate>(
    chart: &mut ChartContext<'a, BitMapBackend<'a>, CT>,
    font: u32,
    position: SeriesLabelPosition,
) -> DrawResult {
    chart
        .configure_series_labels()
        .label_font((FONT, font))
        .background_style(WHITE.mix(0.85))
        .border_style(BLACK)
        .position(position)
        .draw()?;
    Ok(())
}

/// Render with plotters into a temporary file next to `path`, then move it into place: a
/// failed drawing leaves no half-written figure.
pub fn render(
    path: &Path,
    size: (u32, u32),
    draw: impl FnOnce(&DrawingArea<BitMapBackend<'_>, Shift>) -> DrawResult,
) -> Result<(), OutputError> {
    register_fonts();
    write_via_temp(path, |tmp| {
        let root = BitMapBackend::new(tmp, size).into_drawing_area();
        root.fill(&WHITE)
            .map_err(Box::<dyn Error>::from)
            .and_then(|()| draw(&root))
            .and_then(|()| root.present().map_err(Box::<dyn Error>::from))
            .map_err(|e| OutputError::Plot {
                path: path.to_path_buf(),
                reason: e.to_string(),
            })
    })
}

/// Range of the finite values, padded by 5 % (around a constant: ±50 % of it, or ±0.5 around
/// 0; 0..1 if there is no finite value). Tiny constants (a wear depth) keep their scale.
pub fn padded_range(values: impl Iterator<Item = f64>) -> Range<f64> {
    let (lo, hi) = values
        .filter(|v| v.is_finite())
        .fold((f64::INFINITY, f64::NEG_INFINITY), |(lo, hi), v| {
            (lo.min(v), hi.max(v))
        });
    if lo > hi {
        return 0.0..1.0;
    }
    let pad = if hi > lo {
        0.05 * (hi - lo)
    } else if lo != 0.0 {
        0.5 * lo.abs()
    } else {
        0.5
    };
    (lo - pad)..(hi + pad)
}

/// Several curves against a common abscissa, with a legend: time histories, comparisons.
pub fn line_chart(
    path: impl AsRef<Path>,
    figure: &Figure<'_>,
    series: &[Series<'_>],
) -> Result<(), OutputError> {
    let xs = padded_range(series.iter().flat_map(|s| s.x.iter().copied()));
    let ys = padded_range(series.iter().flat_map(|s| s.y.iter().copied()));
    // A tight x range reads better for time axes: drop the padding there.
    let xs = series
        .iter()
        .flat_map(|s| s.x.iter().copied())
        .filter(|v| v.is_finite())
        .fold(None, |r: Option<(f64, f64)>, v| {
            Some(r.map_or((v, v), |(a, b)| (a.min(v), b.max(v))))
        })
        .filter(|(a, b)| b > a)
        .map_or(xs, |(a, b)| a..b);
    render(path.as_ref(), figure.size, |root| {
        let mut chart = ChartBuilder::on(root)
            .caption(figure.title, (FONT, 24))
            .margin(15)
            .x_label_area_size(50)
            .y_label_area_size(80)
            .build_cartesian_2d(xs, ys)?;
        chart
            .configure_mesh()
            .x_desc(figure.x_label)
            .y_desc(figure.y_label)
            .label_style((FONT, 15))
            .axis_desc_style((FONT, 17))
            .light_line_style(RGBColor(235, 235, 235))
            .draw()?;
        for (k, s) in series.iter().enumerate() {
            let style = colour(k).stroke_width(2);
            let points = s.x.iter().zip(s.y).map(|(x, y)| (*x, *y));
            chart
                .draw_series(LineSeries::new(points, style))?
                .label(s.label)
                .legend(key(style));
        }
        if series.iter().any(|s| !s.label.is_empty()) {
            draw_legend(&mut chart, 15, SeriesLabelPosition::UpperRight)?;
        }
        Ok(())
    })
}

/// Wear depth per grid cell (m) against the cell's body-frame angle, one curve per surface;
/// drawn in µm.
pub fn wear_depth(
    path: impl AsRef<Path>,
    title: &str,
    size: (u32, u32),
    surfaces: &[(&str, &[f64])],
) -> Result<(), OutputError> {
    let data: Vec<(Vec<f64>, Vec<f64>)> = surfaces
        .iter()
        .map(|(_, h)| {
            let n = h.len();
            (
                (0..n).map(|k| cell_angle_deg(k, n)).collect(),
                h.iter().map(|d| d * 1e6).collect(),
            )
        })
        .collect();
    let series: Vec<Series<'_>> = surfaces
        .iter()
        .zip(&data)
        .map(|((label, _), (x, y))| Series { label, x, y })
        .collect();
    let figure = Figure {
        title,
        x_label: "angle in body frame (deg)",
        y_label: "wear depth (µm)",
        size,
    };
    line_chart(path, &figure, &series)
}

/// Worn surfaces of one joint, each in its own body frame.
#[derive(Debug, Clone, Copy)]
pub struct WornOutlines<'a> {
    /// Nominal bearing radius, m.
    pub bearing_radius: f64,
    /// Nominal pin radius, m.
    pub pin_radius: f64,
    /// Radius increase of the bearing per cell, m (cell k at [`cell_angle_deg`](sim::surfaces::cell_angle_deg)).
    pub bearing_wear: &'a [f64],
    /// Radius decrease of the pin per cell, m.
    pub pin_wear: &'a [f64],
    /// Factor the wear is drawn magnified by (the clearance itself is drawn true to scale).
    pub exaggeration: f64,
}

/// Closed outline `r(φ)` in mm, sampled at each cell centre.
fn outline(radius: f64, wear: &[f64], sign: f64, k: f64) -> Vec<(f64, f64)> {
    let n = wear.len().max(1);
    let depth = |j: usize| wear.get(j % wear.len().max(1)).copied().unwrap_or(0.0);
    (0..=n)
        .map(|j| {
            let phi = cell_angle_deg(j % n, n).to_radians();
            let r = 1e3 * (radius + sign * k * depth(j));
            (r * phi.cos(), r * phi.sin())
        })
        .collect()
}

fn circle(radius_mm: f64) -> Vec<(f64, f64)> {
    (0..=360)
        .map(|d| {
            let phi = TAU * f64::from(d) / 360.0;
            (radius_mm * phi.cos(), radius_mm * phi.sin())
        })
        .collect()
}

/// A labelled polyline of a square chart (empty label: no legend entry).
type Curve = (String, Vec<(f64, f64)>, ShapeStyle);

/// Width of the legend column right of a square chart, pixels.
const LEGEND_WIDTH: u32 = 210;

/// A tick label without float noise or trailing zeros.
pub(crate) fn tick(v: &f64) -> String {
    let s = format!("{v:.3}");
    let s = s.trim_end_matches('0').trim_end_matches('.');
    if s == "-0" { "0".into() } else { s.into() }
}

/// A plot with equal axes over ±`half` (in `unit`) in a square on the left, its legend in a
/// column on the right, so the legend never hides the curves.
fn square_chart(
    path: &Path,
    title: &str,
    size: (u32, u32),
    half: f64,
    unit: &str,
    curves: &[Curve],
) -> Result<(), OutputError> {
    let side = size.1.min(size.0.saturating_sub(LEGEND_WIDTH)).max(100);
    render(path, size, |root| {
        let root = root.titled(title, (FONT, 22))?;
        let (square, legend) = root.split_horizontally(side);
        let mut chart = ChartBuilder::on(&square)
            .margin(10)
            .x_label_area_size(50)
            .y_label_area_size(65)
            .build_cartesian_2d(-half..half, -half..half)?;
        chart
            .configure_mesh()
            .x_desc(format!("x ({unit})"))
            .y_desc(format!("y ({unit})"))
            .x_labels(7)
            .y_labels(7)
            .x_label_formatter(&tick)
            .y_label_formatter(&tick)
            .label_style((FONT, 14))
            .axis_desc_style((FONT, 16))
            .light_line_style(RGBColor(235, 235, 235))
            .draw()?;
        let mut row = 40;
        for (label, points, style) in curves {
            chart.draw_series(LineSeries::new(points.iter().copied(), *style))?;
            if !label.is_empty() {
                legend.draw(&PathElement::new(vec![(5, row), (35, row)], *style))?;
                legend.draw(&Text::new(label.as_str(), (42, row - 8), (FONT, 14)))?;
                row += 26;
            }
        }
        Ok(())
    })
}

/// Outlines of the worn bearing and pin (wear magnified) over their nominal circles (grey), in
/// mm, each in its own body frame.
pub fn worn_outline(
    path: impl AsRef<Path>,
    title: &str,
    size: (u32, u32),
    joint: &WornOutlines<'_>,
) -> Result<(), OutputError> {
    let k = joint.exaggeration;
    let bearing = outline(joint.bearing_radius, joint.bearing_wear, 1.0, k);
    let pin = outline(joint.pin_radius, joint.pin_wear, -1.0, k);
    let half = bearing
        .iter()
        .chain(&pin)
        .map(|(x, y)| x.abs().max(y.abs()))
        .fold(1e3 * joint.bearing_radius, f64::max)
        * 1.15;
    let grey = RGBColor(150, 150, 150).stroke_width(1);
    let curves = [
        (String::new(), circle(1e3 * joint.bearing_radius), grey),
        (String::new(), circle(1e3 * joint.pin_radius), grey),
        (
            format!("bearing (wear ×{k})"),
            bearing,
            colour(0).stroke_width(2),
        ),
        (format!("pin (wear ×{k})"), pin, colour(1).stroke_width(2)),
    ];
    square_chart(path.as_ref(), title, size, half, "mm", &curves)
}

/// Path of the pin centre relative to the bearing centre (`e = r_pin − r_bearing`, m), inside
/// the clearance circle; drawn in µm.
pub fn journal_path(
    path: impl AsRef<Path>,
    title: &str,
    size: (u32, u32),
    ex: &[f64],
    ey: &[f64],
    clearance: f64,
) -> Result<(), OutputError> {
    let c = 1e6 * clearance;
    let points: Vec<(f64, f64)> = ex.iter().zip(ey).map(|(x, y)| (1e6 * x, 1e6 * y)).collect();
    let half = points
        .iter()
        .map(|(x, y)| x.abs().max(y.abs()))
        .filter(|v| v.is_finite())
        .fold(c, f64::max)
        * 1.15;
    let curves = [
        (
            format!("clearance circle ({c:.0} µm)"),
            circle(c),
            BLACK.stroke_width(2),
        ),
        (
            "journal centre".to_string(),
            points,
            colour(0).stroke_width(1),
        ),
    ];
    square_chart(path.as_ref(), title, size, half, "µm", &curves)
}

/// One log–log panel of a multi-panel figure: curves with markers and optional horizontal
/// reference lines (dashed, e.g. a resolution floor).
#[derive(Debug, Clone)]
pub struct Panel<'a> {
    /// Caption above the panel.
    pub title: &'a str,
    /// Horizontal axis label with unit.
    pub x_label: &'a str,
    /// Vertical axis label with unit.
    pub y_label: &'a str,
    /// Curves; non-positive and non-finite points are left out (log axes).
    pub series: Vec<Series<'a>>,
    /// Horizontal dashed lines: (value, legend label).
    pub levels: Vec<(f64, &'a str)>,
    /// Legend in the upper-left corner instead of the lower-left, for curves that rise to the
    /// right and would otherwise run under it.
    pub legend_top: bool,
    /// Per series (same order; missing or empty: none), each point's half-width of a vertical
    /// bar (a noise), drawn from `y − e` (or the axis' floor) to `y + e`.
    pub errors: Vec<&'a [f64]>,
    /// Dashed curves, the `k`-th in series `k`'s colour (e.g. what each run predicts of its
    /// own error).
    pub dashed: Vec<Series<'a>>,
}

/// Tick label of a log axis: powers of ten only (the ticks between stay unlabelled).
fn decade_label(v: &f64) -> String {
    let exponent = v.log10();
    if (exponent - exponent.round()).abs() < 1e-6 {
        format!("1e{}", exponent.round())
    } else {
        String::new()
    }
}

/// Log range covering the positive finite values, padded by a fifth of a decade each side.
fn log_range(values: impl Iterator<Item = f64>) -> Range<f64> {
    let (lo, hi) = values
        .filter(|v| v.is_finite() && *v > 0.0)
        .fold((f64::INFINITY, f64::NEG_INFINITY), |(lo, hi), v| {
            (lo.min(v), hi.max(v))
        });
    if lo > hi {
        return 0.1..10.0;
    }
    let pad = 10f64.powf(0.2);
    (lo / pad)..(hi * pad)
}

/// Log–log panels side by side, `columns` to a row, under a common title: work–precision
/// diagrams. Series `k` has the same colour in every panel, so one legend per panel reads
/// across the figure.
pub fn log_panels(
    path: impl AsRef<Path>,
    title: &str,
    size: (u32, u32),
    columns: usize,
    panels: &[Panel<'_>],
) -> Result<(), OutputError> {
    let columns = columns.max(1);
    let rows = panels.len().div_ceil(columns).max(1);
    render(path.as_ref(), size, |root| {
        let body = root.titled(title, (FONT, 26))?;
        let areas = body.split_evenly((rows, columns));
        for (panel, area) in panels.iter().zip(&areas) {
            let positive = |s: &Series<'_>| {
                s.x.iter()
                    .zip(s.y)
                    .filter(|(x, y)| x.is_finite() && y.is_finite() && **x > 0.0 && **y > 0.0)
                    .map(|(x, y)| (*x, *y))
                    .collect::<Vec<_>>()
            };
            let xs = log_range(panel.series.iter().flat_map(|s| s.x.iter().copied()));
            let ys = log_range(
                panel
                    .series
                    .iter()
                    .chain(&panel.dashed)
                    .flat_map(|s| positive(s).into_iter().map(|(_, y)| y))
                    .chain(panel.levels.iter().map(|(v, _)| *v)),
            );
            let floor = ys.start;
            let mut chart = ChartBuilder::on(area)
                .caption(panel.title, (FONT, 19))
                .margin(12)
                .x_label_area_size(45)
                .y_label_area_size(70)
                .build_cartesian_2d(xs.clone().log_scale(), ys.log_scale())?;
            chart
                .configure_mesh()
                .x_desc(panel.x_label)
                .y_desc(panel.y_label)
                .x_label_formatter(&decade_label)
                .y_label_formatter(&decade_label)
                .label_style((FONT, 13))
                .axis_desc_style((FONT, 15))
                .light_line_style(WHITE)
                .bold_line_style(RGBColor(225, 225, 225))
                .draw()?;
            for (k, s) in panel.series.iter().enumerate() {
                let style = colour(k).stroke_width(2);
                let points = positive(s);
                chart
                    .draw_series(LineSeries::new(points.iter().copied(), style))?
                    .label(s.label)
                    .legend(key(style));
                chart.draw_series(
                    points
                        .iter()
                        .map(|p| Circle::new(*p, 4, colour(k).filled())),
                )?;
                let bars = panel.errors.get(k).copied().unwrap_or_default();
                for ((x, y), e) in s.x.iter().zip(s.y).zip(bars) {
                    if !(x.is_finite() && *x > 0.0 && y.is_finite() && e.is_finite() && *e > 0.0) {
                        continue;
                    }
                    let bar = [(*x, (y - e).max(floor)), (*x, (y + e).max(floor))];
                    chart.draw_series(LineSeries::new(bar, colour(k).stroke_width(1)))?;
                }
            }
            for (k, s) in panel.dashed.iter().enumerate() {
                let style = colour(k).stroke_width(1);
                chart
                    .draw_series(DashedLineSeries::new(positive(s), 6, 4, style))?
                    .label(s.label)
                    .legend(key(style));
            }
            for (k, (value, label)) in panel.levels.iter().enumerate() {
                let style = RGBColor(90, 90, 90).stroke_width(1 + k as u32);
                let line = [(xs.start, *value), (xs.end, *value)];
                chart
                    .draw_series(DashedLineSeries::new(line, 8, 5, style))?
                    .label(*label)
                    .legend(key(style));
            }
            let position = if panel.legend_top {
                SeriesLabelPosition::UpperLeft
            } else {
                SeriesLabelPosition::LowerLeft
            };
            draw_legend(&mut chart, 13, position)?;
        }
        Ok(())
    })
}
