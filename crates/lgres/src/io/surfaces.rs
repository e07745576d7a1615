//! Starting a run from worn surfaces: the last-stage wear grids an earlier run wrote.
//!
//! A run writes `wear_<joint>_stage<k>.csv` (cell angle, bearing depth, pin depth; depths are
//! cumulative over the stages). [`load_last_stage`] reads, for every active clearance joint of
//! a scene that wears, the file with the highest `k` in a folder and turns it into that joint's
//! [`WornJoint`], so a run can start (and stage on) from there: a worn mechanism can be
//! re-simulated under other settings, and a long life computation resumed stage by stage.

use std::path::{Path, PathBuf};

use wear::{Side, WearError, WornJoint, WornProfile};

use crate::scene::Scene;

/// Why the surfaces could not be loaded; every variant names the joint and the file.
#[derive(Debug, thiserror::Error)]
pub enum SurfacesError {
    /// The folder cannot be listed.
    #[error("--surfaces {dir}: cannot read the folder: {source}")]
    Folder {
        /// The folder.
        dir: PathBuf,
        /// Cause.
        source: std::io::Error,
    },
    /// No wear file for a joint that wears.
    #[error(
        "--surfaces {dir}: no wear_{joint}_stage<k>.csv for clearance joint {joint:?} (a run of \
         a scene with a joint of that name and wear on writes it)"
    )]
    Missing {
        /// The folder.
        dir: PathBuf,
        /// Joint name.
        joint: String,
    },
    /// A file that cannot be read or parsed.
    #[error("{file}: {reason}")]
    Unreadable {
        /// The file.
        file: PathBuf,
        /// What is wrong (line and column named where it helps).
        reason: String,
    },
    /// A file whose grid does not match the scene's joint.
    #[error(
        "{file}: {found} cells, but clearance joint {joint:?} of the scene has wear.cells = \
         {expected}"
    )]
    GridMismatch {
        /// The file.
        file: PathBuf,
        /// Joint name.
        joint: String,
        /// Cells in the scene.
        expected: usize,
        /// Rows in the file.
        found: usize,
    },
    /// The depths do not make a valid worn joint (e.g. a pin worn through).
    #[error("{file}: joint {joint:?}: {source}")]
    Invalid {
        /// The file.
        file: PathBuf,
        /// Joint name.
        joint: String,
        /// Cause.
        source: WearError,
    },
}

/// The worn joints in `dir` for `scene`'s active clearance joints (scene order; `None` where
/// the scene has no wear for that joint, which then stays round). `unworn` is what
/// [`crate::build::unworn_joints`] gives for the scene: it fixes the wear parameters, radii and
/// sliding choice; only the depths come from the files.
pub fn load_last_stage(
    dir: &Path,
    scene: &Scene,
    unworn: &[Option<WornJoint>],
) -> Result<Vec<Option<WornJoint>>, SurfacesError> {
    let entries = std::fs::read_dir(dir).map_err(|source| SurfacesError::Folder {
        dir: dir.to_path_buf(),
        source,
    })?;
    let names: Vec<String> = entries
        .filter_map(Result::ok)
        .filter_map(|e| e.file_name().into_string().ok())
        .collect();
    scene
        .active_clearance_joints()
        .zip(unworn)
        .map(|(joint, base)| {
            let Some(base) = base else { return Ok(None) };
            let stage = names
                .iter()
                .filter_map(|n| stage_of(n, &joint.name))
                .max()
                .ok_or_else(|| SurfacesError::Missing {
                    dir: dir.to_path_buf(),
                    joint: joint.name.clone(),
                })?;
            let file = dir.join(format!("wear_{}_stage{stage}.csv", joint.name));
            load_joint(&file, &joint.name, base).map(Some)
        })
        .collect()
}

/// `k` of a file named `wear_<joint>_stage<k>.csv`.
fn stage_of(file_name: &str, joint: &str) -> Option<u32> {
    file_name
        .strip_prefix("wear_")?
        .strip_prefix(joint)?
        .strip_prefix("_stage")?
        .strip_suffix(".csv")?
        .parse()
        .ok()
}

fn load_joint(file: &Path, joint: &str, base: &WornJoint) -> Result<WornJoint, SurfacesError> {
    let unreadable = |reason: String| SurfacesError::Unreadable {
        file: file.to_path_buf(),
        reason,
    };
    let mut reader = csv::Reader::from_path(file).map_err(|e| unreadable(e.to_string()))?;
    let header: Vec<String> = reader
        .headers()
        .map_err(|e| unreadable(e.to_string()))?
        .iter()
        .map(str::to_string)
        .collect();
    let expected = ["angle [deg]", "bearing_depth [m]", "pin_depth [m]"];
    if header != expected {
        return Err(unreadable(format!(
            "header {header:?}, expected {expected:?} (a wear file written by `wearsim run`)"
        )));
    }
    let (mut bearing, mut pin) = (Vec::new(), Vec::new());
    for (row, record) in reader.records().enumerate() {
        let record = record.map_err(|e| unreadable(e.to_string()))?;
        let value = |column: usize| -> Result<f64, SurfacesError> {
            let text = record.get(column).unwrap_or("");
            text.trim().parse::<f64>().map_err(|_| {
                unreadable(format!(
                    "line {}: {} = {text:?} is not a number",
                    row + 2,
                    expected[column]
                ))
            })
        };
        bearing.push(value(1)?);
        pin.push(value(2)?);
    }
    let cells = base.bearing().cells();
    if bearing.len() != cells {
        return Err(SurfacesError::GridMismatch {
            file: file.to_path_buf(),
            joint: joint.to_string(),
            expected: cells,
            found: bearing.len(),
        });
    }
    let invalid = |source| SurfacesError::Invalid {
        file: file.to_path_buf(),
        joint: joint.to_string(),
        source,
    };
    let bearing = WornProfile::from_depths(Side::Bearing, base.bearing().nominal_radius(), bearing)
        .map_err(invalid)?;
    let pin =
        WornProfile::from_depths(Side::Pin, base.pin().nominal_radius(), pin).map_err(invalid)?;
    WornJoint::from_profiles(base.wear_coefficient(), base.hinge_width(), bearing, pin)
        .map(|j| j.with_sliding(base.sliding()))
        .map_err(invalid)
}
