//! `samples.html`: a sweep on one self-contained page (figures embedded, see
//! [`output::html`]): what was varied and measured, how many samples ran, the figures and
//! the rows table as `samples.csv` holds it.

use std::path::{Path, PathBuf};

use output::files::OutputError;
use output::html::{Html, Td};

use crate::life::{LIFE_FILE, RESAMPLES, SweepLife};
use crate::table::{self, Status};
use crate::{Mode, Row, Sweep};

/// The page's file name in a sweep's folder.
pub const PAGE_FILE: &str = "samples.html";

/// Writes `<out>/samples.html` for `rows` (sorted by sample), embedding the `figures`.
pub fn write_page(
    sweep: &Sweep,
    rows: &[Row],
    figures: &[PathBuf],
    life: Option<&SweepLife>,
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
    // A sweep's lives first: what a maintenance engineer came for.
    if let Some(life) = life {
        life_section(&mut html, sweep, life, figures)?;
    }
    if figures.iter().any(|f| !f.ends_with(LIFE_FILE)) {
        html.heading(2, "Figures");
        for f in figures {
            let name = f
                .file_name()
                .map(|n| n.to_string_lossy().into_owned())
                .unwrap_or_default();
            if name == LIFE_FILE {
                continue;
            }
            let caption = if name.starts_with("scatter") {
                "Every metric (rows) against every input (columns), with ± one noise as a bar \
                 where the sweep keeps a metric's noise: a trend is a slope, scatter at one \
                 input value is the chaotic dynamics' noise."
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

/// The combined life to the clearance limit: what it is, the figure, the B lives.
fn life_section(
    html: &mut Html,
    sweep: &Sweep,
    life: &SweepLife,
    figures: &[PathBuf],
) -> Result<(), OutputError> {
    html.heading(2, "Life to the clearance limit");
    let weights = match sweep.mode {
        Mode::Grid { .. } => {
            "a grid: the mixture weighs every grid point equally, as if the inputs were \
             uniform over the grid"
        }
        Mode::Random { .. } => "random samples: the mixture is over the inputs' distributions",
    };
    let correlation = life.correlation.name();
    html.lede(&format!(
        "The cycles to a largest local clearance of {:.3} mm. Each sample's joints reach it \
         after a lognormal number of cycles (median the simulated one, the standard deviation \
         of ln k_d its k_d scatter: exact from the one simulated life, since Archard wear is \
         linear in k_d); a mechanism's life is its first joint's ({correlation} k_d scatter \
         between the joints, run.k_d_correlation). The samples' distributions are averaged \
         with equal weights ({weights}). ± is the bootstrap over the {} samples used \
         ({RESAMPLES} resamples) and each sample's own sampling noise, in quadrature.",
        1e3 * life.limit_m,
        life.used.len()
    ));
    if !life.not_reached.is_empty() {
        html.paragraph(&format!(
            "Not combined: sample(s) {:?} ran but a joint did not reach the limit (its life is \
             longer than the run and not known; raise run.max_cycles in the scene, or run \
             with run.until_limit).",
            life.not_reached
        ));
    }
    let Some(sampled) = &life.distributions else {
        return Ok(());
    };
    if let Some(f) = figures.iter().find(|f| f.ends_with(LIFE_FILE)) {
        html.figure(
            f,
            LIFE_FILE,
            &format!(
                "{LIFE_FILE}: the fraction of joints (and mechanisms) that reached the limit by \
                 a number of drive cycles, over the samples' inputs and k_d scatter; circles \
                 mark B10, squares B50."
            ),
        )?;
    }
    let text = sim::life_distribution::cycles_with_noise;
    let rows: Vec<Vec<Td>> = sampled
        .curves
        .iter()
        .map(|c| {
            vec![
                Td::text(c.of.label()),
                Td::num(text(c.lives.b10_cycles, c.lives.b10_noise)),
                Td::num(text(c.lives.b50_cycles, c.lives.b50_noise)),
            ]
        })
        .collect();
    html.table(&["life of", "B10 cycles", "B50 cycles"], &rows);
    Ok(())
}
