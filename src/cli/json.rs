//! # JSON output without disguised NaN
//!
//! serde_json writes a NaN or infinite `f64` as `null`. The oracle commands
//! have no field that may be absent-as-null (absent values are left out), so
//! [`strict`] refuses any `null` in their output: a `null` there could only
//! be a non-finite number. Table output, whose `null` means "not computed"
//! or "not published", checks its numbers before it is written instead.
//!
//! Items: [`strict`], [`pretty`].

use crate::error::{Error, Result};
use serde::Serialize;

/// Pretty JSON of `value`, or an error naming the first `null` (a
/// non-finite number) by its path. The text is written directly, without
/// a `serde_json::Value` tree of the whole document, so that its memory is
/// the text's (a large run's particles); only a refused document is
/// walked again to name the path.
pub fn strict<T: Serialize>(value: &T) -> Result<String> {
    let text = pretty(value)?;
    if has_bare_null(&text) {
        let tree = serde_json::to_value(value)
            .map_err(|e| Error::InvalidArgument(format!("cannot write JSON: {e}")))?;
        let path = first_null(&tree, String::new()).unwrap_or_else(|| "/".into());
        return Err(Error::NonFinite {
            what: format!("JSON output at {path} (NaN or ±∞ would be written as null)"),
            value: f64::NAN,
        });
    }
    Ok(text)
}

/// Whether JSON text holds a `null` outside its strings.
fn has_bare_null(text: &str) -> bool {
    let bytes = text.as_bytes();
    let (mut in_string, mut escaped) = (false, false);
    for (i, &b) in bytes.iter().enumerate() {
        if in_string {
            match (escaped, b) {
                (true, _) => escaped = false,
                (false, b'\\') => escaped = true,
                (false, b'"') => in_string = false,
                _ => {}
            }
        } else if b == b'"' {
            in_string = true;
        } else if b == b'n' && bytes[i..].starts_with(b"null") {
            return true;
        }
    }
    false
}

/// Pretty JSON of `value`, nulls allowed, with a final newline.
pub fn pretty<T: Serialize>(value: &T) -> Result<String> {
    serde_json::to_string_pretty(value)
        .map(|s| s + "\n")
        .map_err(|e| Error::InvalidArgument(format!("cannot write JSON: {e}")))
}

fn first_null(v: &serde_json::Value, path: String) -> Option<String> {
    match v {
        serde_json::Value::Null => Some(if path.is_empty() { "/".into() } else { path }),
        serde_json::Value::Array(items) => items
            .iter()
            .enumerate()
            .find_map(|(i, x)| first_null(x, format!("{path}/{i}"))),
        serde_json::Value::Object(map) => map
            .iter()
            .find_map(|(k, x)| first_null(x, format!("{path}/{k}"))),
        _ => None,
    }
}
