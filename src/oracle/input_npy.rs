//! # NumPy `.npy` and `.npz` files
//!
//! Python codes (Taichi's examples, NumPy scripts) write their particles
//! with `np.save` (one array) or `np.savez`/`np.savez_compressed` (named
//! arrays in a zip archive). The `.npy` format is NumPy's own
//! (numpy.lib.format, versions 1.0, 2.0 and 3.0): the magic `\x93NUMPY`,
//! a version, a header length, a header that is a Python dict literal of
//! exactly three keys (`descr`, `fortran_order`, `shape`), then the raw
//! data. The zip layer is the `zip` crate's, the header is read by
//! [`super::npy_header`], and the data layout here, strictly: a header with another key, a type
//! hompm cannot hold exactly, or data of another length is one sentence
//! and exit 2 (docs/oracle.md, "Formats").
//!
//! How arrays become columns:
//!
//! - In an `.npz`, the array `u.npy` of shape (n,) is the column `u`; of
//!   shape (n, 2) the columns `u_x`, `u_y`; of shape (n, 4) or (n, 2, 2)
//!   the columns `u_xx`, `u_xy`, `u_yx`, `u_yy` (row-major, as the JSON
//!   reader splits [x, y] pairs and [xx, xy, yx, yy] rows); any other
//!   width w gives `u:0` … `u:w−1` (ParaView's spelling). A 0-d array is
//!   metadata (`cells`, `dt`, a convention's word), checked against the
//!   run like a CSV `# key: value` line.
//! - A single `.npy` of a plain type and shape (n,) is the column `0`; of
//!   shape (n, k) the columns `0` … `k−1`. One with named fields (a
//!   structured array) gives a column per field, split as above.
//!
//! Floats of 4 and 8 bytes are read exactly; integers only where |v| ≤
//! 2^53 (a float64 holds them exactly). Booleans, complex numbers, half
//! and long doubles, objects and byte strings are refused.
//!
//! Items: none public; `oracle::input::parse_input_as` calls
//! `parse_npy` and `parse_npz`.

use super::binary::{Kind, Scalar};
use super::npy_header::{header, Header};
use super::table::{finite, short, Parsed, TableBuilder};
use crate::error::{Error, Result};

/// The first bytes of a zip archive (an `.npz`).
pub(crate) const ZIP_MAGIC: &[u8] = b"PK\x03\x04";

fn bad(what: String) -> Error {
    Error::Input(what)
}

// ---- data -------------------------------------------------------------------

/// The column names of an array called `name` with `width` numbers per row
/// (trailing shape `shape`): see the module's list.
fn column_names(name: &str, shape: &[usize]) -> Vec<String> {
    let width: usize = shape.iter().product();
    let suffixes: &[&str] = match shape {
        [] => &[""],
        [2] => &["_x", "_y"],
        [4] | [2, 2] => &["_xx", "_xy", "_yx", "_yy"],
        _ => &[],
    };
    if suffixes.is_empty() {
        (0..width).map(|j| format!("{name}:{j}")).collect()
    } else {
        suffixes.iter().map(|s| format!("{name}{s}")).collect()
    }
}

/// The number of elements of `shape`, refusing an overflow.
fn count(shape: &[usize]) -> Result<usize> {
    shape
        .iter()
        .try_fold(1usize, |n, &d| n.checked_mul(d))
        .ok_or_else(|| bad(".npy: the shape's element count overflows".into()))
}

/// The values of `data` as `rows` rows of `fields`, in C order.
fn columns_of(name: &str, header: &Header, data: &[u8], table: &mut TableBuilder) -> Result<()> {
    let label = if name.is_empty() {
        "the .npy array"
    } else {
        name
    };
    // A plain array: its first axis is the particles, the rest one row.
    if let Some(scalar) = header.plain {
        if header.shape.is_empty() {
            return metadata(name, scalar, data, table);
        }
        if scalar.kind == Kind::Text {
            return Err(bad(format!(
                "'{}' is text; hompm reads numbers per particle",
                short(label)
            )));
        }
        let rows = header.shape[0];
        let trailing = &header.shape[1..];
        let width = count(trailing)?;
        let total = count(&header.shape)?;
        expect_length(label, data, total, scalar.size)?;
        let names = if name.is_empty() {
            match trailing {
                [] => vec!["0".to_string()],
                [k] => (0..*k).map(|j| j.to_string()).collect(),
                _ => {
                    return Err(bad(format!(
                        "a .npy of shape {:?}: hompm reads (n,) or (n, k); save named arrays with np.savez",
                        header.shape
                    )))
                }
            }
        } else {
            column_names(name, trailing)
        };
        let mut columns = vec![vec![0.0; rows]; width];
        for flat in 0..total {
            // Element `flat` of the file; in Fortran order the first axis
            // varies fastest.
            let (row, within) = if header.fortran_order {
                fortran_position(flat, &header.shape)
            } else {
                (flat / width.max(1), flat % width.max(1))
            };
            let at = flat * scalar.size;
            let value = scalar
                .read(&data[at..at + scalar.size])
                .map_err(|e| bad(format!("row {}, '{}': {e}", row + 1, names[within])))?;
            columns[within][row] = finite(value, row + 1, &names[within])?;
        }
        for (n, column) in names.into_iter().zip(columns) {
            table.column(n, column)?;
        }
        return Ok(());
    }
    // A structured array: one record per particle.
    let fields = header.fields.as_deref().unwrap_or_default();
    let [rows] = header.shape[..] else {
        return Err(bad(format!(
            "a structured array of shape {:?}: hompm reads one record per particle, shape (n,)",
            header.shape
        )));
    };
    let mut record = 0usize;
    let mut layout = Vec::new();
    for f in fields {
        let width = count(&f.shape)?;
        layout.push((record, width, column_names(&f.name, &f.shape)));
        record += width * f.scalar.size;
    }
    expect_length(label, data, rows, record)?;
    for (f, (offset, width, names)) in fields.iter().zip(layout) {
        let mut columns = vec![Vec::with_capacity(rows); width];
        for row in 0..rows {
            for (j, column) in columns.iter_mut().enumerate() {
                let at = row * record + offset + j * f.scalar.size;
                let value = f
                    .scalar
                    .read(&data[at..at + f.scalar.size])
                    .map_err(|e| bad(format!("row {}, '{}': {e}", row + 1, names[j])))?;
                column.push(finite(value, row + 1, &names[j])?);
            }
        }
        for (n, column) in names.into_iter().zip(columns) {
            table.column(n, column)?;
        }
    }
    Ok(())
}

/// The (row, position within the row in C order) of the `flat`-th element
/// of a Fortran-ordered array of `shape`.
fn fortran_position(flat: usize, shape: &[usize]) -> (usize, usize) {
    let mut rest = flat;
    let mut index = Vec::with_capacity(shape.len());
    for &d in shape {
        index.push(rest % d.max(1));
        rest /= d.max(1);
    }
    let within = index[1..]
        .iter()
        .zip(&shape[1..])
        .fold(0, |acc, (&i, &d)| acc * d + i);
    (index[0], within)
}

fn expect_length(label: &str, data: &[u8], elements: usize, size: usize) -> Result<()> {
    let want = elements
        .checked_mul(size)
        .ok_or_else(|| bad(".npy: the data's length overflows".into()))?;
    if data.len() != want {
        return Err(bad(format!(
            "'{}' needs {want} bytes of data for its shape and type but has {}{}",
            short(label),
            data.len(),
            if data.len() > want {
                " (trailing bytes)"
            } else {
                " (the file is cut short)"
            }
        )));
    }
    Ok(())
}

/// A 0-d array: one number or one text, kept as metadata.
fn metadata(name: &str, scalar: Scalar, data: &[u8], table: &mut TableBuilder) -> Result<()> {
    if name.is_empty() {
        return Err(bad("the .npy holds one number, not particles".into()));
    }
    expect_length(name, data, 1, scalar.size)?;
    let text = if scalar.kind == Kind::Text {
        let mut s = String::new();
        for unit in data.chunks_exact(4) {
            let mut b = [unit[0], unit[1], unit[2], unit[3]];
            if scalar.big_endian {
                b.reverse();
            }
            match u32::from_le_bytes(b) {
                0 => break,
                c => s.push(char::from_u32(c).ok_or_else(|| {
                    bad(format!("'{}' is text that is not Unicode", short(name)))
                })?),
            }
        }
        s
    } else {
        let v = scalar
            .read(data)
            .map_err(|e| bad(format!("'{}': {e}", short(name))))?;
        finite(v, 1, name)?.to_string()
    };
    table.scalar(name);
    table.metadata(name, text);
    Ok(())
}

/// Reads a single `.npy` file.
pub(crate) fn parse_npy(bytes: &[u8]) -> Result<Parsed> {
    let (header, data) = header(bytes)?;
    let mut table = TableBuilder::default();
    columns_of("", &header, data, &mut table)?;
    Ok(Parsed::Particles(table.finish()))
}

/// Reads an `.npz` archive: every member must be an `.npy` file, and
/// together they unpack to at most `budget` bytes.
pub(crate) fn parse_npz(bytes: &[u8], mut budget: u64) -> Result<Parsed> {
    use std::io::Read;
    let zip_error = |e: zip::result::ZipError| bad(format!("the .npz archive: {e}"));
    let mut archive = zip::ZipArchive::new(std::io::Cursor::new(bytes)).map_err(zip_error)?;
    if archive.is_empty() {
        return Err(bad("the .npz archive has no arrays".into()));
    }
    let mut table = TableBuilder::default();
    for k in 0..archive.len() {
        let mut member = archive.by_index(k).map_err(zip_error)?;
        let member_name = member.name().map_err(zip_error)?.to_string();
        let Some(name) = member_name.strip_suffix(".npy") else {
            return Err(bad(format!(
                "the .npz member '{}' is not an .npy array",
                short(&member_name)
            )));
        };
        let name = name.to_string();
        // The declared size bounds the read, and all members together stay
        // within the byte limit of the file itself (`--max-memory`).
        let declared = member.size();
        if declared > budget {
            return Err(bad(format!(
                "the .npz member '{}' unpacks to {declared} bytes, over the {budget} bytes left of the limit (raise --max-memory)",
                short(&member_name)
            )));
        }
        budget -= declared;
        let mut contents = Vec::with_capacity(declared as usize);
        member
            .by_ref()
            .take(declared + 1)
            .read_to_end(&mut contents)
            .map_err(|e| bad(format!("the .npz member '{}': {e}", short(&member_name))))?;
        if contents.len() as u64 != declared {
            return Err(bad(format!(
                "the .npz member '{}' unpacks to another size than its zip header says",
                short(&member_name)
            )));
        }
        let (header, data) = header(&contents)
            .map_err(|e| bad(format!("the .npz member '{}': {e}", short(&member_name))))?;
        columns_of(&name, &header, data, &mut table)?;
    }
    Ok(Parsed::Particles(table.finish()))
}

#[cfg(test)]
mod tests {
    use super::*;

    fn npy(descr: &str, fortran: bool, shape: &str, data: &[u8]) -> Vec<u8> {
        let mut header = format!(
            "{{'descr': {descr}, 'fortran_order': {}, 'shape': {shape}, }}",
            if fortran { "True" } else { "False" }
        );
        while (10 + header.len() + 1) % 64 != 0 {
            header.push(' ');
        }
        header.push('\n');
        let mut out = super::super::npy_header::NPY_MAGIC.to_vec();
        out.extend([1, 0]);
        out.extend((header.len() as u16).to_le_bytes());
        out.extend(header.as_bytes());
        out.extend(data);
        out
    }

    fn f64s(values: &[f64]) -> Vec<u8> {
        values.iter().flat_map(|v| v.to_le_bytes()).collect()
    }

    fn table(p: Parsed) -> super::super::table::ParticleTable {
        match p {
            Parsed::Particles(t) => t.table,
            Parsed::Trace(_) => panic!("not particles"),
        }
    }

    #[test]
    fn a_fortran_ordered_array_is_read_by_rows() {
        // [[1, 2], [3, 4], [5, 6]] in Fortran order is 1 3 5 2 4 6.
        let bytes = npy("'<f8'", true, "(3, 2)", &f64s(&[1., 3., 5., 2., 4., 6.]));
        let t = table(parse_npy(&bytes).unwrap());
        assert_eq!(t.column("0").unwrap(), &[1.0, 3.0, 5.0]);
        assert_eq!(t.column("1").unwrap(), &[2.0, 4.0, 6.0]);
    }

    #[test]
    fn a_big_endian_float32_and_a_signed_byte_are_read_exactly() {
        let data: Vec<u8> = [0.1f32, -2.5]
            .iter()
            .flat_map(|v| v.to_be_bytes())
            .collect();
        let t = table(parse_npy(&npy("'>f4'", false, "(2,)", &data)).unwrap());
        assert_eq!(t.column("0").unwrap(), &[f64::from(0.1f32), -2.5]);
        let t = table(parse_npy(&npy("'|i1'", false, "(2,)", &[0xff, 7])).unwrap());
        assert_eq!(t.column("0").unwrap(), &[-1.0, 7.0]);
    }

    #[test]
    fn structured_fields_become_columns_split_like_json() {
        let descr = "[('x0', '<f8'), ('u', '<f8', (2,))]";
        let data = f64s(&[0.5, 1.0, 2.0, 1.5, 3.0, 4.0]);
        let t = table(parse_npy(&npy(descr, false, "(2,)", &data)).unwrap());
        assert_eq!(t.column("x0").unwrap(), &[0.5, 1.5]);
        assert_eq!(t.column("u_x").unwrap(), &[1.0, 3.0]);
        assert_eq!(t.column("u_y").unwrap(), &[2.0, 4.0]);
    }

    #[test]
    fn an_integer_beyond_two_to_the_53_is_refused() {
        let data = ((1u64 << 53) + 1).to_le_bytes();
        let e = parse_npy(&npy("'<u8'", false, "(1,)", &data)).unwrap_err();
        assert!(e.to_string().contains("2^53"), "{e}");
    }
}
