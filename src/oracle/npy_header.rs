//! # The header of a NumPy `.npy` file
//!
//! After the magic `\x93NUMPY`, a version (1.0, 2.0 or 3.0) and a header
//! length, an `.npy` file holds a Python dict literal of exactly three
//! keys: `descr` (a type string such as `'<f8'`, or a list of named
//! fields), `fortran_order` and `shape` (numpy.lib.format). This module
//! reads that header strictly, with a recursive-descent reader of the part
//! of Python's literal syntax NumPy writes: strings without escapes, whole
//! numbers, True and False, tuples, lists and dicts. A key NumPy does not
//! write, a key given twice, a type hompm cannot hold exactly, or a field
//! without a name is one sentence and exit 2. No equation of the seeds
//! lives here; it is the strict reading of issue #36.
//!
//! Items: none public; `oracle::input_npy` calls `header`.

use super::binary::{Kind, Scalar};
use super::table::short;
use crate::error::{Error, Result};

/// The first bytes of every `.npy` file.
pub(crate) const NPY_MAGIC: &[u8] = b"\x93NUMPY";

fn bad(what: String) -> Error {
    Error::Input(what)
}

// ---- the header: a Python literal ---------------------------------------

/// The part of Python's literal syntax a `.npy` header uses.
#[derive(Debug, Clone, PartialEq)]
enum Literal {
    Str(String),
    Bool(bool),
    Int(u64),
    /// A tuple or a list.
    Seq(Vec<Literal>),
    Dict(Vec<(String, Literal)>),
}

/// A recursive-descent reader of [`Literal`]s over the header's bytes.
struct LiteralReader<'a> {
    text: &'a [u8],
    at: usize,
}

impl LiteralReader<'_> {
    fn skip_space(&mut self) {
        while self.text.get(self.at).is_some_and(u8::is_ascii_whitespace) {
            self.at += 1;
        }
    }

    fn peek(&mut self) -> Option<u8> {
        self.skip_space();
        self.text.get(self.at).copied()
    }

    fn expect(&mut self, byte: u8) -> Result<()> {
        if self.peek() == Some(byte) {
            self.at += 1;
            Ok(())
        } else {
            Err(self.unexpected(&format!("'{}'", byte as char)))
        }
    }

    fn unexpected(&self, wanted: &str) -> Error {
        let found = self
            .text
            .get(self.at)
            .map_or("the end".to_string(), |b| format!("'{}'", b.escape_ascii()));
        bad(format!(
            ".npy header, byte {}: {found} where {wanted} was expected",
            self.at
        ))
    }

    /// Items up to `close`, separated by commas, a trailing comma allowed.
    fn sequence(&mut self, close: u8) -> Result<Vec<Literal>> {
        let mut items = Vec::new();
        loop {
            if self.peek() == Some(close) {
                self.at += 1;
                return Ok(items);
            }
            items.push(self.value()?);
            match self.peek() {
                Some(b',') => self.at += 1,
                Some(c) if c == close => {}
                _ => return Err(self.unexpected(&format!("',' or '{}'", close as char))),
            }
        }
    }

    fn value(&mut self) -> Result<Literal> {
        match self.peek() {
            Some(q @ (b'\'' | b'"')) => {
                self.at += 1;
                let start = self.at;
                while let Some(&c) = self.text.get(self.at) {
                    if c == q {
                        let s = std::str::from_utf8(&self.text[start..self.at])
                            .map_err(|_| bad(".npy header: a string is not UTF-8".into()))?;
                        self.at += 1;
                        return Ok(Literal::Str(s.to_string()));
                    }
                    if c == b'\\' {
                        return Err(bad(
                            ".npy header: a string with a backslash escape; NumPy writes none"
                                .into(),
                        ));
                    }
                    self.at += 1;
                }
                Err(self.unexpected("the string's closing quote"))
            }
            Some(b'(') => {
                self.at += 1;
                self.sequence(b')').map(Literal::Seq)
            }
            Some(b'[') => {
                self.at += 1;
                self.sequence(b']').map(Literal::Seq)
            }
            Some(b'{') => {
                self.at += 1;
                let mut entries: Vec<(String, Literal)> = Vec::new();
                loop {
                    if self.peek() == Some(b'}') {
                        self.at += 1;
                        return Ok(Literal::Dict(entries));
                    }
                    let Literal::Str(key) = self.value()? else {
                        return Err(bad(".npy header: a dict key that is not a string".into()));
                    };
                    self.expect(b':')?;
                    let value = self.value()?;
                    if entries.iter().any(|(k, _)| *k == key) {
                        return Err(bad(format!(
                            ".npy header: the key '{}' appears twice",
                            short(&key)
                        )));
                    }
                    entries.push((key, value));
                    match self.peek() {
                        Some(b',') => self.at += 1,
                        Some(b'}') => {}
                        _ => return Err(self.unexpected("',' or '}'")),
                    }
                }
            }
            Some(b'0'..=b'9') => {
                let start = self.at;
                while self.text.get(self.at).is_some_and(u8::is_ascii_digit) {
                    self.at += 1;
                }
                let digits = std::str::from_utf8(&self.text[start..self.at]).unwrap_or("");
                digits
                    .parse()
                    .map(Literal::Int)
                    .map_err(|_| bad(format!(".npy header: the number {digits} is too large")))
            }
            _ => {
                for (word, v) in [("True", true), ("False", false)] {
                    if self.text[self.at..].starts_with(word.as_bytes()) {
                        self.at += word.len();
                        return Ok(Literal::Bool(v));
                    }
                }
                Err(self.unexpected("a string, a number, True, False, a tuple, a list or a dict"))
            }
        }
    }
}

// ---- types ----------------------------------------------------------------

/// A `descr` string such as `<f8` as a [`Scalar`].
fn scalar_of(descr: &str) -> Result<Scalar> {
    let refuse = |why: &str| {
        bad(format!(
            "the NumPy type '{}' {why}; hompm reads float32/float64 and integers (save with .astype(np.float64))",
            short(descr)
        ))
    };
    let bytes = descr.as_bytes();
    let (order, kind, count) = match bytes {
        [o, k, rest @ ..] if !rest.is_empty() => (*o, *k, rest),
        _ => return Err(refuse("is not a type string")),
    };
    let count: usize = std::str::from_utf8(count)
        .ok()
        .and_then(|c| c.parse().ok())
        .ok_or_else(|| refuse("has no size"))?;
    let (kind, size) = match (kind, count) {
        (b'f', 4 | 8) => (Kind::Float, count),
        (b'f', _) => return Err(refuse("is a float of another size")),
        (b'i', 1 | 2 | 4 | 8) => (Kind::Signed, count),
        (b'u', 1 | 2 | 4 | 8) => (Kind::Unsigned, count),
        (b'U', _) => (Kind::Text, 4 * count),
        (b'b', _) => return Err(refuse("is boolean")),
        (b'c', _) => return Err(refuse("is complex")),
        (b'O', _) => return Err(refuse("holds Python objects")),
        _ => return Err(refuse("is not a number")),
    };
    let big_endian = match order {
        b'<' => false,
        b'>' => true,
        b'|' if size == 1 => false,
        _ => {
            return Err(refuse(
                "has no byte order NumPy writes ('<', '>', or '|' for one byte)",
            ))
        }
    };
    Ok(Scalar {
        kind,
        big_endian,
        size,
    })
}

/// One named field of a structured type, or the whole of a plain one.
#[derive(Debug, Clone, PartialEq)]
pub(crate) struct Field {
    pub(crate) name: String,
    pub(crate) scalar: Scalar,
    /// The field's own shape (empty for a scalar field).
    pub(crate) shape: Vec<usize>,
}

/// A parsed header.
#[derive(Debug, Clone, PartialEq)]
pub(crate) struct Header {
    /// `None` for a plain type; the fields of a structured one.
    pub(crate) fields: Option<Vec<Field>>,
    pub(crate) plain: Option<Scalar>,
    pub(crate) fortran_order: bool,
    pub(crate) shape: Vec<usize>,
}

fn shape_of(literal: &Literal, what: &str) -> Result<Vec<usize>> {
    let Literal::Seq(items) = literal else {
        return Err(bad(format!(".npy header: {what} is not a tuple")));
    };
    items
        .iter()
        .map(|d| match d {
            Literal::Int(n) => usize::try_from(*n)
                .map_err(|_| bad(format!(".npy header: {what} has a dimension of {n}"))),
            _ => Err(bad(format!(
                ".npy header: {what} has a dimension that is not a whole number"
            ))),
        })
        .collect()
}

fn field(item: &Literal) -> Result<Field> {
    let parts = match item {
        Literal::Seq(p) if p.len() == 2 || p.len() == 3 => p,
        _ => return Err(bad(
            ".npy header: a field of a structured type is not (name, type) or (name, type, shape)"
                .into(),
        )),
    };
    let Literal::Str(name) = &parts[0] else {
        return Err(bad(
            ".npy header: a field's name is not a string (titles are not read)".into(),
        ));
    };
    let Literal::Str(descr) = &parts[1] else {
        return Err(bad(format!(
            ".npy header: the field '{}' has a nested type; hompm reads fields of one number type",
            short(name)
        )));
    };
    if name.is_empty() {
        return Err(bad(
            ".npy header: a field without a name (padding) is not read".into(),
        ));
    }
    let scalar = scalar_of(descr)?;
    if scalar.kind == Kind::Text {
        return Err(bad(format!(
            "the field '{}' is text; hompm reads numbers per particle",
            short(name)
        )));
    }
    let shape = match parts.get(2) {
        Some(s) => shape_of(s, &format!("the shape of field '{}'", short(name)))?,
        None => Vec::new(),
    };
    Ok(Field {
        name: name.clone(),
        scalar,
        shape,
    })
}

/// Reads the magic, version, header length and header; returns the header
/// and the data that follows it.
pub(crate) fn header(bytes: &[u8]) -> Result<(Header, &[u8])> {
    let rest = bytes
        .strip_prefix(NPY_MAGIC)
        .ok_or_else(|| bad("not a .npy file (its first bytes are not \\x93NUMPY)".into()))?;
    let (length, rest) = match rest {
        [1, 0, a, b, rest @ ..] => (u16::from_le_bytes([*a, *b]) as usize, rest),
        [2 | 3, 0, a, b, c, d, rest @ ..] => (u32::from_le_bytes([*a, *b, *c, *d]) as usize, rest),
        [major, minor, ..] => {
            return Err(bad(format!(
                ".npy version {major}.{minor}; hompm reads 1.0, 2.0 and 3.0"
            )))
        }
        _ => return Err(bad("the .npy file ends inside its preamble".into())),
    };
    if rest.len() < length {
        return Err(bad(format!(
            "the .npy header is {length} bytes long but the file has {} after the preamble",
            rest.len()
        )));
    }
    let (text, data) = rest.split_at(length);
    let mut reader = LiteralReader { text, at: 0 };
    let Literal::Dict(entries) = reader.value()? else {
        return Err(bad(".npy header: not a dict".into()));
    };
    if reader.peek().is_some() {
        return Err(reader.unexpected("the end of the header"));
    }
    let get = |key: &str| {
        entries
            .iter()
            .find(|(k, _)| k == key)
            .map(|(_, v)| v)
            .ok_or_else(|| bad(format!(".npy header: no '{key}'")))
    };
    if let Some((k, _)) = entries
        .iter()
        .find(|(k, _)| !["descr", "fortran_order", "shape"].contains(&k.as_str()))
    {
        return Err(bad(format!(
            ".npy header: the key '{}' is not NumPy's",
            short(k)
        )));
    }
    let Literal::Bool(fortran_order) = get("fortran_order")? else {
        return Err(bad(".npy header: fortran_order is not True or False".into()));
    };
    let shape = shape_of(get("shape")?, "shape")?;
    let (plain, fields) = match get("descr")? {
        Literal::Str(d) => (Some(scalar_of(d)?), None),
        Literal::Seq(items) => (
            None,
            Some(items.iter().map(field).collect::<Result<Vec<_>>>()?),
        ),
        _ => {
            return Err(bad(
                ".npy header: descr is neither a type string nor a list of fields".into(),
            ))
        }
    };
    Ok((
        Header {
            fields,
            plain,
            fortran_order: *fortran_order,
            shape,
        },
        data,
    ))
}
