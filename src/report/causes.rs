//! # Why a published number deviates
//!
//! Every published number that hompm computes but does not reproduce gets a
//! cause in `golden/deviation-causes.json`, of one of two kinds (issue #11):
//!
//! - **demonstrated**: an experiment in the code, a test or a study row
//!   named in `evidence`, shows the published number appearing under the
//!   changed assumption, or shows that no assumption the text allows
//!   produces it;
//! - **hypothesis**: the most likely reason, with the experiments tried so
//!   far; not yet shown.
//!
//! A rule names a table and a row and a column label, either of which may be
//! `*` (every label); the first matching rule wins, so specific rules come
//! before general ones. docs/reproduction.md shows the cause beside each
//! deviation and counts both kinds in its summary.
//!
//! Items: [`CauseKind`], [`DeviationCause`], [`causes`], [`cause_of`].

use crate::error::{Error, Result};
use serde::{Deserialize, Serialize};

/// Whether a cause is shown by an experiment or only supposed.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "kebab-case")]
pub enum CauseKind {
    /// Shown by the test or study row named in `evidence`.
    Demonstrated,
    /// The most likely reason, not yet shown.
    Hypothesis,
}

/// The cause of the deviations a rule matches.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct DeviationCause {
    /// Table id.
    pub table: String,
    /// Row label, or `*`.
    pub row: String,
    /// Column label, or `*`.
    pub column: String,
    /// Demonstrated or hypothesis.
    pub kind: CauseKind,
    /// The cause, one or two sentences.
    pub cause: String,
    /// The experiment: `tests/<file>.rs::<test>` or `table <id> note`, and
    /// for a hypothesis, what was tried.
    pub evidence: String,
}

/// The rules of golden/deviation-causes.json.
pub fn causes() -> Result<Vec<DeviationCause>> {
    serde_json::from_str(include_str!("../../golden/deviation-causes.json")).map_err(|e| {
        Error::Published {
            id: "deviation-causes".into(),
            message: e.to_string(),
        }
    })
}

/// The first rule matching (table, row, column), if any.
pub fn cause_of<'a>(
    rules: &'a [DeviationCause],
    table: &str,
    row: &str,
    column: &str,
) -> Option<&'a DeviationCause> {
    let matches = |rule: &str, label: &str| rule == "*" || rule == label;
    rules
        .iter()
        .find(|c| c.table == table && matches(&c.row, row) && matches(&c.column, column))
}
