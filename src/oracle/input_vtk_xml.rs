//! # VTK particle files: the XML formats `.vtp` and `.vtu`
//!
//! The XML VTK formats (PolyData and UnstructuredGrid) are what ParaView,
//! cb-geo's mpm and most newer codes write. hompm reads the one `Piece`'s
//! `Points` and `PointData`, and names the columns as the legacy reader
//! does ([`super::input_vtk`]: `Points:0…2`, `name` or `name:j`). Each
//! data array may be
//!
//! - `format="ascii"`: numbers separated by white space;
//! - `format="binary"`: base64 of a byte-count header and the data (the
//!   header encoded with the data or on its own, both as VTK writes them);
//! - `format="appended"` with an `offset` into the `AppendedData` section,
//!   `encoding="raw"` or `"base64"`;
//!
//! in the file's `byte_order`, with a `header_type` of UInt32 (the default)
//! or UInt64, uncompressed or zlib-compressed in blocks
//! (`compressor="vtkZLibDataCompressor"`). LZ4 and LZMA, several pieces,
//! text arrays and a count of values other than points × components are
//! refused, one sentence each. The XML is quick-xml's, base64 the base64
//! crate's, zlib flate2's; the VTK layout is read here (docs/oracle.md,
//! "Formats").
//!
//! Items: none public; `oracle::input::parse_input_as` calls `parse_xml`.

use super::binary::Scalar;
use super::input_vtk::{add_columns, vtk_columns, vtk_type};
use super::table::{finite, short, Parsed, TableBuilder};
use crate::error::{Error, Result};
use quick_xml::events::{BytesStart, Event};

fn bad(what: impl std::fmt::Display) -> Error {
    Error::Input(format!("VTK XML file: {what}"))
}

/// Where a data array stands in the piece.
#[derive(Debug, Clone, Copy, PartialEq)]
enum Place {
    Points,
    PointData,
    Elsewhere,
}

/// A `DataArray` element as read.
#[derive(Debug)]
struct DataArray {
    name: String,
    ty: String,
    components: usize,
    format: String,
    offset: Option<usize>,
    text: String,
    place: Place,
}

/// The `VTKFile` element's settings.
struct File {
    big_endian: bool,
    /// Bytes of each header integer (UInt32: 4, UInt64: 8).
    header_size: usize,
    compressed: bool,
}

fn attributes(e: &BytesStart) -> Result<Vec<(String, String)>> {
    let mut out = Vec::new();
    for a in e.attributes() {
        let a = a.map_err(|err| bad(format!("an attribute: {err}")))?;
        let key = String::from_utf8_lossy(a.key.as_ref()).into_owned();
        let value = a
            .unescape_value()
            .map_err(|err| bad(format!("attribute {key}: {err}")))?
            .into_owned();
        out.push((key, value));
    }
    Ok(out)
}

fn attribute<'a>(attrs: &'a [(String, String)], key: &str) -> Option<&'a str> {
    attrs
        .iter()
        .find(|(k, _)| k == key)
        .map(|(_, v)| v.as_str())
}

fn whole(attrs: &[(String, String)], key: &str, element: &str) -> Result<Option<usize>> {
    attribute(attrs, key)
        .map(|v| {
            v.trim()
                .parse()
                .map_err(|_| bad(format!("{element} {key}='{}' is not a count", short(v))))
        })
        .transpose()
}

/// The `DataArray` of element `e`, standing in `place`.
fn data_array(e: &BytesStart, place: Place) -> Result<DataArray> {
    let attrs = attributes(e)?;
    Ok(DataArray {
        name: attribute(&attrs, "Name").unwrap_or("").to_string(),
        ty: attribute(&attrs, "type")
            .ok_or_else(|| bad("a DataArray without a type"))?
            .to_string(),
        components: whole(&attrs, "NumberOfComponents", "DataArray")?.unwrap_or(1),
        format: attribute(&attrs, "format").unwrap_or("ascii").to_string(),
        offset: whole(&attrs, "offset", "DataArray")?,
        text: String::new(),
        place,
    })
}

/// Decodes base64 text that may be several padded streams one after the
/// other (VTK encodes a header and its data separately).
fn base64_segments(text: &[u8]) -> Result<Vec<u8>> {
    use base64::Engine;
    let clean: Vec<u8> = text
        .iter()
        .copied()
        .filter(|b| !b.is_ascii_whitespace())
        .collect();
    if !clean.len().is_multiple_of(4) {
        return Err(bad("base64 data whose length is not a multiple of 4"));
    }
    let mut out = Vec::new();
    let mut start = 0;
    for (k, group) in clean.chunks(4).enumerate() {
        if group.contains(&b'=') || (k + 1) * 4 == clean.len() {
            base64::engine::general_purpose::STANDARD
                .decode_vec(&clean[start..(k + 1) * 4], &mut out)
                .map_err(|e| bad(format!("base64 data: {e}")))?;
            start = (k + 1) * 4;
        }
    }
    Ok(out)
}

impl File {
    fn integer(&self, bytes: &[u8], at: usize) -> Result<usize> {
        let chunk = bytes
            .get(at..at + self.header_size)
            .ok_or_else(|| bad("a data block ends inside its header"))?;
        let kind = Scalar {
            kind: super::binary::Kind::Unsigned,
            big_endian: self.big_endian,
            size: self.header_size,
        };
        let v = kind.read(chunk).map_err(bad)?;
        Ok(v as usize)
    }

    /// The block at `at` of `bytes` (header and data, compressed or
    /// not): its data and the bytes it took.
    fn block(&self, bytes: &[u8], at: usize, budget: &mut u64) -> Result<(Vec<u8>, usize)> {
        let h = self.header_size;
        if !self.compressed {
            let n = self.integer(bytes, at)?;
            let data = bytes
                .get(at + h..(at + h).saturating_add(n))
                .ok_or_else(|| bad(format!("a data block of {n} bytes ends early")))?;
            return Ok((data.to_vec(), h + n));
        }
        let blocks = self.integer(bytes, at)?;
        let size = self.integer(bytes, at + h)?;
        let last = self.integer(bytes, at + 2 * h)?;
        let header = h.saturating_mul(blocks.saturating_add(3));
        let mut out = Vec::new();
        let mut read = at + header;
        for b in 0..blocks {
            let compressed = self.integer(bytes, at + (3 + b) * h)?;
            let expected = if b + 1 == blocks && last != 0 {
                last
            } else {
                size
            };
            if expected as u64 > *budget {
                return Err(bad(
                    "compressed data unpack beyond the memory limit (raise --max-memory)",
                ));
            }
            *budget -= expected as u64;
            let input = bytes
                .get(read..read.saturating_add(compressed))
                .ok_or_else(|| bad("a compressed block ends early"))?;
            let before = out.len();
            use std::io::Read;
            flate2::read::ZlibDecoder::new(input)
                .take(expected as u64 + 1)
                .read_to_end(&mut out)
                .map_err(|e| bad(format!("a zlib block: {e}")))?;
            if out.len() - before != expected {
                return Err(bad(format!(
                    "a zlib block unpacks to {} bytes, its header says {expected}",
                    out.len() - before
                )));
            }
            read += compressed;
        }
        Ok((out, read - at))
    }

    /// The bytes of a base64 data array (inline, or cut from the
    /// appended section).
    fn base64_block(&self, text: &[u8], budget: &mut u64) -> Result<Vec<u8>> {
        use base64::Engine;
        let clean: Vec<u8> = text
            .iter()
            .copied()
            .filter(|b| !b.is_ascii_whitespace())
            .collect();
        let bytes = if self.compressed {
            // The header is its own stream: its first integer gives its
            // length.
            let chars = |n: usize| n.div_ceil(3) * 4;
            let engine = base64::engine::general_purpose::STANDARD;
            let first = engine
                .decode(clean.get(..chars(self.header_size)).unwrap_or(&clean))
                .map_err(|e| bad(format!("base64 header: {e}")))?;
            let blocks = self.integer(&first, 0)?;
            let header_chars = chars(self.header_size.saturating_mul(blocks.saturating_add(3)));
            let (head, rest) = clean.split_at(header_chars.min(clean.len()));
            let mut bytes = engine
                .decode(head)
                .map_err(|e| bad(format!("base64 header: {e}")))?;
            bytes.truncate(self.header_size * (blocks + 3));
            bytes.extend(base64_segments(rest)?);
            bytes
        } else {
            base64_segments(&clean)?
        };
        let (data, used) = self.block(&bytes, 0, budget)?;
        if used != bytes.len() {
            return Err(bad(format!(
                "a base64 data array has {} bytes after its data",
                bytes.len() - used
            )));
        }
        Ok(data)
    }
}

/// Reads an XML VTK file (`.vtp` or `.vtu`); decompressed data may take
/// at most `budget` bytes.
pub(crate) fn parse_xml(bytes: &[u8], mut budget: u64) -> Result<Parsed> {
    let appended_at = find(bytes, b"<AppendedData");
    let xml = &bytes[..appended_at.unwrap_or(bytes.len())];
    let mut reader = quick_xml::Reader::from_reader(xml);
    let mut stack: Vec<String> = Vec::new();
    let mut file: Option<File> = None;
    let (mut pieces, mut points) = (0usize, None);
    let mut arrays: Vec<DataArray> = Vec::new();
    let mut open: Option<DataArray> = None;
    loop {
        let event = reader
            .read_event()
            .map_err(|e| bad(format!("at byte {}: {e}", reader.buffer_position())))?;
        let (e, empty) = match &event {
            Event::Start(e) => (e, false),
            Event::Empty(e) => (e, true),
            Event::End(end) => {
                if end.name().as_ref() == b"DataArray" {
                    if let Some(a) = open.take() {
                        arrays.push(a);
                    }
                }
                stack.pop();
                continue;
            }
            // Text directly inside a DataArray is its data; text anywhere
            // else (an InformationKey's values) is not read.
            Event::Text(t) if stack.last().map(String::as_str) == Some("DataArray") => {
                if let Some(a) = open.as_mut() {
                    a.text.push_str(
                        std::str::from_utf8(t).map_err(|_| bad("text that is not UTF-8"))?,
                    );
                }
                continue;
            }
            Event::Eof => break,
            Event::GeneralRef(_) | Event::CData(_)
                if stack.last().map(String::as_str) == Some("DataArray") =>
            {
                return Err(bad("an entity or CDATA inside a DataArray"))
            }
            _ => continue,
        };
        let name = String::from_utf8_lossy(e.name().as_ref()).into_owned();
        let parent = stack.last().map(String::as_str);
        match (name.as_str(), parent) {
            ("VTKFile", None) => {
                let attrs = attributes(e)?;
                match attribute(&attrs, "type") {
                    Some("PolyData" | "UnstructuredGrid") => {}
                    other => {
                        return Err(bad(format!(
                            "type '{}': hompm reads particles as PolyData (.vtp) or UnstructuredGrid (.vtu)",
                            short(other.unwrap_or(""))
                        )))
                    }
                }
                file = Some(File {
                    big_endian: match attribute(&attrs, "byte_order") {
                        Some("LittleEndian") | None => false,
                        Some("BigEndian") => true,
                        Some(o) => return Err(bad(format!("byte_order '{}'", short(o)))),
                    },
                    header_size: match attribute(&attrs, "header_type") {
                        Some("UInt32") | None => 4,
                        Some("UInt64") => 8,
                        Some(o) => return Err(bad(format!("header_type '{}'", short(o)))),
                    },
                    compressed: match attribute(&attrs, "compressor") {
                        None => false,
                        Some("vtkZLibDataCompressor") => true,
                        Some(o) => {
                            return Err(bad(format!(
                                "compressor '{}': hompm reads zlib (vtkZLibDataCompressor) or none",
                                short(o)
                            )))
                        }
                    },
                });
            }
            ("Piece", _) => {
                pieces += 1;
                if pieces > 1 {
                    return Err(bad("more than one Piece; write the particles as one piece"));
                }
                points = whole(&attributes(e)?, "NumberOfPoints", "Piece")?;
            }
            ("DataArray", Some(p)) => {
                let place = match p {
                    "Points" => Place::Points,
                    "PointData" => Place::PointData,
                    _ => Place::Elsewhere,
                };
                let array = data_array(e, place)?;
                if empty {
                    arrays.push(array);
                } else {
                    open = Some(array);
                }
            }
            _ => {}
        }
        if !empty {
            stack.push(name);
        }
    }
    let file = file.ok_or_else(|| bad("no VTKFile element"))?;
    let points = points.ok_or_else(|| bad("no Piece with NumberOfPoints"))?;
    let appended = appended_at
        .map(|at| appended_section(bytes, at))
        .transpose()?;
    let mut offsets: Vec<usize> = arrays.iter().filter_map(|a| a.offset).collect();
    offsets.sort_unstable();
    let mut table = TableBuilder::default();
    if !arrays.iter().any(|a| a.place == Place::Points) {
        return Err(bad("the Piece has no Points"));
    }
    for array in arrays.iter().filter(|a| a.place != Place::Elsewhere) {
        let label = if array.place == Place::Points {
            "Points"
        } else {
            &array.name
        };
        if label.is_empty() {
            return Err(bad("a PointData array without a Name"));
        }
        let scalar = vtk_type(&array.ty, file.big_endian).map_err(bad)?;
        let count = points.saturating_mul(array.components);
        let values: Vec<f64> = match array.format.as_str() {
            "ascii" => array
                .text
                .split_whitespace()
                .enumerate()
                .map(|(k, t)| {
                    let v = t
                        .parse::<f64>()
                        .map_err(|_| bad(format!("{label}: '{}' is not a number", short(t))))?;
                    scalar
                        .of_text(finite(v, k / array.components.max(1) + 1, label)?)
                        .map_err(|e| bad(format!("{label} ({}): {e}", array.ty)))
                })
                .collect::<Result<_>>()?,
            "binary" => numbers(
                &file.base64_block(array.text.as_bytes(), &mut budget)?,
                scalar,
                label,
            )?,
            "appended" => {
                let (encoding, data) = appended.as_ref().ok_or_else(|| {
                    bad(format!("{label} is appended, but there is no AppendedData"))
                })?;
                let offset = array
                    .offset
                    .ok_or_else(|| bad(format!("{label} is appended without an offset")))?;
                let bytes = if *encoding == "raw" {
                    file.block(data, offset, &mut budget)?.0
                } else {
                    let end = offsets
                        .iter()
                        .find(|&&o| o > offset)
                        .copied()
                        .unwrap_or(data.len());
                    let text = data.get(offset..end).ok_or_else(|| {
                        bad(format!("{label}'s offset is beyond the AppendedData"))
                    })?;
                    file.base64_block(text, &mut budget)?
                };
                numbers(&bytes, scalar, label)?
            }
            other => return Err(bad(format!("{label}: format '{}'", short(other)))),
        };
        if values.len() != count {
            return Err(bad(format!(
                "{label} has {} values for {points} points × {} components",
                values.len(),
                array.components
            )));
        }
        for (k, v) in values.iter().enumerate() {
            finite(*v, k / array.components.max(1) + 1, label)?;
        }
        add_columns(&mut table, vtk_columns(label, array.components), &values)?;
    }
    Ok(Parsed::Particles(table.finish()))
}

/// The numbers of a decoded data array.
fn numbers(bytes: &[u8], scalar: Scalar, label: &str) -> Result<Vec<f64>> {
    if !bytes.len().is_multiple_of(scalar.size) {
        return Err(bad(format!(
            "{label}: {} bytes are not whole values",
            bytes.len()
        )));
    }
    bytes
        .chunks_exact(scalar.size)
        .map(|c| scalar.read(c).map_err(|e| bad(format!("{label}: {e}"))))
        .collect()
}

/// The `AppendedData` section starting at `at`: its encoding and its data
/// (after the `_`, up to the closing tag, which must end the file but for
/// `</VTKFile>`).
fn appended_section(bytes: &[u8], at: usize) -> Result<(String, &[u8])> {
    let tag_end =
        at + find(&bytes[at..], b">").ok_or_else(|| bad("an unclosed AppendedData tag"))?;
    let tag = std::str::from_utf8(&bytes[at..tag_end])
        .map_err(|_| bad("an AppendedData tag that is not text"))?;
    let encoding = if tag.contains("encoding=\"raw\"") {
        "raw"
    } else if tag.contains("encoding=\"base64\"") {
        "base64"
    } else {
        return Err(bad("AppendedData needs encoding=\"raw\" or \"base64\""));
    };
    let mut start = tag_end + 1;
    while bytes.get(start).is_some_and(u8::is_ascii_whitespace) {
        start += 1;
    }
    if bytes.get(start) != Some(&b'_') {
        return Err(bad("AppendedData does not start with '_'"));
    }
    let close = rfind(bytes, b"</AppendedData>")
        .filter(|&c| c > start)
        .ok_or_else(|| bad("AppendedData is not closed"))?;
    let tail = std::str::from_utf8(&bytes[close..]).map_err(|_| bad("bytes after AppendedData"))?;
    let tail: String = tail.split_whitespace().collect();
    if tail != "</AppendedData></VTKFile>" {
        return Err(bad("something other than </VTKFile> after AppendedData"));
    }
    let mut end = close;
    if encoding == "base64" {
        while end > start + 1 && bytes[end - 1].is_ascii_whitespace() {
            end -= 1;
        }
    }
    Ok((encoding.to_string(), &bytes[start + 1..end]))
}

fn find(hay: &[u8], needle: &[u8]) -> Option<usize> {
    hay.windows(needle.len()).position(|w| w == needle)
}

fn rfind(hay: &[u8], needle: &[u8]) -> Option<usize> {
    hay.windows(needle.len()).rposition(|w| w == needle)
}
