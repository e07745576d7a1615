//! Serde defaults shared by the scene's tables (`types` and `run_settings`).

/// `#[serde(default = "yes")]`: a switch that is on unless the file turns it off.
pub(super) fn yes() -> bool {
    true
}
