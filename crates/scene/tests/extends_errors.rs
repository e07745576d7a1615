//! Type errors through `extends` chains, fuzzed by kind: every field of the LGRES scene (as it
//! serializes, defaults included, and the contact model's own choices) given a value of the
//! wrong type in one file of a chain of three (the file run, its base, the base's base), the
//! root being the LGRES. Each must be refused naming the field path and the line of the file
//! that wrote it, and a choice given a number must say what it takes.

use std::path::{Path, PathBuf};

use scene::SceneError;

/// The LGRES scene file (the chain's root; it extends nothing).
fn lgres_text() -> String {
    let path = Path::new(env!("CARGO_MANIFEST_DIR")).join("../lgres/scenes/lgres.toml");
    std::fs::read_to_string(path).unwrap()
}

/// One leaf of a scene table: its segments (keys; a named array element as `(array, name,
/// index)`) and its value.
#[derive(Debug, Clone)]
enum Seg {
    Key(String),
    Named(String, String, usize),
}

fn walk(table: &toml::Table, at: &[Seg], out: &mut Vec<(Vec<Seg>, toml::Value)>) {
    for (key, value) in table {
        let here = |seg: Seg| [at, &[seg]].concat();
        match value {
            toml::Value::Table(t) => walk(t, &here(Seg::Key(key.clone())), out),
            toml::Value::Array(items)
                if !items.is_empty()
                    && items
                        .iter()
                        .all(|v| v.get("name").is_some_and(|n| n.is_str())) =>
            {
                for (i, item) in items.iter().enumerate() {
                    let name = item["name"].as_str().unwrap().to_string();
                    if let Some(t) = item.as_table() {
                        walk(t, &here(Seg::Named(key.clone(), name, i)), out);
                    }
                }
            }
            // A name picks the element; it is not a field to break.
            _ if key == "name" => {}
            _ => out.push((here(Seg::Key(key.clone())), value.clone())),
        }
    }
}

/// A value of another type than `value`'s.
fn wrong(value: &toml::Value) -> toml::Value {
    match value {
        toml::Value::String(_) => toml::Value::Integer(3),
        _ => toml::Value::String("x".into()),
    }
}

/// The field path as errors write it (`clearance_joints[0].wear.k_d`).
fn field_path(segs: &[Seg]) -> String {
    segs.iter()
        .map(|s| match s {
            Seg::Key(k) => k.clone(),
            Seg::Named(array, _, i) => format!("{array}[{i}]"),
        })
        .collect::<Vec<_>>()
        .join(".")
}

/// TOML text setting the leaf `segs` to `value`, and the line (from 1, counted after
/// `lines_before` lines) that holds the value.
fn patch(segs: &[Seg], value: &toml::Value, lines_before: usize) -> (String, usize) {
    let mut head = Vec::new();
    let mut keys: Vec<&str> = Vec::new();
    // The section: up to the last named element, else all keys but the last as a [table].
    let named = segs.iter().rposition(|s| matches!(s, Seg::Named(..)));
    let (section, rest) = match named {
        Some(k) => (&segs[..=k], &segs[k + 1..]),
        None => (&segs[..segs.len() - 1], &segs[segs.len() - 1..]),
    };
    if let Some(Seg::Named(..)) = section.last() {
        // Only the innermost named element gets a header; outer ones are not nested here.
        let path: Vec<String> = section
            .iter()
            .map(|s| match s {
                Seg::Key(k) | Seg::Named(k, _, _) => k.clone(),
            })
            .collect();
        head.push(format!("[[{}]]", path.join(".")));
        for s in section {
            if let Seg::Named(_, name, _) = s {
                head.push(format!("name = \"{name}\""));
            }
        }
    } else if !section.is_empty() {
        let path: Vec<String> = section
            .iter()
            .map(|s| match s {
                Seg::Key(k) | Seg::Named(k, _, _) => k.clone(),
            })
            .collect();
        head.push(format!("[{}]", path.join(".")));
    }
    for s in rest {
        if let Seg::Key(k) = s {
            keys.push(k);
        }
    }
    // The rest nested as inline tables on one line: `a = { b = { c = V } }`.
    let mut line = value.to_string();
    for k in keys.iter().skip(1).rev() {
        line = format!("{{ {k} = {line} }}");
    }
    line = format!("{} = {line}", keys[0]);
    let at = lines_before + head.len() + 1;
    head.push(line);
    (head.join("\n") + "\n", at)
}

/// Whether the leaf can be patched as [`patch`] writes it (an element named inside another
/// named element is left out: TOML cannot name both in one header).
fn patchable(segs: &[Seg]) -> bool {
    segs.iter().filter(|s| matches!(s, Seg::Named(..))).count() <= 1
}

#[test]
fn type_errors_through_extends_chains_name_the_field_the_file_and_the_line() {
    let dir = std::env::temp_dir().join(format!("wornjoint-extends-{}", std::process::id()));
    let _ = std::fs::remove_dir_all(&dir);
    std::fs::create_dir_all(&dir).unwrap();
    std::fs::write(dir.join("root.toml"), lgres_text()).unwrap();
    let root = scene::load_path(&dir.join("root.toml"), &[]).unwrap();
    let table: toml::Table = toml::from_str(&root.to_toml()).unwrap();
    let mut leaves = Vec::new();
    walk(&table, &[], &mut leaves);
    // The layer's own choices, left to their defaults in the LGRES (not serialized).
    for (field, value) in [("quadrature", "simpson"), ("layer", "paper")] {
        let joint = Seg::Named("clearance_joints".into(), "A".into(), 0);
        leaves.push((
            vec![joint, Seg::Key("contact".into()), Seg::Key(field.into())],
            toml::Value::String(value.into()),
        ));
    }
    leaves.retain(|(segs, _)| patchable(segs));
    assert!(leaves.len() > 100, "{} leaves", leaves.len());
    // The chain: run.toml extends mid.toml extends base.toml extends root.toml (the LGRES).
    let files = ["run.toml", "mid.toml", "base.toml"];
    let parents = ["mid.toml", "base.toml", "root.toml"];
    let mut kinds = std::collections::BTreeMap::<String, usize>::new();
    for (n, (segs, value)) in leaves.iter().enumerate() {
        let level = n % files.len();
        let bad = wrong(value);
        let (text, line) = patch(segs, &bad, 1);
        for (k, (file, parent)) in files.iter().zip(parents).enumerate() {
            let head = format!("extends = \"{parent}\"\n");
            let body = if k == level { text.as_str() } else { "" };
            std::fs::write(dir.join(file), head + body).unwrap();
        }
        let path = field_path(segs);
        let e = match scene::load_path(&dir.join("run.toml"), &[]) {
            Err(e) => e,
            Ok(_) => panic!("{path} = {bad} accepted"),
        };
        let message = e.to_string();
        let SceneError::Merged {
            path: named,
            line: at,
            file,
            ..
        } = &e
        else {
            panic!("{path} = {bad}: not a merged-scene type error: {message}");
        };
        // A tag (`law`, `kind`, `model`) of another value replaces its table: the error may
        // name the table.
        let parent = path.rsplit_once('.').map_or("", |(p, _)| p);
        assert!(
            named == &path || named.starts_with(parent),
            "{path} = {bad}: names {named}: {message}"
        );
        assert_eq!(
            *at,
            Some(line),
            "{path} = {bad} in {}: {message}",
            files[level]
        );
        let expected_file = (level > 0).then(|| dir.join(files[level]).display().to_string());
        assert_eq!(file, &expected_file, "{path}: {message}");
        if let Some(f) = &expected_file {
            assert!(
                message.contains(&format!("line {line} of {f}")),
                "{message}"
            );
        }
        if bad.is_integer() {
            assert!(
                !message.contains("unit variant") && message.contains("integer `3`"),
                "{path}: {message}"
            );
        }
        let kind = match bad {
            toml::Value::Integer(_) => "a string field given 3",
            _ => "a field given \"x\"",
        };
        *kinds
            .entry(format!("{kind}, in {}", files[level]))
            .or_default() += 1;
    }
    eprintln!("{} fields: {kinds:#?}", leaves.len());
    let _ = std::fs::remove_dir_all(&dir);
}

/// A choice given a number says what it takes, with or without `extends`.
#[test]
fn a_choice_given_a_number_names_what_it_found_and_what_it_takes() {
    let dir = std::env::temp_dir().join(format!("wornjoint-choices-{}", std::process::id()));
    let _ = std::fs::remove_dir_all(&dir);
    std::fs::create_dir_all(&dir).unwrap();
    std::fs::write(dir.join("root.toml"), lgres_text()).unwrap();
    for (field, value, takes) in [
        ("quadrature", "3", "`simpson`"),
        ("layer", "3", "`pin-in-hole`"),
        ("model", "3", "`line-of-centres`"),
        ("quadrature", "true", "`trapezoid`"),
        ("layer", "1.5", "`paper`"),
    ] {
        let text = format!(
            "extends = \"root.toml\"\n[[clearance_joints]]\nname = \"A\"\n\
             contact = {{ {field} = {value} }}\n"
        );
        let file: PathBuf = dir.join("run.toml");
        std::fs::write(&file, text).unwrap();
        let e = scene::load_path(&file, &[]).unwrap_err().to_string();
        assert!(
            !e.contains("unit variant") && e.contains(takes) && e.contains(value),
            "{field} = {value}: {e}"
        );
    }
    let _ = std::fs::remove_dir_all(&dir);
}
