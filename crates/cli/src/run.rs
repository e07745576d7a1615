//! `wearsim run` and `wearsim check`: one scene simulated and written, or checked.

use crate::error::CliError;
use crate::load::{Loaded, in_scene, load, out_dir};
use crate::overrides::Overrides;
use crate::{print, progress};

/// `wearsim check`: everything `run` checks before it simulates, then what the scene contains.
pub fn check(spec: &str, o: &Overrides) -> Result<(), CliError> {
    let Loaded { name, scene: s } = load(spec, o)?;
    // Every check `run` makes before simulating, before anything is called valid.
    let options = o.run_options();
    let check = sim::check_assembly(&name, &s, &options).map_err(|e| in_scene(spec, e))?;
    print::scene_check(&name, &s, &check);
    Ok(())
}

/// `wearsim run`: the scene run and written into a staged output folder, then summarised.
pub fn run(spec: &str, no_animation: bool, o: &Overrides) -> Result<(), CliError> {
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
    print::run_summary(&outcome, &out, files.len());
    Ok(())
}
