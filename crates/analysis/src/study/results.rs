//! What a study run is and what it produced: the studies ([`StudyKind`]), their settings
//! ([`StudyOptions`]) and results ([`StudyResults`]), shared by the runner, the verdicts
//! ([`super::judge`]) and the report ([`super::report`]).

use std::path::{Path, PathBuf};

use lgres::studies::{ExtrapolationStudy, Study};
use sim::RunOutcome;

/// Default simulated cycles per wear stage in a study (the paper's K is 100).
pub const DEFAULT_CYCLES_PER_STAGE: u32 = 2;
/// Default response cycles per scene in a study.
pub const DEFAULT_RESPONSE_CYCLES: u32 = 10;
/// The name that runs every study.
pub const ALL: &str = "all";

/// One study to run.
#[derive(Debug, Clone, Copy)]
pub enum StudyKind {
    /// One of the paper's studies (the scenes it compares, in the paper's order).
    Paper(&'static Study),
    /// One wear stage of a scene, adaptive sub-steps against the paper's single jump.
    Extrapolation(&'static ExtrapolationStudy),
}

impl StudyKind {
    /// Name used on the command line and in the report.
    pub fn name(&self) -> &'static str {
        match self {
            StudyKind::Paper(s) => s.name,
            StudyKind::Extrapolation(s) => s.name,
        }
    }

    /// What it runs, for the command line's help.
    pub fn summary(&self) -> &'static str {
        match self {
            StudyKind::Paper(s) => s.summary,
            StudyKind::Extrapolation(s) => s.summary,
        }
    }

    /// The runs this study needs.
    pub fn runs(&self) -> Vec<StudyRun> {
        let as_it_is = |scene| StudyRun {
            key: scene,
            scene,
            single_jump: false,
        };
        match self {
            StudyKind::Paper(s) => s.scenes.iter().copied().map(as_it_is).collect(),
            StudyKind::Extrapolation(s) => vec![
                as_it_is(s.scene),
                StudyRun {
                    key: s.single_jump_run,
                    scene: s.scene,
                    single_jump: true,
                },
            ],
        }
    }
}

/// One run a study needs: a built-in scene under a key.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct StudyRun {
    /// The run's key: its folder's name, and how the report finds it.
    pub key: &'static str,
    /// The built-in scene it runs.
    pub scene: &'static str,
    /// Whether its wear stage is the paper's single jump instead of the scene's extrapolation;
    /// such a run is compared on its worn profile only (no worn response).
    pub single_jump: bool,
}

/// Settings of a study run.
#[derive(Debug, Clone)]
pub struct StudyOptions {
    /// Output folder: `<out>/<scene>/` per scene, `<out>/report.md` and study figures.
    pub out: PathBuf,
    /// Simulated cycles per wear stage K (see the module docs).
    pub cycles_per_stage: u32,
    /// Response cycles per scene (scene: `run.cycles`).
    pub response_cycles: u32,
    /// Relative tolerance override (scene: `solver.rtol`).
    pub rtol: Option<f64>,
    /// Drive cycles one wear stage stands for, instead of the scene's `cycles_per_stage ×
    /// amplification` (2 million): a quick look at the machinery (`study --stage-cycles`), not
    /// the paper's study.
    pub cycles_represented: Option<f64>,
    /// Scene runs at once, each on its own thread (default: the machine's cores). Runs are
    /// independent and deterministic, so the results do not depend on it.
    pub jobs: usize,
}

impl StudyOptions {
    /// The documented defaults, writing to `out`.
    pub fn new(out: impl Into<PathBuf>) -> Self {
        Self {
            out: out.into(),
            cycles_per_stage: DEFAULT_CYCLES_PER_STAGE,
            response_cycles: DEFAULT_RESPONSE_CYCLES,
            rtol: None,
            cycles_represented: None,
            jobs: std::thread::available_parallelism().map_or(1, usize::from),
        }
    }
}

/// One run of a study and where its files went.
#[derive(Debug, Clone)]
pub struct SceneRun {
    /// Run key: the scene name, or the extrapolation study's single-jump run.
    pub key: String,
    /// Folder of its files (`<out>/<key>`).
    pub dir: PathBuf,
    /// What the run produced.
    pub outcome: RunOutcome,
}

/// Everything a study run produced.
#[derive(Debug, Clone)]
pub struct StudyResults {
    /// The studies, in order.
    pub studies: Vec<StudyKind>,
    /// The runs, each once, in first-use order.
    pub runs: Vec<SceneRun>,
    /// Settings used.
    pub options: StudyOptions,
    /// Wall time of all runs and their files, s (the report adds its own figures).
    pub wall_time_s: f64,
}

impl StudyResults {
    /// The run with key `key`.
    pub fn run(&self, key: &str) -> Option<&SceneRun> {
        self.runs.iter().find(|r| r.key == key)
    }
}

/// `path` relative to `base` when it lies inside it (for links in the report).
pub(crate) fn relative(path: &Path, base: &Path) -> String {
    path.strip_prefix(base)
        .unwrap_or(path)
        .to_string_lossy()
        .replace('\\', "/")
}
