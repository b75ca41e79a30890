//! # Numbers as other codes' binary files store them
//!
//! `.npy` arrays and VTK data arrays hold numbers as raw bytes of a named
//! type and byte order. This module reads one such number into an f64,
//! exactly or not at all: floats of 4 and 8 bytes always, integers only
//! where |v| ≤ 2^53, the largest range in which a float64 holds every
//! integer. No equation of the seeds lives here; it is the strict reading
//! of issue #36.
//!
//! Items: none public; `oracle::input_npy` and `oracle::input_vtk` use
//! `Scalar`.

/// The largest integer magnitude up to which a float64 holds every
/// integer exactly (2^53).
pub(crate) const EXACT_INTEGER: u64 = 1 << 53;

/// What the bytes of one element mean.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub(crate) enum Kind {
    Float,
    Signed,
    Unsigned,
    /// NumPy's `U`: UTF-32 text, read only as 0-d metadata.
    Text,
}

/// One element type: its kind, byte order and size in bytes (floats 4 or
/// 8, integers 1, 2, 4 or 8).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub(crate) struct Scalar {
    pub(crate) kind: Kind,
    pub(crate) big_endian: bool,
    pub(crate) size: usize,
}

impl Scalar {
    /// The value of the element in `bytes` (exactly `size` long), or why
    /// it has none as an f64.
    pub(crate) fn read(&self, bytes: &[u8]) -> std::result::Result<f64, String> {
        let mut b = [0u8; 8];
        b[..self.size].copy_from_slice(bytes);
        if self.big_endian {
            b[..self.size].reverse();
        }
        let (signed, unsigned) = (i64::from_le_bytes(b), u64::from_le_bytes(b));
        match (self.kind, self.size) {
            (Kind::Float, 4) => Ok(f64::from(f32::from_le_bytes([b[0], b[1], b[2], b[3]]))),
            (Kind::Float, _) => Ok(f64::from_le_bytes(b)),
            (Kind::Signed, s) => {
                let shift = 64 - 8 * s as u32;
                let v = (signed << shift) >> shift;
                if v.unsigned_abs() > EXACT_INTEGER {
                    Err(format!(
                        "the integer {v} is beyond 2^53, where a float64 is not exact"
                    ))
                } else {
                    Ok(v as f64)
                }
            }
            (Kind::Unsigned, _) if unsigned > EXACT_INTEGER => Err(format!(
                "the integer {unsigned} is beyond 2^53, where a float64 is not exact"
            )),
            (Kind::Unsigned, _) => Ok(unsigned as f64),
            (Kind::Text, _) => Err("text is metadata, not a number per particle".into()),
        }
    }
}

impl Scalar {
    /// A number written as text in an array of this type, as a reader of
    /// the type holds it: rounded to float32 for a 4-byte float (VTK's own
    /// reader does so; a Float32 array of 17-digit text is float32 data),
    /// and only a whole number within the type's range for an integer.
    pub(crate) fn of_text(&self, v: f64) -> std::result::Result<f64, String> {
        match (self.kind, self.size) {
            (Kind::Float, 4) => {
                let rounded = f64::from(v as f32);
                if v.is_finite() && !rounded.is_finite() {
                    Err(format!("{v} is beyond float32's range"))
                } else {
                    Ok(rounded)
                }
            }
            (Kind::Float, _) | (Kind::Text, _) => Ok(v),
            (kind, size) => {
                let bits = 8 * size as i32;
                let (low, high) = if kind == Kind::Signed {
                    (-(2f64.powi(bits - 1)), 2f64.powi(bits - 1) - 1.0)
                } else {
                    (0.0, 2f64.powi(bits) - 1.0)
                };
                if v.fract() != 0.0 || v < low || v > high || v.abs() > EXACT_INTEGER as f64 {
                    Err(format!(
                        "{v} is not a whole number of a {}{bits}-bit integer",
                        if kind == Kind::Signed {
                            "signed "
                        } else {
                            "unsigned "
                        }
                    ))
                } else {
                    Ok(v)
                }
            }
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_signed_integer_is_sign_extended_from_its_own_width() {
        let int16 = Scalar {
            kind: Kind::Signed,
            big_endian: true,
            size: 2,
        };
        assert_eq!(int16.read(&[0xff, 0xfe]), Ok(-2.0));
        assert_eq!(int16.read(&[0x7f, 0xff]), Ok(32767.0));
    }

    #[test]
    fn text_in_a_float32_array_is_rounded_to_float32_and_an_integer_must_fit_its_type() {
        let float32 = Scalar {
            kind: Kind::Float,
            big_endian: false,
            size: 4,
        };
        assert_eq!(float32.of_text(0.1), Ok(f64::from(0.1f32)));
        assert!(float32.of_text(1e39).is_err());
        let uint8 = Scalar {
            kind: Kind::Unsigned,
            big_endian: false,
            size: 1,
        };
        assert_eq!(uint8.of_text(255.0), Ok(255.0));
        assert!(uint8.of_text(256.0).is_err() && uint8.of_text(-1.0).is_err());
        assert!(uint8.of_text(1.5).is_err());
    }

    #[test]
    fn two_to_the_53_is_exact_and_one_more_is_refused() {
        let int64 = Scalar {
            kind: Kind::Signed,
            big_endian: false,
            size: 8,
        };
        let at = |v: i64| int64.read(&v.to_le_bytes());
        assert_eq!(at(-(1 << 53)), Ok(-9007199254740992.0));
        assert!(at((1 << 53) + 1).is_err());
    }
}
