//! What a run reports while it goes on ([`Progress`]).

/// Receives progress; every method defaults to doing nothing (`()` ignores everything).
pub trait Progress {
    /// A new phase of `cycles` drive periods starts (e.g. `"response"`, `"stage 1.2"`).
    fn phase(&mut self, _label: &str, _cycles: f64) {}
    /// Position within the current phase, in periods.
    fn advance(&mut self, _cycles: f64) {}
    /// The current phase is done.
    fn finish(&mut self) {}
    /// A note or warning for the user (e.g. a single-jump extrapolation warning).
    fn note(&mut self, _text: &str) {}
}

impl Progress for () {}
