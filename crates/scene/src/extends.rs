//! Loading: parse a scene's TOML, follow its `extends` chain (merging each patch into its
//! base), deserialize once and validate.

use std::collections::{HashMap, HashSet};
use std::path::Path;

use super::builtins::{Builtin, known_names, source};
use super::{Issue, Scene, SceneError, ValidScene};

/// How many `extends` levels are followed before giving up (guards against cycles).
const MAX_EXTENDS_DEPTH: usize = 8;

/// Parse and validate scene text; `extends` may name the scenes of `builtins` only.
pub fn load_str(text: &str, origin: &str, builtins: &[Builtin]) -> Result<ValidScene, SceneError> {
    ValidScene::new(parse(text, origin, None, builtins)?, origin)
}

/// The scene of `builtins` named `name`, parsed and validated (its `extends` resolved against
/// `builtins`).
pub fn builtin(builtins: &[Builtin], name: &str) -> Result<ValidScene, SceneError> {
    let text = source(builtins, name).ok_or_else(|| SceneError::UnknownBuiltin {
        name: name.to_string(),
        known: known_names(builtins),
    })?;
    load_str(text, name, builtins)
}

/// Read, parse and validate a scene file; `extends` may name a scene of `builtins` or a file
/// relative to it.
pub fn load_path(path: &Path, builtins: &[Builtin]) -> Result<ValidScene, SceneError> {
    let text = read(path)?;
    let origin = path.display().to_string();
    ValidScene::new(parse(&text, &origin, path.parent(), builtins)?, &origin)
}

fn read(path: &Path) -> Result<String, SceneError> {
    std::fs::read_to_string(path).map_err(|source| SceneError::Io {
        path: path.to_path_buf(),
        source,
    })
}

fn toml_err(origin: &str) -> impl Fn(toml::de::Error) -> SceneError + '_ {
    move |source| SceneError::Toml {
        origin: origin.to_string(),
        source,
    }
}

/// Parse without validating, following `extends`.
fn parse(
    text: &str,
    origin: &str,
    dir: Option<&Path>,
    builtins: &[Builtin],
) -> Result<Scene, SceneError> {
    let table: toml::Table = toml::from_str(text).map_err(toml_err(origin))?;
    if !table.contains_key("extends") {
        // Deserialize from the text itself so type errors keep their line and column.
        return toml::from_str(text).map_err(toml_err(origin));
    }
    let mut bases = Vec::new();
    let merged = resolve_extends(table, origin, dir, builtins, 0, &mut bases)?;
    // The merged table has no line numbers: keep the field path of a type error, and find
    // its line in the file that gives the field last: the extending file, else its base,
    // and so on down the chain.
    serde_path_to_error::deserialize(toml::Value::Table(merged.clone())).map_err(|e| {
        let path = e.path().to_string();
        let at = std::iter::once((origin.to_string(), text.to_string()))
            .chain(bases)
            .find_map(|(file, text)| line_of(&text, &merged, &path).map(|line| (file, line)));
        let (file, line) = at.map_or((None, None), |(file, line)| {
            ((file != origin).then_some(file), Some(line))
        });
        SceneError::Merged {
            origin: origin.to_string(),
            line,
            file,
            source: Box::new(super::type_errors::readable(e.into_inner(), &merged, &path)),
            path,
        }
    })
}

/// 1-based line of `path`'s last key in `text`, searched after the `name = "…"` line of the
/// innermost named array element on the path (the merged index differs from the file's).
fn line_of(text: &str, merged: &toml::Table, path: &str) -> Option<usize> {
    let mut table = Some(merged);
    let mut name = None;
    let mut key = "";
    for segment in path.split('.') {
        let (k, index) = match segment.split_once('[') {
            Some((k, rest)) => (k, rest.trim_end_matches(']').parse::<usize>().ok()),
            None => (segment, None),
        };
        key = k;
        let value = table.and_then(|t| t.get(k));
        let value = match (value, index) {
            (Some(toml::Value::Array(a)), Some(i)) => a.get(i),
            (v, _) => v,
        };
        if let Some(n) = value
            .and_then(|v| v.get("name"))
            .and_then(toml::Value::as_str)
        {
            name = Some(n);
        }
        table = value.and_then(toml::Value::as_table);
    }
    let lines: Vec<&str> = text.lines().collect();
    let header = |l: &str| l.trim_start().starts_with('[');
    // The section the key is written in: the named element's, a `[table]`'s, or the top.
    let start = match (name, path.rsplit_once('.')) {
        (Some(n), _) => lines
            .iter()
            .position(|l| l.trim_start().starts_with("name") && l.contains(&format!("\"{n}\"")))?,
        (None, Some((section, _))) => {
            lines
                .iter()
                .position(|l| l.trim() == format!("[{section}]"))?
                + 1
        }
        (None, None) => 0,
    };
    let end = (start..lines.len())
        .find(|&k| k > start && header(lines[k]))
        .unwrap_or(lines.len());
    let assigns = |l: &str| {
        l.split(['{', ',']).any(|part| {
            part.trim_start()
                .strip_prefix(key)
                .is_some_and(|rest| rest.trim_start().starts_with('='))
        })
    };
    (start..end).find(|&k| assigns(lines[k])).map(|k| k + 1)
}

/// `table` with its `extends` chain merged in, as raw TOML (deserialized once, at the end).
/// Each base's origin and text is pushed onto `bases`, nearest first.
fn resolve_extends(
    mut table: toml::Table,
    origin: &str,
    dir: Option<&Path>,
    builtins: &[Builtin],
    depth: usize,
    bases: &mut Vec<(String, String)>,
) -> Result<toml::Table, SceneError> {
    let Some(target) = table.remove("extends") else {
        return Ok(table);
    };
    let fail = |reason: &str| SceneError::Extends {
        origin: origin.to_string(),
        target: target.to_string(),
        reason: reason.to_string(),
    };
    let name = target.as_str().ok_or_else(|| fail("must be a string"))?;
    if depth >= MAX_EXTENDS_DEPTH {
        return Err(fail("too many nested `extends` (a cycle?)"));
    }
    let (text, base_origin, base_dir) = if let Some(text) = source(builtins, name) {
        (text.to_string(), name.to_string(), None)
    } else if let Some(path) = dir.map(|d| d.join(name)).filter(|p| p.is_file()) {
        let parent = path.parent().map(Path::to_path_buf);
        (read(&path)?, path.display().to_string(), parent)
    } else {
        return Err(fail("no built-in scene or file of this name"));
    };
    let base: toml::Table = toml::from_str(&text).map_err(toml_err(&base_origin))?;
    bases.push((base_origin.clone(), text));
    let mut base = resolve_extends(
        base,
        &base_origin,
        base_dir.as_deref(),
        builtins,
        depth + 1,
        bases,
    )?;
    merge(&mut base, table, "", origin)?;
    Ok(base)
}

/// Merge `patch` into `base`: tables key by key, arrays of named tables by `name`. An empty
/// array replaces (so `drivers = []` removes the base's), and so does a table whose `law`,
/// `kind` or `model` tag differs from the base's (a different law or contact model has
/// different keys; [`TAGS`]). `path` is the
/// field path of `base`, for errors.
fn merge(
    base: &mut toml::Table,
    patch: toml::Table,
    path: &str,
    origin: &str,
) -> Result<(), SceneError> {
    // A patch that gives one key of a mutually exclusive group replaces the base's other
    // (a drive law's `omega` replaces the base's `rpm`, instead of failing as "both given").
    for group in EXCLUSIVE_KEYS {
        if group.iter().any(|k| patch.contains_key(*k)) {
            for k in *group {
                if !patch.contains_key(*k) {
                    base.remove(*k);
                }
            }
        }
    }
    for (key, value) in patch {
        let here = if path.is_empty() {
            key.clone()
        } else {
            format!("{path}.{key}")
        };
        match (base.get_mut(&key), value) {
            (Some(toml::Value::Table(b)), toml::Value::Table(p)) if same_tag(b, &p) => {
                merge(b, p, &here, origin)?;
            }
            (Some(toml::Value::Array(b)), toml::Value::Array(p))
                if !p.is_empty() && all_named(b) && all_named(&p) =>
            {
                merge_named(b, p, &here, origin)?;
            }
            (_, value) => {
                base.insert(key, value);
            }
        }
    }
    Ok(())
}

/// Keys of which a table may give only one: a patch's choice replaces the base's.
const EXCLUSIVE_KEYS: &[&[&str]] = &[&["rpm", "omega"]];

/// Keys that choose what the rest of a table means, each with the value its absence stands
/// for: a drive or friction `law`, a normal law's `kind`, a contact `model` (the foundation
/// unless named). A patch naming another one replaces the table: the base's keys belong to
/// the model it leaves (a line-of-centres contact takes none of the foundation's).
const TAGS: &[(&str, Option<&str>)] =
    &[("law", None), ("kind", None), ("model", Some("foundation"))];

/// Whether `patch` keeps `base`'s tags ([`TAGS`]; a patch that gives none keeps them).
fn same_tag(base: &toml::Table, patch: &toml::Table) -> bool {
    TAGS.iter().all(|(tag, absent)| {
        patch.get(*tag).is_none_or(|t| match base.get(*tag) {
            Some(b) => b == t,
            None => absent.is_some_and(|a| t.as_str() == Some(a)),
        })
    })
}

/// Merge a patch array of named tables into `base` by name (linear: names are indexed); a
/// name given twice in the patch is an error, not a silent double merge.
fn merge_named(
    base: &mut Vec<toml::Value>,
    patch: Vec<toml::Value>,
    path: &str,
    origin: &str,
) -> Result<(), SceneError> {
    let mut index: HashMap<String, usize> = HashMap::with_capacity(base.len());
    for (k, v) in base.iter().enumerate() {
        if let Some(name) = v.get("name").and_then(toml::Value::as_str) {
            index.entry(name.to_string()).or_insert(k);
        }
    }
    let mut seen = HashSet::with_capacity(patch.len());
    for (k, item) in patch.into_iter().enumerate() {
        let toml::Value::Table(item) = item else {
            continue;
        };
        let name = item
            .get("name")
            .and_then(toml::Value::as_str)
            .unwrap_or_default()
            .to_string();
        if !seen.insert(name.clone()) {
            return Err(SceneError::Invalid {
                origin: origin.to_string(),
                issues: vec![Issue {
                    path: format!("{path}[{k}].name"),
                    value: format!("{name:?}"),
                    reason: "duplicate name in this patch (each element may be patched once)"
                        .into(),
                }],
            });
        }
        match index.get(&name).copied() {
            Some(i) => {
                if let Some(toml::Value::Table(e)) = base.get_mut(i) {
                    merge(e, item, &format!("{path}[{i}]"), origin)?;
                }
            }
            None => {
                index.insert(name, base.len());
                base.push(toml::Value::Table(item));
            }
        }
    }
    Ok(())
}

fn all_named(items: &[toml::Value]) -> bool {
    items.iter().all(|v| {
        v.as_table()
            .is_some_and(|t| t.get("name").is_some_and(|n| n.is_str()))
    })
}

/// Scene text with its `extends` chain merged in, as a TOML table, neither deserialized nor
/// validated: the form sweeps and the Python bindings edit before [`from_table`]. `dir` is the
/// folder file `extends` are relative to (`None`: the scenes of `builtins` only).
pub fn merged_table(
    text: &str,
    origin: &str,
    dir: Option<&Path>,
    builtins: &[Builtin],
) -> Result<toml::Table, SceneError> {
    let table: toml::Table = toml::from_str(text).map_err(toml_err(origin))?;
    resolve_extends(table, origin, dir, builtins, 0, &mut Vec::new())
}

/// A scene file's [`merged_table`] (file `extends` relative to its folder) and its file stem,
/// the name its outputs are filed under.
pub fn merged_table_of_file(
    path: &Path,
    builtins: &[Builtin],
) -> Result<(String, toml::Table), SceneError> {
    let text = read(path)?;
    let stem = file_stem_name(path);
    let table = merged_table(&text, &path.display().to_string(), path.parent(), builtins)?;
    Ok((stem, table))
}

/// The name a scene file's outputs are filed under: its stem, `scene` if it has none.
pub(crate) fn file_stem_name(path: &Path) -> String {
    path.file_stem()
        .map_or_else(|| "scene".to_string(), |s| s.to_string_lossy().into_owned())
}

/// Deserialize and validate a scene table (e.g. from [`merged_table`], edited); a type error
/// or unknown key names its field path.
pub fn from_table(table: toml::Table, origin: &str) -> Result<ValidScene, SceneError> {
    let scene: Scene = serde_path_to_error::deserialize(toml::Value::Table(table.clone()))
        .map_err(|e| {
            let path = e.path().to_string();
            SceneError::Field {
                origin: origin.to_string(),
                source: Box::new(super::type_errors::readable(e.into_inner(), &table, &path)),
                path,
            }
        })?;
    ValidScene::new(scene, origin)
}
