//! `wearsim`: the command line of the worn-clearance-joint toolkit.
//!
//! Thin by design: it parses arguments, refuses flags a command does not take, hands each
//! command to its module and maps errors to exit codes (0 success, 1 could not run, 2 bad
//! input). `run` and `check` (the `run` module) load scenes (`load`), run them with
//! [`sim::run_scene`] and write the outputs with [`output::write_run`], with progress bars
//! (`progress`) and a summary (`print`); `study`, `sweep`, `stress` and `precision` run
//! [`analysis`]'s studies, the sweep files, the stress battery and the work–precision sweep
//! in modules of those names.

#[macro_use]
mod console;
mod error;
mod load;
mod overrides;
mod precision;
mod print;
mod progress;
mod run;
mod stress;
mod study;
mod sweep;

use std::path::PathBuf;
use std::process::ExitCode;

use clap::{Parser, Subcommand};
use lgres::scenes;
use overrides::Overrides;
use precision::PrecisionArgs;

#[derive(Parser)]
#[command(
    name = "wearsim",
    version,
    about = "Planar mechanisms with worn clearance joints"
)]
struct Cli {
    #[command(subcommand)]
    command: Command,
    #[command(flatten)]
    overrides: Overrides,
}

#[derive(Subcommand)]
enum Command {
    /// Simulate a scene (a built-in name or a TOML file; default: the paper's LGRES).
    Run {
        scene: Option<String>,
        /// Skip mechanism.gif and the pose recording it needs (scene: run.animation = false).
        #[arg(long)]
        no_animation: bool,
    },
    /// Run one of the paper's studies, or all of them.
    Study {
        /// The study to run.
        #[arg(value_parser = study::name_parser())]
        study: String,
        /// Drive cycles one wear stage stands for (default: the scenes' 2 million). Fewer make a
        /// quick look at the machinery in seconds, not the paper's study.
        #[arg(long, value_name = "CYCLES", allow_hyphen_values = true)]
        stage_cycles: Option<f64>,
    },
    /// Parse and validate a scene and print what it contains.
    Check { scene: String },
    /// List the built-in scenes and studies.
    Scenes,
    /// Run a sweep file: scene fields over a grid or random distributions, one CSV row per
    /// sample (inputs, metrics, status, wall time) and figures (default folder
    /// out/sweep/<file stem>).
    Sweep {
        /// The sweep file (TOML).
        file: PathBuf,
        /// Keep the rows already in samples.csv and run only the missing samples.
        #[arg(long)]
        resume: bool,
    },
    /// Stress battery: the default scene under stiff and extreme overrides (short runs).
    Stress {
        /// Leave out the 1000-cycle case.
        #[arg(long)]
        quick: bool,
    },
    /// Work–precision: every integrator over a tolerance sweep, error against run time, for
    /// one drive cycle of a scene (default: the paper's LGRES). Writes CSV, markdown, JSON and
    /// a PNG diagram (default folder out/precision).
    Precision {
        /// A built-in scene name or a TOML file.
        scene: Option<String>,
        /// Integrators, comma-separated (default: all).
        #[arg(long, value_delimiter = ',', value_parser = method_parser())]
        methods: Vec<scene::Integrator>,
        /// Relative tolerances, comma-separated (default: 1e-3 to 1e-10 by decades).
        #[arg(long, value_delimiter = ',', allow_negative_numbers = true)]
        rtols: Vec<f64>,
        /// Timed repeats per run and variant, 1 to 1000; the median is reported.
        #[arg(long, default_value_t = 3, allow_negative_numbers = true,
              value_parser = clap::builder::RangedU64ValueParser::<usize>::new().range(1..=1000))]
        repeats: usize,
        /// Simulated time, s (default: one drive period).
        #[arg(long, allow_negative_numbers = true)]
        duration: Option<f64>,
        /// End of the start-up window of error (a), s.
        #[arg(long, default_value_t = analysis::precision::DEFAULT_START_UP, allow_negative_numbers = true)]
        start_up: f64,
        /// Accepted-step budget per run; a method that exceeds it is not run tighter.
        #[arg(long, default_value_t = analysis::precision::DEFAULT_MAX_STEPS, allow_negative_numbers = true)]
        max_steps: usize,
    },
}

/// Integrator names on the command line: the names of the scene format and the reports.
fn method_parser() -> impl clap::builder::TypedValueParser<Value = scene::Integrator> {
    use clap::builder::TypedValueParser;
    let names = analysis::precision::ALL_METHODS.map(analysis::precision::method_name);
    clap::builder::PossibleValuesParser::new(names).try_map(|name| {
        analysis::precision::method_by_name(&name).ok_or("no integrator of this name")
    })
}

fn list_scenes() {
    outln!("built-in scenes:");
    for b in scenes::BUILTINS {
        let default = if b.name == scenes::DEFAULT {
            " (default)"
        } else {
            ""
        };
        outln!("  {:<24} {}{default}", b.name, b.summary);
    }
    outln!("studies:");
    for s in lgres::studies::STUDIES {
        outln!("  {:<24} {}: {}", s.name, s.summary, s.scenes.join(", "));
    }
}

/// Exit code after SIGINT/SIGTERM (128 + SIGINT, as shells report an interrupt).
const EXIT_INTERRUPTED: i32 = 130;

fn main() -> ExitCode {
    let cli = Cli::parse();
    // On SIGINT/SIGTERM remove the staging folder and lock of a run in progress and say what
    // each output folder holds.
    if let Err(e) = ctrlc::set_handler(|| {
        let left = output::files::abandon_staged();
        if left.is_empty() {
            errln!("wearsim: interrupted; no output folder was being written");
        }
        for folder in left {
            errln!("wearsim: interrupted; the output folder {folder}");
        }
        std::process::exit(EXIT_INTERRUPTED);
    }) {
        errln!("wearsim: warning: cannot install the signal handler: {e}");
    }
    let o = &cli.overrides;
    let scene_settings = [
        "--cycles",
        "--stages",
        "--rtol",
        "--cycles-per-stage",
        "--trajectories",
        "--wear-tolerance",
        "--max-steps",
        "--max-wall-time",
    ];
    let flags = match &cli.command {
        Command::Run { .. } => o.only(
            "run",
            &[&scene_settings[..], &["--out", "--surfaces", "--jobs"]].concat(),
            "",
        ),
        Command::Check { .. } => o.only("check", &scene_settings, "; check writes nothing"),
        // `--stages` is refused by the study itself, with its reason.
        Command::Study { .. } => o.only(
            "study",
            &[
                "--out",
                "--cycles",
                "--stages",
                "--rtol",
                "--cycles-per-stage",
                "--jobs",
            ],
            "",
        ),
        Command::Scenes => o.only("scenes", &[], ""),
        Command::Stress { .. } => o.only("stress", &["--out"], "; the battery sets its own cases"),
        Command::Sweep { .. } => o.only(
            "sweep",
            &["--out", "--jobs"],
            "; set it in the sweep file's [run] table",
        ),
        // (`--max-steps` is precision's own option, which shares the global's name.)
        Command::Precision { .. } => o.only(
            "precision",
            &["--out", "--max-steps"],
            "; precision sweeps the tolerances over one drive period (see its own options)",
        ),
    };
    if let Err(e) = flags {
        errln!("wearsim: error: {e}");
        return ExitCode::from(e.exit_code());
    }
    let result = match &cli.command {
        Command::Run {
            scene,
            no_animation,
        } => run::run(
            scene.as_deref().unwrap_or(scenes::DEFAULT),
            *no_animation,
            o,
        ),
        Command::Study {
            study: s,
            stage_cycles,
        } => study::run(s, *stage_cycles, o),
        Command::Check { scene } => run::check(scene, o),
        Command::Scenes => {
            list_scenes();
            Ok(())
        }
        Command::Stress { quick } => stress::run(*quick, o),
        Command::Sweep { file, resume } => sweep::run(file, *resume, o),
        Command::Precision {
            scene,
            methods,
            rtols,
            repeats,
            duration,
            start_up,
            max_steps,
        } => precision::run(
            scene.as_deref().unwrap_or(scenes::DEFAULT),
            &PrecisionArgs {
                methods,
                rtols,
                repeats: *repeats,
                duration: *duration,
                start_up: *start_up,
                max_steps: *max_steps,
            },
            o,
        ),
    };
    match result {
        // The work is done (an output folder is complete), but what it printed was lost.
        Ok(()) if console::stdout_closed() => ExitCode::from(console::EXIT_CLOSED_PIPE),
        Ok(()) => ExitCode::SUCCESS,
        Err(_) if output::files::is_abandoned() => {
            // The interrupt handler removed the output under a writer, which failed for that
            // reason only: the handler is about to report the interrupt and exit with 130, so
            // this thread must not exit first with the writer's error and 1.
            std::thread::sleep(std::time::Duration::from_secs(5));
            std::process::exit(EXIT_INTERRUPTED)
        }
        Err(e) => {
            errln!("wearsim: error: {e}");
            ExitCode::from(e.exit_code())
        }
    }
}
