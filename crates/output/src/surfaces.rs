//! Worn-surface files: the wear grid of every stage a run writes (`wear_<joint>_stage<k>.csv`:
//! cell angle, bearing depth, pin depth; depths cumulative over the stages), and the last stage
//! read back ([`load_last_stage`], [`folder`]) for a run that starts from an earlier run's
//! surfaces. The checks of the rows themselves are `sim::surfaces::joint_from_rows`.

use std::io::Read;
use std::path::{Path, PathBuf};
use std::sync::Arc;

use wear::WornJoint;

use crate::files::{Column, OutputError, write_csv};
use scene::file_names::JointFile;
use scene::{MAX_WEAR_CELLS, Scene};
use sim::surfaces::{COLUMNS, SurfaceSource, SurfacesError, cell_angle_deg, joint_from_rows};

/// Writes stage `stage` (1-based) of joint `joint`'s wear grid into `dir`; returns the file.
pub fn write_stage(
    dir: &Path,
    joint: &str,
    stage: usize,
    surfaces: &WornJoint,
) -> Result<PathBuf, OutputError> {
    let (bearing, pin) = (surfaces.bearing().depth(), surfaces.pin().depth());
    let angle: Vec<f64> = (0..bearing.len())
        .map(|c| cell_angle_deg(c, bearing.len()))
        .collect();
    let path = dir.join(JointFile::StageWear(stage).name(joint));
    write_csv(
        &path,
        &[
            (
                Column {
                    name: "angle",
                    unit: "deg",
                },
                &angle,
            ),
            (
                Column {
                    name: "bearing_depth",
                    unit: "m",
                },
                bearing,
            ),
            (
                Column {
                    name: "pin_depth",
                    unit: "m",
                },
                pin,
            ),
        ],
    )
}

/// The folder of an earlier run's surfaces, as a run's [`SurfaceSource`] (its last stage's
/// files, [`load_last_stage`]).
#[derive(Debug, Clone)]
pub struct Folder(pub PathBuf);

impl SurfaceSource for Folder {
    fn load(
        &self,
        scene: &Scene,
        unworn: &[Option<WornJoint>],
    ) -> Result<Vec<Option<WornJoint>>, SurfacesError> {
        load_last_stage(&self.0, scene, unworn)
    }
}

/// The surfaces in `dir`, for `sim::RunOptions::surfaces`.
pub fn folder(dir: impl Into<PathBuf>) -> Arc<dyn SurfaceSource> {
    Arc::new(Folder(dir.into()))
}

/// The worn joints in `dir` for `scene`'s active clearance joints (scene order; `None` where
/// the scene has no wear for that joint, which then stays round). `unworn` is what
/// [`sim::build::unworn_joints`] gives for the scene: it fixes the wear parameters, radii and
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
    if !unworn.iter().any(Option::is_some) {
        return Err(SurfacesError::NothingWears {
            dir: dir.to_path_buf(),
        });
    }
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

/// `k` of a file named `wear_<joint>_stage<k>.csv` exactly as a run names it
/// ([`JointFile::StageWear`]): `wear_A_stage+2.csv` or `wear_A_stage02.csv` is no stage file
/// (read as stage 2, the run would then look for `wear_A_stage2.csv`).
fn stage_of(file_name: &str, joint: &str) -> Option<u32> {
    let k: u32 = file_name
        .strip_prefix("wear_")?
        .strip_prefix(joint)?
        .strip_prefix("_stage")?
        .strip_suffix(".csv")?
        .parse()
        .ok()?;
    (JointFile::StageWear(k as usize).name(joint) == file_name).then_some(k)
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
    let expected = COLUMNS;
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
    joint_from_rows(file, joint, base, &rows)
}
