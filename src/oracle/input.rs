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
//! - **LAMMPS-style dump files** (Karamelo and other LAMMPS-derived
//!   codes), one timestep block, the last unless `--dump-step` names
//!   another ([`super::input_dump`]).
//! - **VTK** particle files: legacy `.vtk` ([`super::input_vtk`]) and XML
//!   `.vtp`/`.vtu` ([`super::input_vtk_xml`]); columns `Points:0…2` and
//!   each point-data array (`name`, or `name:j` per component).
//! - **NumPy** `.npy` and `.npz` ([`super::input_npy`]).
//!
//! The binary formats are found by their first bytes, the text ones by
//! their first non-blank text; `--format` forces one reader ([`Format`]). Column names are hompm's ([`known_columns`]); `--columns ours=theirs`
//! renames the file's. Every value must be a finite number. Anything
//! unusable is [`Error::Input`] with one sentence naming the row and
//! column.
//!
//! Items: [`ParticleTable`], [`Input`], [`Format`], [`read_input`], [`parse_input`], [`parse_input_as`],
//! [`known_columns`], [`ColumnMap`].

pub use super::columns::known_columns;
use super::columns::{quantity, PHYSICAL_FIELDS};
pub use super::table::ParticleTable;
use super::table::{finite, short, Parsed, ParsedTable, TableBuilder};
use super::trace::{Trace, TraceStep, TRACE_SCHEMA, TRACE_VERSION};
use crate::error::{Error, Result};
use std::collections::BTreeMap;

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
    /// Parses `ours=theirs,ours=theirs`. One of hompm's names mapped
    /// twice, or one of the file's names mapped to two of hompm's, is
    /// refused: a map that would compare one column as two fields, or drop
    /// one of two, is never taken.
    pub fn parse(text: &str) -> Result<Self> {
        let mut out: Vec<(String, String)> = Vec::new();
        for pair in text.split(',').map(str::trim).filter(|p| !p.is_empty()) {
            let Some((ours, theirs)) = pair.split_once('=') else {
                return Err(Error::Input(format!(
                    "--columns takes ours=theirs pairs, got '{}'",
                    short(pair)
                )));
            };
            let (ours, theirs) = (ours.trim().to_string(), theirs.trim().to_string());
            if ours.is_empty() || theirs.is_empty() {
                return Err(Error::Input(format!(
                    "--columns takes ours=theirs pairs with both names, got '{}'",
                    short(pair)
                )));
            }
            if let Some((o, _)) = out.iter().find(|(_, t)| *t == theirs) {
                return Err(Error::Input(format!(
                    "--columns maps your column '{}' to both '{}' and '{}'; one column is one field",
                    short(&theirs),
                    short(o),
                    short(&ours)
                )));
            }
            if let Some((_, t)) = out.iter().find(|(o, _)| *o == ours) {
                return Err(Error::Input(format!(
                    "--columns maps both '{}' and '{}' to hompm's '{}'",
                    short(t),
                    short(&theirs),
                    short(&ours)
                )));
            }
            out.push((ours, theirs));
        }
        Ok(Self(out))
    }

    fn ours<'a>(&'a self, theirs: &'a str) -> &'a str {
        self.0
            .iter()
            .find(|(_, t)| t == theirs)
            .map_or(theirs, |(o, _)| o.as_str())
    }
}

/// Reads `path` through a reader that stops at `max_memory /`
/// [`super::INPUT_MEMORY_FACTOR`] bytes, so that the limit holds for
/// pipes, devices and FIFOs as for regular files; a regular file over it
/// is refused by its size before it is read. Returns the bytes: the text
/// formats must be UTF-8 ([`parse_input_as`] says so), the binary ones
/// need not.
pub fn read_input(path: &std::path::Path, max_memory: u64) -> Result<Vec<u8>> {
    use std::io::Read;
    let cannot = |e: std::io::Error| Error::Input(format!("cannot read {}: {e}", path.display()));
    let allowed = max_memory / super::INPUT_MEMORY_FACTOR;
    let over = |what: String| {
        Error::Input(format!(
            "{} has {what}; reading it needs about {} bytes per byte, over the memory limit of {max_memory} bytes (raise --max-memory)",
            path.display(),
            super::INPUT_MEMORY_FACTOR,
        ))
    };
    let meta = std::fs::metadata(path).map_err(cannot)?;
    if meta.is_file() && meta.len() > allowed {
        return Err(over(format!(
            "{} bytes (needs about {} bytes)",
            meta.len(),
            meta.len().saturating_mul(super::INPUT_MEMORY_FACTOR)
        )));
    }
    let file = std::fs::File::open(path).map_err(cannot)?;
    let mut bytes = Vec::new();
    file.take(allowed.saturating_add(1))
        .read_to_end(&mut bytes)
        .map_err(cannot)?;
    if bytes.len() as u64 > allowed {
        return Err(over(format!("more than {allowed} bytes")));
    }
    Ok(bytes)
}

/// Parses a file's text as CSV or JSON (by its first non-blank character),
/// renaming columns by `map`. Returns the input and the names of the
/// columns that are not hompm's (not compared; also in
/// [`ParticleTable::ignored`]).
pub fn parse_input(text: &str, map: &ColumnMap, two_d: bool) -> Result<(Input, Vec<String>)> {
    parse_input_as(text.as_bytes(), Format::Auto, None, map, two_d, u64::MAX)
}

/// `--format`: how an input file is read.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default, clap::ValueEnum)]
pub enum Format {
    /// By its first non-blank text: `{` or `[` JSON, `ITEM:` a LAMMPS
    /// dump, anything else CSV.
    #[default]
    Auto,
    /// CSV with a header line.
    Csv,
    /// JSON (hompm's run document, columns, rows or a trace).
    Json,
    /// A LAMMPS-style dump file (Karamelo; `oracle::input_dump`).
    LammpsDump,
    /// A legacy VTK file, ASCII or binary (`oracle::input_vtk`).
    Vtk,
    /// An XML VTK file, `.vtp` or `.vtu` (`oracle::input_vtk_xml`).
    VtkXml,
    /// A NumPy `.npy` array (`oracle::input_npy`).
    Npy,
    /// A NumPy `.npz` archive of named arrays (`oracle::input_npy`).
    Npz,
}

impl Format {
    /// The format of `bytes`: binary formats by their magic bytes, text
    /// ones by their first non-blank text.
    fn detect(bytes: &[u8]) -> Self {
        let text = bytes.trim_ascii_start();
        if bytes.starts_with(super::npy_header::NPY_MAGIC) {
            Self::Npy
        } else if bytes.starts_with(super::input_npy::ZIP_MAGIC) {
            Self::Npz
        } else if text.starts_with(super::input_vtk::LEGACY_MAGIC) {
            Self::Vtk
        } else if text.starts_with(b"<?xml") || text.starts_with(b"<VTKFile") {
            Self::VtkXml
        } else if text.starts_with(b"{") || text.starts_with(b"[") {
            Self::Json
        } else if super::input_dump::is_dump(&String::from_utf8_lossy(
            &text[..text.len().min(4096)],
        )) {
            Self::LammpsDump
        } else {
            Self::Csv
        }
    }
}

/// [`parse_input`] of a file's bytes with the format forced (or
/// detected) and, for a dump file, the timestep to read (default: the
/// last). Compressed data (`.npz`, zlib in VTK XML) may unpack to at most
/// `unpack_limit` bytes.
pub fn parse_input_as(
    bytes: &[u8],
    format: Format,
    dump_step: Option<u64>,
    map: &ColumnMap,
    two_d: bool,
    unpack_limit: u64,
) -> Result<(Input, Vec<String>)> {
    if bytes.trim_ascii_start().is_empty() {
        return Err(Error::Input("the file is empty".into()));
    }
    let format = match format {
        Format::Auto => Format::detect(bytes),
        given => given,
    };
    if dump_step.is_some() && format != Format::LammpsDump {
        return Err(Error::Input(
            "--dump-step applies to a LAMMPS dump file only".into(),
        ));
    }
    let text = || {
        std::str::from_utf8(bytes).map_err(|e| {
            Error::Input(format!(
                "the file is not UTF-8 text (byte {} is not), and not a binary format hompm reads (.npy, .npz, binary VTK)",
                e.valid_up_to()
            ))
        })
    };
    let parsed = match format {
        Format::Json => super::input_json::parse_json(text()?.trim_start())?,
        Format::LammpsDump => super::input_dump::parse_dump(text()?, dump_step)?,
        Format::Vtk => super::input_vtk::parse_legacy(bytes)?,
        Format::VtkXml => super::input_vtk_xml::parse_xml(bytes, unpack_limit)?,
        Format::Npy => super::input_npy::parse_npy(bytes)?,
        Format::Npz => super::input_npy::parse_npz(bytes, unpack_limit)?,
        Format::Csv | Format::Auto => parse_csv(text()?)?,
    };
    match parsed {
        Parsed::Trace(t) => Ok((Input::Trace(t), Vec::new())),
        Parsed::Particles(table) => {
            let table = rename(table, map, two_d)?;
            let ignored = table.ignored.clone();
            Ok((Input::Particles(table), ignored))
        }
    }
}

fn rename(parsed: ParsedTable, map: &ColumnMap, two_d: bool) -> Result<ParticleTable> {
    let ParsedTable { table, scalars } = parsed;
    let known = known_columns(two_d);
    for (ours, theirs) in &map.0 {
        if !known.contains(&ours.as_str()) {
            return Err(Error::Input(format!(
                "--columns maps '{}' to '{}', which is not a column of hompm's (known: {})",
                short(theirs),
                short(ours),
                known.join(", ")
            )));
        }
        if table.column(theirs).is_none() {
            return Err(Error::Input(format!(
                "--columns names '{}', which the file does not have as a column",
                short(theirs)
            )));
        }
    }
    // A single value under a column's name or a quantity's name (a 2D `u`
    // is the quantity of the columns u_x, u_y): never metadata.
    let names_a_quantity = |name: &str| {
        known.contains(&name) || quantity(name).is_some_and(|q| !q.columns(two_d).is_empty())
    };
    if let Some(s) = scalars.iter().find(|s| names_a_quantity(map.ours(s))) {
        return Err(Error::Input(format!(
            "'{}' is one number, not a column: hompm's {} is an array with a value per particle",
            short(s),
            map.ours(s)
        )));
    }
    let mut out = TableBuilder::default();
    for (key, value) in table.metadata {
        out.metadata(&key, value);
    }
    let mut ignored = Vec::new();
    for (name, values) in table.columns {
        let ours = map.ours(&name);
        if known.contains(&ours) {
            out.column(ours.to_string(), values)?;
        } else if let Some(problem) = misshapen(ours, two_d) {
            return Err(Error::Input(problem));
        } else {
            ignored.push(name);
        }
    }
    let mut out = out.finish().table;
    if out.columns.is_empty() {
        return Err(Error::Input(format!(
            "the file has none of hompm's columns ({}); map yours with --columns ours=theirs",
            known.join(", ")
        )));
    }
    if out.rows() == 0 {
        return Err(Error::Input("the file has no particles".into()));
    }
    out.ignored = ignored;
    derive_displacement(&mut out, two_d)?;
    Ok(out)
}

/// u = x − x0 where the file has positions but no displacement (or a
/// displacement that is exactly x − x0), so that a
/// code that writes only x (Karamelo's dumps) is compared in u, whose
/// scale is the motion's, not the domain's: x's tolerance, scaled by
/// max |x| ≈ L, cannot see a difference of 1e-9 of the displacement. The
/// subtraction rounds at ε·L, far below the tolerance of u for any motion
/// larger than 1e-6 L. Recorded in [`ParticleTable::derived`].
fn derive_displacement(t: &mut ParticleTable, two_d: bool) -> Result<()> {
    let axes: &[(&str, &str, &str)] = if two_d {
        &[("u_x", "x_x", "x0_x"), ("u_y", "x_y", "x0_y")]
    } else {
        &[("u", "x", "x0")]
    };
    for (u, x, x0) in axes {
        let (Some(xs), Some(x0s)) = (t.column(x), t.column(x0)) else {
            continue;
        };
        let values: Vec<f64> = xs.iter().zip(x0s).map(|(a, b)| a - b).collect();
        match t.column(u) {
            // A file's u that is its x − x0 bit for bit carries the same
            // rounding: it gets the same floor (Taichi's u, issue #36).
            Some(given) if given == values.as_slice() => {
                t.derived
                    .push(format!("{u} = {x} − {x0} (your {u}, bit for bit)"));
            }
            Some(_) => {}
            None => {
                t.columns.push((u.to_string(), values));
                t.derived.push(format!("{u} = {x} − {x0}"));
            }
        }
    }
    Ok(())
}

/// Why a column that is not one of hompm's must not be ignored: it is
/// one of hompm's quantities in another shape (issue #35's fuzz: a JSON
/// `volume` of [v, v] pairs became `volume_x`/`volume_y`, a 2D `u` of
/// single numbers stayed `u`, and both were dropped while the check agreed
/// on the rest). A component (`u_x`, `stress_xy`) of a quantity that has
/// none in this dimension, or one number per particle under the name of a
/// 2D vector or tensor of the physics (u, v, stress, F), is refused.
fn misshapen(name: &str, two_d: bool) -> Option<String> {
    const SUFFIXES: [&str; 6] = ["_xx", "_xy", "_yx", "_yy", "_x", "_y"];
    let dimension = if two_d { "2D" } else { "1D" };
    let shape = |width: usize| match width {
        1 => "one number per particle",
        2 => "an [x, y] pair per particle (columns _x, _y)",
        _ => "an [xx, xy, yx, yy] row per particle (columns _xx, _xy, _yx, _yy)",
    };
    let width_of = |base: &str| quantity(base).map(|q| q.columns(two_d).len());
    let component = SUFFIXES.iter().find_map(|suffix| {
        let base = name.strip_suffix(suffix)?;
        width_of(base).filter(|&w| w > 0).map(|w| (base, w))
    });
    if let Some((base, width)) = component {
        return Some(format!(
            "column '{}' is a component of '{base}', which hompm's {dimension} run has as {}; map it with --columns or write '{base}' in that shape",
            short(name),
            shape(width)
        ));
    }
    match width_of(name) {
        Some(width) if width > 1 && PHYSICAL_FIELDS.contains(&name) => Some(format!(
            "column '{name}' has one number per particle, but hompm's {dimension} '{name}' is {}",
            shape(width)
        )),
        _ => None,
    }
}

/// A number from a CSV cell or JSON value, finite, or an error naming where.
fn number(text: &str, row: usize, column: &str) -> Result<f64> {
    let v: f64 = text.trim().trim_matches('"').parse().map_err(|_| {
        Error::Input(format!(
            "row {row}, column '{}': '{}' is not a number",
            short(column),
            short(text.trim())
        ))
    })?;
    finite(v, row, column)
}

fn parse_csv(text: &str) -> Result<Parsed> {
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
                let key = k.trim().to_string();
                if metadata.contains_key(&key) {
                    return Err(Error::Input(format!(
                        "the comment line '# {}:' appears twice",
                        short(&key)
                    )));
                }
                metadata.insert(key, v.trim().to_string());
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
        return csv_trace(&header, &rows, metadata).map(Parsed::Trace);
    }
    let mut table = TableBuilder::default();
    for (k, v) in metadata {
        table.metadata(&k, v);
    }
    for (c, name) in header.iter().enumerate() {
        let values: Result<Vec<f64>> = rows
            .iter()
            .enumerate()
            .map(|(r, cells)| number(cells[c], r + 1, name))
            .collect();
        table.column(name.clone(), values?)?;
    }
    Ok(Parsed::Particles(table.finish()))
}

/// A whole number from a trace's `step` or `index` cell.
fn whole(text: &str, row: usize, column: &str, least: f64) -> Result<usize> {
    let v = number(text, row, column)?;
    if v < least || v.fract() != 0.0 || v >= u32::MAX as f64 {
        return Err(Error::Input(format!(
            "row {row}: {column} must be a whole number from {least} to {}, got {}",
            u32::MAX - 1,
            short(text.trim())
        )));
    }
    Ok(v as usize)
}

fn csv_trace(
    header: &[String],
    rows: &[Vec<&str>],
    metadata: BTreeMap<String, String>,
) -> Result<Trace> {
    let col = |name: &str| -> Result<usize> {
        let mut at = header.iter().enumerate().filter(|(_, h)| *h == name);
        match (at.next(), at.next()) {
            (Some((c, _)), None) => Ok(c),
            (Some(_), Some(_)) => Err(Error::Input(format!(
                "the column '{name}' appears twice"
            ))),
            _ => Err(Error::Input(format!(
                "a trace in CSV needs the columns step,time,equation,index,value; '{name}' is missing"
            ))),
        }
    };
    let (cs, ct, ce, ci, cv) = (
        col("step")?,
        col("time")?,
        col("equation")?,
        col("index")?,
        col("value")?,
    );
    if header.len() != 5 {
        return Err(Error::Input(format!(
            "a trace in CSV has the columns step,time,equation,index,value and no others; this one has {}",
            header.len()
        )));
    }
    let mut steps: BTreeMap<usize, TraceStep> = BTreeMap::new();
    for (r, cells) in rows.iter().enumerate() {
        let row = r + 1;
        let step = whole(cells[cs], row, "step", 1.0)?;
        let index = whole(cells[ci], row, "index", 0.0)?;
        let time = number(cells[ct], row, "time")?;
        let value = number(cells[cv], row, "value")?;
        let key = cells[ce].trim().trim_matches('"').to_string();
        if key.is_empty() {
            return Err(Error::Input(format!("row {row}: the equation is empty")));
        }
        let current = steps.entry(step).or_insert_with(|| TraceStep {
            step,
            time,
            equations: BTreeMap::new(),
        });
        if current.time != time {
            return Err(Error::Input(format!(
                "row {row}: step {step} has the time {time:e} here and {:e} before",
                current.time
            )));
        }
        let values = current.equations.entry(key.clone()).or_default();
        if index != values.len() {
            return Err(Error::Input(format!(
                "row {row}: equation {} at step {step} has index {index} where {} was next",
                short(&key),
                values.len()
            )));
        }
        values.push(value);
    }
    let mut version = TRACE_VERSION;
    if let Some(v) = metadata.get("version") {
        version = v
            .trim()
            .parse()
            .ok()
            .filter(|v| *v <= TRACE_VERSION)
            .ok_or_else(|| {
                Error::Input(format!(
                    "the trace has schema version {}; this hompm reads version {TRACE_VERSION}",
                    short(v)
                ))
            })?;
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
        version,
        header,
        steps: steps.into_values().collect(),
    })
}
