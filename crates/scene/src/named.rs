//! A scene given the way people give one — a built-in name or a file path — found and loaded,
//! with the name its outputs are filed under. The command line, the Python bindings and sweep
//! files all take a scene this way; resolving it here keeps them agreeing on which wins (a
//! built-in name, before a file of the same name) and on the output name (the built-in name,
//! or the file's stem).

use std::path::{Path, PathBuf};

use super::builtins::{Builtin, known_names, source};
use super::extends::{file_stem_name, load_path, load_str, merged_table, merged_table_of_file};
use super::{SceneError, ValidScene};

/// The forms a scene given by name or path is loaded as: a [`ValidScene`] (the command
/// line), or a [`toml::Table`] with its `extends` chain merged in and not yet deserialized
/// (what the Python bindings and sweeps edit before [`super::from_table`]).
pub trait Loadable: Sized + private::Sealed {
    /// The scene of `builtins` named `name`, whose TOML is `text`.
    #[doc(hidden)]
    fn from_builtin(name: &str, text: &str, builtins: &[Builtin]) -> Result<Self, SceneError>;
    /// The scene in the file at `path`.
    #[doc(hidden)]
    fn from_file(path: &Path, builtins: &[Builtin]) -> Result<Self, SceneError>;
}

mod private {
    /// Only this crate's forms: what a form does with the two sources is part of the loader.
    pub trait Sealed {}
    impl Sealed for crate::ValidScene {}
    impl Sealed for toml::Table {}
}

impl Loadable for ValidScene {
    fn from_builtin(name: &str, text: &str, builtins: &[Builtin]) -> Result<Self, SceneError> {
        load_str(text, name, builtins)
    }
    fn from_file(path: &Path, builtins: &[Builtin]) -> Result<Self, SceneError> {
        load_path(path, builtins)
    }
}

impl Loadable for toml::Table {
    fn from_builtin(name: &str, text: &str, builtins: &[Builtin]) -> Result<Self, SceneError> {
        merged_table(text, name, None, builtins)
    }
    fn from_file(path: &Path, builtins: &[Builtin]) -> Result<Self, SceneError> {
        merged_table_of_file(path, builtins).map(|(_, table)| table)
    }
}

/// Neither a built-in scene nor an existing file goes by the name given. Each caller words
/// this for its own users (the command line points at `wearsim scenes`, a sweep file at the
/// folder file names are relative to), so this carries what they need.
#[derive(Debug, Clone, thiserror::Error)]
#[error("no built-in scene and no file named {spec:?}")]
pub struct NotFound {
    /// The name or path as given.
    pub spec: String,
    /// The path looked at (`spec` relative to the folder given, if any).
    pub path: PathBuf,
    /// The built-in names, comma-separated (as [`SceneError::UnknownBuiltin`] lists them).
    pub known: String,
}

impl NotFound {
    /// The same failure as an unknown built-in name, listing the known ones.
    pub fn into_unknown_builtin(self) -> SceneError {
        SceneError::UnknownBuiltin {
            name: self.spec,
            known: self.known,
        }
    }
}

/// Why a scene given by name or path could not be loaded.
#[derive(Debug, thiserror::Error)]
pub enum LoadError {
    /// No such built-in scene and no such file.
    #[error(transparent)]
    NotFound(#[from] NotFound),
    /// The scene was found but could not be read, parsed, merged or validated.
    #[error(transparent)]
    Scene(#[from] SceneError),
}

/// Load the scene `spec` names: the scene of `builtins` of that name, else the file at `spec`
/// (relative to `dir` when given), its `extends` resolved against `builtins` (file bases
/// relative to it). Returns the name outputs are filed under — the built-in name, or the
/// file's stem (`scene` if it has none) — and the scene as `T` ([`Loadable`]).
///
/// ```
/// use scene::{Builtin, LoadError, ValidScene, load_named};
///
/// let shipped = [Builtin { name: "empty", summary: "", source: "description = \"\"" }];
/// let e = load_named::<ValidScene>("no-such", None, &shipped).unwrap_err();
/// assert!(matches!(e, LoadError::NotFound(ref n) if n.known == "empty"));
/// let (name, table) = load_named::<toml::Table>("empty", None, &shipped)?;
/// assert_eq!((name.as_str(), table.len()), ("empty", 1));
/// # Ok::<(), LoadError>(())
/// ```
pub fn load_named<T: Loadable>(
    spec: &str,
    dir: Option<&Path>,
    builtins: &[Builtin],
) -> Result<(String, T), LoadError> {
    if let Some(text) = source(builtins, spec) {
        return Ok((spec.to_string(), T::from_builtin(spec, text, builtins)?));
    }
    let path = dir.map_or_else(|| Path::new(spec).to_path_buf(), |d| d.join(spec));
    if !path.is_file() {
        return Err(NotFound {
            spec: spec.to_string(),
            path,
            known: known_names(builtins),
        }
        .into());
    }
    Ok((file_stem_name(&path), T::from_file(&path, builtins)?))
}
