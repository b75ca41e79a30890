//! # Up-front limits
//!
//! Every command estimates, from its arguments alone, the memory and the run
//! time it would need, and refuses what exceeds the limits before it
//! allocates anything (issue #13). Estimates are computed in `f64`, so a
//! size that would overflow an integer is an estimate of +∞ and is refused
//! like any other. They are deliberately rough upper bounds (the constants
//! are documented in docs/conventions.md, "Up-front limits"); a long but
//! feasible command is not refused, it prints its estimate on stderr.
//!
//! Items: [`Limits`], [`ANNOUNCE_SECONDS`], [`bytes`], [`seconds`],
//! [`parse_bytes`], [`parse_seconds`].

use crate::error::{Error, Result};

/// The limits in force (`--max-memory`, `--max-seconds`).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Limits {
    /// Bytes.
    pub max_memory: u64,
    /// Seconds of estimated run time.
    pub max_seconds: f64,
}

impl Default for Limits {
    /// 4 GiB and one hour: a laptop.
    fn default() -> Self {
        Self {
            max_memory: 4 << 30,
            max_seconds: 3600.0,
        }
    }
}

/// Estimated run time above which a command says how long it will take.
pub const ANNOUNCE_SECONDS: f64 = 10.0;

impl Limits {
    /// Refuses `what` if it needs more than `--max-memory`; `needed` (bytes)
    /// is described by `kind` ("a dense matrix").
    pub fn check_memory(
        &self,
        what: impl FnOnce() -> String,
        needed: f64,
        kind: &str,
    ) -> Result<()> {
        if needed.is_nan() || needed > self.max_memory as f64 {
            return Err(Error::OverLimit {
                what: what(),
                needed: format!("{kind} of {}", bytes(needed)),
                limit: bytes(self.max_memory as f64),
                flag: "--max-memory",
            });
        }
        Ok(())
    }

    /// Refuses `what` if its estimated run time exceeds `--max-seconds`;
    /// announces it on stderr if it exceeds [`ANNOUNCE_SECONDS`] and
    /// stderr is a terminal. To a pipe or a file the note is not written,
    /// so that a command that then fails leaves its one error line alone
    /// (issue #35).
    pub fn check_time(&self, what: impl FnOnce() -> String, needed: f64) -> Result<()> {
        if needed.is_nan() || needed > self.max_seconds {
            return Err(Error::OverLimit {
                what: what(),
                needed: format!("an estimated {}", seconds(needed)),
                limit: seconds(self.max_seconds),
                flag: "--max-seconds",
            });
        }
        if needed > ANNOUNCE_SECONDS && std::io::IsTerminal::is_terminal(&std::io::stderr()) {
            eprintln!("note: {} will take about {}", what(), seconds(needed));
        }
        Ok(())
    }
}

/// Bytes in binary units: "512 B", "3.2 MiB", "80.0 GiB", "inf".
pub fn bytes(b: f64) -> String {
    if !b.is_finite() {
        return "more bytes than can be counted".into();
    }
    let units = ["B", "KiB", "MiB", "GiB", "TiB", "PiB", "EiB"];
    let mut value = b;
    let mut unit = 0;
    while value >= 1024.0 && unit + 1 < units.len() {
        value /= 1024.0;
        unit += 1;
    }
    if unit == 0 {
        format!("{value:.0} B")
    } else {
        format!("{value:.1} {}", units[unit])
    }
}

/// A duration: "42 s", "3.5 h", "2.0e9 years".
pub fn seconds(s: f64) -> String {
    if !s.is_finite() {
        return "unbounded time".into();
    }
    if s < 120.0 {
        format!("{s:.0} s")
    } else if s < 7200.0 {
        format!("{:.0} min", s / 60.0)
    } else if s < 86400.0 * 365.0 {
        format!("{:.1} h", s / 3600.0)
    } else {
        format!("{:.1e} years", s / (86400.0 * 365.0))
    }
}

/// Parses a memory size: a number of bytes, or a number with a unit B, K,
/// KB, KiB, M, MB, MiB, G, GB, GiB, T, TB, TiB (KB = 1000, KiB = K = 1024).
pub fn parse_bytes(text: &str) -> std::result::Result<u64, String> {
    let t = text.trim();
    let split = t.find(|c: char| c.is_ascii_alphabetic()).unwrap_or(t.len());
    let (number, unit) = t.split_at(split);
    let value: f64 = number
        .trim()
        .parse()
        .map_err(|_| format!("'{t}' is not a size (e.g. 4GiB, 512MiB, 1000000)"))?;
    let scale = match unit.trim().to_ascii_lowercase().as_str() {
        "" | "b" => 1.0,
        "k" | "kib" => 1024.0,
        "kb" => 1e3,
        "m" | "mib" => 1024.0 * 1024.0,
        "mb" => 1e6,
        "g" | "gib" => 1024.0 * 1024.0 * 1024.0,
        "gb" => 1e9,
        "t" | "tib" => 1024f64.powi(4),
        "tb" => 1e12,
        other => {
            return Err(format!(
                "unknown size unit '{other}' (use B, KiB, MiB, GiB, TiB, KB, MB, GB, TB)"
            ))
        }
    };
    let b = value * scale;
    if !(b.is_finite() && b >= 0.0 && b < u64::MAX as f64) {
        return Err(format!("'{t}' is not a size between 0 and 16 EiB"));
    }
    Ok(b as u64)
}

/// Parses a positive number of seconds.
pub fn parse_seconds(text: &str) -> std::result::Result<f64, String> {
    match text.trim().parse::<f64>() {
        Ok(s) if s > 0.0 && !s.is_nan() => Ok(s),
        Ok(s) => Err(format!("{s} is not a positive number of seconds")),
        Err(_) => Err(format!("'{text}' is not a number of seconds")),
    }
}
