//! # The table a reader hands on
//!
//! What the CSV and JSON readers of [`super::input`] and
//! [`super::input_json`] build, below both of them: a [`ParticleTable`]
//! of named columns, the builder that refuses a column given twice or of
//! another length (linear in the number of columns), the parsed file
//! before `--columns` renames it, and the two helpers of every message
//! (a finite value, a quoted name cut to 60 characters). No equation of
//! the seeds lives here; it is the strict reading of issue #35.
//!
//! Items: [`ParticleTable`].

use super::trace::Trace;
use crate::error::{Error, Result};
use std::collections::{BTreeMap, HashSet};

/// Particle columns by name, every column as long as the others.
#[derive(Debug, Clone, Default, PartialEq)]
pub struct ParticleTable {
    /// The columns, in the file's order.
    pub columns: Vec<(String, Vec<f64>)>,
    /// `# key: value` metadata (CSV) or top-level scalars (JSON).
    pub metadata: BTreeMap<String, String>,
    /// The file's columns that are not hompm's (not compared), by the
    /// file's names.
    pub ignored: Vec<String>,
    /// hompm's columns derived from the file's, e.g. `u = x − x0` where
    /// the file has positions but no displacement (Karamelo's dumps).
    pub derived: Vec<String>,
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
}

/// Builds a [`ParticleTable`] column by column: a name given twice or a
/// column of another length is refused, in time linear in the number of
/// columns.
#[derive(Debug, Default)]
pub(crate) struct TableBuilder {
    table: ParticleTable,
    names: HashSet<String>,
    scalars: Vec<String>,
}

impl TableBuilder {
    /// Adds a column.
    pub(crate) fn column(&mut self, name: String, values: Vec<f64>) -> Result<()> {
        if self.names.contains(&name) {
            return Err(Error::Input(format!(
                "the column '{}' appears twice",
                short(&name)
            )));
        }
        if let Some((first, v)) = self.table.columns.first() {
            if v.len() != values.len() {
                return Err(Error::Input(format!(
                    "the column '{}' has {} values but '{}' has {}",
                    short(&name),
                    values.len(),
                    short(first),
                    v.len()
                )));
            }
        }
        self.names.insert(name.clone());
        self.table.columns.push((name, values));
        Ok(())
    }

    /// Adds a metadata entry.
    pub(crate) fn metadata(&mut self, key: &str, value: String) {
        self.table.metadata.insert(key.to_string(), value);
    }

    /// Records a scalar of an object of columns (refused by [`rename`]
    /// if it stands under one of hompm's column names).
    pub(crate) fn scalar(&mut self, name: &str) {
        self.scalars.push(name.to_string());
    }

    /// The table, any recorded scalars aside.
    pub(crate) fn into_table(self) -> ParticleTable {
        self.table
    }

    pub(crate) fn finish(self) -> ParsedTable {
        ParsedTable {
            table: self.table,
            scalars: self.scalars,
        }
    }
}

/// A table as parsed, before `--columns` renames it.
#[derive(Debug, Clone, PartialEq)]
pub(crate) struct ParsedTable {
    pub(crate) table: ParticleTable,
    pub(crate) scalars: Vec<String>,
}

/// What a file holds before `--columns` renames its particle columns.
#[derive(Debug, Clone, PartialEq)]
pub(crate) enum Parsed {
    Particles(ParsedTable),
    Trace(Trace),
}

/// `v`, or an error naming its row and column if it is not finite.
pub(crate) fn finite(v: f64, row: usize, column: &str) -> Result<f64> {
    if v.is_finite() {
        Ok(v)
    } else {
        Err(Error::Input(format!(
            "row {row}, column '{}' is {v}; every value must be finite",
            short(column)
        )))
    }
}

/// At most 60 characters of a name or value quoted in a message.
pub(crate) fn short(text: &str) -> String {
    if text.chars().count() <= 60 {
        text.to_string()
    } else {
        text.chars().take(57).collect::<String>() + "…"
    }
}
