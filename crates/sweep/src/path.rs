//! Dotted field paths into scene tables and summaries: `clearance_joints.A.clearance`,
//! `drivers.drive.law.rpm`, `wear.joints.B.bearing_peak_depth_m`. A segment that meets an array
//! picks the element whose `name` it is, else the element at that index (`bodies.0.mass`);
//! `key[2]` is the same as `key.2`.

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

fn json_name(v: &serde_json::Value) -> Option<&str> {
    v.get("name").and_then(serde_json::Value::as_str)
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
            let k = pick(items, last, toml_name).ok_or_else(|| {
                format!(
                    "{walked} has no element {last:?} ({})",
                    names(items, toml_name)
                )
            })?;
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
            let k = pick(items, seg, toml_name).ok_or_else(|| {
                format!(
                    "{walked} has no element {seg:?} ({})",
                    names(items, toml_name)
                )
            })?;
            Ok(&mut items[k])
        }
        _ => Err(format!("{walked} is not a table")),
    }
}

/// The number at `path` in a JSON summary: `Ok(None)` for `null`, `true`/`false` as 1/0.
pub fn number(value: &serde_json::Value, path: &str) -> Result<Option<f64>, String> {
    let segs = segments(path).ok_or_else(|| "not a dotted field path".to_string())?;
    let mut here = value;
    let mut walked = String::new();
    for seg in &segs {
        here = match here {
            serde_json::Value::Object(m) => m
                .get(seg)
                .ok_or_else(|| format!("summary.json has no field {seg:?} in {}", show(&walked)))?,
            serde_json::Value::Array(items) => {
                let k = pick(items, seg, json_name).ok_or_else(|| {
                    format!(
                        "summary.json: {} has no element {seg:?} ({})",
                        show(&walked),
                        names(items, json_name)
                    )
                })?;
                &items[k]
            }
            serde_json::Value::Null => return Ok(None),
            _ => return Err(format!("summary.json: {} is not a table", show(&walked))),
        };
        walked = if walked.is_empty() {
            seg.clone()
        } else {
            format!("{walked}.{seg}")
        };
    }
    match here {
        serde_json::Value::Number(n) => Ok(n.as_f64()),
        serde_json::Value::Bool(b) => Ok(Some(f64::from(u8::from(*b)))),
        serde_json::Value::Null => Ok(None),
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
