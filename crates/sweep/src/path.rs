//! Dotted field paths into scene tables and summaries: `clearance_joints.A.clearance`,
//! `drivers.drive.law.rpm`, `wear.joints.B.bearing_peak_depth_m`. A segment that meets an array
//! picks the element whose `name` it is, else the element at that index (`bodies.0.mass`);
//! `key[2]` is the same as `key.2`.

use ciborium::Value;
use serde::Serialize;

/// Split a path into segments (`a.b[2].c` → `a`, `b`, `2`, `c`); `None` if a segment is empty.
pub fn segments(path: &str) -> Option<Vec<String>> {
    let mut out = Vec::new();
    for part in path.split('.') {
        let (key, mut rest) = match part.find('[') {
            Some(i) => (&part[..i], &part[i..]),
            None => (part, ""),
        };
        if key.is_empty() && (out.is_empty() || rest.is_empty()) {
            return None;
        }
        if !key.is_empty() {
            out.push(key.to_string());
        }
        while let Some(r) = rest.strip_prefix('[') {
            let end = r.find(']')?;
            let index = &r[..end];
            if index.is_empty() {
                return None;
            }
            out.push(index.to_string());
            rest = &r[end + 1..];
        }
        if !rest.is_empty() {
            return None;
        }
    }
    Some(out)
}

fn toml_name(v: &toml::Value) -> Option<&str> {
    v.get("name").and_then(toml::Value::as_str)
}

/// A summary element's `name` field, if it has one.
fn summary_name(v: &Value) -> Option<&str> {
    field(v.as_map()?, "name")?.as_text()
}

/// The entry of `map` whose key is `segment` (a field name, or an integer map key written out).
fn field<'a>(map: &'a [(Value, Value)], segment: &str) -> Option<&'a Value> {
    map.iter()
        .find(|(k, _)| match k {
            Value::Text(t) => t == segment,
            Value::Integer(i) => segment.parse::<i128>().ok() == Some(i128::from(*i)),
            _ => false,
        })
        .map(|(_, v)| v)
}

/// Position in `items` of the element named `segment`, else the element at index `segment`.
fn pick<T>(items: &[T], segment: &str, name_of: fn(&T) -> Option<&str>) -> Option<usize> {
    items
        .iter()
        .position(|v| name_of(v) == Some(segment))
        .or_else(|| segment.parse::<usize>().ok().filter(|&k| k < items.len()))
}

fn names<T>(items: &[T], name_of: fn(&T) -> Option<&str>) -> String {
    let names: Vec<&str> = items.iter().filter_map(name_of).collect();
    if names.is_empty() {
        format!("{} unnamed elements", items.len())
    } else {
        format!("names: {}", names.join(", "))
    }
}

/// [`pick`] in the scene table's array `items` at path `walked`; Err names the elements it has.
fn element(items: &[toml::Value], segment: &str, walked: &str) -> Result<usize, String> {
    pick(items, segment, toml_name).ok_or_else(|| {
        format!(
            "{walked} has no element {segment:?} ({})",
            names(items, toml_name)
        )
    })
}

/// Set the field at `path` in a scene table to `value`, creating missing tables on the way
/// (the scene's deserialization then rejects a key that does not exist). An array element must
/// exist. Err: why not, for a message that names the path.
pub fn set(table: &mut toml::Table, path: &str, value: toml::Value) -> Result<(), String> {
    let segs = segments(path).ok_or_else(|| "not a dotted field path".to_string())?;
    let Some((last, parents)) = segs.split_last() else {
        return Err("empty path".into());
    };
    let Some((first, rest)) = parents.split_first() else {
        table.insert(last.clone(), value);
        return Ok(());
    };
    let mut here = table
        .entry(first.clone())
        .or_insert_with(|| toml::Value::Table(toml::Table::new()));
    let mut walked = first.clone();
    for seg in rest {
        here = step_mut(here, seg, &walked)?;
        walked = format!("{walked}.{seg}");
    }
    match here {
        toml::Value::Table(t) => {
            t.insert(last.clone(), value);
            Ok(())
        }
        toml::Value::Array(items) => {
            let k = element(items, last, &walked)?;
            items[k] = value;
            Ok(())
        }
        _ => Err(format!("{walked} is not a table")),
    }
}

/// The value at `path` in a scene table, if there is one.
pub fn get<'a>(table: &'a toml::Table, path: &str) -> Option<&'a toml::Value> {
    let segs = segments(path)?;
    let (first, rest) = segs.split_first()?;
    let mut here = table.get(first)?;
    for seg in rest {
        here = match here {
            toml::Value::Table(t) => t.get(seg)?,
            toml::Value::Array(items) => &items[pick(items, seg, toml_name)?],
            _ => return None,
        };
    }
    Some(here)
}

fn step_mut<'a>(
    here: &'a mut toml::Value,
    seg: &str,
    walked: &str,
) -> Result<&'a mut toml::Value, String> {
    match here {
        toml::Value::Table(t) => Ok(t
            .entry(seg.to_string())
            .or_insert_with(|| toml::Value::Table(toml::Table::new()))),
        toml::Value::Array(items) => {
            let k = element(items, seg, walked)?;
            Ok(&mut items[k])
        }
        _ => Err(format!("{walked} is not a table")),
    }
}

/// A run's summary as a tree [`number`] reads: what `summary.json` holds, but a NaN or infinite
/// number stays one (serde_json writes it as `null`, which reads as "no number here": a NaN
/// metric would pass as a sample that ran, `ok` with an empty cell). CBOR's data model, which
/// `ciborium` builds, has both floats that are not finite and `null`.
pub fn summary_value<T: Serialize + ?Sized>(value: &T) -> Result<Value, ciborium::value::Error> {
    Value::serialized(value)
}

/// The number at `path` in a summary ([`summary_value`]): `Ok(None)` for `null`, `true`/`false`
/// as 1/0, a NaN or infinity as itself (for the caller to refuse, naming it). Paths and errors
/// speak of `summary.json`, the file the tree is written as.
pub fn number(value: &Value, path: &str) -> Result<Option<f64>, String> {
    let segs = segments(path).ok_or_else(|| "not a dotted field path".to_string())?;
    let mut here = value;
    let mut walked = String::new();
    for seg in &segs {
        here = match here {
            Value::Map(m) => field(m, seg)
                .ok_or_else(|| format!("summary.json has no field {seg:?} in {}", show(&walked)))?,
            Value::Array(items) => {
                let k = pick(items, seg, summary_name).ok_or_else(|| {
                    format!(
                        "summary.json: {} has no element {seg:?} ({})",
                        show(&walked),
                        names(items, summary_name)
                    )
                })?;
                &items[k]
            }
            Value::Null => return Ok(None),
            _ => return Err(format!("summary.json: {} is not a table", show(&walked))),
        };
        walked = if walked.is_empty() {
            seg.clone()
        } else {
            format!("{walked}.{seg}")
        };
    }
    match here {
        Value::Float(x) => Ok(Some(*x)),
        // Integers as serde_json reads them back (a u64 beyond 2^53 rounds).
        Value::Integer(i) => Ok(Some(i128::from(*i) as f64)),
        Value::Bool(b) => Ok(Some(f64::from(u8::from(*b)))),
        Value::Null => Ok(None),
        _ => Err(format!("summary.json: {path} is not a number")),
    }
}

fn show(walked: &str) -> &str {
    if walked.is_empty() {
        "the top level"
    } else {
        walked
    }
}
