//! Why `wearsim` stopped, and the exit code each reason gives (2 bad input, 1 could not run).

use output::files::OutputError;
use scene::{LoadError, NotFound, SceneError};
use sim::RunError;

/// Why `wearsim` stopped.
#[derive(Debug, thiserror::Error)]
pub(crate) enum CliError {
    /// The scene could not be loaded or is invalid.
    #[error(transparent)]
    Scene(#[from] SceneError),
    /// Neither a built-in name nor an existing file.
    #[error("{0} (see `wearsim scenes`)")]
    NoSuchScene(#[from] NotFound),
    /// The run failed, or its scene does not assemble.
    #[error(transparent)]
    Run(#[from] RunError),
    /// A scene the run cannot use (its drivers, joints, assembly), named as given.
    #[error("in scene {spec}: {source}")]
    InScene {
        /// The scene as given on the command line (a built-in name or a file).
        spec: String,
        /// Why (boxed: a run error is large).
        source: Box<RunError>,
    },
    /// An output could not be written.
    #[error(transparent)]
    Output(#[from] OutputError),
    /// A study failed or was given bad settings.
    #[error(transparent)]
    Study(#[from] analysis::study::StudyError),
    /// A sweep could not be set up or written (a failed sample is a row, not an error).
    #[error(transparent)]
    Sweep(#[from] ::sweep::SweepError),
    /// A work–precision sweep could not run.
    #[error(transparent)]
    Precision(#[from] analysis::precision::PrecisionError),
    /// A flag the command does not use.
    #[error("{flag} does not apply to `wearsim {command}`{hint}")]
    FlagNotUsed {
        /// The flag.
        flag: &'static str,
        /// The command.
        command: &'static str,
        /// Where the setting goes instead, if anywhere (starts with "; ").
        hint: &'static str,
    },
}

impl From<LoadError> for CliError {
    fn from(e: LoadError) -> Self {
        match e {
            LoadError::NotFound(e) => e.into(),
            LoadError::Scene(e) => e.into(),
        }
    }
}

impl CliError {
    pub(crate) fn exit_code(&self) -> u8 {
        match self {
            CliError::Scene(_) | CliError::NoSuchScene(_) | CliError::FlagNotUsed { .. } => 2,
            CliError::Run(e) if e.is_bad_input() => 2,
            CliError::InScene { source, .. } if source.is_bad_input() => 2,
            CliError::Study(e) if e.is_bad_input() => 2,
            CliError::Precision(
                analysis::precision::PrecisionError::Options { .. }
                | analysis::precision::PrecisionError::Scene(_)
                | analysis::precision::PrecisionError::Unsuitable(_),
            ) => 2,
            CliError::Sweep(e) if e.is_bad_input() => 2,
            CliError::Output(e) if e.is_bad_input() => 2,
            CliError::Precision(analysis::precision::PrecisionError::Output(e))
                if e.is_bad_input() =>
            {
                2
            }
            CliError::Run(_)
            | CliError::InScene { .. }
            | CliError::Sweep(_)
            | CliError::Output(_)
            | CliError::Study(_)
            | CliError::Precision(_) => 1,
        }
    }
}
