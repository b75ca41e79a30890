//! # VTK particle files: the legacy format
//!
//! NairnMPM, cb-geo's mpm, geomechanics/mpm and many other MPM codes write
//! their particles for ParaView as VTK files: legacy `.vtk` (this module)
//! or XML `.vtp`/`.vtu` ([`super::input_vtk_xml`]). hompm reads the
//! points and the point data of one POLYDATA or UNSTRUCTURED_GRID data
//! set, ASCII or BINARY (big-endian, as the format prescribes), versions
//! 2.0 to 5.1 (5.1's cells as OFFSETS and CONNECTIVITY):
//!
//! - the points are the columns `Points:0`, `Points:1`, `Points:2`;
//! - a point-data array with one component is a column of its name; one
//!   with k > 1 (VECTORS, NORMALS, TENSORS, a FIELD array) is `name:0` …
//!   `name:k−1`, ParaView's spelling. A tensor is row-major: `name:0` is
//!   xx, `:1` xy, `:3` yx, `:4` yy.
//!
//! Cells, cell data and LOOKUP_TABLE sections are read to their end and
//! not used; a one-value FIELD array of the data set (ParaView's TIME,
//! CYCLE) is metadata. Anything else is refused, one sentence naming the
//! line (docs/oracle.md, "Formats"). No maintained Rust crate reads the
//! format (vtkio's release is built on nom 3 of 2017; its 0.7 has been a
//! release candidate since 2023), so it is read here.
//!
//! Items: none public; `oracle::input::parse_input_as` calls
//! `parse_legacy`.

use super::binary::{Kind, Scalar};
use super::table::{finite, short, Parsed, TableBuilder};
use crate::error::{Error, Result};

/// The first bytes of every legacy VTK file.
pub(crate) const LEGACY_MAGIC: &[u8] = b"# vtk DataFile Version";

/// A VTK data type name as a [`Scalar`] (`big_endian` for the legacy
/// binary format; the XML reader sets its own).
pub(crate) fn vtk_type(name: &str, big_endian: bool) -> std::result::Result<Scalar, String> {
    let (kind, size) = match name {
        "float" | "Float32" => (Kind::Float, 4),
        "double" | "Float64" => (Kind::Float, 8),
        "char" | "Int8" => (Kind::Signed, 1),
        "unsigned_char" | "UInt8" => (Kind::Unsigned, 1),
        "short" | "Int16" => (Kind::Signed, 2),
        "unsigned_short" | "UInt16" => (Kind::Unsigned, 2),
        "int" | "Int32" => (Kind::Signed, 4),
        "unsigned_int" | "UInt32" => (Kind::Unsigned, 4),
        "long" | "vtktypeint64" | "vtkIdType" | "Int64" => (Kind::Signed, 8),
        "unsigned_long" | "vtktypeuint64" | "UInt64" => (Kind::Unsigned, 8),
        other => {
            return Err(format!(
                "the VTK type '{}' is not a number type hompm reads",
                short(other)
            ))
        }
    };
    Ok(Scalar {
        kind,
        big_endian,
        size,
    })
}

/// The column names of a VTK array of `components` per point.
pub(crate) fn vtk_columns(name: &str, components: usize) -> Vec<String> {
    if components == 1 {
        vec![name.to_string()]
    } else {
        (0..components).map(|j| format!("{name}:{j}")).collect()
    }
}

/// Splits `values` (point after point) into the columns of `names` and
/// adds them.
pub(crate) fn add_columns(
    table: &mut TableBuilder,
    names: Vec<String>,
    values: &[f64],
) -> Result<()> {
    let k = names.len();
    for (j, name) in names.into_iter().enumerate() {
        let column: Vec<f64> = values.iter().skip(j).step_by(k).copied().collect();
        table.column(name, column)?;
    }
    Ok(())
}

/// A position in the file, with its line number for messages.
struct Cursor<'a> {
    bytes: &'a [u8],
    at: usize,
    line: usize,
    binary: bool,
}

impl<'a> Cursor<'a> {
    fn bad(&self, what: impl std::fmt::Display) -> Error {
        Error::Input(format!("VTK file, line {}: {what}", self.line))
    }

    /// The next line (blank lines skipped when `skip_blank`), without its
    /// line end; `None` at the end of the file.
    fn raw_line(&mut self, skip_blank: bool) -> Result<Option<&'a str>> {
        loop {
            if self.at >= self.bytes.len() {
                return Ok(None);
            }
            let rest = &self.bytes[self.at..];
            let end = rest.iter().position(|&b| b == b'\n').unwrap_or(rest.len());
            self.at += (end + 1).min(rest.len());
            self.line += 1;
            let text = std::str::from_utf8(&rest[..end])
                .map_err(|_| self.bad("a line that is not text"))?
                .trim_end_matches('\r');
            if !skip_blank || !text.trim().is_empty() {
                return Ok(Some(text));
            }
        }
    }

    fn keyword_line(&mut self) -> Result<Option<Vec<&'a str>>> {
        Ok(self.raw_line(true)?.map(|l| l.split_whitespace().collect()))
    }

    /// `count` values of type `ty`: whitespace-separated text in an ASCII
    /// file, big-endian bytes (then a line end) in a binary one.
    fn values(&mut self, count: usize, ty: &str, what: &str) -> Result<Vec<f64>> {
        let scalar = vtk_type(ty, true).map_err(|e| self.bad(e))?;
        let mut out = Vec::with_capacity(count.min(self.bytes.len()));
        if self.binary {
            let length = count
                .checked_mul(scalar.size)
                .filter(|&n| n <= self.bytes.len() - self.at)
                .ok_or_else(|| {
                    self.bad(format!("{what}: the file ends inside its {count} values"))
                })?;
            for chunk in self.bytes[self.at..self.at + length].chunks_exact(scalar.size) {
                let v = scalar
                    .read(chunk)
                    .map_err(|e| self.bad(format!("{what}: {e}")))?;
                out.push(finite(v, out.len() + 1, what)?);
            }
            self.at += length;
            if self.bytes.get(self.at) == Some(&b'\n') {
                self.at += 1;
            }
            return Ok(out);
        }
        while out.len() < count {
            let Some(line) = self.raw_line(true)? else {
                return Err(self.bad(format!(
                    "{what}: the file ends after {} of {count} values",
                    out.len()
                )));
            };
            for token in line.split_whitespace() {
                if out.len() == count {
                    return Err(self.bad(format!("{what}: more than {count} values")));
                }
                let v: f64 = token
                    .parse()
                    .map_err(|_| self.bad(format!("{what}: '{}' is not a number", short(token))))?;
                let v = scalar
                    .of_text(finite(v, out.len() + 1, what)?)
                    .map_err(|e| self.bad(format!("{what} ({ty}): {e}")))?;
                out.push(v);
            }
        }
        Ok(out)
    }
}

fn point_count(cursor: &Cursor, points: Option<usize>, key: &str) -> Result<usize> {
    points.ok_or_else(|| cursor.bad(format!("{key} before POINTS")))
}

fn number(cursor: &Cursor, words: &[&str], at: usize) -> Result<usize> {
    words
        .get(at)
        .and_then(|w| w.parse().ok())
        .ok_or_else(|| cursor.bad(format!("'{}' needs a count", words.join(" "))))
}

fn word<'a>(cursor: &Cursor, words: &[&'a str], at: usize) -> Result<&'a str> {
    words
        .get(at)
        .copied()
        .ok_or_else(|| cursor.bad(format!("'{}' is missing a word", words.join(" "))))
}

/// Which attribute block the arrays belong to.
#[derive(PartialEq, Clone, Copy)]
enum Block {
    DataSet,
    Points,
    /// Cell data of this many cells: read and not used.
    Cells(usize),
}

/// Reads a legacy VTK file.
pub(crate) fn parse_legacy(bytes: &[u8]) -> Result<Parsed> {
    let mut c = Cursor {
        bytes,
        at: 0,
        line: 0,
        binary: false,
    };
    let first = c.raw_line(false)?.unwrap_or_default();
    let version = first
        .strip_prefix("# vtk DataFile Version ")
        .ok_or_else(|| c.bad("not a legacy VTK file (no '# vtk DataFile Version')"))?
        .trim();
    let modern = match version
        .split_once('.')
        .map(|(a, b)| (a.parse::<u32>(), b.parse::<u32>()))
    {
        Some((Ok(major @ 2..=5), Ok(minor))) => (major, minor) >= (5, 1),
        _ => {
            return Err(c.bad(format!(
                "version '{}'; hompm reads 2.0 to 5.1",
                short(version)
            )))
        }
    };
    c.raw_line(false)?.ok_or_else(|| c.bad("no title line"))?;
    c.binary = match c.raw_line(true)?.map(str::trim) {
        Some("ASCII") => false,
        Some("BINARY") => true,
        other => {
            return Err(c.bad(format!(
                "'{}' where ASCII or BINARY was expected",
                short(other.unwrap_or(""))
            )))
        }
    };
    let mut table = TableBuilder::default();
    let mut points: Option<usize> = None;
    let mut block = Block::DataSet;
    let mut dataset = false;
    while let Some(words) = c.keyword_line()? {
        let key = words[0];
        match key {
            "DATASET" => match words.get(1).copied() {
                Some("POLYDATA" | "UNSTRUCTURED_GRID") if !dataset => dataset = true,
                Some("POLYDATA" | "UNSTRUCTURED_GRID") => return Err(c.bad("a second DATASET")),
                other => {
                    return Err(c.bad(format!(
                        "DATASET {}: hompm reads particles as POLYDATA or UNSTRUCTURED_GRID",
                        other.unwrap_or("")
                    )))
                }
            },
            "POINTS" if points.is_none() && dataset => {
                let n = number(&c, &words, 1)?;
                let values = c.values(n.saturating_mul(3), word(&c, &words, 2)?, "POINTS")?;
                add_columns(&mut table, vtk_columns("Points", 3), &values)?;
                points = Some(n);
            }
            "POINTS" => return Err(c.bad("POINTS twice, or before DATASET")),
            "VERTICES" | "LINES" | "POLYGONS" | "TRIANGLE_STRIPS" | "CELLS" => {
                let (rows, size) = (number(&c, &words, 1)?, number(&c, &words, 2)?);
                if modern {
                    for (part, count) in [("OFFSETS", rows), ("CONNECTIVITY", size)] {
                        let header = c.keyword_line()?.unwrap_or_default();
                        if header.first() != Some(&part) {
                            return Err(c.bad(format!("{key} of version 5.1 needs {part}")));
                        }
                        c.values(count, word(&c, &header, 1)?, part)?;
                    }
                } else {
                    c.values(size, "int", key)?;
                }
            }
            "CELL_TYPES" => {
                c.values(number(&c, &words, 1)?, "int", key)?;
            }
            "POINT_DATA" => {
                if number(&c, &words, 1)? != point_count(&c, points, key)? {
                    return Err(c.bad("POINT_DATA counts other points than POINTS"));
                }
                block = Block::Points;
            }
            "CELL_DATA" => block = Block::Cells(number(&c, &words, 1)?),
            "METADATA" => {
                // Information keys, to the next blank line.
                while c.raw_line(false)?.is_some_and(|l| !l.trim().is_empty()) {}
            }
            "LOOKUP_TABLE" => {
                let size = number(&c, &words, 2)?;
                // RGBA entries: bytes in a binary file, fractions in text.
                let ty = if c.binary { "unsigned_char" } else { "float" };
                c.values(size.saturating_mul(4), ty, key)?;
            }
            "SCALARS" | "VECTORS" | "NORMALS" | "TENSORS" | "TEXTURE_COORDINATES" => {
                let name = word(&c, &words, 1)?;
                let (components, ty) = match key {
                    "SCALARS" => (words.get(3).map_or(Ok(1), |_| number(&c, &words, 3))?, word(&c, &words, 2)?),
                    "TEXTURE_COORDINATES" => (number(&c, &words, 2)?, word(&c, &words, 3)?),
                    "TENSORS" => (9, word(&c, &words, 2)?),
                    _ => (3, word(&c, &words, 2)?),
                };
                if key == "SCALARS" {
                    // LOOKUP_TABLE is required by the format, but some
                    // writers leave it out.
                    let save = (c.at, c.line);
                    match c.keyword_line()? {
                        Some(w) if w.first() == Some(&"LOOKUP_TABLE") => {}
                        _ => (c.at, c.line) = save,
                    }
                }
                let rows = match block {
                    Block::Points => point_count(&c, points, key)?,
                    Block::Cells(m) => m,
                    Block::DataSet => {
                        return Err(c.bad(format!("{key} outside POINT_DATA or CELL_DATA")))
                    }
                };
                let values = c.values(rows.saturating_mul(components), ty, name)?;
                if block == Block::Points {
                    add_columns(&mut table, vtk_columns(name, components), &values)?;
                }
            }
            "FIELD" => {
                for _ in 0..number(&c, &words, 2)? {
                    let array = c.keyword_line()?.unwrap_or_default();
                    let name = word(&c, &array, 0)?;
                    let (components, tuples) = (number(&c, &array, 1)?, number(&c, &array, 2)?);
                    let values = c.values(components.saturating_mul(tuples), word(&c, &array, 3)?, name)?;
                    match block {
                        Block::Points if tuples == point_count(&c, points, key)? => {
                            add_columns(&mut table, vtk_columns(name, components), &values)?;
                        }
                        Block::DataSet if values.len() == 1 => {
                            table.scalar(name);
                            table.metadata(name, values[0].to_string());
                        }
                        Block::Points => {
                            return Err(c.bad(format!(
                                "FIELD array {name} has {tuples} tuples for {} points",
                                point_count(&c, points, key)?
                            )))
                        }
                        _ => {}
                    }
                }
            }
            other => {
                return Err(c.bad(format!(
                    "'{}' is not a section hompm reads (COLOR_SCALARS, TENSORS6 and structured data sets are not)",
                    short(other)
                )))
            }
        }
    }
    if points.is_none() {
        return Err(c.bad("the file ends without POINTS"));
    }
    Ok(Parsed::Particles(table.finish()))
}
