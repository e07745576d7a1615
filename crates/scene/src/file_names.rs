//! Names that become file names: what a name may be, the files a run writes for each
//! clearance joint, and which two names would write the same file. Validation
//! ([`super::Scene::validate`]) refuses the names these rules reject, and the writers of a
//! run's files name them here and refuse an unsafe name again before writing.

/// Longest name, in characters.
pub const MAX_NAME_CHARS: usize = 64;

/// Whether `name` can be used as (part of) a file name on any platform without creating
/// folders, escaping the output folder or hiding the file.
pub fn is_file_name_safe(name: &str) -> bool {
    !name.is_empty()
        && !name.starts_with('.')
        && name.chars().count() <= MAX_NAME_CHARS
        && name
            .chars()
            .all(|c| c.is_ascii_alphanumeric() || matches!(c, '-' | '_' | '.'))
}

/// The files a run writes for one clearance joint, named after it.
#[derive(Debug, Clone, Copy)]
pub enum JointFile {
    /// `wear_<joint>_stage<k>.csv`.
    StageWear(usize),
    /// `wear_<joint>.png`.
    Wear,
    /// `worn_outline_<joint>.png`.
    Outline,
    /// `wear_life_<joint>.png`.
    Life,
    /// `contact_force_<joint>[_worn].png`.
    Force(bool),
    /// `journal_<joint>[_worn].png`.
    Journal(bool),
}

impl JointFile {
    /// The file name for joint `joint`.
    pub fn name(self, joint: &str) -> String {
        let worn = |w: bool| if w { "_worn" } else { "" };
        match self {
            JointFile::StageWear(k) => format!("wear_{joint}_stage{k}.csv"),
            JointFile::Wear => format!("wear_{joint}.png"),
            JointFile::Outline => format!("worn_outline_{joint}.png"),
            JointFile::Life => format!("wear_life_{joint}.png"),
            JointFile::Force(w) => format!("contact_force_{joint}{}.png", worn(w)),
            JointFile::Journal(w) => format!("journal_{joint}{}.png", worn(w)),
        }
    }
}

/// A file name two clearance joints would both write (the first found), e.g.
/// `contact_force_A_worn.png` for joints `A` and `A_worn`. The per-stage CSVs
/// `wear_<joint>_stage<k>.csv` cannot collide for distinct names (`<k>` is a number, and
/// the other files end otherwise), so only the fixed set is compared: the check costs the
/// same for any number of stages.
pub fn colliding_file(first: &str, second: &str) -> Option<String> {
    let files = |joint: &str| -> Vec<String> {
        [
            JointFile::Wear,
            JointFile::Outline,
            JointFile::Life,
            JointFile::Force(false),
            JointFile::Force(true),
            JointFile::Journal(false),
            JointFile::Journal(true),
        ]
        .into_iter()
        .map(|f| f.name(joint))
        .collect()
    };
    let theirs = files(second);
    files(first).into_iter().find(|f| theirs.contains(f))
}
