//! Starting a run from worn surfaces: the last-stage wear grids an earlier run wrote.
//!
//! A run writes `wear_<joint>_stage<k>.csv` (cell angle, bearing depth, pin depth; depths are
//! cumulative over the stages). [`load_last_stage`] reads, for every active clearance joint of
//! a scene that wears, the file with the highest `k` in a folder and turns it into that joint's
//! [`WornJoint`], so a run can start (and stage on) from there: a worn mechanism can be
//! re-simulated under other settings, and a long life computation resumed stage by stage.

use std::io::Read;
use std::path::{Path, PathBuf};

use wear::{Side, WearError, WornJoint, WornProfile};

use scene::file_names::JointFile;
use scene::{MAX_WEAR_CELLS, Scene};

/// Body-frame angle of the centre of grid cell `k` of `n`, degrees: cell 0 spans 0..360/n.
pub fn cell_angle_deg(k: usize, n: usize) -> f64 {
    (k as f64 + 0.5) * 360.0 / n as f64
}

/// How far a row's angle may sit from its cell's centre, as a fraction of a cell: room for a
/// file re-saved with fewer digits, none for a row out of place.
const ANGLE_TOLERANCE_CELLS: f64 = 1e-3;

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
            let file = dir.join(JointFile::StageWear(stage as usize).name(&joint.name));
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

/// Bytes a wear file may hold: a row of three full-precision numbers is under 80 bytes, and a
/// grid has at most [`MAX_WEAR_CELLS`] rows.
const MAX_FILE_BYTES: u64 = 128 * MAX_WEAR_CELLS as u64 + 1024;

/// The whole text of `file`, which must be a regular file (not a FIFO that blocks, nor a
/// device that never ends) of at most [`MAX_FILE_BYTES`].
fn read_bounded(file: &Path) -> Result<Vec<u8>, String> {
    let metadata = std::fs::metadata(file).map_err(|e| e.to_string())?;
    if !metadata.is_file() {
        return Err("not a regular file (a folder, FIFO or device cannot hold a wear grid)".into());
    }
    let too_large = || {
        format!(
            "larger than {MAX_FILE_BYTES} bytes: more than a wear grid of {MAX_WEAR_CELLS} cells \
             holds"
        )
    };
    if metadata.len() > MAX_FILE_BYTES {
        return Err(too_large());
    }
    let mut bytes = Vec::new();
    std::fs::File::open(file)
        .and_then(|f| f.take(MAX_FILE_BYTES + 1).read_to_end(&mut bytes))
        .map_err(|e| e.to_string())?;
    if bytes.len() as u64 > MAX_FILE_BYTES {
        return Err(too_large());
    }
    Ok(bytes)
}

fn load_joint(file: &Path, joint: &str, base: &WornJoint) -> Result<WornJoint, SurfacesError> {
    let unreadable = |reason: String| SurfacesError::Unreadable {
        file: file.to_path_buf(),
        reason,
    };
    let bytes = read_bounded(file).map_err(unreadable)?;
    let mut reader = csv::Reader::from_reader(bytes.as_slice());
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
    // Parse every row first (the file's size bounds them), so a grid of another size is named
    // as such before any row is judged against this one.
    let mut rows: Vec<[f64; 3]> = Vec::new();
    for (row, record) in reader.records().enumerate() {
        let record = record.map_err(|e| unreadable(e.to_string()))?;
        let mut values = [0.0; 3];
        for (column, value) in values.iter_mut().enumerate() {
            let text = record.get(column).unwrap_or("");
            *value = text.trim().parse::<f64>().map_err(|_| {
                unreadable(format!(
                    "line {}: {} = {text:?} is not a number",
                    row + 2,
                    expected[column]
                ))
            })?;
        }
        rows.push(values);
    }
    let cells = base.bearing().cells();
    if rows.len() != cells {
        return Err(SurfacesError::GridMismatch {
            file: file.to_path_buf(),
            joint: joint.to_string(),
            expected: cells,
            found: rows.len(),
        });
    }
    for (row, values) in rows.iter().enumerate() {
        // The angle column must be the grid's own: rows in order, one per cell centre.
        let (angle, centre) = (values[0], cell_angle_deg(row, cells));
        let off_centre = (angle - centre).abs();
        if off_centre.is_nan() || off_centre > ANGLE_TOLERANCE_CELLS * 360.0 / cells as f64 {
            return Err(unreadable(format!(
                "line {}: angle [deg] = {angle} is not cell {row}'s centre {centre} of a grid of \
                 {cells} cells (rows must list the cells in order, as `wearsim run` writes them)",
                row + 2
            )));
        }
        let radii = [base.bearing().nominal_radius(), base.pin().nominal_radius()];
        for (column, radius) in [(1, radii[0]), (2, radii[1])] {
            // Each surface loses half the depth from its radius (wear::WornProfile).
            if !(values[column].is_finite() && values[column] >= 0.0)
                || values[column] >= 2.0 * radius
            {
                return Err(unreadable(format!(
                    "line {}: {} = {} must be a finite depth ≥ 0 that leaves the surface \
                     (nominal radius {radius} m) a radius: below {} m",
                    row + 2,
                    expected[column],
                    values[column],
                    2.0 * radius
                )));
            }
        }
    }
    let bearing = rows.iter().map(|r| r[1]).collect();
    let pin = rows.iter().map(|r| r[2]).collect();
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
