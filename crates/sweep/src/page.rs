//! `samples.html`: a sweep on one self-contained page (figures embedded, see
//! [`output::html`]): what was varied and measured, how many samples ran, the figures and
//! the rows table as `samples.csv` holds it.

use std::path::{Path, PathBuf};

use output::files::OutputError;
use output::html::{Html, Td};

use crate::table::{self, Status};
use crate::{Mode, Row, Sweep};

/// The page's file name in a sweep's folder.
pub const PAGE_FILE: &str = "samples.html";

/// Writes `<out>/samples.html` for `rows` (sorted by sample), embedding the `figures`.
pub fn write_page(
    sweep: &Sweep,
    rows: &[Row],
    figures: &[PathBuf],
    out: &Path,
) -> Result<PathBuf, OutputError> {
    let mut html = Html::new();
    html.heading(1, &format!("Sweep {}", sweep.name));
    let ok = rows
        .iter()
        .filter(|r| r.written_status() == Status::Ok)
        .count();
    let mode = match sweep.mode {
        Mode::Grid { samples } => format!("a grid of {samples} samples"),
        Mode::Random { samples, seed } => format!("{samples} random samples (seed {seed})"),
    };
    html.lede(&format!(
        "Scene {}, {mode}: {ok} of {} rows ran, {} failed. Rows are in samples.csv beside this \
         page; failed samples are left out of the figures.",
        sweep.scene_name,
        rows.len(),
        rows.len() - ok
    ));
    html.heading(2, "Inputs and metrics");
    let mut items: Vec<String> = sweep
        .inputs
        .iter()
        .map(|i| format!("input {}: sets {}", i.name, i.paths.join(", ")))
        .collect();
    items.extend(
        sweep
            .metrics
            .iter()
            .map(|m| format!("metric {m} (summary.json)")),
    );
    html.list(&items);
    if !figures.is_empty() {
        html.heading(2, "Figures");
        for f in figures {
            let name = f
                .file_name()
                .map(|n| n.to_string_lossy().into_owned())
                .unwrap_or_default();
            let caption = if name.starts_with("scatter") {
                "Every metric (rows) against every input (columns): a trend is a slope, scatter at \
                 one input value is the chaotic dynamics' noise."
            } else {
                "Histograms of the inputs drawn and the metrics they gave."
            };
            html.figure(f, &name, &format!("{name}: {caption}"))?;
        }
    }
    html.heading(2, "Rows");
    let body: Vec<Vec<Td>> = rows.iter().map(row_cells).collect();
    html.table(&table::header(sweep), &body);
    let path = out.join(PAGE_FILE);
    html.write_page(&path, &format!("wearsim sweep: {}", sweep.name))?;
    Ok(path)
}

/// One row's cells in the order of [`table::header`]; a missing or non-finite metric reads
/// `n/a`.
fn row_cells(r: &Row) -> Vec<Td> {
    let mut cells = vec![Td::num(r.sample.to_string())];
    cells.extend(r.inputs.iter().map(|v| Td::num(table::number(*v))));
    // Four significant digits read at a glance; samples.csv has every digit.
    cells.extend(
        r.metrics
            .iter()
            .map(|m| Td::num(m.map_or_else(|| "n/a".into(), |v| output::report::sig(v, 4)))),
    );
    let done = r.written_status() == Status::Ok;
    cells.push(Td::Verdict(if done { "ok" } else { "failed" }.into(), done));
    cells.push(Td::text(&r.error));
    cells.push(Td::num(format!("{:.3} s", r.wall_time_s)));
    cells
}
