//! The rows of a sweep and their CSV file: `sample`, one column per input, one per metric,
//! `status`, `error`, `settings` (what the row ran with besides its inputs), `wall_time_s`.
//! Numbers are written in the shorter of plain and scientific notation, both exact (they read back to the same bits); an empty cell is a
//! metric the sample has no value for.

use std::path::{Path, PathBuf};

use output::files::{AtomicFile, OutputError};

pub use crate::row::{FIXED_COLUMNS, Row, Status, number};
use crate::{Sweep, SweepError};

/// The rows file's name in a sweep's output folder.
pub const ROWS_FILE: &str = "samples.csv";

/// Largest rows file read back, bytes (a million samples' rows fit): a longer one is refused
/// before it is read.
pub const MAX_ROWS_FILE_BYTES: u64 = 1 << 30;

/// The header of `sweep`'s rows file.
pub fn header(sweep: &Sweep) -> Vec<String> {
    let mut h = vec![FIXED_COLUMNS[0].to_string()];
    h.extend(sweep.inputs.iter().map(|i| i.name.clone()));
    h.extend(sweep.metrics.iter().cloned());
    h.extend(FIXED_COLUMNS[1..].iter().map(ToString::to_string));
    h
}

/// Write `rows` (in the order given) to `path`, atomically. No NaN or infinity is written as a
/// metric: such a cell is left empty and an `ok` row holding one is written as failed, naming
/// the metric (whatever engine made the row, the file never shows `ok` beside a non-number).
pub fn write_rows(sweep: &Sweep, rows: &[Row], path: &Path) -> Result<PathBuf, OutputError> {
    let csv_err = |source| OutputError::Csv {
        path: path.to_path_buf(),
        source,
    };
    let settings = sweep.settings_id();
    let mut w = csv::Writer::from_writer(AtomicFile::create(path)?);
    w.write_record(header(sweep)).map_err(csv_err)?;
    for r in rows {
        let mut cells = vec![r.sample.to_string()];
        cells.extend(r.inputs.iter().map(|v| number(*v)));
        cells.extend(
            r.metrics
                .iter()
                .map(|m| m.filter(|v| v.is_finite()).map(number).unwrap_or_default()),
        );
        cells.push(r.written_status().as_str().to_string());
        cells.push(match r.non_finite_ok_metric() {
            Some((k, v)) => {
                let name = sweep.metrics.get(k).map_or("?", String::as_str);
                format!("metric {name} is not finite ({v})")
            }
            None => r.error.clone(),
        });
        cells.push(settings.clone());
        cells.push(format!("{:.3}", r.wall_time_s));
        w.write_record(&cells).map_err(csv_err)?;
    }
    let file = w.into_inner().map_err(|e| OutputError::Io {
        path: path.to_path_buf(),
        source: std::io::Error::other(e.to_string()),
    })?;
    file.commit()
}

/// Read the rows of `sweep` back from `path` (for `--resume`): the header must be this
/// sweep's, each row's inputs those of its sample (the same file and seed) and its settings
/// this sweep's (the same base scene and `[run]` table), and no sample may have two rows. `path` must be a regular file (or a link to one) of at most
/// [`MAX_ROWS_FILE_BYTES`]: a FIFO would block the read, a device or a sparse giant would
/// fill the memory.
pub fn read_rows(sweep: &Sweep, path: &Path) -> Result<Vec<Row>, SweepError> {
    let fail = |reason: String| SweepError::Resume {
        path: path.to_path_buf(),
        reason,
    };
    let meta = std::fs::metadata(path).map_err(|e| fail(format!("cannot read it: {e}")))?;
    if !meta.is_file() {
        return Err(fail(
            "not a regular file (a directory, FIFO or device?): a rows file is one a sweep wrote"
                .into(),
        ));
    }
    let too_large = |len: u64| {
        fail(format!(
            "too large ({len} bytes; a rows file is at most {MAX_ROWS_FILE_BYTES})"
        ))
    };
    if meta.len() > MAX_ROWS_FILE_BYTES {
        return Err(too_large(meta.len()));
    }
    let file = std::fs::File::open(path).map_err(|e| fail(format!("cannot read it: {e}")))?;
    // Bounded even if the file grows while it is read.
    let mut r = csv::Reader::from_reader(std::io::Read::take(file, MAX_ROWS_FILE_BYTES + 1));
    let found: Vec<String> = r
        .headers()
        .map_err(|e| fail(e.to_string()))?
        .iter()
        .map(ToString::to_string)
        .collect();
    let expected = header(sweep);
    if found != expected {
        return Err(fail(format!(
            "its columns {found:?} are not this sweep's {expected:?} (another sweep's file?)"
        )));
    }
    let (ni, nm) = (sweep.inputs.len(), sweep.metrics.len());
    let mut rows = Vec::new();
    // The row (from 1) of each sample read so far; 0: none yet.
    let mut row_of = vec![0usize; sweep.samples()];
    let mut records = r.records();
    for (line, record) in records.by_ref().enumerate() {
        let record = record.map_err(|e| fail(e.to_string()))?;
        let at = |k: usize| record.get(k).unwrap_or_default();
        let bad = |k: usize| {
            fail(format!(
                "row {}: column {:?}: {:?} is not a number",
                line + 1,
                expected[k],
                at(k)
            ))
        };
        let num = |k: usize| at(k).parse::<f64>().map_err(|_| bad(k));
        let sample = at(0).parse::<usize>().map_err(|_| bad(0))?;
        if sample >= sweep.samples() {
            return Err(fail(format!(
                "row {}: sample {sample} is beyond the sweep's {}",
                line + 1,
                sweep.samples()
            )));
        }
        if row_of[sample] > 0 {
            return Err(fail(format!(
                "row {}: sample {sample} is there twice (rows {} and {})",
                line + 1,
                row_of[sample],
                line + 1
            )));
        }
        row_of[sample] = line + 1;
        let inputs = (1..=ni).map(num).collect::<Result<Vec<_>, _>>()?;
        if inputs != sweep.input_values(sample) {
            return Err(fail(format!(
                "row {}: sample {sample}'s inputs are not this sweep's (the file or seed changed?)",
                line + 1
            )));
        }
        let metrics = (ni + 1..=ni + nm)
            .map(|k| {
                if at(k).is_empty() {
                    Ok(None)
                } else {
                    num(k).map(Some)
                }
            })
            .collect::<Result<Vec<_>, _>>()?;
        let status = match at(ni + nm + 1) {
            "ok" => crate::Status::Ok,
            "failed" => crate::Status::Failed,
            other => {
                return Err(fail(format!(
                    "row {}: status {other:?} is neither ok nor failed",
                    line + 1
                )));
            }
        };
        let settings = ni + nm + 3;
        if at(settings) != sweep.settings_id() {
            return Err(fail(format!(
                "row {}: sample {sample} ran with other settings ({} {:?}, this sweep's {:?}): \
                 the base scene or the [run] table changed since; run without --resume or into \
                 another folder",
                line + 1,
                expected[settings],
                at(settings),
                sweep.settings_id()
            )));
        }
        // A duration: NaN or infinity would not survive a row's trip as JSON (`null`).
        let wall = ni + nm + 4;
        let wall_time_s = num(wall)?;
        if !(wall_time_s.is_finite() && wall_time_s >= 0.0) {
            return Err(fail(format!(
                "row {}: column {:?}: {:?} is not a duration (a finite number ≥ 0)",
                line + 1,
                expected[wall],
                at(wall)
            )));
        }
        rows.push(Row {
            sample,
            inputs,
            metrics,
            status,
            error: at(ni + nm + 2).to_string(),
            wall_time_s,
        });
    }
    let read = records.reader().position().byte();
    if read > MAX_ROWS_FILE_BYTES {
        return Err(too_large(read));
    }
    Ok(rows)
}
