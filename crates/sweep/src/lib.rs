//! Parameter sweeps of scenes: vary scene fields over a grid or random distributions, run each
//! sample like `wearsim run`, and keep one row per sample (inputs, chosen `summary.json`
//! numbers, status, wall time).
//!
//! A sweep file (TOML) names a base scene, the fields to vary as dotted paths into the scene
//! (arrays of tables addressed by `name`: `clearance_joints.A.clearance`,
//! `drivers.drive.law.rpm`), and the metrics as paths into `summary.json`:
//!
//! ```toml
//! scene = "lgres"            # a built-in scene, or a file relative to the sweep file
//! samples = 16               # random sweeps: the sample count and the seed
//! seed = 7
//! metrics = ["wear.joints.A.bearing_peak_depth_m", "wear.joints.B.bearing_peak_depth_m"]
//!
//! [run]                      # as wearsim run's flags: cycles, stages, rtol, cycles_per_stage, …
//! cycles = 1
//! stages = 1
//!
//! [[vary]]
//! path = ["clearance_joints.A.clearance", "clearance_joints.B.clearance"]  # one value, both
//! name = "clearance"
//! distribution = "uniform"   # low, high | normal: mean, sd | log-normal: median, sigma (of ln)
//! low = 2e-4
//! high = 5e-4
//! ```
//!
//! A grid gives every input `values = [...]` and runs every combination (the last input
//! varies fastest). An integer field of the scene (`run.cycles`, `clearance_joints.A.wear.cells`)
//! takes whole numbers in its type's range only: another grid value, or a distribution on it,
//! makes the sweep file bad input; nothing is rounded. A sample whose metric is NaN or infinite
//! is a failed row, and `--resume` runs again a row holding one. A varied path that the run
//! settings set in every sample (a field the `[run]` table gives; `run.trajectories` unless it
//! gives `cycles_per_stage`) is refused, so a row's inputs are what its run took; each row
//! records the base scene and `[run]` settings it ran with ([`Sweep::settings_id`]), and a
//! resume refuses rows of other settings. A random sample's values depend on the seed and the sample's index only
//! (a ChaCha stream per sample), so any engine, thread or worker count gives the same rows.
//! [`Sweep::run_sample`] runs one sample (what a Dask task calls); [`run_local`] runs all on
//! local threads and writes `samples.csv` after every finished sample (atomically), so an
//! interrupted sweep resumes ([`LocalOptions::resume`]) where it stopped; [`write_outputs`]
//! writes the rows of any engine the one same way, with the figures.
//!
//! ```
//! let text = r#"
//!     scene = "slider-crank"
//!     metrics = ["response.joints.rod-slider.max_penetration_m"]
//!     [run]
//!     cycles = 1
//!     [[vary]]
//!     path = "clearance_joints.rod-slider.clearance"
//!     values = [4e-4, 5e-4]
//! "#;
//! let sweep = sweep::Sweep::from_str(text, "doc")?;
//! assert_eq!(sweep.samples(), 2);
//! assert_eq!(sweep.input_values(1), vec![5e-4]);
//! # Ok::<(), sweep::SweepError>(())
//! ```

mod definition;
mod error;
pub mod figures;
pub mod life;
mod life_columns;
pub mod page;
pub mod path;
mod plan;
mod row;
mod spec;
pub mod table;

use std::path::{Path, PathBuf};
use std::sync::atomic::{AtomicBool, AtomicUsize, Ordering};
use std::sync::mpsc;
use std::time::{Duration, Instant};

use output::files::OutputError;

pub use definition::{Input, Mode, Sampler};
pub use error::{SampleError, SweepError};
pub use life_columns::{LifeColumns, joint_metrics, life_metrics};
pub use plan::{MAX_SWEEP_FILE_BYTES, Sweep};
pub use row::{Row, Status};
pub use spec::MAX_SAMPLES;
pub use table::MAX_ROWS_FILE_BYTES;

/// Settings of [`run_local`].
#[derive(Debug, Clone)]
pub struct LocalOptions {
    /// Samples run at once, one thread each (results do not depend on it).
    pub jobs: usize,
    /// Keep the rows already in `samples.csv` and run only the missing samples.
    pub resume: bool,
}

impl Default for LocalOptions {
    fn default() -> Self {
        LocalOptions {
            jobs: std::thread::available_parallelism().map_or(1, usize::from),
            resume: false,
        }
    }
}

/// The rows file in an output folder.
pub fn rows_path(out: &Path) -> PathBuf {
    out.join(table::ROWS_FILE)
}

/// Samples still to run: all, or with `resume` those without a finished row in `out`'s rows
/// file (which must have this sweep's columns). Also returns the rows kept. A row `ok` with a
/// NaN or infinite metric (an older version's, or an edited file's) is not finished: it is
/// dropped and its sample run again. Resuming, whatever is at the rows file's path is read as
/// one ([`table::read_rows`]: a regular file, of bounded size), not passed over: a FIFO, a
/// directory or a link to nothing is refused, not replaced by a fresh file.
pub fn pending(
    sweep: &Sweep,
    out: &Path,
    resume: bool,
) -> Result<(Vec<usize>, Vec<Row>), SweepError> {
    let path = rows_path(out);
    let mut kept = if resume && std::fs::symlink_metadata(&path).is_ok() {
        table::read_rows(sweep, &path)?
    } else {
        Vec::new()
    };
    kept.retain(Row::is_done);
    let mut done = vec![false; sweep.samples()];
    for r in &kept {
        if let Some(d) = done.get_mut(r.sample) {
            *d = true;
        }
    }
    let todo = (0..sweep.samples()).filter(|k| !done[*k]).collect();
    Ok((todo, kept))
}

/// Run every sample (or, resuming, the missing ones) on `options.jobs` threads. `samples.csv`
/// in `out` is rewritten (atomically) as rows finish, at most once a second, and once at the
/// end with the figures. `on_row` sees each row as it finishes, with the count done and the
/// total. `stop` set by another thread ends the sweep after the samples under way.
pub fn run_local(
    sweep: &Sweep,
    out: &Path,
    options: &LocalOptions,
    stop: Option<&AtomicBool>,
    on_row: &mut dyn FnMut(&Row, usize, usize),
) -> Result<Vec<Row>, SweepError> {
    let (todo, mut rows) = pending(sweep, out, options.resume)?;
    if !todo.is_empty() {
        // From here the folder holds this sweep's rows only (those kept when resuming).
        remove_drawn_outputs(out)?;
        table::write_rows(sweep, &rows, &rows_path(out))?;
    }
    let total = sweep.samples();
    let next = AtomicUsize::new(0);
    let jobs = options.jobs.max(1).min(todo.len().max(1));
    let mut written = Instant::now();
    let mut write_error = None;
    std::thread::scope(|scope| {
        let (tx, rx) = mpsc::channel::<Row>();
        for _ in 0..jobs {
            let tx = tx.clone();
            let (todo, next) = (&todo, &next);
            scope.spawn(move || {
                loop {
                    if stop.is_some_and(|s| s.load(Ordering::Relaxed)) {
                        break;
                    }
                    let Some(&index) = todo.get(next.fetch_add(1, Ordering::Relaxed)) else {
                        break;
                    };
                    if tx.send(sweep.run_sample(index)).is_err() {
                        break;
                    }
                }
            });
        }
        drop(tx);
        for row in rx {
            on_row(&row, rows.len() + 1, total);
            rows.push(row);
            if write_error.is_none() && written.elapsed() >= Duration::from_secs(1) {
                written = Instant::now();
                if let Err(e) = table::write_rows(sweep, &rows, &rows_path(out)) {
                    write_error = Some(e);
                }
            }
        }
    });
    if let Some(e) = write_error {
        return Err(e.into());
    }
    rows.sort_by_key(|r| r.sample);
    write_outputs(sweep, &rows, out)?;
    Ok(rows)
}

/// Removes the page and figures of an earlier sweep in `out` before new rows are written:
/// they were drawn from the earlier rows, and must not sit beside rows they do not show (an
/// interrupted sweep leaves its rows alone; the end of a sweep draws them again).
fn remove_drawn_outputs(out: &Path) -> Result<(), SweepError> {
    for name in [
        page::PAGE_FILE,
        figures::SCATTER_FILE,
        figures::HISTOGRAMS_FILE,
        life::LIFE_FILE,
    ] {
        let path = out.join(name);
        match std::fs::remove_file(&path) {
            Err(e) if e.kind() != std::io::ErrorKind::NotFound => {
                return Err(OutputError::Io { path, source: e }.into());
            }
            _ => {}
        }
    }
    Ok(())
}

/// Write the rows (of any engine), the figures and the page showing both (`samples.html`) into
/// `out`; returns the files written. The
/// one writer of every engine, so the same rows give the same bytes.
pub fn write_outputs(sweep: &Sweep, rows: &[Row], out: &Path) -> Result<Vec<PathBuf>, SweepError> {
    let mut rows = rows.to_vec();
    rows.sort_by_key(|r| r.sample);
    rows.dedup_by_key(|r| r.sample);
    let mut files = vec![table::write_rows(sweep, &rows, &rows_path(out))?];
    let mut figures = figures::draw(sweep, &rows, out)?;
    let life = life::combine(sweep, &rows);
    if let Some(sampled) = life.as_ref().and_then(|l| l.distributions.as_ref()) {
        let path = out.join(life::LIFE_FILE);
        output::life_plot::life_distribution(
            &path,
            &format!(
                "Sweep {}: life to the clearance limit over the samples' inputs and k_d scatter",
                sweep.name
            ),
            output::plot::DEFAULT_SIZE,
            sampled,
        )?;
        figures.push(path);
    }
    files.push(page::write_page(
        sweep,
        &rows,
        &figures,
        life.as_ref(),
        out,
    )?);
    files.extend(figures);
    Ok(files)
}
