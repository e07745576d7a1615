//! Starting a run from worn surfaces, in memory: where the surfaces come from
//! ([`SurfaceSource`]; crate `output` reads them from the `wear_<joint>_stage<k>.csv` files an
//! earlier run wrote), the rows of a wear grid turned into a joint's [`WornJoint`] with every
//! check a grid read from elsewhere needs ([`joint_from_rows`]), and why that failed
//! ([`SurfacesError`]). A worn mechanism can so be re-simulated under other settings, and a
//! long life computation resumed stage by stage. No file is read here.

use std::path::{Path, PathBuf};

use wear::{Side, WearError, WornJoint, WornProfile};

use scene::Scene;

/// The columns of a wear grid's rows: body-frame angle of the cell centre, bearing depth, pin
/// depth (depths cumulative over the stages).
pub const COLUMNS: [&str; 3] = ["angle [deg]", "bearing_depth [m]", "pin_depth [m]"];

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
    /// The scene has no clearance joint that wears: no surface in the folder would be used.
    #[error(
        "--surfaces {dir}: the scene has no clearance joint with wear, so no surface there \
         would be used (give a scene whose joints wear, or leave out --surfaces)"
    )]
    NothingWears {
        /// The folder.
        dir: PathBuf,
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

/// Where the worn surfaces a run starts from come from (`sim::RunOptions::surfaces`): the
/// run asks for them once, after its scene is settled and before any simulation, so a bad
/// surface is refused before any work.
pub trait SurfaceSource: std::fmt::Debug + Send + Sync {
    /// The worn joints for `scene`'s active clearance joints (scene order; `None` where the
    /// scene has no wear for that joint, which then stays round). `unworn` is what
    /// [`crate::build::unworn_joints`] gives for the scene: it fixes the wear parameters, radii
    /// and sliding choice; only the depths come from the source.
    fn load(
        &self,
        scene: &Scene,
        unworn: &[Option<WornJoint>],
    ) -> Result<Vec<Option<WornJoint>>, SurfacesError>;
}

/// Joint `joint`'s worn surfaces from the rows of its wear grid (read from `file`, which the
/// errors name; columns [`COLUMNS`]) on the parameters of `base`: one row per cell in order,
/// each angle at its cell's centre, each depth finite, non-negative and leaving the surface a
/// radius.
pub fn joint_from_rows(
    file: &Path,
    joint: &str,
    base: &WornJoint,
    rows: &[[f64; 3]],
) -> Result<WornJoint, SurfacesError> {
    let unreadable = |reason: String| SurfacesError::Unreadable {
        file: file.to_path_buf(),
        reason,
    };
    let expected = COLUMNS;
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
