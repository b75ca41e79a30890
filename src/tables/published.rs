//! # Published tables as transcribed, and the tolerance of each number
//!
//! `golden/published/<id>.json` holds a table as printed: its source, its
//! row and column labels, its values (with the significant digits each is
//! printed with, read from the JSON text) and the tolerance rules of its
//! numbers by label (docs/conventions.md, "Tolerances of the table
//! registry", "To the printed digits"). This module parses and judges them;
//! [`super`] registers and runs the computations.
//!
//! Items: [`Source`], [`Published`], [`significant_digits`],
//! [`equal_to_digits`], [`ToleranceKind`], [`CellTolerance`],
//! [`ToleranceRules`], [`Tolerance`], [`Status`], [`effective_tolerance`],
//! [`digits_apply`].

use crate::error::{Error, Result};
use serde::{Deserialize, Serialize};

/// Where a published number comes from.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct Source {
    /// Short name of the document: book, thesis, tls, mls.
    pub document: String,
    /// Table, figure or section, as printed.
    pub table: String,
    /// Printed page (or page range).
    pub page: String,
}

/// A published table as transcribed in `golden/published/<id>.json`.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct Published {
    /// Table id, e.g. `book-4.2`.
    pub id: String,
    /// Human title.
    pub title: String,
    /// Seed file name in ../shared/seeds.
    pub seed: String,
    /// Table and page.
    pub source: Source,
    /// One label per row.
    pub row_labels: Vec<String>,
    /// One label per column.
    pub col_labels: Vec<String>,
    /// The numbers as printed; `null` where the table is blank.
    pub values: Vec<Vec<Option<f64>>>,
    /// Unit of the values.
    pub unit: String,
    /// The tolerance of each number, by label (docs/conventions.md,
    /// "Tolerances of the table registry").
    pub tolerance: ToleranceRules,
    /// The significant digits each value is printed with, read from the
    /// JSON text (`None` where the table is blank): `4.9665e-06` has 5,
    /// `0.27` has 2, `450` has 3.
    #[serde(skip)]
    pub digits: Vec<Vec<Option<u32>>>,
}

/// The significant digits of a JSON number as written: the digits of its
/// mantissa without leading zeros (at least 1).
pub fn significant_digits(literal: &str) -> u32 {
    let mantissa = literal
        .trim()
        .trim_start_matches('-')
        .split(['e', 'E'])
        .next()
        .unwrap_or("");
    let digits: String = mantissa.chars().filter(char::is_ascii_digit).collect();
    let significant = digits.trim_start_matches('0');
    significant.len().max(1) as u32
}

/// The literal tokens of the `"values"` array of a published-table JSON
/// text, row by row (`None` for `null`).
fn value_literals(json: &str) -> Option<Vec<Vec<Option<u32>>>> {
    let start = json.find("\"values\"")?;
    let rest = &json[start + "\"values\"".len()..];
    let open = rest.find('[')?;
    let mut depth = 0usize;
    let mut rows: Vec<Vec<Option<u32>>> = Vec::new();
    let mut token = String::new();
    let flush = |token: &mut String, rows: &mut Vec<Vec<Option<u32>>>| {
        let t = token.trim();
        if !t.is_empty() {
            let cell = (t != "null").then(|| significant_digits(t));
            if let Some(row) = rows.last_mut() {
                row.push(cell);
            }
        }
        token.clear();
    };
    for c in rest[open..].chars() {
        match c {
            '[' => {
                depth += 1;
                if depth == 2 {
                    rows.push(Vec::new());
                }
            }
            ']' => {
                flush(&mut token, &mut rows);
                depth -= 1;
                if depth == 0 {
                    return Some(rows);
                }
            }
            ',' => flush(&mut token, &mut rows),
            c if !c.is_whitespace() => token.push(c),
            _ => {}
        }
    }
    None
}

/// Whether `computed`, rounded to `digits` significant digits, equals
/// `published` as printed: both written with `digits` significant digits
/// in scientific notation and compared as text.
pub fn equal_to_digits(published: f64, computed: f64, digits: u32) -> bool {
    if !computed.is_finite() {
        return false;
    }
    let d = digits.max(1) as usize - 1;
    format!("{published:.d$e}") == format!("{computed:.d$e}")
}

/// The kinds of tolerance a published number can have, as written in
/// `golden/published/<id>.json` (`{"kind": "rms"}`, `{"kind": "relative",
/// "value": 0.005}`, …).
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
#[serde(tag = "kind", rename_all = "kebab-case")]
pub enum ToleranceKind {
    /// Integer counts: equal.
    Exact,
    /// Condition numbers: 1 %.
    ConditionNumber,
    /// RMS errors: 2 %.
    Rms,
    /// Machine-precision conservation.
    MachinePrecision,
    /// Convergence orders: ±0.01.
    Order,
    /// A ratio of two error measures: 4 %.
    ErrorRatio,
    /// An integer order stated in the text against a fitted slope: ±0.2.
    StatedOrder,
    /// The text says "more than".
    AtLeast,
    /// A qualitative claim read as an upper bound (MLS paper, `mls-aligned`).
    AtMost,
    /// A ratio of wall times measured on this machine (TLS paper Table 8):
    /// within a factor of 2.
    Timing,
    /// A documented relative tolerance.
    Relative {
        /// The relative tolerance.
        value: f64,
    },
    /// A documented absolute tolerance.
    Absolute {
        /// The absolute tolerance.
        value: f64,
    },
}

impl From<ToleranceKind> for Tolerance {
    fn from(k: ToleranceKind) -> Self {
        match k {
            ToleranceKind::Exact => Tolerance::Exact,
            ToleranceKind::ConditionNumber => Tolerance::CONDITION_NUMBER,
            ToleranceKind::Rms => Tolerance::RMS,
            ToleranceKind::MachinePrecision => Tolerance::MachinePrecision,
            ToleranceKind::Order => Tolerance::ORDER,
            ToleranceKind::ErrorRatio => Tolerance::ERROR_RATIO,
            ToleranceKind::StatedOrder => Tolerance::STATED_ORDER,
            ToleranceKind::AtLeast => Tolerance::AtLeast,
            ToleranceKind::AtMost => Tolerance::AtMost,
            ToleranceKind::Timing => Tolerance::Timing,
            ToleranceKind::Relative { value } => Tolerance::Relative(value),
            ToleranceKind::Absolute { value } => Tolerance::Absolute(value),
        }
    }
}

/// One cell's tolerance kind, named by its row and column labels.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct CellTolerance {
    /// Row label.
    pub row: String,
    /// Column label.
    pub column: String,
    /// The kind.
    #[serde(flatten)]
    pub kind: ToleranceKind,
}

/// The tolerance rules of a published table, by label: a cell rule wins
/// over a row rule, a row rule over a column rule, and a column rule over
/// the default. Every label a rule names must exist in the table.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct ToleranceRules {
    /// The kind of every number no other rule names.
    pub default: ToleranceKind,
    /// Kinds by row label.
    #[serde(default, skip_serializing_if = "std::collections::BTreeMap::is_empty")]
    pub rows: std::collections::BTreeMap<String, ToleranceKind>,
    /// Kinds by column label.
    #[serde(default, skip_serializing_if = "std::collections::BTreeMap::is_empty")]
    pub columns: std::collections::BTreeMap<String, ToleranceKind>,
    /// Kinds of single cells.
    #[serde(default, skip_serializing_if = "Vec::is_empty")]
    pub cells: Vec<CellTolerance>,
}

impl ToleranceRules {
    /// The tolerance of the number at (row, column).
    pub fn at(&self, row: &str, column: &str) -> Tolerance {
        let cell = self
            .cells
            .iter()
            .find(|c| c.row == row && c.column == column);
        let kind = cell
            .map(|c| &c.kind)
            .or_else(|| self.rows.get(row))
            .or_else(|| self.columns.get(column))
            .unwrap_or(&self.default);
        (*kind).into()
    }
}

impl Published {
    /// Parses and checks the shape of a published-table JSON text.
    pub fn parse(id: &str, json: &str) -> Result<Self> {
        let mut p: Published = serde_json::from_str(json).map_err(|e| Error::Published {
            id: id.into(),
            message: e.to_string(),
        })?;
        p.digits = value_literals(json).unwrap_or_default();
        if p.values.len() != p.row_labels.len()
            || p.values.iter().any(|r| r.len() != p.col_labels.len())
            || p.digits.len() != p.values.len()
            || p.digits.iter().any(|r| r.len() != p.col_labels.len())
        {
            return Err(Error::Published {
                id: id.into(),
                message: "values do not match the row and column labels".into(),
            });
        }
        let t = &p.tolerance;
        let unknown_row = t
            .rows
            .keys()
            .chain(t.cells.iter().map(|c| &c.row))
            .find(|l| !p.row_labels.contains(l));
        let unknown_col = t
            .columns
            .keys()
            .chain(t.cells.iter().map(|c| &c.column))
            .find(|l| !p.col_labels.contains(l));
        if let Some(label) = unknown_row.or(unknown_col) {
            return Err(Error::Published {
                id: id.into(),
                message: format!(
                    "a tolerance rule names '{label}', which is not a row or column label"
                ),
            });
        }
        Ok(p)
    }

    /// Number of published (non-null) numbers.
    pub fn count(&self) -> usize {
        self.values.iter().flatten().filter(|v| v.is_some()).count()
    }
}

/// How close a computed number must be to count as reproduced.
#[derive(Debug, Clone, Copy, PartialEq, Serialize)]
pub enum Tolerance {
    /// Equal (integer counts).
    Exact,
    /// |computed − published| ≤ tol · |published|.
    Relative(f64),
    /// computed ≤ 1e-13 and |log10(computed/published)| ≤ 1 (same decade).
    MachinePrecision,
    /// |computed − published| ≤ tol (convergence orders, docs/conventions.md).
    Absolute(f64),
    /// computed ≥ published (the text says "more than").
    AtLeast,
    /// computed ≤ published (a claim read as an upper bound).
    AtMost,
    /// A wall-time ratio, measured: |log₂(computed/published)| ≤ 1. Wall
    /// time depends on the machine and the code, so this only asks whether
    /// the cost is of the same size (docs/conventions.md); such cells are
    /// left out of the regression baseline.
    Timing,
}

impl Tolerance {
    /// Condition numbers: 1 % (docs/conventions.md).
    pub const CONDITION_NUMBER: Tolerance = Tolerance::Relative(0.01);
    /// RMS errors: 2 % (docs/conventions.md).
    pub const RMS: Tolerance = Tolerance::Relative(0.02);
    /// Convergence orders log2(e(h)/e(h/2)): ±0.01 (docs/conventions.md).
    pub const ORDER: Tolerance = Tolerance::Absolute(0.01);
    /// A ratio of two error measures (error-reduction factors): 4 %, the
    /// combination of two 2 % RMS tolerances (docs/conventions.md).
    pub const ERROR_RATIO: Tolerance = Tolerance::Relative(0.04);
    /// An integer order stated in a paper's text against a fitted slope: ±0.2
    /// (docs/conventions.md).
    pub const STATED_ORDER: Tolerance = Tolerance::Absolute(0.2);

    /// Whether `computed` reproduces `published`.
    pub fn accepts(self, published: f64, computed: f64) -> bool {
        if !computed.is_finite() {
            return false;
        }
        match self {
            Tolerance::Exact => computed == published,
            Tolerance::Relative(tol) => (computed - published).abs() <= tol * published.abs(),
            Tolerance::Absolute(tol) => (computed - published).abs() <= tol,
            Tolerance::AtLeast => computed >= published,
            Tolerance::AtMost => computed <= published,
            Tolerance::Timing => {
                computed > 0.0 && published > 0.0 && (computed / published).log2().abs() <= 1.0
            }
            Tolerance::MachinePrecision => {
                let c = computed.abs().max(1e-300);
                let p = published.abs().max(1e-300);
                computed.abs() <= 1e-13 && (c / p).log10().abs() <= 1.0
            }
        }
    }
}

/// Status of one published number.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "kebab-case")]
pub enum Status {
    /// Within the tolerance of its kind.
    Reproduced,
    /// Computed, but outside the tolerance.
    Deviates,
    /// Not computed (yet), or blank in the publication.
    NotComputed,
}

/// A published value at rounding level (|p| ≤ 1e-13) is noise: a relative
/// tolerance on it is meaningless, so it is judged by the machine-precision
/// rule whatever its row's kind (docs/conventions.md).
pub fn effective_tolerance(kind: Tolerance, published: f64) -> Tolerance {
    match kind {
        Tolerance::Relative(_) if published.abs() <= 1e-13 => Tolerance::MachinePrecision,
        other => other,
    }
}

/// Whether a number of this kind is judged to its printed digits: not a
/// bound (`AtLeast`, `AtMost`), not a wall-time ratio (`Timing`), and not
/// rounding noise (`MachinePrecision`), whose digits no code reproduces
/// (docs/conventions.md, "To the printed digits").
pub fn digits_apply(kind: Tolerance) -> bool {
    !matches!(
        kind,
        Tolerance::AtLeast | Tolerance::AtMost | Tolerance::Timing | Tolerance::MachinePrecision
    )
}
