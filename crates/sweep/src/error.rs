//! Why a sweep could not be set up or written, and why one sample failed.

use std::path::PathBuf;

use output::files::OutputError;
use scene::SceneError;
use sim::RunError;

/// Why a sweep could not be set up or its outputs written (a failed sample is a [`Row`]).
#[derive(Debug, thiserror::Error)]
pub enum SweepError {
    /// The sweep file could not be read.
    #[error("cannot read sweep file {path}: {source}")]
    Io {
        /// File path.
        path: PathBuf,
        /// Cause.
        source: std::io::Error,
    },
    /// TOML syntax error.
    #[error("in sweep {origin}: {source}")]
    Toml {
        /// File path.
        origin: String,
        /// Cause.
        source: Box<toml::de::Error>,
    },
    /// A value of the wrong type or an unknown key.
    #[error("in sweep {origin}: {field}: {source}")]
    Type {
        /// File path.
        origin: String,
        /// Field path, e.g. `vary[0].low`.
        field: String,
        /// Cause.
        source: Box<toml::de::Error>,
    },
    /// A value is not acceptable.
    #[error("in sweep file: {field} = {value}: {reason}")]
    Field {
        /// Field path, e.g. `vary[1].sigma`.
        field: String,
        /// The value as given.
        value: String,
        /// Why it is rejected.
        reason: String,
    },
    /// The base scene could not be loaded.
    #[error(transparent)]
    Scene(#[from] SceneError),
    /// An output could not be written.
    #[error(transparent)]
    Output(#[from] OutputError),
    /// `--resume` found a file it cannot continue.
    #[error("cannot resume from {path}: {reason}")]
    Resume {
        /// The rows file.
        path: PathBuf,
        /// Why.
        reason: String,
    },
    /// A plan or row passed between processes is not what [`Sweep::plan`] or [`Row`] wrote.
    #[error("malformed sweep plan or row: {0}")]
    Json(#[from] serde_json::Error),
    /// A sample index beyond the sweep.
    #[error("sample {index} does not exist: the sweep has {samples} samples")]
    NoSuchSample {
        /// Requested index.
        index: usize,
        /// Samples in the sweep.
        samples: usize,
    },
}

impl SweepError {
    /// Whether the sweep file is at fault (exit code 2) rather than the machine (1).
    pub fn is_bad_input(&self) -> bool {
        // A sweep file that is missing, a folder or not UTF-8 is bad input, as a scene file.
        !matches!(self, SweepError::Output(_))
    }
}

/// Why one sample failed; its message goes into the row's `error` cell.
#[derive(Debug, thiserror::Error)]
pub enum SampleError {
    /// A varied path could not be set.
    #[error("{path}: {reason}")]
    Edit {
        /// The field path.
        path: String,
        /// Why.
        reason: String,
    },
    /// A drawn value does not fit its field (a fraction or an out-of-range number for an
    /// integer field, a non-finite number): refused, never rounded or saturated.
    #[error("{path} = {value}: {reason}")]
    Value {
        /// The field path.
        path: String,
        /// The value, as the rows file writes it.
        value: String,
        /// Why it is refused.
        reason: String,
    },
    /// The edited scene is invalid (field named).
    #[error(transparent)]
    Scene(#[from] SceneError),
    /// The run failed.
    #[error(transparent)]
    Run(#[from] RunError),
    /// A metric is not in the summary.
    #[error("metric {path}: {reason}")]
    Metric {
        /// The metric path.
        path: String,
        /// Why.
        reason: String,
    },
    /// A metric is NaN or infinite: the run's result is not a number to keep.
    #[error("metric {path} is not finite ({value})")]
    NotFinite {
        /// The metric path.
        path: String,
        /// Its value.
        value: f64,
    },
    /// The summary could not be turned into the tree its metrics are read from.
    #[error("summary: {0}")]
    Summary(#[from] ciborium::value::Error),
}
