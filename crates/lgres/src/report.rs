//! The study report (`report.md`): the paper's reported numbers next to ours, and a verdict on
//! each of the paper's trends judged on quantities that do not swing with chaos (MODEL §8).
//!
//! Chaos-robust quantities used by the judge: per-cycle **medians** of the peak normal force
//! after the start-up window (with their interquartile range as the noise level), the largest
//! deviation of rod 3 from the ideal mechanism after the window, the energy dissipated per
//! cycle, the worn volume, the **worn arc** (angular width where the depth is at least
//! [`ARC_FRACTION`] of the surface's peak) and, for irregularity, the coefficient of variation
//! of the depth over the worn arc and the number of separate concentrated ranges (depth at
//! least [`RANGE_FRACTION`] of the peak).

use std::fmt::{self, Write as _};
use std::path::{Path, PathBuf};

use wear::{WornJoint, WornProfile};

use crate::output::{OutputError, write_atomic};
use crate::plot::{self, DEFAULT_SIZE};
use crate::run::{ResponseSummary, RunOutcome};
use crate::study::{EXTRAPOLATION, SINGLE_JUMP_RUN, SceneRun, StudyKind, StudyResults, relative};

/// Fraction of a surface's peak depth that counts as worn, for the worn arc and irregularity.
pub const ARC_FRACTION: f64 = 0.1;
/// Fraction of the peak depth that makes a concentrated range (as in the run summary).
pub const RANGE_FRACTION: f64 = 0.5;
/// Smallest relative change the judge counts as a change at all.
pub const RELATIVE_MARGIN: f64 = 0.05;

/// Whether a trend is seen in our results.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Verdict {
    /// The quantities change the way the paper says.
    Holds,
    /// They change the other way (or not at all while some go the other way).
    DoesNotHold,
    /// Within noise, or mixed.
    Inconclusive,
}

impl fmt::Display for Verdict {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(match self {
            Verdict::Holds => "HOLDS",
            Verdict::DoesNotHold => "DOES NOT HOLD",
            Verdict::Inconclusive => "INCONCLUSIVE",
        })
    }
}

/// One quantity the paper says grows from the `low` case to the `high` case.
#[derive(Debug, Clone, PartialEq)]
pub struct Comparison {
    /// What it is, with its unit.
    pub quantity: String,
    /// Value in the case the paper says is smaller.
    pub low: f64,
    /// Value in the case the paper says is larger.
    pub high: f64,
    /// Spread of the values (e.g. interquartile range of per-cycle peaks); a change must
    /// exceed it to count.
    pub noise: f64,
}

impl Comparison {
    /// Whether this quantity grew: by more than its noise and [`RELATIVE_MARGIN`].
    pub fn verdict(&self) -> Verdict {
        judge_increase(self.low, self.high, self.noise)
    }
}

/// Whether `high` exceeds `low` by more than `noise` and by more than [`RELATIVE_MARGIN`] of
/// the larger magnitude ([`Verdict::DoesNotHold`] for a decrease as large, else inconclusive).
pub fn judge_increase(low: f64, high: f64, noise: f64) -> Verdict {
    if !(low.is_finite() && high.is_finite()) {
        return Verdict::Inconclusive;
    }
    let margin = (RELATIVE_MARGIN * low.abs().max(high.abs())).max(noise.abs());
    if high - low > margin {
        Verdict::Holds
    } else if low - high > margin {
        Verdict::DoesNotHold
    } else {
        Verdict::Inconclusive
    }
}

/// A trend over several quantities: holds when most grow and none shrinks, does not hold when
/// most shrink and none grows, else inconclusive (also for no quantities).
pub fn judge_trend(comparisons: &[Comparison]) -> Verdict {
    let verdicts: Vec<Verdict> = comparisons.iter().map(Comparison::verdict).collect();
    let count = |v| verdicts.iter().filter(|x| **x == v).count();
    let (up, down) = (count(Verdict::Holds), count(Verdict::DoesNotHold));
    let half = verdicts.len() / 2;
    if up > half && down == 0 {
        Verdict::Holds
    } else if down > half && up == 0 {
        Verdict::DoesNotHold
    } else {
        Verdict::Inconclusive
    }
}

/// Wear measures of one surface.
#[derive(Debug, Clone, PartialEq)]
pub struct SurfaceMetrics {
    /// Peak depth, m.
    pub peak_m: f64,
    /// Its body-frame angle, deg.
    pub peak_deg: f64,
    /// Angular width where depth ≥ [`ARC_FRACTION`] × peak, deg.
    pub arc_deg: f64,
    /// Coefficient of variation (std/mean) of depth over those cells.
    pub cv: f64,
    /// Concentrated ranges (depth ≥ [`RANGE_FRACTION`] × peak), deg, deepest first.
    pub ranges_deg: Vec<[f64; 2]>,
}

/// Wear measures of `p` (see [`SurfaceMetrics`]).
pub fn surface_metrics(p: &WornProfile) -> SurfaceMetrics {
    let wear::Peak {
        depth: peak, angle, ..
    } = p.peak();
    let worn: Vec<f64> = p
        .depth()
        .iter()
        .copied()
        .filter(|h| peak > 0.0 && *h >= ARC_FRACTION * peak)
        .collect();
    let n = worn.len() as f64;
    let cv = if worn.is_empty() {
        0.0
    } else {
        let mean = worn.iter().sum::<f64>() / n;
        let var = worn.iter().map(|h| (h - mean).powi(2)).sum::<f64>() / n;
        var.sqrt() / mean
    };
    SurfaceMetrics {
        peak_m: peak,
        peak_deg: angle.to_degrees(),
        arc_deg: n * p.cell_width().to_degrees(),
        cv,
        ranges_deg: p
            .concentrated_ranges(RANGE_FRACTION)
            .iter()
            .map(|r| r.degrees())
            .collect(),
    }
}

/// Wear measures of one joint after a stage.
#[derive(Debug, Clone, PartialEq)]
pub struct JointMetrics {
    /// Joint name.
    pub name: String,
    /// Bearing surface.
    pub bearing: SurfaceMetrics,
    /// Pin surface.
    pub pin: SurfaceMetrics,
    /// Volume removed from both surfaces, m³.
    pub volume_m3: f64,
}

impl JointMetrics {
    fn new(name: &str, j: &WornJoint) -> Self {
        Self {
            name: name.to_string(),
            bearing: surface_metrics(j.bearing()),
            pin: surface_metrics(j.pin()),
            volume_m3: j.worn_volume(),
        }
    }
    /// Deeper of the two surfaces' peaks, m.
    pub fn peak_m(&self) -> f64 {
        self.bearing.peak_m.max(self.pin.peak_m)
    }
    /// Mean worn arc of the two surfaces, deg.
    pub fn arc_deg(&self) -> f64 {
        0.5 * (self.bearing.arc_deg + self.pin.arc_deg)
    }
    /// Mean coefficient of variation of the two surfaces.
    pub fn cv(&self) -> f64 {
        0.5 * (self.bearing.cv + self.pin.cv)
    }
    /// Concentrated ranges on both surfaces.
    pub fn range_count(&self) -> usize {
        self.bearing.ranges_deg.len() + self.pin.ranges_deg.len()
    }
}

/// Wear measures per joint after stage `stage` (0-based) of a run.
pub fn wear_metrics(outcome: &RunOutcome, stage: usize) -> Vec<JointMetrics> {
    outcome
        .wear
        .iter()
        .filter_map(|h| h.stages.get(stage).map(|j| JointMetrics::new(&h.name, j)))
        .collect()
}

/// Wear measures per joint after the last stage of a run.
pub fn final_wear(outcome: &RunOutcome) -> Vec<JointMetrics> {
    let last = outcome
        .wear
        .iter()
        .map(|h| h.stages.len())
        .max()
        .unwrap_or(0);
    wear_metrics(outcome, last.saturating_sub(1))
}

/// The chaos-robust comparisons of a `low` and a `high` run: force medians, rod-3 deviation,
/// dissipation (unworn and worn response) and the wear after the last stage.
pub fn compare_runs(low: &RunOutcome, high: &RunOutcome) -> Vec<Comparison> {
    let mut out = Vec::new();
    let responses = [
        (
            "unworn",
            Some(&low.summary.response),
            Some(&high.summary.response),
        ),
        (
            "worn",
            low.summary.worn_response.as_ref(),
            high.summary.worn_response.as_ref(),
        ),
    ];
    for (label, a, b) in responses {
        let (Some(a), Some(b)) = (a, b) else { continue };
        out.extend(response_comparisons(label, a, b));
    }
    for (a, b) in final_wear(low).iter().zip(final_wear(high)) {
        out.push(Comparison {
            quantity: format!("worn volume {} (mm³)", a.name),
            low: a.volume_m3 * 1e9,
            high: b.volume_m3 * 1e9,
            noise: 0.0,
        });
        out.push(Comparison {
            quantity: format!("worn arc {} (deg, depth ≥ {ARC_FRACTION}·peak)", a.name),
            low: a.arc_deg(),
            high: b.arc_deg(),
            noise: 0.0,
        });
    }
    out
}

fn response_comparisons(label: &str, a: &ResponseSummary, b: &ResponseSummary) -> Vec<Comparison> {
    let mut out = Vec::new();
    for (ja, jb) in a.joints.iter().zip(&b.joints) {
        let (pa, pb) = (
            &ja.normal_force_after_transient,
            &jb.normal_force_after_transient,
        );
        out.push(Comparison {
            quantity: format!("{label}: median cycle peak F_n {} (kN)", ja.name),
            low: pa.cycle_median * 1e-3,
            high: pb.cycle_median * 1e-3,
            noise: 0.5 * (pa.cycle_iqr + pb.cycle_iqr) * 1e-3,
        });
    }
    let (da, db) = (&a.deviation_after_transient, &b.deviation_after_transient);
    out.push(Comparison {
        quantity: format!("{label}: rod-3 max |Δx| (mm)"),
        low: da.x_m * 1e3,
        high: db.x_m * 1e3,
        noise: 0.0,
    });
    out.push(Comparison {
        quantity: format!("{label}: rod-3 max |Δy| (mm)"),
        low: da.y_m * 1e3,
        high: db.y_m * 1e3,
        noise: 0.0,
    });
    out.push(Comparison {
        quantity: format!("{label}: energy dissipated per cycle (J)"),
        low: a.dissipated_per_cycle_j,
        high: b.dissipated_per_cycle_j,
        noise: 0.0,
    });
    out
}

/// Stage 2 against stage 1 of a two-stage run: deeper (peak depth, volume) and more irregular
/// (coefficient of variation over the worn arc, number of concentrated ranges).
pub fn compare_stages(two_stages: &RunOutcome) -> Vec<Comparison> {
    let (one, two) = (wear_metrics(two_stages, 0), wear_metrics(two_stages, 1));
    let mut out = Vec::new();
    for (a, b) in one.iter().zip(&two) {
        out.push(Comparison {
            quantity: format!("peak depth {} (µm)", a.name),
            low: a.peak_m() * 1e6,
            high: b.peak_m() * 1e6,
            noise: 0.0,
        });
        out.push(Comparison {
            quantity: format!("irregularity {}: CV of depth over the worn arc", a.name),
            low: a.cv(),
            high: b.cv(),
            noise: 0.0,
        });
        out.push(Comparison {
            quantity: format!("irregularity {}: concentrated ranges (count)", a.name),
            low: a.range_count() as f64,
            high: b.range_count() as f64,
            noise: 0.0,
        });
    }
    out
}

/// A number the paper reports for one scene, with its section.
struct PaperValue {
    scene: &'static str,
    quantity: Quantity,
    text: &'static str,
}

#[derive(Clone, Copy)]
enum Quantity {
    /// Peak normal force at joint `0` (A) or `1` (B).
    Force(usize),
    /// Rod-3 deviation component (x, y, vx, vy, ax, ay).
    Deviation(usize),
    /// Peak wear depth at a joint after the last stage.
    Wear(usize),
    /// Peak wear depth after stage 1 of a run.
    WearStage1(usize),
}

const fn pv(scene: &'static str, quantity: Quantity, text: &'static str) -> PaperValue {
    PaperValue {
        scene,
        quantity,
        text,
    }
}

use Quantity::{Deviation as D, Force as F, Wear as W, WearStage1 as W1};

/// The paper's §4.2 numbers. Superscripts are lost in the available text ("2.1 × 10 3 m");
/// negative exponents are assumed where the unit makes only that reading sensible.
const PAPER: &[(&str, &str, &[PaperValue])] = &[
    (
        "wear-stages",
        "§4.2.1",
        &[
            pv(
                "lgres-2stages",
                W1(0),
                "1.50e-6 m (§4.2.2: 1.50e-5 m); [0,210]°, [250,255]°, [320,360]°",
            ),
            pv(
                "lgres-2stages",
                W1(1),
                "3.58e-6 m (§4.2.2: 3.58e-5 m); [80,100]°, [250,270]°",
            ),
            pv("lgres-2stages", W(0), "2.83e-5 m"),
            pv("lgres-2stages", W(1), "7.20e-5 m"),
        ],
    ),
    (
        "clearance",
        "§4.2.2",
        &[
            pv("lgres-c02", F(0), "15.86 kN"),
            pv("lgres-c02", F(1), "35.70 kN"),
            pv("lgres-c02", D(0), "8.90e-4 m"),
            pv("lgres-c02", D(1), "8.74e-4 m"),
            pv("lgres-c02", D(2), "6.51e-2 m/s"),
            pv("lgres-c02", D(3), "0.155 m/s"),
            pv("lgres-c02", D(4), "164.79 m/s²"),
            pv("lgres-c02", D(5), "395.41 m/s²"),
            pv("lgres-c02", W(0), "3.45e-6 m; [50,200]°, [350,360]°"),
            pv("lgres-c02", W(1), "2.69e-5 m; [85,95]°, [260,265]°"),
            pv("lgres", F(0), "25.26 kN"),
            pv("lgres", F(1), "47.71 kN"),
            pv("lgres", D(0), "2.1e-3 m"),
            pv("lgres", D(1), "1.91e-3 m"),
            pv("lgres", D(2), "0.149 m/s"),
            pv("lgres", D(3), "0.195 m/s"),
            pv("lgres", D(4), "320.18 m/s²"),
            pv("lgres", D(5), "830 m/s²"),
            pv(
                "lgres",
                W(0),
                "1.50e-5 m; [0,210]°, [250,255]°, [320,360]° (§4.2.1)",
            ),
            pv("lgres", W(1), "3.58e-5 m; [80,100]°, [250,270]° (§4.2.1)"),
        ],
    ),
    (
        "speed",
        "§4.2.3",
        &[
            pv("lgres-45rpm", F(0), "9.575 kN"),
            pv("lgres-45rpm", F(1), "31.886 kN"),
            pv("lgres-45rpm", D(2), "5.65e-2 m/s"),
            pv("lgres-45rpm", D(3), "8.13e-2 m/s"),
            pv("lgres-45rpm", D(4), "72.52 m/s²"),
            pv("lgres-45rpm", D(5), "420.17 m/s²"),
            pv("lgres-45rpm", W(0), "2.36e-6 m; [0,205]°, [330,360]°"),
            pv("lgres-45rpm", W(1), "3.28e-5 m; [85,100]°, [250,265]°"),
            pv("lgres-105rpm", F(0), "21.85 kN"),
            pv("lgres-105rpm", F(1), "79.88 kN"),
            pv("lgres-105rpm", D(2), "9.34e-2 m/s"),
            pv("lgres-105rpm", D(3), "0.271 m/s"),
            pv("lgres-105rpm", D(4), "244.86 m/s²"),
            pv("lgres-105rpm", D(5), "641.54 m/s²"),
            pv("lgres-105rpm", W(0), "1.43e-5 m; almost the whole surface"),
            pv("lgres-105rpm", W(1), "4.52e-5 m; [80,105]°, [245,265]°"),
        ],
    ),
];

const DEVIATIONS: [(&str, &str); 6] = [
    ("|Δx|", "m"),
    ("|Δy|", "m"),
    ("|Δvx|", "m/s"),
    ("|Δvy|", "m/s"),
    ("|Δax|", "m/s²"),
    ("|Δay|", "m/s²"),
];

fn deviation_value(r: &ResponseSummary, c: usize) -> f64 {
    let d = &r.deviation_after_transient;
    [d.x_m, d.y_m, d.vx_m_s, d.vy_m_s, d.ax_m_s2, d.ay_m_s2][c]
}

fn quantity_label(q: Quantity, joints: &[String]) -> String {
    let joint = |j: usize| joints.get(j).cloned().unwrap_or_else(|| format!("#{j}"));
    match q {
        F(j) => format!("peak F_n {}", joint(j)),
        D(c) => format!("rod 3 {} ({})", DEVIATIONS[c].0, DEVIATIONS[c].1),
        W(j) => format!("peak wear {}, ranges", joint(j)),
        W1(j) => format!("peak wear {} after stage 1, ranges", joint(j)),
    }
}

fn force_text(r: &ResponseSummary, j: usize) -> String {
    r.joints.get(j).map_or("—".into(), |s| {
        let p = &s.normal_force_after_transient;
        format!(
            "max {:.1}; median {:.1} (IQR {:.1}) kN",
            p.max * 1e-3,
            p.cycle_median * 1e-3,
            p.cycle_iqr * 1e-3
        )
    })
}

fn ranges_text(ranges: &[[f64; 2]]) -> String {
    if ranges.is_empty() {
        return "—".into();
    }
    let shown: Vec<String> = ranges
        .iter()
        .take(4)
        .map(|[a, b]| format!("[{a:.0},{b:.0}]°"))
        .collect();
    let more = ranges.len().saturating_sub(4);
    if more > 0 {
        format!("{} +{more} more", shown.join(", "))
    } else {
        shown.join(", ")
    }
}

fn wear_text(m: Option<&JointMetrics>) -> String {
    m.map_or("—".into(), |m| {
        format!(
            "bearing {:.1} µm at {:.0}° ({}); pin {:.1} µm at {:.0}° ({})",
            m.bearing.peak_m * 1e6,
            m.bearing.peak_deg,
            ranges_text(&m.bearing.ranges_deg),
            m.pin.peak_m * 1e6,
            m.pin.peak_deg,
            ranges_text(&m.pin.ranges_deg)
        )
    })
}

/// Our value(s) for a paper quantity: (unworn response, worn response or wear).
fn ours(run: &SceneRun, q: Quantity) -> (String, String) {
    let s = &run.outcome.summary;
    match q {
        F(j) => (
            force_text(&s.response, j),
            s.worn_response
                .as_ref()
                .map_or("—".into(), |w| force_text(w, j)),
        ),
        D(c) => (
            format!("{:.3e}", deviation_value(&s.response, c)),
            s.worn_response
                .as_ref()
                .map_or("—".into(), |w| format!("{:.3e}", deviation_value(w, c))),
        ),
        W(j) => ("—".into(), wear_text(final_wear(&run.outcome).get(j))),
        W1(j) => ("—".into(), wear_text(wear_metrics(&run.outcome, 0).get(j))),
    }
}

fn fmt_value(v: f64) -> String {
    if v == 0.0 || (1e-2..1e4).contains(&v.abs()) {
        format!("{v:.3}")
    } else {
        format!("{v:.3e}")
    }
}

fn comparison_table(md: &mut String, low: &str, high: &str, comparisons: &[Comparison]) {
    let _ = writeln!(
        md,
        "| quantity | {low} | {high} | noise | change |\n|---|---|---|---|---|"
    );
    for c in comparisons {
        let _ = writeln!(
            md,
            "| {} | {} | {} | {} | {} |",
            c.quantity,
            fmt_value(c.low),
            fmt_value(c.high),
            fmt_value(c.noise),
            match c.verdict() {
                Verdict::Holds => "grows",
                Verdict::DoesNotHold => "shrinks",
                Verdict::Inconclusive => "within noise",
            }
        );
    }
}

/// Overlays the worn depth of several cases per joint; returns the figure paths.
fn overlay(
    out: &Path,
    stem: &str,
    title: &str,
    cases: &[(String, Vec<JointMetricsSource<'_>>)],
) -> Result<Vec<PathBuf>, OutputError> {
    let joints: Vec<&str> = cases
        .first()
        .map(|(_, j)| j.iter().map(|s| s.name).collect())
        .unwrap_or_default();
    let mut files = Vec::new();
    for (k, name) in joints.iter().enumerate() {
        let labels: Vec<(String, &[f64])> = cases
            .iter()
            .filter_map(|(label, js)| js.get(k).map(|j| (label, j)))
            .flat_map(|(label, j)| {
                [
                    (format!("bearing, {label}"), j.joint.bearing().depth()),
                    (format!("pin, {label}"), j.joint.pin().depth()),
                ]
            })
            .collect();
        let surfaces: Vec<(&str, &[f64])> = labels.iter().map(|(l, d)| (l.as_str(), *d)).collect();
        let path = out.join(format!("{stem}_wear_{name}.png"));
        plot::wear_depth(
            &path,
            &format!("{title}: wear depth at joint {name}"),
            DEFAULT_SIZE,
            &surfaces,
        )?;
        files.push(path);
    }
    Ok(files)
}

/// A joint's worn surfaces after some stage, for overlays.
struct JointMetricsSource<'a> {
    name: &'a str,
    joint: &'a WornJoint,
}

fn stage_surfaces(outcome: &RunOutcome, stage: Option<usize>) -> Vec<JointMetricsSource<'_>> {
    outcome
        .wear
        .iter()
        .filter_map(|h| {
            let j = match stage {
                Some(s) => h.stages.get(s),
                None => h.stages.last(),
            }?;
            Some(JointMetricsSource {
                name: &h.name,
                joint: j,
            })
        })
        .collect()
}

fn figure_links(md: &mut String, out: &Path, files: &[PathBuf]) {
    for f in files {
        let rel = relative(f, out);
        let _ = writeln!(md, "![{rel}]({rel})");
    }
    md.push('\n');
}

fn scene_links(md: &mut String, out: &Path, run: &SceneRun) {
    let joints: Vec<&str> = run
        .outcome
        .response
        .contact
        .iter()
        .map(|c| c.name.as_str())
        .collect();
    let dir = relative(&run.dir, out);
    let mut links = vec![
        format!("[summary.json]({dir}/summary.json)"),
        format!("[x]({dir}/response_x.png)"),
        format!("[y]({dir}/response_y.png)"),
    ];
    for j in &joints {
        links.push(format!("[F {j}]({dir}/contact_force_{j}.png)"));
        if run.outcome.worn_response.is_some() {
            links.push(format!("[F {j} worn]({dir}/contact_force_{j}_worn.png)"));
        }
        links.push(format!("[journal {j}]({dir}/journal_{j}.png)"));
        if !run.outcome.wear.is_empty() {
            links.push(format!("[wear {j}]({dir}/wear_{j}.png)"));
            links.push(format!("[outline {j}]({dir}/worn_outline_{j}.png)"));
        }
    }
    let _ = writeln!(md, "- `{}`: {}", run.key, links.join(", "));
}

fn paper_section(md: &mut String, study: &str, scenes: &[&str], results: &StudyResults) {
    let base = crate::scenes::physical_counterpart(study);
    let Some((_, section, values)) = PAPER.iter().find(|(s, _, _)| *s == base) else {
        return;
    };
    // Our scene standing for a paper value's scene in this study's formulation.
    let ours_for = |paper_scene: &'static str| -> &str {
        scenes
            .iter()
            .find(|s| crate::scenes::physical_counterpart(s) == paper_scene)
            .copied()
            .unwrap_or(paper_scene)
    };
    let _ = writeln!(
        md,
        "Paper's numbers (Ma, Jiang & Yin 2026, {section}) next to ours. Ours: forces are \
         after the {}-s start-up window, as the maximum and the median (IQR) of per-cycle \
         peaks; deviations are maxima after the window; wear is the depth after the stage(s) \
         with concentrated ranges (depth ≥ {RANGE_FRACTION}·peak) in body frames.\n",
        results
            .runs
            .first()
            .map_or(0.0, |r| r.outcome.summary.transient_window_s)
    );
    let _ = writeln!(
        md,
        "| scene | quantity | paper | ours, unworn response | ours, after wear |\n|---|---|---|---|---|"
    );
    for v in values.iter() {
        let scene = ours_for(v.scene);
        let Some(run) = results.run(scene) else {
            continue;
        };
        let names: Vec<String> = run
            .outcome
            .response
            .contact
            .iter()
            .map(|c| c.name.clone())
            .collect();
        let (unworn, worn) = ours(run, v.quantity);
        let _ = writeln!(
            md,
            "| {} | {} | {} | {unworn} | {worn} |",
            scene,
            quantity_label(v.quantity, &names),
            v.text
        );
    }
    md.push('\n');
}

/// Marks every worn response whose geometry left the contact model's validity: its force
/// peaks and deviations are shown in the tables above but are not results.
fn validity_lines(md: &mut String, scenes: &[&str], results: &StudyResults) {
    let mut lines = Vec::new();
    for scene in scenes {
        let Some(run) = results.run(scene) else {
            continue;
        };
        if let Some(w) = &run.outcome.summary.wear {
            for (k, applied) in w.cycles_applied_at_limits.iter().enumerate() {
                if let Some(cycles) = applied {
                    lines.push(format!(
                        "- `{scene}` stage {}: ended at the slope limit after {cycles:.3e} of \
                         its {:.3e} cycles",
                        k + 1,
                        w.cycles_represented_per_stage
                    ));
                }
            }
        }
        let Some(worn) = &run.outcome.summary.worn_response else {
            continue;
        };
        for j in &worn.joints {
            let Some(v) = &j.validity else { continue };
            let verdict = if v.inside {
                "inside".to_string()
            } else {
                format!("**OUTSIDE** ({})", v.reasons.join("; "))
            };
            lines.push(format!(
                "- `{scene}` worn response, joint {}: {verdict}; slope |c'|/|e| ≤ {:.2}, \
                 conformity ≤ {:.2}",
                j.name, v.max_slope_ratio, v.max_conformity_ratio
            ));
        }
    }
    if !lines.is_empty() {
        md.push_str(
            "Validity of the worn geometry (docs/model.md §9; a worn response outside it is not a \
             result: its forces and deviations above only show what the model does there):\n\n",
        );
        for line in lines {
            let _ = writeln!(md, "{line}");
        }
        md.push('\n');
    }
}

/// A trend verdict for the summary.
#[derive(Debug, Clone)]
pub struct TrendVerdict {
    /// Study name.
    pub study: &'static str,
    /// The paper's claim.
    pub claim: String,
    /// Our verdict.
    pub verdict: Verdict,
    /// Quantities: how many grew, of how many.
    pub grew: usize,
    /// Number of quantities.
    pub total: usize,
}

fn trend_verdict(study: &'static str, claim: &str, c: &[Comparison]) -> TrendVerdict {
    TrendVerdict {
        study,
        claim: claim.to_string(),
        verdict: judge_trend(c),
        grew: c.iter().filter(|c| c.verdict() == Verdict::Holds).count(),
        total: c.len(),
    }
}

/// The trends of `results`' studies, with their comparisons.
pub fn trends(results: &StudyResults) -> Vec<(TrendVerdict, Vec<Comparison>, [String; 2])> {
    let mut out = Vec::new();
    for kind in &results.studies {
        let StudyKind::Paper(study) = kind else {
            continue;
        };
        let (claim, comparisons, labels) = match crate::scenes::physical_counterpart(study.name)
            .as_str()
        {
            "wear-stages" => {
                let Some(run) = study.scenes.get(1).and_then(|s| results.run(s)) else {
                    continue;
                };
                (
                    "second wear stage → deeper and more irregular wear than the first",
                    compare_stages(&run.outcome),
                    ["stage 1".to_string(), "stage 2".to_string()],
                )
            }
            _ => {
                let (Some(low), Some(high)) = (
                    study.scenes.first().and_then(|s| results.run(s)),
                    study.scenes.get(1).and_then(|s| results.run(s)),
                ) else {
                    continue;
                };
                let claim = if crate::scenes::physical_counterpart(study.name) == "clearance" {
                    "larger clearance → larger forces, deviations, dissipation and wear over a wider arc"
                } else {
                    "faster drive → larger forces, deviations, dissipation and wear over a wider arc"
                };
                (
                    claim,
                    compare_runs(&low.outcome, &high.outcome),
                    [low.key.clone(), high.key.clone()],
                )
            }
        };
        out.push((
            trend_verdict(study.name, claim, &comparisons),
            comparisons,
            labels,
        ));
    }
    out
}

fn extrapolation_section(
    md: &mut String,
    out: &Path,
    results: &StudyResults,
) -> Result<(), OutputError> {
    let (Some(adaptive), Some(single)) = (
        results.run(crate::scenes::DEFAULT),
        results.run(SINGLE_JUMP_RUN),
    ) else {
        return Ok(());
    };
    let _ = writeln!(
        md,
        "## Study `{EXTRAPOLATION}`: one wear stage, adaptive sub-steps vs the paper's single jump\n\n\
         The default LGRES after one stage (2 million cycles). The single jump multiplies the \
         wear of K simulated cycles by the whole amplification at once (the paper's scheme); \
         the adaptive scheme splits the stage into sub-steps, each changing any local clearance \
         by at most {:.0} %, re-simulating K cycles on the worn surfaces in between (MODEL §8).\n",
        100.0 * adaptive.outcome.scene.run.max_clearance_change
    );
    let _ = writeln!(
        md,
        "| joint | scheme | sub-steps | bearing peak | pin peak | worn volume (mm³) | worn arc (deg) | bearing ranges | pin ranges |\n|---|---|---|---|---|---|---|---|---|"
    );
    let schemes = [("adaptive", adaptive), ("single jump", single)];
    for (k, h) in adaptive.outcome.wear.iter().enumerate() {
        for (label, run) in schemes {
            let Some(m) = final_wear(&run.outcome).into_iter().nth(k) else {
                continue;
            };
            let substeps = run
                .outcome
                .summary
                .wear
                .as_ref()
                .map_or("—".into(), |w| format!("{:?}", w.substeps_per_stage));
            let _ = writeln!(
                md,
                "| {} | {label} | {substeps} | {:.1} µm at {:.0}° | {:.1} µm at {:.0}° | {:.3} | {:.0} | {} | {} |",
                h.name,
                m.bearing.peak_m * 1e6,
                m.bearing.peak_deg,
                m.pin.peak_m * 1e6,
                m.pin.peak_deg,
                m.volume_m3 * 1e9,
                m.arc_deg(),
                ranges_text(&m.bearing.ranges_deg),
                ranges_text(&m.pin.ranges_deg)
            );
        }
    }
    md.push('\n');
    let warnings: Vec<&String> = single
        .outcome
        .summary
        .wear
        .iter()
        .flat_map(|w| &w.warnings)
        .collect();
    if warnings.is_empty() {
        md.push_str("The single jump raised no warning.\n\n");
    } else {
        md.push_str("The single jump's warning:\n\n");
        for w in warnings {
            let _ = writeln!(md, "> {w}");
        }
        md.push('\n');
    }
    let files = overlay(
        out,
        EXTRAPOLATION,
        "One stage, adaptive vs single jump",
        &[
            ("adaptive".into(), stage_surfaces(&adaptive.outcome, None)),
            ("single jump".into(), stage_surfaces(&single.outcome, None)),
        ],
    )?;
    figure_links(md, out, &files);
    md.push_str("Per-scene outputs:\n\n");
    scene_links(md, out, adaptive);
    scene_links(md, out, single);
    md.push('\n');
    Ok(())
}

/// Writes `<out>/report.md` (atomically) and its study figures; returns the report's path.
pub fn write_report(results: &StudyResults, out: &Path) -> Result<PathBuf, OutputError> {
    let o = &results.options;
    let mut md = String::new();
    let names: Vec<&str> = results.studies.iter().map(StudyKind::name).collect();
    let represented = results
        .runs
        .iter()
        .find_map(|r| r.outcome.summary.wear.as_ref())
        .map_or(0.0, |w| w.cycles_represented_per_stage);
    let _ = writeln!(
        md,
        "# Study report: {}\n\n\
         - Runs: {} scene run(s), wall time {:.0} s (simulation and files; the report's figures \
         add a few seconds).\n\
         - Response: {} drive cycles per scene, on unworn surfaces (pins concentric at t = 0) and \
         again on the worn surfaces after the stages.\n\
         - Wear, physical formulation (material sliding): **K = {} simulated cycles per \
         stage**, the amplification rescaled so a stage stands for {:.3e} cycles, applied in \
         adaptive sub-steps; a stage ends early where the worn geometry reaches the contact \
         model's slope limit (docs/model.md §9.3; the cycles it applied are listed with the \
         validity). Paper's formulation (`*-paper` studies, wear on δφ̇): the paper's own \
         staging, K = 100 and one jump ×20 000. Wear is gathered after the start-up window.\n\
         - Judging (MODEL §8, the dynamics are chaotic): per-cycle medians of peak force after \
         the start-up window (noise: mean IQR), rod-3 maximum deviation after the window, \
         energy dissipated per cycle, worn volume and worn arc (depth ≥ {ARC_FRACTION}·peak). A \
         quantity changes when it moves by more than its noise and {:.0} %; a trend HOLDS when \
         most of its quantities move the paper's way and none the other way, DOES NOT HOLD in \
         the mirror case, else INCONCLUSIVE.\n",
        names.join(", "),
        results.runs.len(),
        results.wall_time_s,
        o.response_cycles,
        o.cycles_per_stage,
        represented,
        100.0 * RELATIVE_MARGIN
    );

    let trend_list = trends(results);
    if !trend_list.is_empty() {
        md.push_str("## Verdicts\n\n| study | paper's trend | ours | quantities grown |\n|---|---|---|---|\n");
        for (t, _, _) in &trend_list {
            let _ = writeln!(
                md,
                "| {} | {} | **{}** | {}/{} |",
                t.study, t.claim, t.verdict, t.grew, t.total
            );
        }
        md.push('\n');
    }

    for kind in &results.studies {
        let StudyKind::Paper(study) = kind else {
            continue;
        };
        let _ = writeln!(
            md,
            "## Study `{}`: {}\n\nScenes: {}.\n",
            study.name,
            study.summary,
            study.scenes.join(", ")
        );
        paper_section(&mut md, study.name, study.scenes, results);
        validity_lines(&mut md, study.scenes, results);
        if let Some((t, comparisons, [low, high])) =
            trend_list.iter().find(|(t, _, _)| t.study == study.name)
        {
            let _ = writeln!(md, "**Trend: {}: {}.**\n", t.claim, t.verdict);
            comparison_table(&mut md, low, high, comparisons);
            md.push('\n');
        }
        let stages_study = crate::scenes::physical_counterpart(study.name) == "wear-stages";
        let cases: Vec<(String, Vec<JointMetricsSource<'_>>)> = if stages_study {
            study
                .scenes
                .get(1)
                .and_then(|s| results.run(s))
                .map(|r| {
                    vec![
                        ("stage 1".to_string(), stage_surfaces(&r.outcome, Some(0))),
                        ("stage 2".to_string(), stage_surfaces(&r.outcome, Some(1))),
                    ]
                })
                .unwrap_or_default()
        } else {
            study
                .scenes
                .iter()
                .filter_map(|s| results.run(s))
                .map(|r| (r.key.clone(), stage_surfaces(&r.outcome, None)))
                .collect()
        };
        if !cases.is_empty() {
            let files = overlay(out, study.name, study.summary, &cases)?;
            figure_links(&mut md, out, &files);
        }
        md.push_str("Per-scene outputs:\n\n");
        for s in study.scenes {
            if let Some(run) = results.run(s) {
                scene_links(&mut md, out, run);
            }
        }
        md.push('\n');
    }
    if results
        .studies
        .iter()
        .any(|k| matches!(k, StudyKind::Extrapolation))
    {
        extrapolation_section(&mut md, out, results)?;
    }
    md.push_str(WHY_DIFFERENT);
    let path = out.join("report.md");
    write_atomic(&path, md.as_bytes())?;
    Ok(path)
}

const WHY_DIFFERENT: &str = "## Why our numbers differ from the paper's\n\n\
- **Geometry is a reconstruction** (docs/model.md §6): link lengths and joint positions are \
inferred from the paper's figures, so forces and deviations are comparable in order of \
magnitude, not digit for digit.\n\
- **Wear magnitude**: with `K_d = 1.8e-13 m²/N` as printed, one cycle wears ~1e-10–1e-9 m, so \
a stage of 2 million cycles is tenths of a millimetre to millimetres (MODEL §8), far above the \
paper's figures, which themselves differ 10× between §4.2.1 and §4.2.2 for the same case. Our \
worn response therefore runs in much larger clearances than the paper's.\n\
- **Chaos**: the journal paths separate within a fraction of a cycle; single peak forces move \
by tens of percent with tolerances. We judge on medians over cycles, deviations, dissipation \
and wear integrals, not on single peaks.\n\
- **K reduced**: K simulated cycles per stage instead of 100 gather wear over fewer impacts, \
so the profile is noisier; the adaptive sub-steps re-simulate between extrapolations, which \
the paper's single jump does not.\n\
- **Start-up**: the paper does not say whether its peaks include the concentric start-up \
impact; ours exclude the first window (the run's `summary.json` has both).\n";
