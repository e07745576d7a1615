//! Files in and out: atomic writers and number formats ([`output`], which also re-exports the
//! staged, locked output folders of runs and studies), a run's CSV, JSON and PNG files
//! ([`artifacts`]), figures ([`plot`], the life curve in [`life_plot`]), the animated mechanism
//! (`mechanism.gif`, [`animation`]), and the self-contained HTML pages ([`html`]) of a run's
//! report ([`report`]).

pub mod animation;
pub mod artifacts;
pub mod html;
pub mod life_plot;
pub mod output;
mod output_error;
pub mod plot;
pub mod report;
mod staged;
