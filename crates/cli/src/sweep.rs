//! `wearsim sweep FILE`: runs a sweep file through [`sweep::run_local`] with a progress bar;
//! rows go to `<out>/samples.csv` as they finish, the figures at the end.

use std::path::{Path, PathBuf};

use indicatif::{ProgressBar, ProgressDrawTarget, ProgressStyle};
use sweep::{LocalOptions, Status, Sweep};

use crate::error::CliError;
use crate::overrides::Overrides;

/// Runs the sweep in `file`; `resume` keeps the rows already written.
pub fn run(file: &Path, resume: bool, o: &Overrides) -> Result<(), CliError> {
    // The flags a sweep does not use were refused before (main's `Overrides::only`).
    let sweep = Sweep::from_path(file)?;
    let out = o
        .out
        .clone()
        .unwrap_or_else(|| PathBuf::from("out/sweep").join(&sweep.name));
    // The output folder is checked (and locked against a second sweep) before any sample runs.
    let _lock = output::files::FolderLock::take(&out)?;
    let mut options = LocalOptions {
        resume,
        ..LocalOptions::default()
    };
    if let Some(j) = o.jobs {
        options.jobs = j.get();
    }
    let (todo, _) = sweep::pending(&sweep, &out, resume)?;
    outln!(
        "sweep {}: {} samples of scene {} ({} to run, {} thread(s)), {} metric(s)",
        sweep.name,
        sweep.samples(),
        sweep.scene_name,
        todo.len(),
        options.jobs,
        sweep.metrics.len()
    );
    let on_terminal = crate::progress::on_terminal();
    let bar = ProgressBar::with_draw_target(
        Some((sweep.samples() - todo.len()) as u64),
        if on_terminal {
            ProgressDrawTarget::stderr()
        } else {
            ProgressDrawTarget::hidden()
        },
    );
    bar.set_length(sweep.samples() as u64);
    bar.set_position((sweep.samples() - todo.len()) as u64);
    if let Ok(style) = ProgressStyle::with_template("{bar:40} {pos}/{len} samples, {elapsed} {msg}")
    {
        bar.set_style(style);
    }
    let started = std::time::Instant::now();
    let mut throttle = crate::progress::Throttle::default();
    let rows = sweep::run_local(&sweep, &out, &options, None, &mut |row, _, _| {
        bar.inc(1);
        if row.status == Status::Failed {
            let failed = format!("sample {} failed: {}", row.sample, row.error);
            if on_terminal {
                bar.println(failed);
            } else {
                errln!("{failed}");
            }
        }
        // In a log: a line per finished sample, at most about one a second (and the last).
        let done = bar.position();
        if !on_terminal && (throttle.due() || done == sweep.samples() as u64) {
            errln!(
                "sweep {}: {done}/{} samples, {:.0} s",
                sweep.name,
                sweep.samples(),
                started.elapsed().as_secs_f64()
            );
        }
    })?;
    bar.finish_and_clear();
    let failed = rows.iter().filter(|r| r.status == Status::Failed).count();
    outln!(
        "{} rows ({} ok, {failed} failed) in {} in {:.1} s",
        rows.len(),
        rows.len() - failed,
        sweep::rows_path(&out).display(),
        started.elapsed().as_secs_f64()
    );
    Ok(())
}
