//! Output folders of runs and studies in progress: written into a hidden staging folder that
//! replaces the target whole at the end, and locked against a second writer (re-exported by
//! [`crate::files`]).

use std::fs::{self, File, OpenOptions};
use std::io::{self, Write};
use std::path::{Path, PathBuf};
use std::sync::Mutex;
use std::sync::atomic::{AtomicBool, Ordering};

use crate::error::{OutputError, io_err};

/// An output folder being written, for [`abandon_staged`].
struct Active {
    /// The folder the output ends up in.
    target: PathBuf,
    /// Its staging folder, or `None` for a folder written in place ([`FolderLock`]).
    staging: Option<PathBuf>,
    /// Its lock file.
    lock: PathBuf,
}

/// The registry of output folders: those being written, and those whose staged output this
/// process has moved into place (so an interrupt can say what is on disk).
struct Registry {
    active: Vec<Active>,
    committed: Vec<PathBuf>,
}

static ACTIVE: Mutex<Registry> = Mutex::new(Registry {
    active: Vec::new(),
    committed: Vec::new(),
});

/// Set once [`abandon_staged`] has removed the staging folders: no folder or file may be
/// created after that (a writer thread of a study would otherwise re-create the staging folder
/// it removed, and leave it behind when the process exits).
static ABANDONED: AtomicBool = AtomicBool::new(false);

/// Runs `create` (making a folder or a file in an output folder) unless the output was
/// abandoned, under the same lock [`abandon_staged`] holds: a creation either happens before
/// the staging folders are removed (and is removed with them) or not at all.
pub(crate) fn create_unless_abandoned<T>(
    create: impl FnOnce() -> Result<T, OutputError>,
) -> Result<T, OutputError> {
    let _registry = active();
    if ABANDONED.load(Ordering::SeqCst) {
        return Err(OutputError::Interrupted);
    }
    create()
}

/// Temporary files being written (`.name.tmp-<pid>`), until they are moved into place or
/// removed: an interrupt waits for their writers to remove them, and removes what is left, so
/// none outlives the process in a folder written in place (a sweep's, a report folder).
static TEMPS: Mutex<Vec<PathBuf>> = Mutex::new(Vec::new());

fn temps() -> std::sync::MutexGuard<'static, Vec<PathBuf>> {
    TEMPS
        .lock()
        .unwrap_or_else(std::sync::PoisonError::into_inner)
}

/// [`create_unless_abandoned`] for the temporary file `tmp`, which is remembered until
/// [`forget_temp`].
pub(crate) fn create_temp_unless_abandoned<T>(
    tmp: &Path,
    create: impl FnOnce() -> Result<T, OutputError>,
) -> Result<T, OutputError> {
    let _registry = active();
    if ABANDONED.load(Ordering::SeqCst) {
        return Err(OutputError::Interrupted);
    }
    let created = create()?;
    temps().push(tmp.to_path_buf());
    Ok(created)
}

/// The temporary file `tmp` is gone: moved into place or removed.
pub(crate) fn forget_temp(tmp: &Path) {
    let mut temps = temps();
    if let Some(k) = temps.iter().position(|p| p == tmp) {
        temps.swap_remove(k);
    }
}

fn active() -> std::sync::MutexGuard<'static, Registry> {
    ACTIVE
        .lock()
        .unwrap_or_else(std::sync::PoisonError::into_inner)
}

/// Extensions of the files a run writes; a folder holding anything else is not replaced.
const RUN_FILE_EXTENSIONS: [&str; 6] = ["csv", "png", "json", "toml", "html", "gif"];

/// A run's output folder being written. Files go into a hidden staging folder next to the
/// target, which replaces the target whole on [`StagedDir::commit`], so a reader never sees
/// the new run's CSVs next to the previous run's `summary.json`. A lock file next to the
/// target refuses a second run into the same folder meanwhile. Dropped without a commit (the
/// run failed) or abandoned on a signal ([`abandon_staged`]), it leaves the target as it was.
pub struct StagedDir {
    target: PathBuf,
    staging: PathBuf,
    lock: PathBuf,
    /// The lock file, locked while open (closed after the file is removed on drop).
    _held: File,
    done: bool,
}

impl StagedDir {
    /// Lock `target` and create its empty staging folder. Fails if `target` is not a folder,
    /// holds files a run does not write (it would be replaced), or another live run holds it.
    pub fn begin(target: &Path) -> Result<Self, OutputError> {
        Self::begin_holding(target, Holds::RunFiles)
    }

    /// [`begin`](Self::begin) for a study's folder: besides run files it may hold markdown
    /// reports and one level of sub-folders of run files (one per scene), all replaced.
    pub fn begin_study(target: &Path) -> Result<Self, OutputError> {
        Self::begin_holding(target, Holds::StudyFiles)
    }

    fn begin_holding(target: &Path, holds: Holds) -> Result<Self, OutputError> {
        let OutputFolder {
            target,
            parent,
            name,
        } = OutputFolder::new(target)?;
        let parent = parent.as_path();
        let folder_err = |reason: &str| OutputError::Folder {
            path: target.clone(),
            reason: reason.to_string(),
        };
        if current_folder_within(&target) {
            return Err(folder_err(
                "is the current folder or contains it: the output replaces the whole folder, \
                 which would leave the shell in a deleted one; choose a folder inside it",
            ));
        }
        let lock = OutputFolder::lock_file(parent, &name);
        let held = take_lock(&target, &lock)?;
        // Under the lock, so no other run starts writing in between.
        let checked = check_nesting(&target).and_then(|()| {
            let foreign = if target.exists() {
                foreign_entry(&target, holds)
            } else {
                Ok(None)
            };
            foreign.and_then(|foreign| match foreign {
                Some(foreign) => Err(folder_err(&format!(
                    "holds {foreign:?}, which wearsim does not write there; the output replaces \
                     the whole folder, so choose a new or empty folder"
                ))),
                None => Ok(()),
            })
        });
        if let Err(e) = checked {
            let _ = fs::remove_file(&lock);
            return Err(e);
        }
        remove_dead_staging(parent, &name);
        let staging = parent.join(format!(".{name}.staging-{}", std::process::id()));
        let created = fs::remove_dir_all(&staging)
            .or_else(|e| match e.kind() {
                io::ErrorKind::NotFound => Ok(()),
                _ => Err(e),
            })
            .and_then(|()| fs::create_dir(&staging));
        if let Err(e) = created {
            let _ = fs::remove_file(&lock);
            return Err(folder_err(&format!(
                "cannot create the staging folder {} beside it: {e}",
                staging.display()
            )));
        }
        active().active.push(Active {
            target: target.clone(),
            staging: Some(staging.clone()),
            lock: lock.clone(),
        });
        Ok(Self {
            target,
            staging,
            lock,
            _held: held,
            done: false,
        })
    }

    /// The staging folder to write the run's files into.
    pub fn path(&self) -> &Path {
        &self.staging
    }

    /// The folder the run ends up in.
    pub fn target(&self) -> &Path {
        &self.target
    }

    /// Move the staging folder into place (the previous folder is removed) and unlock.
    pub fn commit(mut self) -> Result<PathBuf, OutputError> {
        // Hold the registry so a signal arriving now waits until the folder is whole; once a
        // signal has abandoned the output (its handler is about to exit), nothing is moved:
        // a rename begun then would be cut short by the exit, leaving the target missing.
        let mut registry = active();
        if ABANDONED.load(Ordering::SeqCst) {
            return Err(OutputError::Interrupted);
        }
        let previous = self.staging.with_file_name(format!(
            ".{}.previous-{}",
            self.target
                .file_name()
                .map(|n| n.to_string_lossy().into_owned())
                .unwrap_or_default(),
            std::process::id()
        ));
        let had_previous = self.target.exists();
        // The replaced folder's permissions carry over to the new one (a folder a user made
        // read-only stays read-only).
        let permissions = fs::metadata(&self.target).ok().map(|m| m.permissions());
        if had_previous {
            fs::rename(&self.target, &previous).map_err(io_err(&self.target))?;
        }
        if let Err(e) = fs::rename(&self.staging, &self.target) {
            if had_previous {
                let _ = fs::rename(&previous, &self.target);
            }
            return Err(io_err(&self.target)(e));
        }
        if let Some(permissions) = permissions {
            let _ = fs::set_permissions(&self.target, permissions);
        }
        if had_previous {
            // Best effort: the new run is in place; an old copy left hidden is harmless.
            let _ = fs::remove_dir_all(&previous);
        }
        let _ = fs::remove_file(&self.lock);
        registry
            .active
            .retain(|a| a.staging.as_ref() != Some(&self.staging));
        registry.committed.push(self.target.clone());
        self.done = true;
        Ok(self.target.clone())
    }
}

impl Drop for StagedDir {
    fn drop(&mut self) {
        if !self.done {
            let mut registry = active();
            let _ = fs::remove_dir_all(&self.staging);
            let _ = fs::remove_file(&self.lock);
            registry
                .active
                .retain(|a| a.staging.as_ref() != Some(&self.staging));
        }
    }
}

/// A lock on an output folder whose reports are written in place, file by file at the end
/// (`wearsim precision`, `wearsim stress`: their folders may hold other reports' sub-folders,
/// which a staged replacement would delete). A second writer into the same folder is refused
/// meanwhile. Released on drop, and by [`abandon_staged`] on a signal.
pub struct FolderLock {
    lock: PathBuf,
    /// The lock file, locked while open (closed after the file is removed on drop).
    _held: File,
}

impl FolderLock {
    /// Takes the lock of `target` (the folder need not exist yet).
    pub fn take(target: &Path) -> Result<Self, OutputError> {
        let OutputFolder {
            target,
            parent,
            name,
        } = OutputFolder::new(target)?;
        let lock = OutputFolder::lock_file(&parent, &name);
        let held = take_lock(&target, &lock)?;
        if let Err(e) = check_nesting(&target) {
            let _ = fs::remove_file(&lock);
            return Err(e);
        }
        active().active.push(Active {
            target,
            staging: None,
            lock: lock.clone(),
        });
        Ok(Self { lock, _held: held })
    }
}

impl Drop for FolderLock {
    fn drop(&mut self) {
        let mut registry = active();
        let _ = fs::remove_file(&self.lock);
        registry.active.retain(|a| a.lock != self.lock);
    }
}

/// An output folder's absolute path, its parent (created) and its name.
struct OutputFolder {
    target: PathBuf,
    parent: PathBuf,
    name: String,
}

impl OutputFolder {
    /// `target` made absolute; a symbolic link is followed to the folder it names, so the
    /// output is written through it and the link stays (replacing the link's own path would
    /// put a real folder in its place and leave the linked folder with the old results).
    fn new(target: &Path) -> Result<Self, OutputError> {
        let mut target = std::path::absolute(target).map_err(io_err(target))?;
        if fs::symlink_metadata(&target).is_ok_and(|m| m.file_type().is_symlink()) {
            target = fs::canonicalize(&target).map_err(|e| OutputError::Folder {
                path: target.clone(),
                reason: format!("is a symbolic link to a folder that cannot be used: {e}"),
            })?;
        }
        let folder_err = |reason: &str| OutputError::Folder {
            path: target.clone(),
            reason: reason.to_string(),
        };
        let (Some(parent), Some(name)) = (target.parent(), target.file_name()) else {
            return Err(folder_err(
                "names no folder of its own (the root, or a path ending in `..`)",
            ));
        };
        let (parent, name) = (parent.to_path_buf(), name.to_string_lossy().into_owned());
        if target
            .components()
            .any(|c| c == std::path::Component::ParentDir)
        {
            return Err(folder_err("must not contain `..`"));
        }
        if target.exists() && !target.is_dir() {
            return Err(folder_err("exists and is not a folder"));
        }
        fs::create_dir_all(&parent).map_err(|e| {
            folder_err(&format!(
                "cannot create its parent folder {}: {e}",
                parent.display()
            ))
        })?;
        Ok(Self {
            target,
            parent,
            name,
        })
    }

    /// The lock file of folder `name` in `parent`, beside the folder.
    fn lock_file(parent: &Path, name: &str) -> PathBuf {
        parent.join(format!(".{name}.lock"))
    }
}

/// What is on disk in an output folder after [`abandon_staged`].
#[derive(Debug, Clone, PartialEq, Eq)]
pub enum LeftBehind {
    /// A staged output was removed before it was moved in: the folder is as it was.
    AsItWas(PathBuf),
    /// The output was moved in before the interrupt: the folder holds the finished output.
    Finished(PathBuf),
    /// A folder written in place (a sweep's rows, the precision and stress reports) holds
    /// what was written before the interrupt.
    WrittenSoFar(PathBuf),
}

impl std::fmt::Display for LeftBehind {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        match self {
            LeftBehind::AsItWas(p) => write!(f, "{} is left as it was", p.display()),
            LeftBehind::Finished(p) => {
                write!(
                    f,
                    "{} holds the finished output (written before the interrupt)",
                    p.display()
                )
            }
            LeftBehind::WrittenSoFar(p) => write!(
                f,
                "{} holds the files written before the interrupt (a sweep: the finished rows \
                 in samples.csv, its page and figures only at the end; --resume continues it)",
                p.display()
            ),
        }
    }
}

/// Remove every staging folder and lock of this process (for a SIGINT/SIGTERM handler, which
/// then exits) and say what each output folder holds: a staged target stays as it was before
/// the interrupted run, unless its output was already moved in.
pub fn abandon_staged() -> Vec<LeftBehind> {
    let mut left = Vec::new();
    {
        let mut registry = active();
        ABANDONED.store(true, Ordering::SeqCst);
        left.extend(registry.committed.drain(..).map(LeftBehind::Finished));
        for entry in registry.active.drain(..) {
            match &entry.staging {
                Some(staging) => {
                    remove_while_writers_finish(staging);
                    left.push(LeftBehind::AsItWas(entry.target));
                }
                None => left.push(LeftBehind::WrittenSoFar(entry.target)),
            }
            let _ = fs::remove_file(&entry.lock);
        }
    }
    // A writer in flight removes its temporary file once its move is refused: wait for them
    // (bounded), then remove whatever is left.
    for _ in 0..400 {
        if temps().is_empty() {
            break;
        }
        std::thread::sleep(std::time::Duration::from_millis(5));
    }
    for tmp in temps().drain(..) {
        let _ = fs::remove_file(tmp);
    }
    left
}

/// Removes `dir`, again while it reappears: a writer that opened its file before the
/// interrupt (a figure encoder opens its own path) may create it while the folder is being
/// emptied, which leaves the folder behind; every later creation is refused, so the retries
/// end once the writers in flight have failed.
fn remove_while_writers_finish(dir: &Path) {
    for _ in 0..200 {
        let _ = fs::remove_dir_all(dir);
        if !dir.exists() {
            return;
        }
        std::thread::sleep(std::time::Duration::from_millis(5));
    }
}

/// Whether [`abandon_staged`] ran: a write that fails from now on failed because its output
/// was abandoned (an interrupt), not for a reason of its own.
pub fn is_abandoned() -> bool {
    ABANDONED.load(Ordering::SeqCst)
}

/// What an existing output folder may hold for [`StagedDir`] to replace it.
#[derive(Clone, Copy, PartialEq)]
enum Holds {
    /// A run's files only.
    RunFiles,
    /// Run files, markdown reports and sub-folders of run files (a study).
    StudyFiles,
}

/// The first entry of `dir` that the output does not write (as `sub/name` inside a
/// sub-folder): another extension, or a sub-folder where none belongs.
fn foreign_entry(dir: &Path, holds: Holds) -> Result<Option<String>, OutputError> {
    for entry in fs::read_dir(dir).map_err(io_err(dir))? {
        let entry = entry.map_err(io_err(dir))?;
        let path = entry.path();
        let name = entry.file_name().to_string_lossy().into_owned();
        let file_type = entry.file_type().map_err(io_err(&path))?;
        if file_type.is_dir() && holds == Holds::StudyFiles {
            if let Some(inner) = foreign_entry(&path, Holds::RunFiles)? {
                return Ok(Some(format!("{name}/{inner}")));
            }
            continue;
        }
        let extension = path.extension().and_then(|e| e.to_str());
        let ours = file_type.is_file()
            && extension.is_some_and(|e| {
                RUN_FILE_EXTENSIONS.contains(&e) || (holds == Holds::StudyFiles && e == "md")
            });
        if !ours {
            return Ok(Some(name));
        }
    }
    Ok(None)
}

/// Takes `lock`: an advisory lock (`flock`) on the file, held as long as the returned file
/// is open, with our process id written in it for the message of a refused run. The system
/// releases it when its process ends however it ends, so a lock left by a killed run is free
/// and one held by a live run is not, with no window between telling the two apart (a
/// process id alone cannot tell a live owner that has not written it yet from a dead one).
fn take_lock(target: &Path, lock: &Path) -> Result<File, OutputError> {
    let folder_err = |reason: String| OutputError::Folder {
        path: target.to_path_buf(),
        reason,
    };
    // A holder that finishes removes the file: a file opened just before that is locked in
    // vain, so the lock counts only while the path still names the locked file.
    for _ in 0..100 {
        let mut file = OpenOptions::new()
            .read(true)
            .write(true)
            .create(true)
            .truncate(false)
            .open(lock)
            .map_err(|e| {
                folder_err(format!(
                    "cannot write its lock file {} beside it: {e}",
                    lock.display()
                ))
            })?;
        match file.try_lock() {
            Ok(()) => {}
            Err(fs::TryLockError::WouldBlock) => {
                return Err(OutputError::Locked {
                    path: target.to_path_buf(),
                    lock: lock.to_path_buf(),
                    pid: fs::read_to_string(lock)
                        .ok()
                        .and_then(|s| s.trim().parse::<u32>().ok()),
                });
            }
            Err(fs::TryLockError::Error(e)) => {
                return Err(folder_err(format!(
                    "cannot lock its lock file {}: {e}",
                    lock.display()
                )));
            }
        }
        if !names_file(lock, &file) {
            continue;
        }
        // The lock is ours: a failure to write it (a full disk) removes the file, as every
        // later failure does.
        if let Err(e) = file
            .set_len(0)
            .and_then(|()| write!(file, "{}", std::process::id()))
        {
            let _ = fs::remove_file(lock);
            return Err(io_err(lock)(e));
        }
        return Ok(file);
    }
    Err(folder_err(format!(
        "cannot take the lock file {}: it is replaced again and again",
        lock.display()
    )))
}

/// Whether the current folder is `target` or lies inside it (`--out .`, `--out ..`).
fn current_folder_within(target: &Path) -> bool {
    match (
        std::env::current_dir().and_then(fs::canonicalize),
        fs::canonicalize(target),
    ) {
        (Ok(cwd), Ok(target)) => cwd.starts_with(target),
        _ => false,
    }
}

/// How deep [`check_nesting`] looks for other runs' lock files inside an output folder (a
/// study's folder holds its scenes' folders one level down; deeper is far beyond any output).
const NESTING_DEPTH: usize = 8;

/// Most entries [`check_nesting`] reads inside an output folder: an output holds a few hundred
/// files, a folder of far more is no output (a run refuses its foreign files next).
const NESTING_ENTRIES: usize = 100_000;

/// Refuses `target` while another live writer holds a folder that contains it or that lies
/// inside it (the lock of `target` itself taken): one of them replaces its folder whole at the
/// end, which would delete or hide the other's output. The other's lock files are found where
/// it keeps them, beside its folder: beside every folder on `target`'s real path, and inside
/// `target` (to [`NESTING_DEPTH`] levels, links not followed).
fn check_nesting(target: &Path) -> Result<(), OutputError> {
    let real = match (target.parent().map(fs::canonicalize), target.file_name()) {
        (Some(Ok(parent)), Some(name)) => parent.join(name),
        _ => target.to_path_buf(),
    };
    for folder in real.ancestors().skip(1) {
        let (Some(parent), Some(name)) = (folder.parent(), folder.file_name()) else {
            continue;
        };
        let lock = OutputFolder::lock_file(parent, &name.to_string_lossy());
        if let Some(pid) = held_elsewhere(&lock) {
            return Err(OutputError::NestedLocked {
                path: target.to_path_buf(),
                other: folder.to_path_buf(),
                around: true,
                lock,
                pid,
            });
        }
    }
    let mut folders = vec![(real, 0)];
    let mut budget = NESTING_ENTRIES;
    while let Some((dir, depth)) = folders.pop() {
        let Ok(entries) = fs::read_dir(&dir) else {
            continue;
        };
        for entry in entries.flatten() {
            budget = match budget.checked_sub(1) {
                Some(b) => b,
                None => return Ok(()),
            };
            let Ok(kind) = entry.file_type() else {
                continue;
            };
            let name = entry.file_name().to_string_lossy().into_owned();
            if kind.is_dir() && depth < NESTING_DEPTH {
                folders.push((entry.path(), depth + 1));
            } else if kind.is_file()
                && let Some(folder) = name.strip_prefix('.').and_then(|n| n.strip_suffix(".lock"))
                && let Some(pid) = held_elsewhere(&entry.path())
            {
                return Err(OutputError::NestedLocked {
                    path: target.to_path_buf(),
                    other: dir.join(folder),
                    around: false,
                    lock: entry.path(),
                    pid,
                });
            }
        }
    }
    Ok(())
}

/// `Some(process id, once written)` when another open file holds the lock on `lock`; `None`
/// when nothing does (or no such file). A free lock is taken for an instant and let go.
fn held_elsewhere(lock: &Path) -> Option<Option<u32>> {
    let file = File::open(lock).ok()?;
    match file.try_lock_shared() {
        Err(fs::TryLockError::WouldBlock) => Some(
            fs::read_to_string(lock)
                .ok()
                .and_then(|s| s.trim().parse::<u32>().ok()),
        ),
        _ => None,
    }
}

/// Whether `path` names the open `file` (not a file created at the path since).
fn names_file(path: &Path, file: &File) -> bool {
    #[cfg(unix)]
    {
        use std::os::unix::fs::MetadataExt;
        match (fs::metadata(path), file.metadata()) {
            (Ok(a), Ok(b)) => a.dev() == b.dev() && a.ino() == b.ino(),
            _ => false,
        }
    }
    #[cfg(not(unix))]
    {
        let _ = file;
        path.exists()
    }
}

/// Staging and replaced folders (`.<name>.staging-<pid>`, `.<name>.previous-<pid>`) that runs
/// killed on the way left behind: the lock is ours, so no live run is writing them.
fn remove_dead_staging(parent: &Path, name: &str) {
    let ours = std::process::id().to_string();
    let prefixes = [format!(".{name}.staging-"), format!(".{name}.previous-")];
    let Ok(entries) = fs::read_dir(parent) else {
        return;
    };
    for entry in entries.flatten() {
        let file = entry.file_name().to_string_lossy().into_owned();
        let stale = prefixes.iter().any(|prefix| {
            file.strip_prefix(prefix.as_str())
                .is_some_and(|pid| pid.parse::<u32>().is_ok() && pid != ours)
        });
        if stale {
            let _ = fs::remove_dir_all(entry.path());
        }
    }
}
