//! Dotted field paths into scene tables and summaries: `clearance_joints.A.clearance`,
//! `drivers.drive.law.rpm`, `wear.joints.B.bearing_peak_depth_m`. A segment that meets an array
//! picks the element whose `name` it is, else the element at that index (`bodies.0.mass`);
//! `key[2]` is the same as `key.2`.

use serde::ser::{self, Serialize};
use serde_json::{Map, Value};

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

/// The number at `path` in a JSON summary: `Ok(None)` for `null`, `true`/`false` as 1/0, a NaN
/// or infinity kept by [`summary_json`] as itself (for the caller to refuse, naming it).
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
    if let Some(v) = non_finite(here) {
        return Ok(Some(v));
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

/// Key of the one-entry object [`summary_json`] puts where a number is NaN or infinite (a NUL
/// byte: no summary field or scene name is spelled so).
const NON_FINITE_KEY: &str = "\u{0}non-finite";

/// The NaN or infinity `value` stands for, if it is [`summary_json`]'s marker.
fn non_finite(value: &serde_json::Value) -> Option<f64> {
    let serde_json::Value::Object(m) = value else {
        return None;
    };
    if m.len() != 1 {
        return None;
    }
    let v: f64 = m.get(NON_FINITE_KEY)?.as_str()?.parse().ok()?;
    (!v.is_finite()).then_some(v)
}

/// `value` (a run's summary) as JSON for [`number`], like `serde_json::to_value` except that a
/// NaN or infinite number becomes a marker [`number`] reads back as that number. serde_json
/// writes them as `null`, which reads as "no number here": a NaN metric would pass as a sample
/// that ran (`ok`, empty cell) instead of one whose result is not finite.
pub fn summary_json<T: Serialize + ?Sized>(
    value: &T,
) -> Result<serde_json::Value, serde_json::Error> {
    value.serialize(KeepNonFinite)
}

/// The serializer of [`summary_json`]: builds a [`Value`], non-finite numbers as markers.
struct KeepNonFinite;

type Error = serde_json::Error;

fn marker(v: f64) -> Value {
    let mut m = Map::new();
    m.insert(NON_FINITE_KEY.to_string(), Value::String(v.to_string()));
    Value::Object(m)
}

fn tagged(variant: &str, value: Value) -> Value {
    let mut m = Map::new();
    m.insert(variant.to_string(), value);
    Value::Object(m)
}

/// `value` as an enum variant's content (`{variant: value}`) if it is one, else as it is.
fn tagged_if(variant: Option<&str>, value: Value) -> Value {
    match variant {
        Some(v) => tagged(v, value),
        None => value,
    }
}

/// The integer methods of [`KeepNonFinite`]: every integer as serde_json writes it.
macro_rules! integers {
    ($($method:ident: $t:ty),* $(,)?) => {
        $(fn $method(self, v: $t) -> Result<Value, Error> {
            Ok(Value::from(v))
        })*
    };
}

impl ser::Serializer for KeepNonFinite {
    type Ok = Value;
    type Error = Error;
    type SerializeSeq = Seq;
    type SerializeTuple = Seq;
    type SerializeTupleStruct = Seq;
    type SerializeTupleVariant = Seq;
    type SerializeMap = Object;
    type SerializeStruct = Object;
    type SerializeStructVariant = Object;

    fn serialize_bool(self, v: bool) -> Result<Value, Error> {
        Ok(Value::Bool(v))
    }
    integers!(
        serialize_i8: i8,
        serialize_i16: i16,
        serialize_i32: i32,
        serialize_i64: i64,
        serialize_u8: u8,
        serialize_u16: u16,
        serialize_u32: u32,
        serialize_u64: u64,
    );
    fn serialize_f32(self, v: f32) -> Result<Value, Error> {
        self.serialize_f64(f64::from(v))
    }
    fn serialize_f64(self, v: f64) -> Result<Value, Error> {
        Ok(if v.is_finite() {
            Value::from(v)
        } else {
            marker(v)
        })
    }
    fn serialize_char(self, v: char) -> Result<Value, Error> {
        Ok(Value::String(v.to_string()))
    }
    fn serialize_str(self, v: &str) -> Result<Value, Error> {
        Ok(Value::String(v.to_string()))
    }
    fn serialize_bytes(self, v: &[u8]) -> Result<Value, Error> {
        Ok(Value::Array(v.iter().map(|b| Value::from(*b)).collect()))
    }
    fn serialize_none(self) -> Result<Value, Error> {
        Ok(Value::Null)
    }
    fn serialize_some<T: Serialize + ?Sized>(self, value: &T) -> Result<Value, Error> {
        value.serialize(self)
    }
    fn serialize_unit(self) -> Result<Value, Error> {
        Ok(Value::Null)
    }
    fn serialize_unit_struct(self, _: &'static str) -> Result<Value, Error> {
        Ok(Value::Null)
    }
    fn serialize_unit_variant(
        self,
        _: &'static str,
        _: u32,
        variant: &'static str,
    ) -> Result<Value, Error> {
        Ok(Value::String(variant.to_string()))
    }
    fn serialize_newtype_struct<T: Serialize + ?Sized>(
        self,
        _: &'static str,
        value: &T,
    ) -> Result<Value, Error> {
        value.serialize(self)
    }
    fn serialize_newtype_variant<T: Serialize + ?Sized>(
        self,
        _: &'static str,
        _: u32,
        variant: &'static str,
        value: &T,
    ) -> Result<Value, Error> {
        Ok(tagged(variant, value.serialize(self)?))
    }
    fn serialize_seq(self, len: Option<usize>) -> Result<Seq, Error> {
        Ok(Seq {
            variant: None,
            items: Vec::with_capacity(len.unwrap_or(0)),
        })
    }
    fn serialize_tuple(self, len: usize) -> Result<Seq, Error> {
        self.serialize_seq(Some(len))
    }
    fn serialize_tuple_struct(self, _: &'static str, len: usize) -> Result<Seq, Error> {
        self.serialize_seq(Some(len))
    }
    fn serialize_tuple_variant(
        self,
        _: &'static str,
        _: u32,
        variant: &'static str,
        len: usize,
    ) -> Result<Seq, Error> {
        Ok(Seq {
            variant: Some(variant),
            items: Vec::with_capacity(len),
        })
    }
    fn serialize_map(self, _: Option<usize>) -> Result<Object, Error> {
        Ok(Object {
            variant: None,
            map: Map::new(),
            key: None,
        })
    }
    fn serialize_struct(self, _: &'static str, _: usize) -> Result<Object, Error> {
        self.serialize_map(None)
    }
    fn serialize_struct_variant(
        self,
        _: &'static str,
        _: u32,
        variant: &'static str,
        _: usize,
    ) -> Result<Object, Error> {
        Ok(Object {
            variant: Some(variant),
            map: Map::new(),
            key: None,
        })
    }
}

/// A sequence (or tuple) under construction; `variant` wraps it as `{variant: [...]}`.
struct Seq {
    variant: Option<&'static str>,
    items: Vec<Value>,
}

impl Seq {
    fn push<T: Serialize + ?Sized>(&mut self, value: &T) -> Result<(), Error> {
        self.items.push(value.serialize(KeepNonFinite)?);
        Ok(())
    }

    fn done(self) -> Value {
        tagged_if(self.variant, Value::Array(self.items))
    }
}

/// serde's four sequence traits, the same for [`Seq`] but for the name of the method that adds
/// an item.
macro_rules! sequence {
    ($($trait:ident: $method:ident),* $(,)?) => {
        $(impl ser::$trait for Seq {
            type Ok = Value;
            type Error = Error;
            fn $method<T: Serialize + ?Sized>(&mut self, value: &T) -> Result<(), Error> {
                self.push(value)
            }
            fn end(self) -> Result<Value, Error> {
                Ok(self.done())
            }
        })*
    };
}

sequence!(
    SerializeSeq: serialize_element,
    SerializeTuple: serialize_element,
    SerializeTupleStruct: serialize_field,
    SerializeTupleVariant: serialize_field,
);

/// A map (or struct) under construction; `variant` wraps it as `{variant: {...}}`.
struct Object {
    variant: Option<&'static str>,
    map: Map<String, Value>,
    key: Option<String>,
}

impl Object {
    fn insert<T: Serialize + ?Sized>(&mut self, key: String, value: &T) -> Result<(), Error> {
        self.map.insert(key, value.serialize(KeepNonFinite)?);
        Ok(())
    }

    fn done(self) -> Value {
        tagged_if(self.variant, Value::Object(self.map))
    }
}

impl ser::SerializeMap for Object {
    type Ok = Value;
    type Error = Error;
    fn serialize_key<T: Serialize + ?Sized>(&mut self, key: &T) -> Result<(), Error> {
        // As serde_json: string keys as they are, numbers and booleans as their text.
        self.key = Some(match key.serialize(KeepNonFinite)? {
            Value::String(s) => s,
            Value::Number(n) => n.to_string(),
            Value::Bool(b) => b.to_string(),
            _ => return Err(ser::Error::custom("a map key must be a string or a number")),
        });
        Ok(())
    }
    fn serialize_value<T: Serialize + ?Sized>(&mut self, value: &T) -> Result<(), Error> {
        let key = self
            .key
            .take()
            .ok_or_else(|| <Error as ser::Error>::custom("a map value without its key"))?;
        self.insert(key, value)
    }
    fn end(self) -> Result<Value, Error> {
        Ok(self.done())
    }
}

/// serde's two struct traits, the same for [`Object`]: fields are keys.
macro_rules! structure {
    ($($trait:ident),*) => {
        $(impl ser::$trait for Object {
            type Ok = Value;
            type Error = Error;
            fn serialize_field<T: Serialize + ?Sized>(
                &mut self,
                key: &'static str,
                value: &T,
            ) -> Result<(), Error> {
                self.insert(key.to_string(), value)
            }
            fn end(self) -> Result<Value, Error> {
                Ok(self.done())
            }
        })*
    };
}

structure!(SerializeStruct, SerializeStructVariant);
