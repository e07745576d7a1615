//! Type errors of a scene read from a TOML table (merged through `extends`, or edited by a
//! sweep) in words a user can act on. Read from a table, a number or a boolean where a named
//! choice belongs (`contact.quadrature = 3`, `model = 3`) is refused with "invalid type: unit
//! variant, expected string only" (`toml`), "expected string or map" or "expected variant
//! identifier" (serde, inside a tagged table), which name neither what was found nor what is
//! allowed; the message is rewritten here with both.

use serde::de::{DeserializeOwned, Error as _};

/// Whether `message` is one of the words refusing a non-string where a choice belongs.
fn is_choice_refusal(message: &str) -> bool {
    message.starts_with("invalid type: ")
        && [
            "expected string only",
            "expected string or map",
            "expected variant identifier",
        ]
        .iter()
        .any(|words| message.ends_with(words))
}

/// `error`, raised at field `path` (as `serde_path_to_error` writes it: `a.b[0].c`) while
/// deserializing the scene `table`, with a readable message where the words are not.
pub(crate) fn readable(error: toml::de::Error, table: &toml::Table, path: &str) -> toml::de::Error {
    if !is_choice_refusal(error.message()) {
        return error;
    }
    toml::de::Error::custom(readable_in::<super::Scene>(error.message(), table, path))
}

/// `message`, raised at field `path` while deserializing a `T` from `table`: for a choice given
/// another type, what was found and the choices `T` takes there (`invalid type: integer `3`,
/// expected a string, one of `a`, `b``); any other message as it is. A path that names a
/// table (a tagged table loses the path inside it; empty: `table` itself) is searched for the
/// choice, whose key then leads the message (`coordinate: invalid type: …`).
pub(crate) fn readable_in<T: DeserializeOwned>(
    message: &str,
    table: &toml::Table,
    path: &str,
) -> String {
    if !is_choice_refusal(message) {
        return message.to_string();
    }
    let mut path = path.to_string();
    let mut inner: Vec<String> = Vec::new();
    let allowed = loop {
        let here = if path.is_empty() {
            Some(table)
        } else {
            get(table, &path).and_then(toml::Value::as_table)
        };
        let Some(here) = here else {
            break variants::<T>(table, &path);
        };
        let join = |key: &str| {
            if path.is_empty() {
                key.to_string()
            } else {
                format!("{path}.{key}")
            }
        };
        // The key whose value, made a name nobody takes, is refused as an unknown variant.
        let choice = here
            .iter()
            .filter(|(_, v)| !(v.is_str() || v.is_table() || v.is_array()))
            .find_map(|(k, _)| variants::<T>(table, &join(k)).map(|v| (k.clone(), v)));
        if let Some((key, allowed)) = choice {
            path = join(&key);
            inner.push(key);
            break Some(allowed);
        }
        let tables: Vec<&String> = here
            .iter()
            .filter(|(_, v)| v.is_table())
            .map(|(k, _)| k)
            .collect();
        match tables[..] {
            [key] => {
                path = join(key);
                inner.push(key.clone());
            }
            _ => return message.to_string(),
        }
    };
    let Some(found) = get(table, &path).map(describe) else {
        return message.to_string();
    };
    let allowed = allowed.map_or_else(String::new, |v| format!(", one of {v}"));
    let inner = if inner.is_empty() {
        String::new()
    } else {
        format!("{}: ", inner.join("."))
    };
    format!("{inner}invalid type: {found}, expected a string{allowed}")
}

/// A value as a message names it: its kind and, for a scalar, itself.
fn describe(value: &toml::Value) -> String {
    match value {
        toml::Value::String(s) => format!("string {s:?}"),
        toml::Value::Integer(i) => format!("integer `{i}`"),
        toml::Value::Float(x) => format!("float `{x}`"),
        toml::Value::Boolean(b) => format!("boolean `{b}`"),
        toml::Value::Datetime(d) => format!("datetime `{d}`"),
        toml::Value::Array(_) => "an array".into(),
        toml::Value::Table(_) => "a table".into(),
    }
}

/// The variant names the field at `path` takes (`` `a`, `b` ``), as serde lists them when
/// given a name it does not know: found by deserializing a `T` once more with such a name there.
fn variants<T: DeserializeOwned>(table: &toml::Table, path: &str) -> Option<String> {
    let mut probe = table.clone();
    *get_mut(&mut probe, path)? = toml::Value::String(String::new());
    let message = match toml::Value::Table(probe).try_into::<T>() {
        Ok(_) => return None,
        Err(e) => e.message().to_string(),
    };
    let listed = message.split_once("unknown variant ``, expected ")?.1;
    let listed = listed.strip_prefix("one of ").unwrap_or(listed);
    let last = listed.rfind('`')?;
    Some(listed[..=last].to_string())
}

/// The segments of `path`: keys and array indices (`a.b[0].c` → `a`, `b`, `0`, `c`).
fn segments(path: &str) -> Vec<Segment<'_>> {
    let mut out = Vec::new();
    for part in path.split('.') {
        let mut pieces = part.split('[');
        if let Some(key) = pieces.next().filter(|k| !k.is_empty()) {
            out.push(Segment::Key(key));
        }
        for index in pieces {
            match index.trim_end_matches(']').parse() {
                Ok(i) => out.push(Segment::Index(i)),
                Err(_) => out.push(Segment::Key(index)),
            }
        }
    }
    out
}

enum Segment<'a> {
    Key(&'a str),
    Index(usize),
}

fn get<'a>(table: &'a toml::Table, path: &str) -> Option<&'a toml::Value> {
    let mut segments = segments(path).into_iter();
    let Some(Segment::Key(first)) = segments.next() else {
        return None;
    };
    segments.try_fold(table.get(first)?, |value, segment| match segment {
        Segment::Key(k) => value.get(k),
        Segment::Index(i) => value.get(i),
    })
}

fn get_mut<'a>(table: &'a mut toml::Table, path: &str) -> Option<&'a mut toml::Value> {
    let mut segments = segments(path).into_iter();
    let Some(Segment::Key(first)) = segments.next() else {
        return None;
    };
    segments.try_fold(table.get_mut(first)?, |value, segment| match segment {
        Segment::Key(k) => value.get_mut(k),
        Segment::Index(i) => value.get_mut(i),
    })
}
