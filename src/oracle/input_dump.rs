//! # LAMMPS-style dump files
//!
//! Karamelo and other LAMMPS-derived codes write their particles as dump
//! files: blocks of
//!
//! ```text
//! ITEM: TIMESTEP
//! 1999
//! ITEM: NUMBER OF ATOMS
//! 64
//! ITEM: BOX BOUNDS sm sm sm
//! 0 25
//! 0 0
//! 0 0
//! ITEM: ATOMS id type x0 x vx s11
//! 1 1 0.1953125 0.19536 0.00245 0.0248
//! …
//! ```
//!
//! (`ITEM: TIME` and `ITEM: UNITS` sections of one line are allowed). The
//! reader is strict like the CSV one: every block needs its timestep, its
//! atom count and its atoms, in that order; the count must match the rows;
//! every row has one number per column; two blocks of one timestep are
//! refused. The last block is used unless `--dump-step` names another
//! (`hompm check`). LAMMPS numbers atoms from 1: an id below 1 is refused,
//! and the matching reads ids 1..=n as 1-based (`oracle::state`), so ids
//! that are not 1..=n are refused there. The other columns keep their names;
//! `--columns v=vx,stress=s11` maps them (docs/oracle.md, "Recipes by
//! code"). No maintained Rust crate reads this format on its own, so it is
//! written here (docs/conventions.md, "Conventions of other codes").
//!
//! Items: none public; `oracle::input::parse_input_as` calls `parse_dump`.

use super::table::{short, Parsed, TableBuilder};
use crate::error::{Error, Result};

/// One block of a dump file.
struct Block<'a> {
    timestep: u64,
    columns: Vec<&'a str>,
    /// The rows with their line numbers in the file.
    rows: Vec<(usize, &'a str)>,
}

/// Whether `text` reads as a dump file (its first non-blank line is an
/// `ITEM:` line).
pub(crate) fn is_dump(text: &str) -> bool {
    text.lines()
        .find(|l| !l.trim().is_empty())
        .is_some_and(|l| l.trim_start().starts_with("ITEM:"))
}

fn bad(line: usize, what: String) -> Error {
    Error::Input(format!("dump file, line {line}: {what}"))
}

/// The value line after an `ITEM:` line, as a whole number.
fn count_after<'a>(
    lines: &mut impl Iterator<Item = (usize, &'a str)>,
    item: &str,
    at: usize,
) -> Result<u64> {
    let Some((n, text)) = lines.next() else {
        return Err(bad(at, format!("'ITEM: {item}' has no value line")));
    };
    text.trim().parse().map_err(|_| {
        bad(
            n,
            format!("'{}' is not a whole number ({item})", short(text.trim())),
        )
    })
}

/// Splits the file into blocks, strictly.
fn blocks(text: &str) -> Result<Vec<Block<'_>>> {
    let mut lines = text
        .lines()
        .enumerate()
        .map(|(k, l)| (k + 1, l.trim_end_matches('\r')))
        .filter(|(_, l)| !l.trim().is_empty())
        .peekable();
    let mut out: Vec<Block> = Vec::new();
    let mut seen = std::collections::HashSet::new();
    let mut timestep: Option<u64> = None;
    let mut atoms: Option<u64> = None;
    while let Some((n, line)) = lines.next() {
        let Some(item) = line.trim().strip_prefix("ITEM:") else {
            return Err(bad(
                n,
                format!("'{}' is not an ITEM line", short(line.trim())),
            ));
        };
        let item = item.trim();
        if item == "TIMESTEP" {
            if timestep.is_some() {
                return Err(bad(n, "a second TIMESTEP before the block's ATOMS".into()));
            }
            timestep = Some(count_after(&mut lines, item, n)?);
        } else if item == "NUMBER OF ATOMS" {
            if atoms.is_some() {
                return Err(bad(
                    n,
                    "a second NUMBER OF ATOMS before the block's ATOMS".into(),
                ));
            }
            atoms = Some(count_after(&mut lines, item, n)?);
        } else if item == "TIME" || item == "UNITS" {
            if lines.next().is_none() {
                return Err(bad(n, format!("'ITEM: {item}' has no value line")));
            }
        } else if item.starts_with("BOX BOUNDS") {
            for _ in 0..3 {
                let Some((m, bounds)) = lines.next() else {
                    return Err(bad(n, "BOX BOUNDS needs three lines".into()));
                };
                let ok = bounds.split_whitespace().count() >= 2
                    && bounds.split_whitespace().all(|w| w.parse::<f64>().is_ok());
                if !ok {
                    return Err(bad(m, format!("'{}' is not a box bound", short(bounds))));
                }
            }
        } else if let Some(names) = item.strip_prefix("ATOMS") {
            let (Some(step), Some(count)) = (timestep.take(), atoms.take()) else {
                return Err(bad(
                    n,
                    "ATOMS before the block's TIMESTEP and NUMBER OF ATOMS".into(),
                ));
            };
            let columns: Vec<&str> = names.split_whitespace().collect();
            if columns.is_empty() {
                return Err(bad(n, "ATOMS names no column".into()));
            }
            if !seen.insert(step) {
                return Err(bad(n, format!("timestep {step} appears twice")));
            }
            let mut rows = Vec::new();
            for _ in 0..count {
                match lines.peek() {
                    Some((_, l)) if !l.trim_start().starts_with("ITEM:") => {
                        rows.extend(lines.next());
                    }
                    _ => {
                        return Err(bad(
                            n,
                            format!(
                                "NUMBER OF ATOMS is {count} but timestep {step} has {} rows",
                                rows.len()
                            ),
                        ))
                    }
                }
            }
            if let Some((m, l)) = lines.peek() {
                if !l.trim_start().starts_with("ITEM:") {
                    return Err(bad(
                        *m,
                        format!("timestep {step} has more rows than NUMBER OF ATOMS ({count})"),
                    ));
                }
            }
            out.push(Block {
                timestep: step,
                columns,
                rows,
            });
        } else {
            return Err(bad(n, format!("unknown item 'ITEM: {}'", short(item))));
        }
    }
    if timestep.is_some() || atoms.is_some() {
        return Err(Error::Input(
            "dump file: the last block has no ATOMS section".into(),
        ));
    }
    if out.is_empty() {
        return Err(Error::Input("dump file: no ATOMS block".into()));
    }
    Ok(out)
}

/// The particles of one block of a dump file: the last, or the one of
/// timestep `step`.
pub(crate) fn parse_dump(text: &str, step: Option<u64>) -> Result<Parsed> {
    let all = blocks(text)?;
    let block = match step {
        None => all.last(),
        Some(s) => all.iter().find(|b| b.timestep == s),
    };
    let Some(b) = block else {
        let steps: Vec<String> = all.iter().map(|b| b.timestep.to_string()).collect();
        return Err(Error::Input(format!(
            "the dump file has no timestep {} (it has {})",
            step.unwrap_or_default(),
            short(&steps.join(", "))
        )));
    };
    if b.rows.is_empty() {
        return Err(Error::Input(format!(
            "dump file: timestep {} has no atoms",
            b.timestep
        )));
    }
    let mut values = vec![Vec::with_capacity(b.rows.len()); b.columns.len()];
    for &(line, row) in &b.rows {
        let cells: Vec<&str> = row.split_whitespace().collect();
        if cells.len() != b.columns.len() {
            return Err(bad(
                line,
                format!(
                    "{} values but ATOMS names {} columns",
                    cells.len(),
                    b.columns.len()
                ),
            ));
        }
        for (c, cell) in cells.iter().enumerate() {
            let v: f64 = cell.parse().map_err(|_| {
                bad(
                    line,
                    format!(
                        "column '{}': '{}' is not a number",
                        short(b.columns[c]),
                        short(cell)
                    ),
                )
            })?;
            if !v.is_finite() {
                return Err(bad(
                    line,
                    format!(
                        "column '{}' is {v}; every value must be finite",
                        short(b.columns[c])
                    ),
                ));
            }
            values[c].push(v);
        }
    }
    let mut table = TableBuilder::default();
    table.metadata("dump-timestep", b.timestep.to_string());
    for (name, column) in b.columns.iter().zip(values) {
        if *name == "id" {
            if let Some(bad_id) = column.iter().find(|&&i| i < 1.0 || i.fract() != 0.0) {
                return Err(Error::Input(format!(
                    "dump file: atom id {bad_id} is not a whole number from 1"
                )));
            }
        }
        table.column(name.to_string(), column)?;
    }
    Ok(Parsed::Particles(table.finish()))
}
