//! Why an output could not be written ([`OutputError`], shown as `output::OutputError`):
//! shared by the atomic writers ([`crate::files`]) and the staged output folders.

use std::io;
use std::path::{Path, PathBuf};

/// An output file could not be written.
#[derive(Debug, thiserror::Error)]
pub enum OutputError {
    /// File-system error.
    #[error("writing {path}: {source}")]
    Io {
        /// Target file.
        path: PathBuf,
        /// Cause.
        source: io::Error,
    },
    /// CSV encoding error.
    #[error("writing CSV {path}: {source}")]
    Csv {
        /// Target file.
        path: PathBuf,
        /// Cause.
        source: csv::Error,
    },
    /// JSON encoding error.
    #[error("writing JSON {path}: {source}")]
    Json {
        /// Target file.
        path: PathBuf,
        /// Cause.
        source: serde_json::Error,
    },
    /// A row does not match the header.
    #[error("writing CSV {path}: row has {got} values, header has {expected} columns")]
    RowLength {
        /// Target file.
        path: PathBuf,
        /// Columns in the header.
        expected: usize,
        /// Values in the row.
        got: usize,
    },
    /// Columns of different lengths.
    #[error("writing CSV {path}: column {column} has {got} values, the first has {expected}")]
    ColumnLength {
        /// Target file.
        path: PathBuf,
        /// The offending column.
        column: String,
        /// Length of the first column.
        expected: usize,
        /// Length of this one.
        got: usize,
    },
    /// The output folder cannot be used (not a folder, foreign files, no name).
    #[error("output folder {path}: {reason}")]
    Folder {
        /// The folder.
        path: PathBuf,
        /// Why.
        reason: String,
    },
    /// Another run is writing the same output folder.
    #[error(
        "output folder {path}: another wearsim run ({}) is writing it (lock file {lock}); wait \
         for it or choose another --out",
        pid.map_or_else(|| "its process id not yet written".to_string(), |p| format!("process {p}"))
    )]
    Locked {
        /// The folder.
        path: PathBuf,
        /// The lock file.
        lock: PathBuf,
        /// Process holding the lock, once it has written it.
        pid: Option<u32>,
    },
    /// Another run is writing a folder inside this output folder, or one that contains it:
    /// whichever replaces its folder first would delete or hide the other's output.
    #[error(
        "output folder {path}: another wearsim run ({}) is writing {other}, {} (lock file \
         {lock}); wait for it or choose another --out",
        pid.map_or_else(|| "its process id not yet written".to_string(), |p| format!("process {p}")),
        if *around { "which contains it" } else { "inside it" }
    )]
    NestedLocked {
        /// The folder.
        path: PathBuf,
        /// The other run's folder.
        other: PathBuf,
        /// Whether `other` contains `path` (else `path` contains `other`).
        around: bool,
        /// The other run's lock file.
        lock: PathBuf,
        /// Process holding the lock, once it has written it.
        pid: Option<u32>,
    },
    /// A name would not be a plain file name (it could create folders or escape the output
    /// folder); validation normally rejects it first.
    #[error("output file name part {name:?} is not a plain file name")]
    UnsafeName {
        /// The name.
        name: String,
    },
    /// The run was interrupted: its output is being abandoned, nothing more is written.
    #[error("interrupted: the output is abandoned")]
    Interrupted,
    /// Rendering a figure failed.
    #[error("drawing {path}: {reason}")]
    Plot {
        /// Target file.
        path: PathBuf,
        /// What plotters reported.
        reason: String,
    },
}

impl OutputError {
    /// Whether the output folder the user chose cannot be used (exit 2), as opposed to a
    /// write that failed on the way or a folder another run holds for now (exit 1).
    pub fn is_bad_input(&self) -> bool {
        matches!(
            self,
            OutputError::Folder { .. } | OutputError::UnsafeName { .. }
        )
    }
}

pub(crate) fn io_err(path: &Path) -> impl Fn(io::Error) -> OutputError + '_ {
    move |source| OutputError::Io {
        path: path.to_path_buf(),
        source,
    }
}
