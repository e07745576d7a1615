//! The study report (`report.md`, and `report.html` with its figures embedded): the paper's
//! numbers ([`lgres::paper`]) next to ours, the trend verdicts of [`super::judge`], the validity
//! notes and the figures.

use std::fmt::Write as _;
use std::path::{Path, PathBuf};

use wear::WornJoint;

use super::judge::{
    ARC_FRACTION, Comparison, JointMetrics, RANGE_FRACTION, RELATIVE_MARGIN, Verdict, final_wear,
    trends, wear_metrics,
};
use super::results::{SceneRun, StudyKind, StudyResults, relative};
use lgres::claim::Cases;
use lgres::paper::{PaperStudy, PaperValue, Quantity, paper};
use lgres::studies::{ExtrapolationStudy, Study};
use output::files::OutputError;
use output::plot::{self, DEFAULT_SIZE};
use sim::{ResponseSummary, RunOutcome};

const DEVIATIONS: [(&str, &str); 6] = [
    ("|Δx|", "m"),
    ("|Δy|", "m"),
    ("|Δvx|", "m/s"),
    ("|Δvy|", "m/s"),
    ("|Δax|", "m/s²"),
    ("|Δay|", "m/s²"),
];

fn deviation_value(r: &ResponseSummary, c: usize) -> f64 {
    r.deviation_after_transient.as_ref().map_or(f64::NAN, |d| {
        [d.x_m, d.y_m, d.vx_m_s, d.vy_m_s, d.ax_m_s2, d.ay_m_s2]
            .get(c)
            .copied()
            .unwrap_or(f64::NAN)
    })
}

fn quantity_label(v: &PaperValue, joints: &[String]) -> String {
    let j = v.index;
    let joint = || joints.get(j).cloned().unwrap_or_else(|| format!("#{j}"));
    match v.quantity {
        Quantity::Force => format!("peak F_n {}", joint()),
        Quantity::Deviation => {
            let (name, unit) = DEVIATIONS.get(j).copied().unwrap_or(("?", "?"));
            format!("rod 3 {name} ({unit})")
        }
        Quantity::Wear => format!("peak wear {}, ranges", joint()),
        Quantity::WearStage1 => format!("peak wear {} after stage 1, ranges", joint()),
    }
}

fn force_text(r: &ResponseSummary, j: usize) -> String {
    r.joints.get(j).map_or("—".into(), |s| {
        let Some(p) = &s.normal_force_after_transient else {
            return "n/a (the start-up window covers the run)".into();
        };
        let share = if p.elastic_share_median.is_finite() {
            let flag = if p.elastic_share_median < sim::MIN_ELASTIC_SHARE {
                ", MOSTLY DAMPING"
            } else {
                ""
            };
            format!("; elastic {:.0} %{flag}", 100.0 * p.elastic_share_median)
        } else {
            String::new()
        };
        format!(
            "max {:.1}; median {:.1} ± {:.1} (IQR {:.1}) kN{share}",
            p.max * 1e-3,
            p.cycle_median * 1e-3,
            p.cycle_median_noise * 1e-3,
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
        let [bearing_noise, pin_noise] = m.peak_noises();
        let depth = |peak: f64, noise: Option<f64>| match noise {
            Some(n) => format!("{:.1} ± {:.1} µm", peak * 1e6, n * 1e6),
            None => format!("{:.1} µm", peak * 1e6),
        };
        format!(
            "bearing {} at {:.0}° ({}); pin {} at {:.0}° ({})",
            depth(m.bearing.peak_m, bearing_noise),
            m.bearing.peak_deg,
            ranges_text(&m.bearing.ranges_deg),
            depth(m.pin.peak_m, pin_noise),
            m.pin.peak_deg,
            ranges_text(&m.pin.ranges_deg)
        )
    })
}

/// Our value(s) for a paper quantity: (unworn response, worn response or wear).
fn ours(run: &SceneRun, v: &PaperValue) -> (String, String) {
    let s = &run.outcome.summary;
    let j = v.index;
    match v.quantity {
        Quantity::Force => (
            force_text(&s.response, j),
            s.worn_response
                .as_ref()
                .map_or("—".into(), |w| force_text(w, j)),
        ),
        Quantity::Deviation => (
            format!("{:.3e}", deviation_value(&s.response, j)),
            s.worn_response
                .as_ref()
                .map_or("—".into(), |w| format!("{:.3e}", deviation_value(w, j))),
        ),
        Quantity::Wear => ("—".into(), wear_text(final_wear(&run.outcome).get(j))),
        Quantity::WearStage1 => ("—".into(), wear_text(wear_metrics(&run.outcome, 0).get(j))),
    }
}

fn fmt_value(v: f64) -> String {
    if !v.is_finite() {
        "n/a".into()
    } else if v == 0.0 || (1e-2..1e4).contains(&v.abs()) {
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
                // A single quantity is never judged in part.
                Verdict::Inconclusive | Verdict::HoldsInPart => "within noise",
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
        format!("[report]({dir}/report.html)"),
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

fn paper_section(md: &mut String, study: &Study, results: &StudyResults) {
    let studies = match paper() {
        Ok(studies) => studies,
        Err(e) => {
            let _ = writeln!(md, "(The paper's numbers are unavailable: {e}.)\n");
            return;
        }
    };
    let Some(PaperStudy {
        section, values, ..
    }) = studies.iter().find(|s| s.name == study.paper_name())
    else {
        return;
    };
    let _ = writeln!(
        md,
        "Paper's numbers (Ma, Jiang & Yin 2026, {section}) next to ours. Ours: forces are \
         after the {}-s start-up window, as the maximum and the median ± its bootstrap noise \
         (IQR) of per-cycle peaks, with the median elastic share of the peaks (the rest is the \
         contact law's damping; below 50 % the response is outside validity); deviations are maxima after the window; wear is the depth after the stage(s) \
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
        let Some(run) = study.scene_for(&v.scene).and_then(|s| results.run(s)) else {
            continue;
        };
        let names: Vec<String> = run
            .outcome
            .response
            .contact
            .iter()
            .map(|c| c.name.clone())
            .collect();
        let (unworn, worn) = ours(run, v);
        let _ = writeln!(
            md,
            "| {} | {} | {} | {unworn} | {worn} |",
            run.key,
            quantity_label(v, &names),
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
            let measures = v.measured();
            lines.push(format!(
                "- `{scene}` worn response, joint {}: {verdict}; {measures}",
                j.name
            ));
        }
    }
    if !lines.is_empty() {
        md.push_str(
            "Validity of the worn geometry (docs/model.md §9–10; a worn response outside it is not \
             a result: its forces and deviations above only show what the model does there):\n\n",
        );
        for line in lines {
            let _ = writeln!(md, "{line}");
        }
        md.push('\n');
    }
}

fn extrapolation_section(
    md: &mut String,
    out: &Path,
    study: &ExtrapolationStudy,
    results: &StudyResults,
) -> Result<(), OutputError> {
    let (Some(adaptive), Some(single)) =
        (results.run(study.scene), results.run(study.single_jump_run))
    else {
        return Ok(());
    };
    let _ = writeln!(
        md,
        "## Study `{}`: {}\n\n\
         The default LGRES after one stage (2 million cycles). The single jump multiplies the \
         wear of K simulated cycles by the whole amplification at once (the paper's scheme); \
         the adaptive scheme splits the stage into sub-steps, each changing any local clearance \
         by at most {:.0} %, re-simulating K cycles on the worn surfaces in between (docs/model.md §8).\n",
        study.name,
        study.summary,
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
        study.name,
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

/// Writes `<out>/report.md`, the same as the page `<out>/report.html` (both atomically) and
/// their study figures; returns the markdown report's path.
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
         adaptive sub-steps on the worn surfaces' contact named below (docs/model.md §10; a \
         stage on the line-of-centres contact would end early at its slope limit, and the cycles \
         it applied would be listed with the validity). Paper's formulation (`*-paper` studies, \
         wear on δφ̇): the paper's own \
         staging, K = 100 and one jump ×20 000. Wear is gathered after the start-up window.\n\
         - Judging (docs/model.md §8, the dynamics are chaotic): per-cycle medians of peak force after \
         the start-up window (noise: their bootstrap noises combined), rod-3 maximum deviation \
         after the window (noise: the jackknife over the cycles' maxima), energy dissipated per \
         cycle (noise: the spread of the whole cycles after the window over √cycles), worn \
         volume, peak depth and the depth's variation (noise: the jackknife over the wear \
         stage's batches, levelled as the life curves, docs/model.md §10.4), worn arc (depth ≥ \
         {ARC_FRACTION}·peak) and concentrated ranges, which move in jumps (noise: their spread \
         over surfaces one noise away, with Laplace's rule where none moved); the noise of a \
         change is √(σ_low² + σ_high²), n/a where a case measured none. A quantity changes when it moves by more than its noise and {:.0} %. A trend is \
         INCONCLUSIVE when at most half of its quantities change; otherwise it HOLDS when none \
         moves against the paper, HOLDS IN PART when more move with it than against, and DOES \
         NOT HOLD when at least as many move against it.\n",
        names.join(", "),
        results.runs.len(),
        results.wall_time_s,
        o.response_cycles,
        o.cycles_per_stage,
        represented,
        100.0 * RELATIVE_MARGIN
    );
    // What ran at the clearance joints, each distinct description once (with its scenes).
    let mut contacts: Vec<(String, Vec<&str>)> = Vec::new();
    for run in &results.runs {
        for contact in &run.outcome.summary.contacts {
            match contacts.iter_mut().find(|(c, _)| c == contact) {
                Some((_, keys)) => keys.push(&run.key),
                None => contacts.push((contact.clone(), vec![&run.key])),
            }
        }
    }
    for (contact, keys) in &contacts {
        let _ = writeln!(md, "- Contact {contact} (scenes: {}).", keys.join(", "));
    }
    md.push('\n');

    let trend_list = trends(results);
    if !trend_list.is_empty() {
        md.push_str(
            "## Verdicts\n\n| study | paper's trend | ours | quantities grown / shrunk / of |\n\
             |---|---|---|---|\n",
        );
        for (t, _, _) in &trend_list {
            let _ = writeln!(
                md,
                "| {} | {} | **{}** | {} / {} / {} |",
                t.study, t.claim, t.verdict, t.grew, t.shrank, t.total
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
        paper_section(&mut md, study, results);
        validity_lines(&mut md, study.scenes, results);
        if let Some((t, comparisons, [low, high])) =
            trend_list.iter().find(|(t, _, _)| t.study == study.name)
        {
            let _ = writeln!(md, "**Trend: {}: {}.**\n", t.claim, t.verdict);
            let against: Vec<&str> = comparisons
                .iter()
                .filter(|c| c.verdict() == Verdict::DoesNotHold)
                .map(|c| c.quantity.as_str())
                .collect();
            if !against.is_empty() {
                let _ = writeln!(md, "Against the paper: {}.\n", against.join("; "));
            }
            comparison_table(&mut md, low, high, comparisons);
            md.push('\n');
        }
        let cases: Vec<(String, Vec<JointMetricsSource<'_>>)> = match study.claim.cases {
            Cases::Stages {
                scene,
                first,
                second,
            } => results
                .run(scene)
                .map(|r| {
                    [first, second]
                        .iter()
                        .map(|n| {
                            let stage = Some(n.saturating_sub(1));
                            (format!("stage {n}"), stage_surfaces(&r.outcome, stage))
                        })
                        .collect()
                })
                .unwrap_or_default(),
            Cases::Scenes { .. } => study
                .scenes
                .iter()
                .filter_map(|s| results.run(s))
                .map(|r| (r.key.clone(), stage_surfaces(&r.outcome, None)))
                .collect(),
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
    for kind in &results.studies {
        if let StudyKind::Extrapolation(study) = kind {
            extrapolation_section(&mut md, out, study, results)?;
        }
    }
    md.push_str(lgres::paper::WHY_DIFFERENT);
    let title = format!("wearsim study: {}", names.join(", "));
    output::html::write_markdown_and_page(out, "report", &md, &title)
}
