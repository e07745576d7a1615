//! `wearsim`: the command line of the worn-clearance-joint toolkit.
//!
//! Thin by design: it parses arguments, loads and validates scenes through `lgres`, prints and
//! maps errors to exit codes (0 success, 1 could not run, 2 bad input). `run` and `study` stop
//! after validation until `lgres` is wired to the `multibody`, `contact` and `wear` crates.

use std::path::{Path, PathBuf};
use std::process::ExitCode;

use clap::{Parser, Subcommand, ValueEnum};
use lgres::scene::{self, Scene, SceneError};
use lgres::scenes;

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

/// Options that override the scene's settings.
#[derive(clap::Args)]
struct Overrides {
    /// Output folder (default: out/<scene>).
    #[arg(long, global = true, value_name = "DIR")]
    out: Option<PathBuf>,
    /// Drive cycles of the response run (scene: run.cycles).
    #[arg(long, global = true)]
    cycles: Option<u32>,
    /// Wear stages (scene: run.wear_stages).
    #[arg(long, global = true)]
    stages: Option<u32>,
    /// Relative tolerance (scene: solver.rtol).
    #[arg(long, global = true, allow_negative_numbers = true)]
    rtol: Option<f64>,
}

#[derive(Subcommand)]
enum Command {
    /// Simulate a scene (a built-in name or a TOML file; default: the paper's LGRES).
    Run { scene: Option<String> },
    /// Run one of the paper's studies, or all of them.
    Study { study: StudyName },
    /// Parse and validate a scene and print what it contains.
    Check { scene: String },
    /// List the built-in scenes and studies.
    Scenes,
}

#[derive(Clone, Copy, ValueEnum)]
enum StudyName {
    WearStages,
    Clearance,
    Speed,
    All,
}

impl StudyName {
    fn studies(self) -> Vec<&'static scenes::Study> {
        let name = match self {
            StudyName::WearStages => "wear-stages",
            StudyName::Clearance => "clearance",
            StudyName::Speed => "speed",
            StudyName::All => return scenes::STUDIES.iter().collect(),
        };
        scenes::study(name).into_iter().collect()
    }
}

/// Why `wearsim` stopped.
#[derive(Debug, thiserror::Error)]
enum CliError {
    /// The scene could not be loaded or is invalid.
    #[error(transparent)]
    Scene(#[from] SceneError),
    /// Neither a built-in name nor an existing file.
    #[error("no built-in scene and no file named {0:?} (see `wearsim scenes`)")]
    NoSuchScene(String),
    /// Simulation is not available yet.
    #[error(
        "{what}: scene valid, but simulation is not wired yet (the multibody, contact and wear \
         crates are being built); nothing was written to {}",
        out.display()
    )]
    NotWired { what: String, out: PathBuf },
}

impl CliError {
    fn exit_code(&self) -> u8 {
        match self {
            CliError::Scene(_) | CliError::NoSuchScene(_) => 2,
            CliError::NotWired { .. } => 1,
        }
    }
}

/// A loaded scene and the name outputs are filed under.
struct Loaded {
    name: String,
    scene: Scene,
}

/// Load a built-in scene by name, else a file; apply command-line overrides and re-validate.
fn load(spec: &str, o: &Overrides) -> Result<Loaded, CliError> {
    let (name, mut scene) = if scenes::source(spec).is_some() {
        (spec.to_string(), scenes::builtin(spec)?)
    } else if Path::new(spec).is_file() {
        let path = Path::new(spec);
        let stem = path
            .file_stem()
            .map_or_else(|| "scene".to_string(), |s| s.to_string_lossy().into_owned());
        (stem, scene::load_path(path)?)
    } else {
        return Err(CliError::NoSuchScene(spec.to_string()));
    };
    if let Some(c) = o.cycles {
        scene.run.cycles = c;
    }
    if let Some(s) = o.stages {
        scene.run.wear_stages = s;
    }
    if let Some(r) = o.rtol {
        scene.solver.rtol = r;
    }
    scene.validate(&format!("{spec} with command-line overrides"))?;
    Ok(Loaded { name, scene })
}

fn out_dir(o: &Overrides, name: &str) -> PathBuf {
    o.out.clone().unwrap_or_else(|| Path::new("out").join(name))
}

fn check(spec: &str, o: &Overrides) -> Result<(), CliError> {
    let Loaded { name, scene: s } = load(spec, o)?;
    println!("scene {name}: valid");
    println!("  {}", s.description);
    println!("  inertia: {}", s.inertia_convention);
    println!("  bodies ({}):", s.bodies.len());
    for b in &s.bodies {
        println!(
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
    println!(
        "  revolute joints: {}",
        names(s.revolute_joints.iter().map(|j| j.name.as_str()).collect())
    );
    println!(
        "  prismatic joints: {}",
        names(s.prismatic_joints.iter().map(|j| j.name.as_str()).collect())
    );
    println!(
        "  drivers: {}",
        names(s.drivers.iter().map(|d| d.name.as_str()).collect())
    );
    println!("  clearance joints ({}):", s.clearance_joints.len());
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
        println!(
            "    {:<12} bearing on {}, pin on {}: {role}",
            c.name, c.bearing_body, c.pin_body
        );
    }
    println!(
        "  constraint equations: {}; degrees of freedom (3·{} − {}, clearance joints as 0): {}",
        s.constraint_count(),
        s.bodies.len(),
        s.constraint_count(),
        s.degrees_of_freedom()
    );
    let t = s.tolerances();
    println!(
        "  solver: {:?}, rtol {:e}, atol {:.3e} m / {:.3e} rad / {:.3e} (m|rad)/s; cycle {} s",
        s.solver.integrator,
        s.solver.rtol,
        t.position,
        t.angle,
        t.velocity,
        s.cycle_period().map_or("-".into(), |p| format!("{p:.6}"))
    );
    println!("  assembly (rank, initial consistency) is checked once the multibody wiring lands.");
    Ok(())
}

fn run(spec: &str, o: &Overrides) -> Result<(), CliError> {
    let loaded = load(spec, o)?;
    Err(CliError::NotWired {
        what: format!("run {}", loaded.name),
        out: out_dir(o, &loaded.name),
    })
}

fn study(which: StudyName, o: &Overrides) -> Result<(), CliError> {
    let studies = which.studies();
    for st in &studies {
        for name in st.scenes {
            load(name, o)?;
        }
    }
    let list: Vec<&str> = studies.iter().map(|s| s.name).collect();
    Err(CliError::NotWired {
        what: format!("study {}", list.join(", ")),
        out: o.out.clone().unwrap_or_else(|| PathBuf::from("out")),
    })
}

fn list_scenes() {
    println!("built-in scenes:");
    for b in scenes::BUILTINS {
        let default = if b.name == scenes::DEFAULT {
            " (default)"
        } else {
            ""
        };
        println!("  {:<24} {}{default}", b.name, b.summary);
    }
    println!("studies:");
    for s in scenes::STUDIES {
        println!("  {:<24} {}: {}", s.name, s.summary, s.scenes.join(", "));
    }
}

fn main() -> ExitCode {
    let cli = Cli::parse();
    let o = &cli.overrides;
    let result = match &cli.command {
        Command::Run { scene } => run(scene.as_deref().unwrap_or(scenes::DEFAULT), o),
        Command::Study { study: s } => study(*s, o),
        Command::Check { scene } => check(scene, o),
        Command::Scenes => {
            list_scenes();
            Ok(())
        }
    };
    match result {
        Ok(()) => ExitCode::SUCCESS,
        Err(e) => {
            eprintln!("wearsim: error: {e}");
            ExitCode::from(e.exit_code())
        }
    }
}
