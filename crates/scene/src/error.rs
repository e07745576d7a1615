//! Why a scene could not be loaded: the error type and the validation issues it lists.

use std::fmt;
use std::path::PathBuf;

/// One problem found by validation.
#[derive(Debug, Clone, PartialEq)]
pub struct Issue {
    /// Field path, e.g. `clearance_joints[0].clearance`.
    pub path: String,
    /// The offending value as written.
    pub value: String,
    /// Why it is rejected.
    pub reason: String,
}

/// Collects [`Issue`]s while walking a scene (in `validate` and [`super::limits`]).
#[derive(Default)]
pub(crate) struct Validator {
    pub(super) issues: Vec<Issue>,
}

impl Validator {
    pub(crate) fn push(
        &mut self,
        path: impl Into<String>,
        value: impl fmt::Debug,
        reason: impl Into<String>,
    ) {
        self.issues.push(Issue {
            path: path.into(),
            value: format!("{value:?}"),
            reason: reason.into(),
        });
    }

    /// Finite and, if `positive`, > 0; returns whether it passed.
    pub(crate) fn number(&mut self, path: &str, x: f64, positive: bool) -> bool {
        if !x.is_finite() {
            self.push(path, x, "must be a finite number");
            false
        } else if positive && x <= 0.0 {
            self.push(path, x, "must be positive");
            false
        } else {
            true
        }
    }

    /// `|x| ≤ max` (a limit of [`super::limits`]' kind); non-finite values are
    /// [`Self::number`]'s to report.
    pub(crate) fn at_most(&mut self, path: &str, x: f64, max: f64, unit: &str) {
        if x.is_finite() && x.abs() > max {
            self.push(path, x, format!("magnitude must not exceed {max:e} {unit}"));
        }
    }
}

impl fmt::Display for Issue {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        write!(f, "{} = {}: {}", self.path, self.value, self.reason)
    }
}

/// Why a scene could not be loaded.
#[derive(Debug, thiserror::Error)]
pub enum SceneError {
    /// The file could not be read.
    #[error("cannot read scene file {path}: {source}")]
    Io {
        /// File path.
        path: PathBuf,
        /// Cause.
        source: std::io::Error,
    },
    /// TOML syntax or type error; the message carries line and column when known.
    #[error("in scene {origin}: {source}")]
    Toml {
        /// File path or scene name.
        origin: String,
        /// Cause.
        source: toml::de::Error,
    },
    /// The scene merged with its `extends` base has a value of the wrong type or a missing or
    /// unknown key; `path` is the field (in the merged scene).
    #[error(
        "in scene {origin} (merged with its `extends` base): {path}{}: {source}",
        match (line, file) {
            (Some(l), Some(f)) => format!(" (line {l} of {f})"),
            (Some(l), None) => format!(" (line {l})"),
            _ => String::new(),
        }
    )]
    Merged {
        /// File path or scene name.
        origin: String,
        /// Field path, e.g. `bodies[2].mass`.
        path: String,
        /// Line of the field in the file that gives it last (the extending file's unless
        /// `file` names a base).
        line: Option<usize>,
        /// The base file (or built-in scene) of `line`, when not the extending file.
        file: Option<String>,
        /// Cause (boxed: keeps the error type small).
        source: Box<toml::de::Error>,
    },
    /// `extends` names no built-in scene and no file, or nests too deep.
    #[error("in scene {origin}: extends = {target}: {reason}")]
    Extends {
        /// File path or scene name.
        origin: String,
        /// The `extends` value, as TOML writes it (a string quoted).
        target: String,
        /// Why it could not be followed.
        reason: String,
    },
    /// The scene parsed but its values are not acceptable.
    #[error("in scene {origin}: {}", list_issues(.issues))]
    Invalid {
        /// File path or scene name.
        origin: String,
        /// Every problem found, in file order.
        issues: Vec<Issue>,
    },
    /// A scene given as a table (see [`super::from_table`]) has a value of the wrong type or
    /// a missing or unknown key; `path` is the field.
    #[error("in scene {origin}: {path}: {source}")]
    Field {
        /// Scene name.
        origin: String,
        /// Field path, e.g. `clearance_joints[0].clearance`.
        path: String,
        /// Cause (boxed: keeps the error type small).
        source: Box<toml::de::Error>,
    },
    /// No built-in scene of that name.
    #[error("no built-in scene named {name:?} (known: {known})")]
    UnknownBuiltin {
        /// Requested name.
        name: String,
        /// Comma-separated list of built-in names.
        known: String,
    },
}

fn list_issues(issues: &[Issue]) -> String {
    match issues {
        [one] => one.to_string(),
        many => {
            let lines: Vec<String> = many.iter().map(|i| format!("\n  {i}")).collect();
            format!("{} problems:{}", many.len(), lines.concat())
        }
    }
}
