//! The files of a run and of a study: atomic writers and number formats ([`files`], which also
//! re-exports the staged, locked output folders of runs and studies), a run's CSV, JSON and PNG
//! files ([`artifacts`], entry point [`write_run`]), figures ([`plot`], the life curve in
//! [`life_plot`]), the animated mechanism (`mechanism.gif`, [`animation`]), the self-contained
//! HTML pages ([`html`]) of a run's report ([`report`]), and the worn surfaces a run writes and
//! a later run starts from ([`surfaces`]).
//!
//! Everything here takes what a run computed in memory (`sim::RunOutcome`) and writes it; no
//! number is computed here that a run's checks depend on.
//!
//! ```no_run
//! # fn main() -> Result<(), Box<dyn std::error::Error>> {
//! let scene = scene::load_path(std::path::Path::new("my_scene.toml"), &[])?;
//! let outcome = sim::run_scene("my_scene", &scene, &sim::RunOptions::default(), &mut ())?;
//! let files = output::write_run(&outcome, std::path::Path::new("out/my_scene"))?;
//! println!("{} files written", files.len());
//! # Ok(())
//! # }
//! ```

#![warn(missing_docs)]

pub mod animation;
pub mod artifacts;
mod error;
pub mod files;
pub mod html;
pub mod life_plot;
pub mod plot;
pub mod report;
mod staged;
pub mod surfaces;

pub use artifacts::write_run;
pub use error::OutputError;
