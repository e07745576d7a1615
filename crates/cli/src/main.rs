//! `wearsim`: the command line of the worn-clearance-joint toolkit.
//!
//! Thin by design: it parses arguments, loads and validates scenes through `lgres`, runs them
//! with [`sim::run_scene`], writes the outputs with [`output::write_run`], shows progress
//! bars and maps errors to exit codes (0 success, 1 could not run, 2 bad input). `study` runs
//! [`analysis::study`] (see the `study` module).

#[macro_use]
mod console;
mod error;
mod overrides;
mod progress;
mod study;
mod sweep;

use std::path::{Path, PathBuf};
use std::process::ExitCode;

use clap::{Parser, Subcommand};
use error::CliError;
use lgres::scenes;
use overrides::Overrides;
use scene::ValidScene;
use sim::{RunError, RunOutcome};

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

/// A loaded scene and the name outputs are filed under.
struct Loaded {
    name: String,
    scene: ValidScene,
}

/// A run error, named after the scene when the scene is what is wrong with it (a scene error
/// names its scene already).
fn in_scene(spec: &str, e: RunError) -> CliError {
    if let RunError::Scene(e) = e {
        CliError::Scene(e)
    } else if e.is_bad_input() {
        CliError::InScene {
            spec: spec.to_string(),
            source: Box::new(e),
        }
    } else {
        CliError::Run(e)
    }
}

/// Load a built-in scene by name, else a file, with the command-line overrides (checked again
/// only if they change it).
fn load(spec: &str, o: &Overrides) -> Result<Loaded, CliError> {
    let (name, scene) = scene::load_named::<ValidScene>(spec, None, scenes::BUILTINS)?;
    let origin = format!("{spec} with command-line overrides");
    let scene = o.run_overrides().apply(scene, &origin)?;
    Ok(Loaded { name, scene })
}

fn out_dir(o: &Overrides, name: &str) -> PathBuf {
    o.out.clone().unwrap_or_else(|| Path::new("out").join(name))
}

fn check(spec: &str, o: &Overrides) -> Result<(), CliError> {
    let Loaded { name, scene: s } = load(spec, o)?;
    // Every check `run` makes before simulating, before anything is called valid.
    let options = o.run_options();
    let check = sim::check_assembly(&name, &s, &options).map_err(|e| in_scene(spec, e))?;
    outln!("scene {name}: valid");
    outln!("  {}", s.description);
    outln!("  inertia: {}", s.inertia_convention);
    outln!("  bodies ({}):", s.bodies.len());
    for b in &s.bodies {
        outln!(
            "    {:<12} m = {} kg, I = {} kg·m², at ({}, {}) m, {:.4}°",
            b.name,
            b.mass,
            b.inertia,
            b.x,
            b.y,
            b.theta.deg()
        );
    }
    let names = |v: Vec<&str>| {
        if v.is_empty() {
            "-".into()
        } else {
            v.join(", ")
        }
    };
    outln!(
        "  revolute joints: {}",
        names(s.revolute_joints.iter().map(|j| j.name.as_str()).collect())
    );
    outln!(
        "  prismatic joints: {}",
        names(s.prismatic_joints.iter().map(|j| j.name.as_str()).collect())
    );
    outln!(
        "  drivers: {}",
        names(s.drivers.iter().map(|d| d.name.as_str()).collect())
    );
    outln!("  clearance joints ({}):", s.clearance_joints.len());
    for c in &s.clearance_joints {
        let role = if c.ideal {
            "ideal revolute (2 equations)".to_string()
        } else {
            format!(
                "clearance {} mm, bearing R = {} mm, wear {}",
                c.clearance * 1e3,
                c.bearing_radius * 1e3,
                if c.wear.is_some() { "on" } else { "off" }
            )
        };
        outln!(
            "    {:<12} bearing on {}, pin on {}: {role}",
            c.name,
            c.bearing_body,
            c.pin_body
        );
        if !c.ideal {
            outln!("    {:<12} {}", "", c.contact_description());
        }
    }
    outln!(
        "  constraint equations: {}; degrees of freedom (3·{} − {}, clearance joints as 0): {}",
        s.constraint_count(),
        s.bodies.len(),
        s.constraint_count(),
        s.degrees_of_freedom()
    );
    let t = s.tolerances();
    outln!(
        "  solver: {:?}, rtol {:e}, atol {:.3e} m / {:.3e} rad / {:.3e} (m|rad)/s; cycle {} s",
        s.solver.integrator,
        s.solver.rtol,
        t.position,
        t.angle,
        t.velocity,
        s.cycle_period().map_or("-".into(), |p| format!("{p:.6}"))
    );
    outln!(
        "  assembly at t = 0: ok, {} coordinates, {} constraint equations, {} degrees of freedom \
         (clearance joints as force elements); largest joint-centre move from the file's poses \
         {:.3e} m",
        check.coordinates,
        check.constraints,
        check.degrees_of_freedom,
        check.largest_move
    );
    Ok(())
}

fn run(spec: &str, no_animation: bool, o: &Overrides) -> Result<(), CliError> {
    let Loaded { name, scene } = load(spec, o)?;
    let scene = if no_animation && scene.run.animation {
        scene.edit(&format!("{spec} without animation"), |s| {
            s.run.animation = false;
        })?
    } else {
        scene
    };
    let out = out_dir(o, &name);
    let options = o.run_options();
    // Lock the folder before simulating, so a second run is refused at once; files go to a
    // staging folder that replaces `out` whole only when every file is written.
    let staged = output::files::StagedDir::begin(&out)?;
    let mut bars = progress::Bars::new();
    let outcome =
        sim::run_scene(&name, &scene, &options, &mut bars).map_err(|e| in_scene(spec, e))?;
    drop(bars);
    let files = output::write_run(&outcome, staged.path())?;
    staged.commit()?;
    print_summary(&outcome, &out, files.len());
    Ok(())
}

/// Peak statistics after the start-up window, or "n/a" when the window covers the run (no
/// cycle has a sample after it, so there is no peak to report).
fn peak_after(b: Option<&sim::PeakStats>, window: f64) -> String {
    let Some(b) = b else {
        return format!("n/a after {window} s (the start-up window covers the whole run)");
    };
    format!(
        "{:.2} kN after {window} s (median of {} cycle peaks {:.2} ± {:.2} kN, range {:.2}–{:.2} \
         kN; elastic share at the peaks {})",
        b.max * 1e-3,
        b.cycles,
        b.cycle_median * 1e-3,
        b.cycle_median_noise * 1e-3,
        b.cycle_min * 1e-3,
        b.cycle_max * 1e-3,
        elastic_share(b)
    )
}

/// The elastic share of the per-cycle peaks in words: median and smallest, and a warning when
/// the median peak is mostly damping.
fn elastic_share(b: &sim::PeakStats) -> String {
    if !b.elastic_share_median.is_finite() {
        return "n/a".to_string();
    }
    let warning = if b.elastic_share_median < sim::MIN_ELASTIC_SHARE {
        " — MOSTLY DAMPING: not a load the surfaces carry"
    } else {
        ""
    };
    format!(
        "median {:.0} %, min {:.0} %{warning}",
        100.0 * b.elastic_share_median,
        100.0 * b.elastic_share_min
    )
}

/// The one-screen summary at the end of a run.
fn print_summary(outcome: &RunOutcome, out: &Path, files: usize) {
    let s = &outcome.summary;
    outln!("scene {}: {}", s.scene, s.description);
    for contact in &s.contacts {
        outln!("  contact {contact}");
    }
    let r = &s.response;
    outln!(
        "response: {} cycle(s) of {:.3} s; peaks are statistics of per-cycle maxima",
        r.cycles,
        s.period_s
    );
    print_joints(r, s.transient_window_s);
    match &r.deviation_after_transient {
        Some(d) => outln!(
            "  {} vs ideal after {} s: |Δx| {:.1} µm, |Δy| {:.1} µm, |Δv| {:.4}/{:.4} m/s, |Δa| \
             {:.1}/{:.1} m/s²",
            s.response_body,
            s.transient_window_s,
            d.x_m * 1e6,
            d.y_m * 1e6,
            d.vx_m_s,
            d.vy_m_s,
            d.ax_m_s2,
            d.ay_m_s2
        ),
        None => outln!(
            "  {} vs ideal after {} s: n/a (the start-up window covers the whole run)",
            s.response_body,
            s.transient_window_s
        ),
    }
    if let Some(n) = &r.numerics {
        outln!(
            "  integrator: {} steps ({} rejected), {} events, drift {:.1e} m, energy residual \
             {:.2e} J ({:.1e} relative), {:.1} s",
            n.steps,
            n.rejected_steps,
            n.events,
            n.drift_position,
            n.energy_residual_j,
            n.energy_relative_residual,
            n.wall_time_s
        );
    }
    if let Some(w) = &s.wear {
        outln!(
            "wear: {} stage(s), K = {} cycles per stage (scene: {}) on {} trajector{}, ×{:.0} so \
             a stage stands for {:.3e} cycles; {}; sub-steps {:?}{}; {:.1} s",
            w.stages,
            w.cycles_per_stage,
            w.scene_cycles_per_stage,
            w.trajectories,
            if w.trajectories == 1 { "y" } else { "ies" },
            w.amplification,
            w.cycles_represented_per_stage,
            w.extrapolation,
            w.substeps_per_stage,
            // Controlled sub-steps need one more run per stage, and rejected predictions.
            if w.runs_per_stage == w.substeps_per_stage {
                String::new()
            } else {
                format!(
                    " (runs {:?}, of which rejected {:?})",
                    w.runs_per_stage, w.rejected_runs_per_stage
                )
            },
            w.wall_time_s
        );
        for j in &w.joints {
            outln!(
                "  joint {}: bearing peak {:.1} µm at {:.0}°, pin peak {:.1} µm at {:.0}°",
                j.name,
                j.bearing_peak_depth_m * 1e6,
                j.bearing_peak_angle_deg,
                j.pin_peak_depth_m * 1e6,
                j.pin_peak_angle_deg
            );
        }
        for j in &w.joints {
            if let Some(limit) = &j.clearance_limit {
                outln!(
                    "  {}",
                    clearance_limit_line(&j.name, limit, w.cycles_applied)
                );
            }
        }
        for text in &w.warnings {
            outln!("  {text}");
        }
    }
    if let Some(r) = &s.worn_response {
        outln!("worn response (on the surfaces after the last stage):");
        print_joints(r, s.transient_window_s);
    }
    outln!(
        "wrote {files} files to {} in {:.1} s total",
        out.display(),
        s.wall_time_s
    );
}

/// When joint `name`'s largest local clearance reaches the maintenance limit, in a line.
fn clearance_limit_line(
    name: &str,
    limit: &sim::ClearanceLimitReport,
    cycles_applied: f64,
) -> String {
    // Two decimals as in "1.00 mm", more when the limit needs them (0.501 mm).
    let value = limit.limit_m * 1e3;
    let mm = (2..=6)
        .map(|d| format!("{value:.d$}"))
        .find(|t| {
            t.parse::<f64>()
                .is_ok_and(|v| (v - value).abs() <= 1e-9 * value)
        })
        .unwrap_or_else(|| format!("{value:e}"));
    match limit.cycles {
        Some(c) if c > 0.0 => {
            format!("joint {name} reaches {mm} mm clearance after {c:.1e} cycles")
        }
        Some(_) => format!(
            "joint {name} is at {mm} mm clearance from the start (the surfaces the run started \
             from)"
        ),
        None => format!(
            "joint {name} does not reach {mm} mm clearance within {cycles_applied:.1e} cycles"
        ),
    }
}

/// Per-joint peaks and energy books of one response, and what the books flag.
fn print_joints(r: &sim::ResponseSummary, window: f64) {
    for j in &r.joints {
        let (a, b) = (&j.normal_force_all, j.normal_force_after_transient.as_ref());
        if let Some(v) = j.validity.as_ref().filter(|v| !v.inside) {
            outln!(
                "  joint {}: OUTSIDE the contact model's validity, so its force peaks are not \
                 results (summary.json has them, and the measures): {}",
                j.name,
                v.reasons.join("; ")
            );
            continue;
        }
        outln!(
            "  joint {}: peak F_n {:.2} kN (all), {}; max penetration {:.2} µm",
            j.name,
            a.max * 1e-3,
            peak_after(b, window),
            j.max_penetration_m * 1e6,
        );
        outln!(
            "    dissipated per cycle: {:.3} J (damping {:.3} J + friction {:.3} J; books close \
             to {:.1e} J)",
            j.contact_dissipation_per_cycle_j,
            j.damping_dissipation_per_cycle_j,
            j.friction_dissipation_per_cycle_j,
            j.energy_books_residual_per_cycle_j
        );
    }
    for w in &r.energy_warnings {
        outln!("  WARNING: {w}");
    }
}

/// `wearsim stress`: runs [`analysis::stress`], prints each case as it ends, writes the tables.
fn stress(quick: bool, o: &Overrides) -> Result<(), CliError> {
    let out = o
        .out
        .clone()
        .unwrap_or_else(|| Path::new("out").join("stress"));
    let _lock = output::files::FolderLock::take(&out)?;
    let options = analysis::stress::StressOptions {
        quick,
        ..Default::default()
    };
    let started = std::time::Instant::now();
    let results = analysis::stress::run_battery(&options, &mut |case, result| match result {
        None => err!("{:<24} ", case.name),
        Some(r) => errln!(
            "{} ({:.1} s) {}",
            r.outcome.label(),
            r.wall_time_s,
            r.outcome.detail()
        ),
    })
    .map_err(|e| match e {
        analysis::stress::StressError::Scene(e) => CliError::Scene(e),
        analysis::stress::StressError::Output(e) => CliError::Output(e),
    })?;
    let files = analysis::stress::write_report(&results, &out)?;
    out!("{}", analysis::stress::markdown(&results));
    let failed = results
        .iter()
        .filter(|r| r.outcome.label() == "FAILED")
        .count();
    outln!(
        "{} case(s), {failed} failed; wrote {} files to {} in {:.1} s",
        results.len(),
        files.len(),
        out.display(),
        started.elapsed().as_secs_f64()
    );
    Ok(())
}

/// Settings of `wearsim precision` beyond the scene.
struct PrecisionArgs<'a> {
    methods: &'a [scene::Integrator],
    rtols: &'a [f64],
    repeats: usize,
    duration: Option<f64>,
    start_up: f64,
    max_steps: usize,
}

/// `wearsim precision`: runs [`analysis::precision`], one line per run, writes the report.
fn precision(spec: &str, args: &PrecisionArgs<'_>, o: &Overrides) -> Result<(), CliError> {
    let Loaded { name, scene } = load(spec, o)?;
    let out = o
        .out
        .clone()
        .unwrap_or_else(|| Path::new("out").join("precision"));
    let _lock = output::files::FolderLock::take(&out)?;
    let mut options = analysis::precision::PrecisionOptions {
        repeats: args.repeats,
        duration: args.duration,
        start_up: args.start_up,
        max_steps: args.max_steps,
        ..Default::default()
    };
    if !args.methods.is_empty() {
        options.methods = args.methods.to_vec();
    }
    if !args.rtols.is_empty() {
        options.rtols = args.rtols.to_vec();
    }
    let started = std::time::Instant::now();
    let report =
        analysis::precision::run_sweep(&name, &scene, &options, &mut |event| match event {
            analysis::precision::Event::Start(method, rtol, what) => {
                errln!(
                    "[{:>6.0} s] {method:<9} rtol {rtol:.0e}: {what}",
                    started.elapsed().as_secs_f64()
                );
            }
            analysis::precision::Event::Row(row) => match row.errors() {
                Some(e) => errln!(
                    "           {} steps, {:.3} s; start-up error {:.2e} m, cycle error {:.2e}",
                    row.steps,
                    row.wall_s,
                    e.start_up_m(),
                    e.cycle_max()
                ),
                None => errln!("           {:?}", row.outcome),
            },
        })?;
    let files = report.write(&out)?;
    outln!("{}", report.markdown(None));
    outln!(
        "wrote {} files to {} in {:.1} s",
        files.len(),
        out.display(),
        started.elapsed().as_secs_f64()
    );
    Ok(())
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
        } => run(
            scene.as_deref().unwrap_or(scenes::DEFAULT),
            *no_animation,
            o,
        ),
        Command::Study {
            study: s,
            stage_cycles,
        } => study::run(s, *stage_cycles, o),
        Command::Check { scene } => check(scene, o),
        Command::Scenes => {
            list_scenes();
            Ok(())
        }
        Command::Stress { quick } => stress(*quick, o),
        Command::Sweep { file, resume } => sweep::run(file, *resume, o),
        Command::Precision {
            scene,
            methods,
            rtols,
            repeats,
            duration,
            start_up,
            max_steps,
        } => precision(
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
