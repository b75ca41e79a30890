//! # Reading another code's output
//!
//! `hompm check --input FILE` reads the other code's particles at the end
//! of its run, or its trace:
//!
//! - **CSV** with a header line; lines starting with `#` are comments, and
//!   `# key: value` comment lines are metadata (`# cells: 32` names the
//!   resolution for `--convergence`). A trace in CSV has the columns
//!   `step,time,equation,index,value`.
//! - **JSON**: `hompm run --json`'s document (its `particles` object of
//!   columns; [x, y] pairs and [xx, xy, yx, yy] rows are split into
//!   `_x`/`_y` and `_xx`… columns), an object of columns, an array of row
//!   objects, or a trace (`"schema": "hompm-trace"`).
//!
//! Column names are hompm's ([`known_columns`]); `--columns ours=theirs`
//! renames the file's. Every value must be a finite number. Anything
//! unusable is [`Error::Input`] with one sentence naming the row and
//! column.
//!
//! Items: [`ParticleTable`], [`Input`], [`read_input`], [`parse_input`],
//! [`known_columns`], [`ColumnMap`].

use super::trace::{Trace, TraceStep, TRACE_SCHEMA};
use crate::error::{Error, Result};
use std::collections::BTreeMap;

/// hompm's particle columns in 1D or 2D.
pub fn known_columns(two_d: bool) -> &'static [&'static str] {
    if two_d {
        &[
            "id",
            "x0_x",
            "x0_y",
            "x_x",
            "x_y",
            "u_x",
            "u_y",
            "v_x",
            "v_y",
            "stress_xx",
            "stress_yy",
            "stress_xy",
            "stress_yx",
            "F_xx",
            "F_xy",
            "F_yx",
            "F_yy",
            "volume",
            "density",
        ]
    } else {
        &["id", "x0", "x", "u", "v", "stress", "volume", "density"]
    }
}

/// Particle columns by name, every column as long as the others.
#[derive(Debug, Clone, Default, PartialEq)]
pub struct ParticleTable {
    /// The columns, in the file's order.
    pub columns: Vec<(String, Vec<f64>)>,
    /// `# key: value` metadata (CSV) or top-level scalars (JSON).
    pub metadata: BTreeMap<String, String>,
}

impl ParticleTable {
    /// The column called `name`.
    pub fn column(&self, name: &str) -> Option<&[f64]> {
        self.columns
            .iter()
            .find(|(n, _)| n == name)
            .map(|(_, v)| v.as_slice())
    }

    /// Number of rows.
    pub fn rows(&self) -> usize {
        self.columns.first().map_or(0, |(_, v)| v.len())
    }

    fn push(&mut self, name: String, values: Vec<f64>) -> Result<()> {
        if self.columns.iter().any(|(n, _)| *n == name) {
            return Err(Error::Input(format!("the column '{name}' appears twice")));
        }
        if let Some((first, v)) = self.columns.first() {
            if v.len() != values.len() {
                return Err(Error::Input(format!(
                    "the column '{name}' has {} values but '{first}' has {}",
                    values.len(),
                    v.len()
                )));
            }
        }
        self.columns.push((name, values));
        Ok(())
    }
}

/// What a file holds.
#[derive(Debug, Clone, PartialEq)]
pub enum Input {
    /// Particles at the end of a run.
    Particles(ParticleTable),
    /// A trace in `hompm trace`'s schema.
    Trace(Trace),
}

/// `--columns ours=theirs,…`: hompm's name for each of the file's.
#[derive(Debug, Clone, Default, PartialEq)]
pub struct ColumnMap(pub Vec<(String, String)>);

impl ColumnMap {
    /// Parses `ours=theirs,ours=theirs`.
    pub fn parse(text: &str) -> Result<Self> {
        let mut out = Vec::new();
        for pair in text.split(',').map(str::trim).filter(|p| !p.is_empty()) {
            let Some((ours, theirs)) = pair.split_once('=') else {
                return Err(Error::Input(format!(
                    "--columns takes ours=theirs pairs, got '{pair}'"
                )));
            };
            out.push((ours.trim().to_string(), theirs.trim().to_string()));
        }
        Ok(Self(out))
    }

    fn ours(&self, theirs: &str) -> String {
        self.0
            .iter()
            .find(|(_, t)| t == theirs)
            .map_or_else(|| theirs.to_string(), |(o, _)| o.clone())
    }
}

/// Reads `path`, refusing by its size, before reading it, a file whose
/// parsing would need more than `max_memory` bytes
/// ([`super::INPUT_MEMORY_FACTOR`] per byte of the file).
pub fn read_input(path: &std::path::Path, max_memory: u64) -> Result<String> {
    let meta = std::fs::metadata(path)
        .map_err(|e| Error::Input(format!("cannot read {}: {e}", path.display())))?;
    let needed = meta.len().saturating_mul(super::INPUT_MEMORY_FACTOR);
    if needed > max_memory {
        return Err(Error::Input(format!(
            "{} has {} bytes; reading it needs about {needed} bytes, over the memory limit of {max_memory} bytes (raise --max-memory)",
            path.display(),
            meta.len(),
        )));
    }
    std::fs::read_to_string(path)
        .map_err(|e| Error::Input(format!("cannot read {}: {e}", path.display())))
}

/// Parses a file's text as CSV or JSON (by its first non-blank character),
/// renaming columns by `map`. Returns the input and the names of the
/// columns that are not hompm's (ignored, for one warning line).
pub fn parse_input(text: &str, map: &ColumnMap, two_d: bool) -> Result<(Input, Vec<String>)> {
    let trimmed = text.trim_start();
    if trimmed.is_empty() {
        return Err(Error::Input("the file is empty".into()));
    }
    let input = if trimmed.starts_with('{') || trimmed.starts_with('[') {
        parse_json(trimmed)?
    } else {
        parse_csv(text)?
    };
    match input {
        Input::Trace(t) => Ok((Input::Trace(t), Vec::new())),
        Input::Particles(table) => {
            let (table, ignored) = rename(table, map, two_d)?;
            Ok((Input::Particles(table), ignored))
        }
    }
}

fn rename(
    table: ParticleTable,
    map: &ColumnMap,
    two_d: bool,
) -> Result<(ParticleTable, Vec<String>)> {
    let known = known_columns(two_d);
    for (ours, theirs) in &map.0 {
        if !known.contains(&ours.as_str()) {
            return Err(Error::Input(format!(
                "--columns maps '{theirs}' to '{ours}', which is not a column of hompm's (known: {})",
                known.join(", ")
            )));
        }
        if table.column(theirs).is_none() {
            return Err(Error::Input(format!(
                "--columns names '{theirs}', which the file does not have"
            )));
        }
    }
    let mut out = ParticleTable {
        metadata: table.metadata,
        ..Default::default()
    };
    let mut ignored = Vec::new();
    for (name, values) in table.columns {
        let ours = map.ours(&name);
        if known.contains(&ours.as_str()) {
            out.push(ours, values)?;
        } else {
            ignored.push(name);
        }
    }
    if out.columns.is_empty() {
        return Err(Error::Input(format!(
            "the file has none of hompm's columns ({}); map yours with --columns ours=theirs",
            known.join(", ")
        )));
    }
    if out.rows() == 0 {
        return Err(Error::Input("the file has no particles".into()));
    }
    Ok((out, ignored))
}

/// A number from a CSV cell or JSON value, finite, or an error naming where.
fn number(text: &str, row: usize, column: &str) -> Result<f64> {
    let v: f64 = text.trim().trim_matches('"').parse().map_err(|_| {
        Error::Input(format!(
            "row {row}, column '{column}': '{}' is not a number",
            text.trim()
        ))
    })?;
    finite(v, row, column)
}

fn finite(v: f64, row: usize, column: &str) -> Result<f64> {
    if v.is_finite() {
        Ok(v)
    } else {
        Err(Error::Input(format!(
            "row {row}, column '{column}' is {v}; every value must be finite"
        )))
    }
}

fn parse_csv(text: &str) -> Result<Input> {
    let mut metadata = BTreeMap::new();
    let mut header: Option<Vec<String>> = None;
    let mut rows: Vec<Vec<&str>> = Vec::new();
    for line in text.lines() {
        let line = line.trim_end_matches('\r');
        if line.trim().is_empty() {
            continue;
        }
        if let Some(comment) = line.trim_start().strip_prefix('#') {
            if let Some((k, v)) = comment.split_once(':') {
                metadata.insert(k.trim().to_string(), v.trim().to_string());
            }
            continue;
        }
        match header {
            None => {
                header = Some(
                    line.split(',')
                        .map(|h| h.trim().trim_matches('"').to_string())
                        .collect(),
                )
            }
            Some(_) => rows.push(line.split(',').collect()),
        }
    }
    let Some(header) = header else {
        return Err(Error::Input("the file has no header line".into()));
    };
    if rows.is_empty() {
        return Err(Error::Input("the file has a header but no rows".into()));
    }
    for (r, cells) in rows.iter().enumerate() {
        if cells.len() != header.len() {
            return Err(Error::Input(format!(
                "row {} has {} values but the header names {} columns",
                r + 1,
                cells.len(),
                header.len()
            )));
        }
    }
    if header.iter().any(|h| h == "equation") {
        return csv_trace(&header, &rows, metadata).map(Input::Trace);
    }
    let mut table = ParticleTable {
        metadata,
        ..Default::default()
    };
    for (c, name) in header.iter().enumerate() {
        let values: Result<Vec<f64>> = rows
            .iter()
            .enumerate()
            .map(|(r, cells)| number(cells[c], r + 1, name))
            .collect();
        table.push(name.clone(), values?)?;
    }
    Ok(Input::Particles(table))
}

fn csv_trace(
    header: &[String],
    rows: &[Vec<&str>],
    metadata: BTreeMap<String, String>,
) -> Result<Trace> {
    let col = |name: &str| -> Result<usize> {
        header.iter().position(|h| h == name).ok_or_else(|| {
            Error::Input(format!(
                "a trace in CSV needs the columns step,time,equation,index,value; '{name}' is missing"
            ))
        })
    };
    let (cs, ct, ce, ci, cv) = (
        col("step")?,
        col("time")?,
        col("equation")?,
        col("index")?,
        col("value")?,
    );
    let mut steps: Vec<TraceStep> = Vec::new();
    for (r, cells) in rows.iter().enumerate() {
        let row = r + 1;
        let step = number(cells[cs], row, "step")?;
        let index = number(cells[ci], row, "index")?;
        if step < 1.0 || step.fract() != 0.0 || index < 0.0 || index.fract() != 0.0 {
            return Err(Error::Input(format!(
                "row {row}: step must be a whole number ≥ 1 and index ≥ 0, got {step} and {index}"
            )));
        }
        let (step, index) = (step as usize, index as usize);
        let time = number(cells[ct], row, "time")?;
        let value = number(cells[cv], row, "value")?;
        let key = cells[ce].trim().trim_matches('"').to_string();
        if steps.last().map(|s| s.step) != Some(step) {
            steps.push(TraceStep {
                step,
                time,
                equations: BTreeMap::new(),
            });
        }
        let Some(current) = steps.last_mut() else {
            continue;
        };
        let values = current.equations.entry(key.clone()).or_default();
        if index != values.len() {
            return Err(Error::Input(format!(
                "row {row}: equation {key} at step {step} has index {index} where {} was next",
                values.len()
            )));
        }
        values.push(value);
    }
    let header = metadata
        .into_iter()
        .filter(|(k, _)| k != "schema" && k != "version")
        .map(|(k, v)| {
            let value = serde_json::from_str(&v).unwrap_or(serde_json::Value::String(v));
            (k, value)
        })
        .collect();
    Ok(Trace {
        schema: TRACE_SCHEMA.into(),
        version: super::trace::TRACE_VERSION,
        header,
        steps,
    })
}

fn parse_json(text: &str) -> Result<Input> {
    let value: serde_json::Value = serde_json::from_str(text)
        .map_err(|e| Error::Input(format!("the file is not valid JSON: {e}")))?;
    if value.get("schema").and_then(|s| s.as_str()) == Some(TRACE_SCHEMA) {
        let trace: Trace = serde_json::from_value(value)
            .map_err(|e| Error::Input(format!("the trace does not follow hompm's schema: {e}")))?;
        return Ok(Input::Trace(trace));
    }
    let mut table = ParticleTable::default();
    if let Some(obj) = value.as_object() {
        for (k, v) in obj {
            if let Some(s) = v.as_str() {
                table.metadata.insert(k.clone(), s.to_string());
            } else if v.is_number() {
                table.metadata.insert(k.clone(), v.to_string());
            }
        }
    }
    let columns = match (&value, value.get("particles")) {
        (_, Some(p)) if p.is_object() => p,
        (serde_json::Value::Object(_), _) => &value,
        (serde_json::Value::Array(rows), _) => return json_rows(rows, table).map(Input::Particles),
        _ => {
            return Err(Error::Input(
                "the JSON is neither columns nor rows of particles".into(),
            ))
        }
    };
    let Some(obj) = columns.as_object() else {
        return Err(Error::Input(
            "'particles' is not an object of columns".into(),
        ));
    };
    for (name, v) in obj {
        let Some(items) = v.as_array() else {
            continue;
        };
        json_column(name, items, &mut table)?;
    }
    Ok(Input::Particles(table))
}

/// One JSON column: numbers, or [x, y] pairs, or [xx, xy, yx, yy] rows.
fn json_column(name: &str, items: &[serde_json::Value], table: &mut ParticleTable) -> Result<()> {
    let name = if name == "deformation_gradient" {
        "F"
    } else {
        name
    };
    let width = match items.first() {
        Some(serde_json::Value::Array(a)) => a.len(),
        _ => 0,
    };
    let suffixes: &[&str] = match width {
        0 => &[""],
        2 => &["_x", "_y"],
        4 => &["_xx", "_xy", "_yx", "_yy"],
        w => {
            return Err(Error::Input(format!(
            "column '{name}' has entries of {w} numbers; hompm reads numbers, pairs or 2 × 2 rows"
        )))
        }
    };
    for (c, suffix) in suffixes.iter().enumerate() {
        let col = format!("{name}{suffix}");
        let values: Result<Vec<f64>> = items
            .iter()
            .enumerate()
            .map(|(r, item)| {
                let cell = if width == 0 { Some(item) } else { item.get(c) };
                match cell.and_then(serde_json::Value::as_f64) {
                    Some(v) => finite(v, r + 1, &col),
                    None => Err(Error::Input(format!(
                        "row {}, column '{col}': {} is not a number",
                        r + 1,
                        cell.map_or("nothing".into(), ToString::to_string)
                    ))),
                }
            })
            .collect();
        table.push(col, values?)?;
    }
    Ok(())
}

fn json_rows(rows: &[serde_json::Value], mut table: ParticleTable) -> Result<ParticleTable> {
    let Some(first) = rows.first().and_then(|r| r.as_object()) else {
        return Err(Error::Input(
            "the JSON array holds no particle objects".into(),
        ));
    };
    for name in first.keys() {
        let items: Vec<serde_json::Value> = rows
            .iter()
            .enumerate()
            .map(|(r, row)| {
                row.get(name)
                    .cloned()
                    .ok_or_else(|| Error::Input(format!("row {} has no '{name}'", r + 1)))
            })
            .collect::<Result<_>>()?;
        json_column(name, &items, &mut table)?;
    }
    Ok(table)
}
