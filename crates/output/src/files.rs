//! Output files that are either complete or absent.
//!
//! Every writer here writes to a hidden temporary file in the target's folder and renames it
//! over the target only when done. Renaming within one folder is atomic, so an error, a panic or
//! Ctrl-C never leaves a half-written CSV, JSON or PNG where a reader expects a finished one (at
//! worst a stray `.name.tmp-<pid>` file).

use std::fs::{self, File};
use std::io::{self, BufWriter, Write};
use std::path::{Path, PathBuf};

use serde::Serialize;

pub use crate::error::OutputError;
pub(crate) use crate::error::io_err;
pub use crate::staged::{FolderLock, LeftBehind, StagedDir, abandon_staged, is_abandoned};
use crate::staged::{create_temp_unless_abandoned, create_unless_abandoned, forget_temp};

/// The temporary sibling of `target`; keeps the extension, since some writers (plotters) pick
/// the format from it.
fn temp_path(target: &Path) -> PathBuf {
    let name = target
        .file_name()
        .map(|n| n.to_string_lossy().into_owned())
        .unwrap_or_default();
    let ext = target
        .extension()
        .map(|e| format!(".{}", e.to_string_lossy()))
        .unwrap_or_default();
    target.with_file_name(format!(".{name}.tmp-{}{ext}", std::process::id()))
}

/// Create `target`'s folder if needed, let `write` fill the temporary path it is given, then
/// rename that over `target`. The temporary file is removed if `write` fails. For writers that
/// insist on opening the file themselves (plotters).
pub fn write_via_temp(
    target: &Path,
    write: impl FnOnce(&Path) -> Result<(), OutputError>,
) -> Result<(), OutputError> {
    let tmp = temp_path(target);
    create_temp_unless_abandoned(&tmp, || {
        if let Some(dir) = target.parent().filter(|d| !d.as_os_str().is_empty()) {
            fs::create_dir_all(dir).map_err(io_err(dir))?;
        }
        // Claim the temporary file now, under the lock: the writer that fills it may only
        // open an existing path's folder, never re-create one.
        File::create(&tmp).map(drop).map_err(io_err(&tmp))
    })?;
    let result = write(&tmp).and_then(|()| {
        create_unless_abandoned(|| fs::rename(&tmp, target).map_err(io_err(target)))
    });
    if result.is_err() {
        // Best effort: the error being reported matters more than a leftover temp file.
        let _ = fs::remove_file(&tmp);
    }
    forget_temp(&tmp);
    result
}

/// A file being written that appears at its path only on [`AtomicFile::commit`]; dropped
/// without commit, it vanishes.
pub struct AtomicFile {
    target: PathBuf,
    tmp: PathBuf,
    file: Option<BufWriter<File>>,
}

impl AtomicFile {
    /// Start writing `target` (its folder is created if needed).
    pub fn create(target: impl AsRef<Path>) -> Result<Self, OutputError> {
        let target = target.as_ref().to_path_buf();
        let tmp = temp_path(&target);
        let file = create_temp_unless_abandoned(&tmp, || {
            if let Some(dir) = target.parent().filter(|d| !d.as_os_str().is_empty()) {
                fs::create_dir_all(dir).map_err(io_err(dir))?;
            }
            File::create(&tmp).map_err(io_err(&tmp))
        })?;
        Ok(Self {
            target,
            tmp,
            file: Some(BufWriter::new(file)),
        })
    }

    /// Flush, sync and move into place.
    pub fn commit(mut self) -> Result<PathBuf, OutputError> {
        let target = self.target.clone();
        let file = self.file.take().map(BufWriter::into_inner);
        let moved = match file {
            Some(Ok(f)) => f.sync_all().map_err(io_err(&target)),
            Some(Err(e)) => Err(io_err(&target)(e.into_error())),
            None => Ok(()),
        }
        .and_then(|()| {
            // Under the lock: a file moved into a staging folder being removed would keep it.
            create_unless_abandoned(|| fs::rename(&self.tmp, &target).map_err(io_err(&target)))
        });
        if moved.is_err() {
            let _ = fs::remove_file(&self.tmp);
        }
        forget_temp(&self.tmp);
        moved.map(|()| target)
    }
}

impl Write for AtomicFile {
    fn write(&mut self, buf: &[u8]) -> io::Result<usize> {
        match &mut self.file {
            Some(f) => f.write(buf),
            None => Err(io::Error::other("file already committed")),
        }
    }
    fn flush(&mut self) -> io::Result<()> {
        self.file.as_mut().map_or(Ok(()), Write::flush)
    }
}

impl Drop for AtomicFile {
    fn drop(&mut self) {
        if self.file.take().is_some() {
            let _ = fs::remove_file(&self.tmp);
            forget_temp(&self.tmp);
        }
    }
}

/// Write `bytes` to `target` atomically.
pub fn write_atomic(target: impl AsRef<Path>, bytes: &[u8]) -> Result<(), OutputError> {
    let target = target.as_ref();
    let mut f = AtomicFile::create(target)?;
    f.write_all(bytes).map_err(io_err(target))?;
    f.commit().map(|_| ())
}

/// Write `value` as pretty JSON to `target` atomically (run summaries).
pub fn write_json(target: impl AsRef<Path>, value: &impl Serialize) -> Result<(), OutputError> {
    let target = target.as_ref();
    let mut text = serde_json::to_string_pretty(value).map_err(|source| OutputError::Json {
        path: target.to_path_buf(),
        source,
    })?;
    text.push('\n');
    write_atomic(target, text.as_bytes())
}

/// A CSV column: name and unit; the header cell reads `name [unit]`.
#[derive(Debug, Clone, Copy)]
pub struct Column<'a> {
    /// Quantity, e.g. `x3`.
    pub name: &'a str,
    /// Unit, e.g. `m` (`1` for dimensionless).
    pub unit: &'a str,
}

/// One value of a CSV row written with [`CsvWriter::record`].
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum Cell<'a> {
    /// A label (a joint's name), written as it is (quoted if it needs to be).
    Text(&'a str),
    /// A count or an index, written as an integer.
    Count(usize),
    /// A number, written in scientific notation like every value of [`CsvWriter::row`].
    Number(f64),
}

impl std::fmt::Display for Cell<'_> {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        match self {
            Cell::Text(text) => f.write_str(text),
            Cell::Count(n) => write!(f, "{n}"),
            Cell::Number(v) => f.write_str(ExpFormatter::default().format(*v)),
        }
    }
}

/// Formats numbers exactly as `format!("{v:e}")` does (the shortest digits that read back
/// to the same `f64`, in scientific notation: `1.5e-3`, `2e0`, `-0e0`, `NaN`, `inf`), several
/// times faster, from ryu's digits, into storage it reuses: the CSVs' millions of numbers
/// were a large part of writing a run.
#[derive(Default)]
pub(crate) struct ExpFormatter {
    ryu: ryu::Buffer,
    out: String,
}

impl ExpFormatter {
    /// `v` as `{v:e}` writes it.
    pub(crate) fn format(&mut self, v: f64) -> &str {
        use std::fmt::Write as _;
        self.out.clear();
        if !v.is_finite() || may_tie(v) {
            // Infallible: writing to a String.
            let _ = write!(self.out, "{v:e}");
            return &self.out;
        }
        // ryu writes `[-]D[.F]e[-]X` (already the digits `{:e}` writes), `[-]0.F` (below 1)
        // or `[-]I.F` (the digits `IF` with their trailing zeros, `I` the integer part).
        let text = self.ryu.format_finite(v);
        let (sign, text) = text.split_at(usize::from(text.starts_with('-')));
        self.out.push_str(sign);
        if text.contains('e') {
            self.out.push_str(text);
            return &self.out;
        }
        let (int, frac) = text.split_once('.').unwrap_or((text, ""));
        let (first, rest_int, frac, exponent) = if int == "0" {
            let zeros = frac.len() - frac.trim_start_matches('0').len();
            let Some(first) = frac.get(zeros..=zeros) else {
                // v == 0.
                self.out.push_str("0e0");
                return &self.out;
            };
            (first, "", &frac[zeros + 1..], -(zeros as i32) - 1)
        } else {
            (&int[..1], &int[1..], frac, int.len() as i32 - 1)
        };
        let frac = frac.trim_end_matches('0');
        let rest_int = if frac.is_empty() {
            rest_int.trim_end_matches('0')
        } else {
            rest_int
        };
        self.out.push_str(first);
        if !(rest_int.is_empty() && frac.is_empty()) {
            self.out.push('.');
            self.out.push_str(rest_int);
            self.out.push_str(frac);
        }
        // Infallible: writing to a String.
        let _ = write!(self.out, "e{exponent}");
        &self.out
    }
}

/// Whether `v`'s exact decimal value could lie halfway between its two nearest shortest
/// representations: ryu then keeps the even last digit where `{:e}` rounds up (e.g.
/// 1658206780088562.25 is `1.6582067800885622e15` for ryu, `…623e15` for `{:e}`). Such a tie
/// needs an exact value of at most 18 significant digits, which a double `m·2^e` (`m` odd) has
/// only if `e ≥ 0` or `m·5^(−e) < 10^18`; the rare values that might are left to `{:e}`.
fn may_tie(v: f64) -> bool {
    let bits = v.to_bits();
    let biased = ((bits >> 52) & 0x7ff) as i32;
    let fraction = bits & ((1 << 52) - 1);
    let (mantissa, exponent) = if biased == 0 {
        (fraction, -1074)
    } else {
        (fraction | (1 << 52), biased - 1075)
    };
    if mantissa == 0 {
        return true;
    }
    let zeros = mantissa.trailing_zeros();
    let (odd, e) = (mantissa >> zeros, exponent + zeros as i32);
    // log2(m·5^(−e)) ≥ bit length(m) − 1 + (−e)·log2 5, and 10^18 < 2^60.
    const LOG2_5: f64 = 2.321_928_094_887_362;
    e >= 0 || f64::from(64 - odd.leading_zeros()) + f64::from(-e) * LOG2_5 <= 62.0
}

/// Streams rows of numbers to a CSV file with a `name [unit]` header; the file appears only on
/// [`CsvWriter::finish`].
pub struct CsvWriter {
    path: PathBuf,
    columns: usize,
    inner: csv::Writer<AtomicFile>,
    numbers: ExpFormatter,
    counts: String,
}

impl CsvWriter {
    /// Start a file with this header.
    pub fn create(target: impl AsRef<Path>, columns: &[Column<'_>]) -> Result<Self, OutputError> {
        let path = target.as_ref().to_path_buf();
        let mut inner = csv::Writer::from_writer(AtomicFile::create(&path)?);
        let csv_err = |source| OutputError::Csv {
            path: path.clone(),
            source,
        };
        inner
            .write_record(columns.iter().map(|c| format!("{} [{}]", c.name, c.unit)))
            .map_err(csv_err)?;
        Ok(Self {
            path,
            columns: columns.len(),
            inner,
            numbers: ExpFormatter::default(),
            counts: String::new(),
        })
    }

    /// Append one row of numbers; it must have one value per column.
    pub fn row(&mut self, values: &[f64]) -> Result<(), OutputError> {
        self.write(values.len(), values.iter().map(|v| Cell::Number(*v)))
    }

    /// Append one row of labels, counts and numbers; it must have one cell per column.
    pub fn record(&mut self, cells: &[Cell<'_>]) -> Result<(), OutputError> {
        self.write(cells.len(), cells.iter().copied())
    }

    fn write<'a>(
        &mut self,
        len: usize,
        mut cells: impl Iterator<Item = Cell<'a>>,
    ) -> Result<(), OutputError> {
        if len != self.columns {
            return Err(OutputError::RowLength {
                path: self.path.clone(),
                expected: self.columns,
                got: len,
            });
        }
        // Field by field from reused storage: no allocation per cell.
        let mut write = |cell: Cell<'_>| match cell {
            Cell::Text(text) => self.inner.write_field(text),
            Cell::Count(n) => {
                use std::fmt::Write as _;
                self.counts.clear();
                // Infallible: writing to a String.
                let _ = write!(self.counts, "{n}");
                self.inner.write_field(&self.counts)
            }
            Cell::Number(v) => self.inner.write_field(self.numbers.format(v)),
        };
        cells
            .try_for_each(&mut write)
            .and_then(|()| self.inner.write_record(None::<&[u8]>))
            .map_err(|source| OutputError::Csv {
                path: self.path.clone(),
                source,
            })
    }

    /// Flush and move the file into place.
    pub fn finish(self) -> Result<PathBuf, OutputError> {
        let path = self.path;
        let file = self.inner.into_inner().map_err(|e| OutputError::Io {
            path: path.clone(),
            source: io::Error::other(e.to_string()),
        })?;
        file.commit()
    }
}

/// Write whole columns as a CSV time series (all slices the same length).
pub fn write_csv(
    target: impl AsRef<Path>,
    columns: &[(Column<'_>, &[f64])],
) -> Result<PathBuf, OutputError> {
    let target = target.as_ref();
    let rows = columns.first().map_or(0, |(_, v)| v.len());
    if let Some((c, v)) = columns.iter().find(|(_, v)| v.len() != rows) {
        return Err(OutputError::ColumnLength {
            path: target.to_path_buf(),
            column: c.name.to_string(),
            expected: rows,
            got: v.len(),
        });
    }
    let header: Vec<Column<'_>> = columns.iter().map(|(c, _)| *c).collect();
    let mut w = CsvWriter::create(target, &header)?;
    let mut row = vec![0.0; columns.len()];
    for k in 0..rows {
        for (slot, (_, values)) in row.iter_mut().zip(columns) {
            *slot = values[k];
        }
        w.row(&row)?;
    }
    w.finish()
}

/// `x` in scientific notation with `digits` decimals, or `-` when it is not finite (tables).
pub fn sci(x: f64, digits: usize) -> String {
    if x.is_finite() {
        format!("{x:.digits$e}")
    } else {
        "-".into()
    }
}

#[cfg(test)]
mod tests {
    use super::ExpFormatter;

    /// The CSVs' bytes must not change: every value class against `{:e}`.
    #[test]
    fn numbers_are_written_as_lower_exp_writes_them() {
        let mut f = ExpFormatter::default();
        let special = [
            0.0,
            -0.0,
            1.0,
            -1.5,
            0.1,
            123.0,
            1e-7,
            1.234e20,
            1e16,
            1e15,
            9.999e-6,
            1e-5,
            f64::MIN_POSITIVE,
            f64::MAX,
            f64::MIN,
            5e-324,
            // A tie: exactly 1658206780088562.25.
            1_658_206_780_088_562.0 + 0.25,
            0.375,
            2.5,
            f64::NAN,
            f64::INFINITY,
            f64::NEG_INFINITY,
        ];
        for v in special {
            assert_eq!(f.format(v), format!("{v:e}"), "{v:?}");
        }
        // A deterministic sweep of bit patterns (every exponent, varied mantissas) and of
        // decimal-looking values.
        let mut bits: u64 = 0x9E37_79B9_7F4A_7C15;
        for k in 0..300_000u64 {
            bits ^= bits << 13;
            bits ^= bits >> 7;
            bits ^= bits << 17;
            let v = f64::from_bits(bits);
            assert_eq!(f.format(v), format!("{v:e}"), "{v:?}");
            // Magnitudes a simulation writes (about 1e-21 to 1e21).
            let w = f64::from_bits((bits & !(0x7ff << 52)) | ((1023 - 70 + (k % 140)) << 52));
            assert_eq!(f.format(w), format!("{w:e}"), "{w:?}");
            let d = (k as f64) * 1e-3 - 17.0;
            assert_eq!(f.format(d), format!("{d:e}"), "{d:?}");
        }
    }
}
