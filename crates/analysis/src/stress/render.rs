//! The battery's report: CSV and a markdown table.

use std::fmt::Write as _;
use std::path::{Path, PathBuf};

use super::{CaseResult, Outcome};
use output::files::{OutputError, sci, write_atomic};

/// A number for the CSV: NaN means "not measured" (see [`CaseResult`]) and is left empty, so
/// no `ok` row reads `NaN`; an infinity (only in a failed case) stays visible.
fn cell(x: f64) -> String {
    if x.is_nan() {
        String::new()
    } else {
        x.to_string()
    }
}

fn peaks(r: &CaseResult, sep: &str) -> String {
    if r.peak_normal_force_n.is_empty() {
        return "-".into();
    }
    r.peak_normal_force_n
        .iter()
        .map(|(n, f)| {
            if f.is_finite() {
                format!("{n} {:.1}", f * 1e-3)
            } else {
                format!("{n} -")
            }
        })
        .collect::<Vec<_>>()
        .join(sep)
}

/// The results as CSV (one row a case; peaks in N, one column per joint name seen; a number
/// not measured is an empty cell).
pub fn csv(results: &[CaseResult]) -> String {
    let mut joints: Vec<String> = Vec::new();
    for r in results {
        for (n, _) in &r.peak_normal_force_n {
            if !joints.contains(n) {
                joints.push(n.clone());
            }
        }
    }
    let quote = |s: &str| format!("\"{}\"", s.replace('"', "\"\""));
    let mut out = String::from(
        "case,outcome,duration_s,steps,rejected_steps,newton_failures,smallest_step_s,events,\
         drift_position,energy_residual_j,energy_relative_residual,atol_position_m",
    );
    for j in &joints {
        let _ = write!(out, ",peak_normal_force_{j}_n");
    }
    out.push_str(",wall_time_s,detail\n");
    for r in results {
        let _ = write!(
            out,
            "{},{},{},{},{},{},{},{},{},{},{},{}",
            quote(&r.name),
            r.outcome.label(),
            cell(r.duration_s),
            r.steps,
            r.rejected_steps,
            r.newton_failures,
            cell(r.smallest_step_s),
            r.events,
            cell(r.drift_position),
            cell(r.energy_residual_j),
            cell(r.energy_relative_residual),
            cell(r.atol_position_m)
        );
        for j in &joints {
            let f = r
                .peak_normal_force_n
                .iter()
                .find(|(n, _)| n == j)
                .map_or(f64::NAN, |(_, f)| *f);
            let _ = write!(out, ",{}", cell(f));
        }
        let _ = writeln!(out, ",{:.3},{}", r.wall_time_s, quote(&r.outcome.detail()));
    }
    out
}

/// The results as a markdown table plus the failure/error details below it.
pub fn markdown(results: &[CaseResult]) -> String {
    let mut out = String::from(
        "| case | outcome | sim. time (s) | steps | rejected | smallest step (s) | drift \\|Φ\\| | \
         energy residual (J) | rel. residual | peak F_n (kN) | wall (s) |\n\
         |---|---|---:|---:|---:|---:|---:|---:|---:|---|---:|\n",
    );
    for r in results {
        let ran = !matches!(
            r.outcome,
            Outcome::Skipped { .. } | Outcome::ExpectedError { .. }
        ) && r.steps > 0;
        let count = |n: usize| if ran { n.to_string() } else { "-".into() };
        let _ = writeln!(
            out,
            "| {} | {} | {:.1} | {} | {} | {} | {} | {} | {} | {} | {:.2} |",
            r.name,
            r.outcome.label(),
            r.duration_s,
            count(r.steps),
            count(r.rejected_steps),
            sci(r.smallest_step_s, 1),
            sci(r.drift_position, 1),
            sci(r.energy_residual_j, 2),
            sci(r.energy_relative_residual, 1),
            peaks(r, ", "),
            r.wall_time_s
        );
    }
    let worn: Vec<&CaseResult> = results
        .iter()
        .filter(|r| !r.wear_depth_m.is_empty())
        .collect();
    if !worn.is_empty() {
        out.push_str(
            "\nWear accumulated on every accepted step (surfaces frozen during the run, so the \
             dynamics do not depend on the grid): deepest cell and grid/Archard volume ratio\n\n",
        );
        for r in worn {
            let parts: Vec<String> = r
                .wear_depth_m
                .iter()
                .zip(&r.wear_volume_ratio)
                .map(|((n, d), (_, v))| format!("{n} {d:.2e} m, ratio {v:.4}"))
                .collect();
            let _ = writeln!(out, "- {}: {}", r.name, parts.join("; "));
        }
    }
    let notes: Vec<&CaseResult> = results
        .iter()
        .filter(|r| !matches!(r.outcome, Outcome::Completed))
        .collect();
    if !notes.is_empty() {
        out.push('\n');
        for r in notes {
            let _ = writeln!(
                out,
                "- **{}** ({}): {}",
                r.name,
                r.outcome.label(),
                r.outcome.detail()
            );
        }
    }
    out
}

/// Writes `stress.csv`, `stress.md` and `stress.json` into `dir`; returns their paths.
pub fn write_report(results: &[CaseResult], dir: &Path) -> Result<Vec<PathBuf>, OutputError> {
    let files = [
        (dir.join("stress.csv"), csv(results)),
        (dir.join("stress.md"), markdown(results)),
    ];
    let mut paths = Vec::new();
    for (path, text) in files {
        write_atomic(&path, text.as_bytes())?;
        paths.push(path);
    }
    let json = dir.join("stress.json");
    output::files::write_json(&json, &results)?;
    paths.push(json);
    Ok(paths)
}
