//! # Reading another code's JSON strictly
//!
//! `hompm check --input FILE.json` reads hompm's own `run --json` document,
//! an object of columns, an array of row objects, or a trace in
//! `hompm trace`'s schema. Every one is read strictly (issue #35,
//! docs/oracle.md "Strict reading"):
//!
//! - a key that appears twice in one object is refused ([`parse_strict`]);
//!   `serde_json` alone would keep the last one silently;
//! - a column is an array of numbers, of [x, y] pairs or of
//!   [xx, xy, yx, yy] rows, every entry of one width; anything else in a
//!   place where a column stands (`null`, a string, a number, an object)
//!   is refused, never skipped;
//! - every row object of an array of rows has the same keys;
//! - a trace has `schema`, `version` (at most hompm's), `steps` and an
//!   optional `header`; every step has `step`, `time` and `equations`,
//!   and nothing else; its steps are returned ordered by number, and a
//!   step number given twice is refused.
//!
//! Items: [`parse_strict`]; the crate's `parse_json` serves
//! `oracle::input::parse_input`.

use super::table::{finite, short, Parsed, TableBuilder};
use super::trace::{Trace, TraceStep, TRACE_SCHEMA, TRACE_VERSION};
use crate::error::{Error, Result};
use serde::de::{DeserializeSeed, Deserializer, Error as _, MapAccess, SeqAccess, Visitor};
use serde::Deserialize;
use serde_json::{Map, Number, Value};
use std::collections::BTreeMap;

/// A JSON value in which no object holds a key twice.
struct StrictValue;

impl<'de> DeserializeSeed<'de> for StrictValue {
    type Value = Value;
    fn deserialize<D: Deserializer<'de>>(self, d: D) -> std::result::Result<Value, D::Error> {
        d.deserialize_any(StrictValue)
    }
}

impl<'de> Visitor<'de> for StrictValue {
    type Value = Value;
    fn expecting(&self, f: &mut std::fmt::Formatter) -> std::fmt::Result {
        f.write_str("a JSON value")
    }
    fn visit_bool<E>(self, v: bool) -> std::result::Result<Value, E> {
        Ok(Value::Bool(v))
    }
    fn visit_i64<E>(self, v: i64) -> std::result::Result<Value, E> {
        Ok(Value::Number(v.into()))
    }
    fn visit_u64<E>(self, v: u64) -> std::result::Result<Value, E> {
        Ok(Value::Number(v.into()))
    }
    fn visit_f64<E: serde::de::Error>(self, v: f64) -> std::result::Result<Value, E> {
        Number::from_f64(v)
            .map(Value::Number)
            .ok_or_else(|| E::custom(format!("{v} is not a finite number")))
    }
    fn visit_str<E>(self, v: &str) -> std::result::Result<Value, E> {
        Ok(Value::String(v.to_string()))
    }
    fn visit_string<E>(self, v: String) -> std::result::Result<Value, E> {
        Ok(Value::String(v))
    }
    fn visit_unit<E>(self) -> std::result::Result<Value, E> {
        Ok(Value::Null)
    }
    fn visit_none<E>(self) -> std::result::Result<Value, E> {
        Ok(Value::Null)
    }
    fn visit_seq<A: SeqAccess<'de>>(self, mut seq: A) -> std::result::Result<Value, A::Error> {
        let mut items = Vec::new();
        while let Some(v) = seq.next_element_seed(StrictValue)? {
            items.push(v);
        }
        Ok(Value::Array(items))
    }
    fn visit_map<A: MapAccess<'de>>(self, mut map: A) -> std::result::Result<Value, A::Error> {
        let mut object = Map::new();
        while let Some(key) = map.next_key::<String>()? {
            if object.contains_key(&key) {
                return Err(A::Error::custom(format!(
                    "the key '{}' appears twice in one object",
                    short(&key)
                )));
            }
            let value = map.next_value_seed(StrictValue)?;
            object.insert(key, value);
        }
        Ok(Value::Object(object))
    }
}

/// Parses JSON text, refusing a key that appears twice in one object.
pub fn parse_strict(text: &str) -> Result<Value> {
    let mut d = serde_json::Deserializer::from_str(text);
    let value = StrictValue
        .deserialize(&mut d)
        .and_then(|v| d.end().map(|()| v))
        .map_err(|e| Error::Input(format!("the file is not valid JSON: {e}")))?;
    Ok(value)
}

/// The trace as a file holds it: `header` may be left out.
#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
struct TraceFile {
    schema: String,
    version: u32,
    #[serde(default)]
    header: BTreeMap<String, Value>,
    steps: Vec<StepFile>,
}

#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
struct StepFile {
    step: usize,
    time: f64,
    equations: BTreeMap<String, Vec<f64>>,
}

/// Steps ordered by number; a number given twice is refused.
pub(crate) fn ordered_steps(mut steps: Vec<TraceStep>) -> Result<Vec<TraceStep>> {
    steps.sort_by_key(|s| s.step);
    if let Some(w) = steps.windows(2).find(|w| w[0].step == w[1].step) {
        return Err(Error::Input(format!(
            "the trace has step {} twice",
            w[0].step
        )));
    }
    Ok(steps)
}

fn trace(value: Value) -> Result<Trace> {
    let file: TraceFile = serde_json::from_value(value).map_err(|e| {
        Error::Input(format!(
            "the trace does not follow hompm's schema: {}",
            short(&e.to_string())
        ))
    })?;
    if file.version > TRACE_VERSION {
        return Err(Error::Input(format!(
            "the trace has schema version {}; this hompm reads version {TRACE_VERSION}",
            file.version
        )));
    }
    let steps = file
        .steps
        .into_iter()
        .map(|s| TraceStep {
            step: s.step,
            time: s.time,
            equations: s.equations,
        })
        .collect();
    Ok(Trace {
        schema: file.schema,
        version: file.version,
        header: file.header,
        steps: ordered_steps(steps)?,
    })
}

/// Parses JSON text: a trace (`"schema": "hompm-trace"`), `hompm run
/// --json`'s document (its `particles` object), an object of columns or an
/// array of row objects.
pub(crate) fn parse_json(text: &str) -> Result<Parsed> {
    let value = parse_strict(text)?;
    if value.get("schema").and_then(Value::as_str) == Some(TRACE_SCHEMA) {
        return trace(value).map(Parsed::Trace);
    }
    let mut table = TableBuilder::default();
    match value {
        Value::Array(rows) => json_rows(&rows, &mut table)?,
        Value::Object(mut top) => {
            let particles = top.remove("particles");
            for (k, v) in &top {
                match v {
                    Value::String(s) => table.metadata(k, s.clone()),
                    Value::Number(n) => table.metadata(k, n.to_string()),
                    // `hompm run --json` names another code's conventions
                    // in one object; each is metadata the setup must match.
                    Value::Object(c) if k == "conventions" => {
                        for (ck, cv) in c {
                            if let Value::String(s) = cv {
                                table.metadata(ck, s.clone());
                            }
                        }
                    }
                    // The aligned vibration's form, where the run names it.
                    Value::Object(params) if k == "params" => {
                        if let Some(Value::String(form)) = params.get("solution") {
                            table.metadata("solution", form.clone());
                        }
                    }
                    _ => {}
                }
            }
            match particles {
                Some(Value::Object(columns)) => {
                    for (name, v) in &columns {
                        let Value::Array(items) = v else {
                            return Err(not_a_column(&format!("particles.{name}"), v));
                        };
                        json_column(name, items, &mut table)?;
                    }
                }
                Some(other) => return Err(not_a_column("particles", &other)),
                None => {
                    for (name, v) in &top {
                        match v {
                            Value::Array(items) => json_column(name, items, &mut table)?,
                            // A scalar of an object of columns is metadata,
                            // unless it stands where one of hompm's columns
                            // would (checked by name after --columns).
                            Value::String(_) | Value::Number(_) => table.scalar(name),
                            other => return Err(not_a_column(name, other)),
                        }
                    }
                }
            }
        }
        _ => {
            return Err(Error::Input(
                "the JSON is neither columns nor rows of particles".into(),
            ))
        }
    }
    Ok(Parsed::Particles(table.finish()))
}

/// A value where a column (an array) must stand.
fn not_a_column(name: &str, v: &Value) -> Error {
    Error::Input(format!(
        "'{}' is {}, not a column: a column is an array of numbers, of [x, y] pairs or of [xx, xy, yx, yy] rows",
        short(name),
        kind(v)
    ))
}

/// A JSON value's kind in words.
fn kind(v: &Value) -> &'static str {
    match v {
        Value::Null => "null",
        Value::Bool(_) => "a boolean",
        Value::Number(_) => "a number",
        Value::String(_) => "a string",
        Value::Array(_) => "an array",
        Value::Object(_) => "an object",
    }
}

/// One JSON column: numbers, or [x, y] pairs, or [xx, xy, yx, yy] rows,
/// every entry of the first entry's width.
fn json_column(name: &str, items: &[Value], table: &mut TableBuilder) -> Result<()> {
    let name = if name == "deformation_gradient" {
        "F"
    } else {
        name
    };
    let width = match items.first() {
        Some(Value::Array(a)) => a.len(),
        _ => 0,
    };
    let suffixes: &[&str] = match width {
        0 => &[""],
        2 => &["_x", "_y"],
        4 => &["_xx", "_xy", "_yx", "_yy"],
        w => {
            return Err(Error::Input(format!(
                "column '{}' has entries of {w} numbers; hompm reads numbers, [x, y] pairs or [xx, xy, yx, yy] rows",
                short(name)
            )))
        }
    };
    let mut columns: Vec<Vec<f64>> = vec![Vec::with_capacity(items.len()); suffixes.len()];
    for (r, item) in items.iter().enumerate() {
        let row = r + 1;
        let cells: &[Value] = match (width, item) {
            (0, Value::Array(a)) => {
                return Err(Error::Input(format!(
                    "row {row}, column '{}': an entry of {} numbers where the first entry is one number",
                    short(name),
                    a.len()
                )))
            }
            (0, v) => std::slice::from_ref(v),
            (w, Value::Array(a)) if a.len() == w => a,
            (w, v) => {
                return Err(Error::Input(format!(
                    "row {row}, column '{}': {} where the first entry has {w} numbers",
                    short(name),
                    match v {
                        Value::Array(a) => format!("an entry of {} numbers", a.len()),
                        other => kind(other).to_string(),
                    }
                )))
            }
        };
        for ((column, cell), suffix) in columns.iter_mut().zip(cells).zip(suffixes) {
            let v = cell.as_f64().ok_or_else(|| {
                Error::Input(format!(
                    "row {row}, column '{}{suffix}': {} is not a number",
                    short(name),
                    kind(cell)
                ))
            })?;
            column.push(finite(v, row, &format!("{name}{suffix}"))?);
        }
    }
    for (suffix, values) in suffixes.iter().zip(columns) {
        table.column(format!("{name}{suffix}"), values)?;
    }
    Ok(())
}

/// An array of row objects, every one with the first one's keys.
fn json_rows(rows: &[Value], table: &mut TableBuilder) -> Result<()> {
    let Some(first) = rows.first().and_then(Value::as_object) else {
        return Err(Error::Input(
            "the JSON array holds no particle objects".into(),
        ));
    };
    for (r, row) in rows.iter().enumerate() {
        let Some(object) = row.as_object() else {
            return Err(Error::Input(format!(
                "row {} is {}, not a particle object",
                r + 1,
                kind(row)
            )));
        };
        if let Some(extra) = object.keys().find(|k| !first.contains_key(*k)) {
            return Err(Error::Input(format!(
                "row {} has '{}', which row 1 does not have",
                r + 1,
                short(extra)
            )));
        }
    }
    for name in first.keys() {
        let items: Vec<Value> = rows
            .iter()
            .enumerate()
            .map(|(r, row)| {
                row.get(name)
                    .cloned()
                    .ok_or_else(|| Error::Input(format!("row {} has no '{}'", r + 1, short(name))))
            })
            .collect::<Result<_>>()?;
        json_column(name, &items, table)?;
    }
    Ok(())
}
