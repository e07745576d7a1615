//! Reading a `wearsim run`'s wear results (each wearing joint's bearing and pin peak depth and
//! worn volume, with the noise the run printed for each) from its `summary.json`; shared by the
//! examples that compare runs.

use std::error::Error;
use std::path::Path;

/// One wear result of a run with its printed noise (one standard error).
#[derive(Debug, Clone, Copy)]
pub struct Value {
    pub value: f64,
    pub noise: f64,
}

/// The quantities of [`WearResults::joints`], in that order.
pub const QUANTITIES: [&str; 3] = ["bearing peak", "pin peak", "worn volume"];

/// What one run's stage gives.
#[derive(Debug, Clone)]
pub struct WearResults {
    /// Per wearing joint: its name, then bearing peak depth (m), pin peak depth (m) and worn
    /// volume (m³).
    pub joints: Vec<(String, [Value; 3])>,
    /// Sub-steps over all stages.
    pub substeps: u64,
}

/// Reads `dir/summary.json`.
pub fn read_wear_results(dir: &Path) -> Result<WearResults, Box<dyn Error>> {
    let path = dir.join("summary.json");
    let text = std::fs::read_to_string(&path).map_err(|e| format!("{}: {e}", path.display()))?;
    let summary: serde_json::Value = serde_json::from_str(&text)?;
    let wear = &summary["wear"];
    let number = |v: &serde_json::Value, field: &str| -> Result<f64, String> {
        v[field]
            .as_f64()
            .ok_or_else(|| format!("{}: no number `{field}`", path.display()))
    };
    let mut joints = Vec::new();
    for j in wear["joints"]
        .as_array()
        .ok_or_else(|| format!("{}: no wear joints", path.display()))?
    {
        let value = |field: &str, noise: &str| -> Result<Value, String> {
            Ok(Value {
                value: number(j, field)?,
                noise: number(j, noise)?,
            })
        };
        joints.push((
            j["name"].as_str().unwrap_or("?").to_string(),
            [
                value("bearing_peak_depth_m", "bearing_peak_depth_noise_m")?,
                value("pin_peak_depth_m", "pin_peak_depth_noise_m")?,
                value("worn_volume_m3", "worn_volume_noise_m3")?,
            ],
        ));
    }
    let substeps = wear["substeps_per_stage"]
        .as_array()
        .map_or(0, |s| s.iter().filter_map(serde_json::Value::as_u64).sum());
    Ok(WearResults { joints, substeps })
}
