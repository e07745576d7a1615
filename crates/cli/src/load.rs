//! Scenes as the commands take them: loaded by name or path with the command-line overrides,
//! their run errors named after them, and where their outputs go.

use std::path::{Path, PathBuf};

use lgres::scenes;
use scene::ValidScene;
use sim::RunError;

use crate::error::CliError;
use crate::overrides::Overrides;

/// A loaded scene and the name outputs are filed under.
pub struct Loaded {
    /// The name outputs are filed under: the built-in name or the file's stem.
    pub name: String,
    /// The scene, overrides applied.
    pub scene: ValidScene,
}

/// A run error, named after the scene when the scene is what is wrong with it (a scene error
/// names its scene already).
pub fn in_scene(spec: &str, e: RunError) -> CliError {
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
pub fn load(spec: &str, o: &Overrides) -> Result<Loaded, CliError> {
    let (name, scene) = scene::load_named::<ValidScene>(spec, None, scenes::BUILTINS)?;
    let origin = format!("{spec} with command-line overrides");
    let scene = o.run_overrides().apply(scene, &origin)?;
    Ok(Loaded { name, scene })
}

/// The output folder: `--out`, else `out/<name>`.
pub fn out_dir(o: &Overrides, name: &str) -> PathBuf {
    o.out.clone().unwrap_or_else(|| Path::new("out").join(name))
}
