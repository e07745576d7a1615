//! One sample's row of `samples.csv`: its status, values and fixed columns.

use serde::{Deserialize, Serialize};

use crate::error::SweepError;

/// Columns every rows file has besides the inputs and metrics.
/// (`settings`: the [`crate::Sweep::settings_id`] the row ran with.)
pub const FIXED_COLUMNS: [&str; 5] = ["sample", "status", "error", "settings", "wall_time_s"];

/// Whether a sample ran.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "lowercase")]
pub enum Status {
    /// Ran; the metrics are its summary's.
    Ok,
    /// Could not run; `error` says why.
    Failed,
}

impl Status {
    /// As written in the file.
    pub fn as_str(self) -> &'static str {
        match self {
            Status::Ok => "ok",
            Status::Failed => "failed",
        }
    }
}

/// One sample's result.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct Row {
    /// Sample index.
    pub sample: usize,
    /// Input values, in input order.
    pub inputs: Vec<f64>,
    /// Metric values, in metric order (`None`: not a number in this sample's summary).
    pub metrics: Vec<Option<f64>>,
    /// Whether it ran.
    pub status: Status,
    /// Why it failed (empty when it ran).
    pub error: String,
    /// Wall time of the sample, s (the one cell that differs between engines).
    pub wall_time_s: f64,
}

impl Row {
    /// As JSON (how rows travel between processes; numbers come back bit-exact).
    pub fn to_json(&self) -> String {
        serde_json::to_string(self).unwrap_or_default()
    }

    /// From [`Row::to_json`].
    pub fn from_json(text: &str) -> Result<Row, SweepError> {
        Ok(serde_json::from_str(text)?)
    }

    /// The first metric that is NaN or infinite, as (metric index, value).
    pub fn non_finite_metric(&self) -> Option<(usize, f64)> {
        self.metrics
            .iter()
            .enumerate()
            .find_map(|(k, m)| m.filter(|v| !v.is_finite()).map(|v| (k, v)))
    }

    /// The NaN or infinite metric, as (metric index, value), that an `ok` row is written as
    /// failed for (rows file and page alike): such a row has no result to keep. `None` for a
    /// failed row (its own error says why) and for an `ok` row whose metrics are finite.
    pub fn non_finite_ok_metric(&self) -> Option<(usize, f64)> {
        self.non_finite_metric()
            .filter(|_| self.status == Status::Ok)
    }

    /// The status the rows file and the page write: failed for an `ok` row with a non-finite
    /// metric ([`Row::non_finite_ok_metric`]), else the row's own.
    pub fn written_status(&self) -> Status {
        if self.non_finite_ok_metric().is_some() {
            Status::Failed
        } else {
            self.status
        }
    }

    /// Whether a resumed sweep keeps this row: a failed row, or an `ok` one, whose metrics are
    /// all finite (or missing). A row with a NaN metric (an older version's, or an edited
    /// file's: [`write_rows`] writes none) is not a result: its sample runs again.
    pub fn is_done(&self) -> bool {
        self.non_finite_metric().is_none()
    }
}

/// A number in the shorter of `{}` and `{:e}` (both round-trip exactly).
pub fn number(v: f64) -> String {
    let (plain, sci) = (format!("{v}"), format!("{v:e}"));
    if sci.len() < plain.len() { sci } else { plain }
}
