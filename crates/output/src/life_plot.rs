//! The life-curve figure of a wearing joint (`wear_life_<joint>.png`), on the helpers of
//! [`super::plot`].

use std::path::Path;

use plotters::prelude::*;

use super::plot::*;
use crate::files::OutputError;

/// A joint's life curve for [`life_curve`]: its wear after each sub-step against the drive
/// cycles it stands for (all slices the same length; extra values are ignored).
#[derive(Debug, Clone, Copy)]
pub struct LifeCurve<'a> {
    /// Drive cycles, increasing from 0.
    pub cycles: &'a [f64],
    /// Peak bearing depth, m.
    pub bearing_depth: &'a [f64],
    /// Peak pin depth, m.
    pub pin_depth: &'a [f64],
    /// Largest local clearance, m.
    pub max_clearance: &'a [f64],
    /// The sampling noise of the bearing depth, the pin depth and the largest clearance at
    /// each point, m (0 where not measured; empty: no band), drawn as a band of ± one noise.
    pub noise: [&'a [f64]; 3],
    /// Cycles where one stage ends and the next begins (dashed verticals).
    pub stage_boundaries: &'a [f64],
    /// Maintenance limit on the largest local clearance, m (dashed horizontal), and the
    /// cycles at which the curve reaches it (marked), if it does.
    pub limit: Option<(f64, Option<f64>)>,
}

/// Tick label of a cycle count: `0`, else two significant digits in scientific notation.
fn cycles_label(v: &f64) -> String {
    if *v == 0.0 {
        "0".into()
    } else {
        format!("{v:.1e}")
    }
}

/// A joint's life curve in two panels over a common, linear cycle axis (the start at 0 cycles
/// belongs on it, and Archard wear grows about linearly in the cycles): the peak depths of
/// bearing and pin above, the largest local clearance below, both in µm, one marker per
/// sub-step, each in a pale band of ± its sampling noise; stage boundaries dashed in both, the
/// clearance limit dashed below.
pub fn life_curve(
    path: impl AsRef<Path>,
    title: &str,
    size: (u32, u32),
    curve: &LifeCurve<'_>,
) -> Result<(), OutputError> {
    let um = |v: &[f64]| v.iter().map(|x| x * 1e6).collect::<Vec<f64>>();
    let (bearing, pin, clearance) = (
        um(curve.bearing_depth),
        um(curve.pin_depth),
        um(curve.max_clearance),
    );
    let [bearing_noise, pin_noise, clearance_noise] = curve.noise.map(um);
    let band = |y: &[f64], noise: &[f64], sign: f64| -> Vec<f64> {
        y.iter().zip(noise).map(|(v, n)| v + sign * n).collect()
    };
    let (bearing_high, pin_high, clearance_high, clearance_low) = (
        band(&bearing, &bearing_noise, 1.0),
        band(&pin, &pin_noise, 1.0),
        band(&clearance, &clearance_noise, 1.0),
        band(&clearance, &clearance_noise, -1.0),
    );
    let limit = curve.limit.map(|(l, at)| (l * 1e6, at));
    let last = curve.cycles.iter().copied().filter(|c| c.is_finite());
    let xs = 0.0..last.fold(0.0, f64::max).max(1.0);
    let panels = [
        (
            "peak wear depth (µm)",
            padded_range(
                bearing
                    .iter()
                    .chain(&pin)
                    .chain(&bearing_high)
                    .chain(&pin_high)
                    .copied()
                    .chain([0.0]),
            ),
            vec![
                ("bearing", &bearing, &bearing_noise),
                ("pin", &pin, &pin_noise),
            ],
        ),
        (
            "largest local clearance (µm)",
            padded_range(
                clearance
                    .iter()
                    .chain(&clearance_high)
                    .chain(&clearance_low)
                    .copied()
                    .chain(limit.map(|(l, _)| l)),
            ),
            vec![("c0 + (max h_i + max h_j)/2", &clearance, &clearance_noise)],
        ),
    ];
    render(path.as_ref(), size, |root| {
        let body = root.titled(title, (FONT, 24))?;
        let areas = body.split_evenly((2, 1));
        for (k, ((y_label, ys, series), area)) in panels.iter().zip(&areas).enumerate() {
            let mut chart = ChartBuilder::on(area)
                .margin(12)
                // Room for the last cycle label, centred on the axis end.
                .margin_right(30)
                .x_label_area_size(45)
                .y_label_area_size(80)
                .build_cartesian_2d(xs.clone(), ys.clone())?;
            chart
                .configure_mesh()
                .x_desc("drive cycles")
                .y_desc(*y_label)
                .x_label_formatter(&cycles_label)
                .label_style((FONT, 14))
                .axis_desc_style((FONT, 16))
                .light_line_style(RGBColor(235, 235, 235))
                .draw()?;
            for (n, (label, y, noise)) in series.iter().enumerate() {
                // Colours run on across the panels: each quantity its own.
                let c = colour(2 * k + n);
                let points: Vec<(f64, f64)> = curve
                    .cycles
                    .iter()
                    .copied()
                    .zip(y.iter().copied())
                    .collect();
                if !noise.is_empty() {
                    // Up along the upper edge, back along the lower.
                    let edge = |sign: f64| {
                        points
                            .iter()
                            .zip(noise.iter())
                            .map(move |((x, v), e)| (*x, v + sign * e))
                    };
                    let outline: Vec<(f64, f64)> = edge(1.0)
                        .chain(edge(-1.0).collect::<Vec<_>>().into_iter().rev())
                        .collect();
                    chart.draw_series([Polygon::new(outline, c.mix(0.2).filled())])?;
                }
                chart
                    .draw_series(LineSeries::new(points.iter().copied(), c.stroke_width(2)))?
                    .label(*label)
                    .legend(key(c.stroke_width(2)));
                chart.draw_series(points.iter().map(|p| Circle::new(*p, 3, c.filled())))?;
            }
            let grey = RGBColor(110, 110, 110).stroke_width(1);
            for (n, at) in curve.stage_boundaries.iter().enumerate() {
                let line = [(*at, ys.start), (*at, ys.end)];
                let drawn = chart.draw_series(DashedLineSeries::new(line, 6, 4, grey))?;
                if n == 0 {
                    drawn.label("stage boundary").legend(key(grey));
                }
            }
            if let (1, Some((value, reached))) = (k, limit) {
                let red = RGBColor(200, 0, 0).stroke_width(2);
                let line = [(xs.start, value), (xs.end, value)];
                chart
                    .draw_series(DashedLineSeries::new(line, 10, 6, red))?
                    .label(format!("limit {} µm", tick(&value)))
                    .legend(key(red));
                if let Some(at) = reached {
                    chart.draw_series([Circle::new((at, value), 6, red)])?;
                }
            }
            draw_legend(&mut chart, 14, SeriesLabelPosition::UpperLeft)?;
        }
        Ok(())
    })
}

/// The life distribution figure (`life_distribution.png`): the fraction of joints (and of
/// mechanisms) that have reached the clearance limit against the drive cycles, on a log cycle
/// axis, one curve per distribution of `lives` (the mechanism's dashed); each curve's B10 and
/// B50 marked (a circle on the 10 % line, a square on the 50 % line), their values in the
/// legend, with noise.
pub fn life_distribution(
    path: impl AsRef<Path>,
    title: &str,
    size: (u32, u32),
    lives: &sim::life_distribution::SampledLives,
) -> Result<(), OutputError> {
    let cycles = &lives.cycles;
    let (Some(first), Some(last)) = (cycles.first(), cycles.last()) else {
        return Err(OutputError::Plot {
            path: path.as_ref().to_path_buf(),
            reason: "no cycles to draw the life distribution over".into(),
        });
    };
    let xs = *first..last.max(first * 10.0);
    let labels: Vec<String> = lives
        .curves
        .iter()
        .map(|c| {
            let b = &c.lives;
            format!(
                "{}: B10 {}, B50 {}",
                c.of.label(),
                sim::life_distribution::cycles_with_noise(b.b10_cycles, b.b10_noise),
                sim::life_distribution::cycles_with_noise(b.b50_cycles, b.b50_noise)
            )
        })
        .collect();
    render(path.as_ref(), size, |root| {
        let mut chart = ChartBuilder::on(root)
            .caption(title, (FONT, 22))
            .margin(15)
            .margin_right(30)
            .x_label_area_size(50)
            .y_label_area_size(70)
            .build_cartesian_2d(xs.clone().log_scale(), 0.0..1.0)?;
        chart
            .configure_mesh()
            .x_desc("drive cycles to the clearance limit")
            .y_desc("fraction that reached the limit")
            .x_label_formatter(&|v| format!("{v:.1e}"))
            .label_style((FONT, 14))
            .axis_desc_style((FONT, 16))
            .light_line_style(RGBColor(235, 235, 235))
            .draw()?;
        let grey = RGBColor(110, 110, 110).stroke_width(1);
        for level in [0.1, 0.5] {
            chart.draw_series(DashedLineSeries::new(
                [(xs.start, level), (xs.end, level)],
                6,
                4,
                grey,
            ))?;
        }
        for (k, (curve, label)) in lives.curves.iter().zip(&labels).enumerate() {
            let c = colour(k);
            let points = cycles.iter().copied().zip(curve.failed.iter().copied());
            // The mechanism's curve dashed: where one joint always goes first it lies on it.
            if curve.of == sim::life_distribution::LifeOf::Mechanism {
                chart
                    .draw_series(DashedLineSeries::new(points, 10, 6, c.stroke_width(2)))?
                    .label(label.as_str())
                    .legend(key(c.stroke_width(2)));
            } else {
                chart
                    .draw_series(LineSeries::new(points, c.stroke_width(2)))?
                    .label(label.as_str())
                    .legend(key(c.stroke_width(2)));
            }
            let b = &curve.lives;
            chart.draw_series([Circle::new((b.b10_cycles, 0.1), 6, c.filled())])?;
            // A square of 11 pixels about the B50 (pixel offsets from its point).
            chart.draw_series(std::iter::once(
                EmptyElement::at((b.b50_cycles, 0.5))
                    + Rectangle::new([(-5, -5), (5, 5)], c.filled()),
            ))?;
        }
        draw_legend(&mut chart, 14, SeriesLabelPosition::UpperLeft)?;
        Ok(())
    })
}
