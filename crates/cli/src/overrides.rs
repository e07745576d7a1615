//! The options that override a scene's settings, shared by every command.

use std::path::PathBuf;

use crate::error::CliError;

/// Options that override the scene's settings.
#[derive(clap::Args)]
pub(crate) struct Overrides {
    /// Output folder (default: out/<scene>).
    #[arg(long, global = true, value_name = "DIR")]
    pub(crate) out: Option<PathBuf>,
    /// Drive cycles of the response run (scene: run.cycles, at least 1).
    #[arg(long, global = true, allow_negative_numbers = true)]
    pub(crate) cycles: Option<u32>,
    /// Wear stages (scene: run.wear_stages).
    #[arg(long, global = true, allow_negative_numbers = true)]
    pub(crate) stages: Option<u32>,
    /// Relative tolerance (scene: solver.rtol).
    #[arg(long, global = true, allow_negative_numbers = true)]
    pub(crate) rtol: Option<f64>,
    /// Simulated cycles per wear stage K (scene: run.cycles_per_stage, the paper's 100). The
    /// amplification is rescaled so a stage still stands for the scene's K × amplification
    /// cycles. `run` defaults to 2 (even, so the stage's convergence in K is checked; the LGRES
    /// stage is within 2.6 % of finer sub-steps, docs/convergence.md); give 100 for the paper's
    /// staging.
    #[arg(
        long,
        global = true,
        value_name = "K",
        allow_negative_numbers = true,
        value_parser = clap::value_parser!(u32).range(1..)
    )]
    pub(crate) cycles_per_stage: Option<u32>,
    /// Accepted-step budget of each simulation (scene: solver.max_steps).
    #[arg(long, global = true, value_name = "N", allow_negative_numbers = true)]
    pub(crate) max_steps: Option<usize>,
    /// Wall-time budget of each simulation, s (scene: solver.max_wall_time).
    #[arg(
        long,
        global = true,
        value_name = "SECONDS",
        allow_negative_numbers = true
    )]
    pub(crate) max_wall_time: Option<f64>,
    /// Trajectories a wear sub-step's K cycles are spread over, run on threads, each
    /// continuing from where it ended (scene: run.trajectories; a divisor of K). `run`
    /// defaults to 2 with its default K = 2 (one cycle each), else to the scene's (1: one
    /// trajectory, restarted at every sub-step).
    #[arg(
        long,
        global = true,
        value_name = "M",
        allow_negative_numbers = true,
        value_parser = clap::value_parser!(u32).range(1..)
    )]
    pub(crate) trajectories: Option<u32>,
    /// Error-controlled wear sub-steps: accept a sub-step when its local error estimate is
    /// within this fraction (scene: run.wear_tolerance, e.g. 0.05; `max_clearance_change`
    /// becomes the smallest sub-step; docs/model.md §10.4).
    #[arg(long, global = true, value_name = "TOL", allow_negative_numbers = true)]
    pub(crate) wear_tolerance: Option<f64>,
    /// `study`: scene runs at once; `run`: threads of the wear trajectories (default: the
    /// machine's cores; results do not depend on it).
    #[arg(long, global = true, value_name = "N", allow_negative_numbers = true)]
    pub(crate) jobs: Option<std::num::NonZeroUsize>,
    /// `run`: start from the worn surfaces an earlier run wrote into DIR (its last-stage
    /// wear_<joint>_stage<k>.csv files, for the joints of the same names).
    #[arg(long, global = true, value_name = "DIR")]
    pub(crate) surfaces: Option<PathBuf>,
}

impl Overrides {
    /// The flags given on the command line, by name.
    pub(crate) fn given(&self) -> Vec<&'static str> {
        [
            ("--out", self.out.is_some()),
            ("--cycles", self.cycles.is_some()),
            ("--stages", self.stages.is_some()),
            ("--rtol", self.rtol.is_some()),
            ("--cycles-per-stage", self.cycles_per_stage.is_some()),
            ("--trajectories", self.trajectories.is_some()),
            ("--wear-tolerance", self.wear_tolerance.is_some()),
            ("--max-steps", self.max_steps.is_some()),
            ("--max-wall-time", self.max_wall_time.is_some()),
            ("--jobs", self.jobs.is_some()),
            ("--surfaces", self.surfaces.is_some()),
        ]
        .into_iter()
        .filter_map(|(flag, given)| given.then_some(flag))
        .collect()
    }

    /// Refuses, before any work, a flag `command` does not use (it would be silently ignored
    /// while the command runs for minutes).
    pub(crate) fn only(
        &self,
        command: &'static str,
        allowed: &[&str],
        hint: &'static str,
    ) -> Result<(), CliError> {
        match self.given().into_iter().find(|f| !allowed.contains(f)) {
            Some(flag) => Err(CliError::FlagNotUsed {
                flag,
                command,
                hint,
            }),
            None => Ok(()),
        }
    }

    /// The options of a run: the run-setting overrides' and, with `--surfaces`, the folder of
    /// worn surfaces to start from.
    pub(crate) fn run_options(&self) -> sim::RunOptions {
        sim::RunOptions {
            surfaces: self.surfaces.clone().map(output::surfaces::folder),
            ..self.run_overrides().run_options()
        }
    }

    /// The run-setting overrides, as every front end applies them.
    pub(crate) fn run_overrides(&self) -> sim::overrides::RunOverrides {
        sim::overrides::RunOverrides {
            cycles: self.cycles,
            stages: self.stages,
            rtol: self.rtol,
            max_steps: self.max_steps,
            max_wall_time: self.max_wall_time,
            cycles_per_stage: self.cycles_per_stage,
            trajectories: self.trajectories,
            wear_tolerance: self.wear_tolerance,
            threads: self.jobs.map(std::num::NonZeroUsize::get),
        }
    }
}
