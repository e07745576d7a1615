//! Files in and out: atomic writers and number formats ([`output`]), a run's CSV, JSON and PNG
//! files ([`artifacts`]), figures ([`plot`]) and worn surfaces read back from an earlier run
//! ([`surfaces`]).

pub mod artifacts;
pub mod output;
pub mod plot;
pub mod surfaces;
