//! # The registry of published tables
//!
//! A *published table* is a JSON file in `golden/published/`, transcribed from
//! a seed with its table and page, with the tolerance kind of its numbers by
//! label ([`ToleranceRules`]: a default, then rules by column, row and cell
//! label; a rule naming an unknown label is an error). A *registered table*
//! pairs it with a function that computes the same grid from the documented
//! setup (docs/conventions.md, "Tolerances of the table registry"):
//!
//! | kind | rule |
//! |---|---|
//! | [`Tolerance::Exact`] | integer counts: equal |
//! | [`Tolerance::Relative`] | condition numbers 1 %, RMS errors 2 % |
//! | [`Tolerance::MachinePrecision`] | computed ≤ 1e-13 and within one decade of the published value |
//!
//! Adding a table is one registration in [`registry`] plus one JSON file.
//! Published values are only ever read from the JSON; a computation never sees
//! them.
//!
//! Items: [`Source`], [`Published`], [`ToleranceKind`], [`CellTolerance`],
//! [`ToleranceRules`], [`Tolerance`], [`Status`], [`Entry`],
//! [`RunOptions`], [`LabelledRow`], [`Computed`], [`TableSpec`], [`TableReport`],
//! [`registry`], [`ids`], [`find`], [`run`], [`run_many`], [`LONGEST_TABLES`],
//! [`effective_tolerance`], [`significant_digits`], [`equal_to_digits`],
//! [`digits_apply`], [`compare`], [`book`], [`facts`], [`mls`], [`thesis`],
//! [`tls`].

pub mod book;
pub mod facts;
pub mod mls;
pub mod thesis;
pub mod tls;

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

/// Options of a table computation.
#[derive(Debug, Clone, Copy, Default)]
pub struct RunOptions {
    /// Reduced sizes for smoke tests.
    pub quick: bool,
    /// The largest sizes and the extra studies (`hompm reproduce --full`).
    pub full: bool,
}

/// One computed row, named by the label of the published row it fills.
pub type LabelledRow = (String, Vec<Option<f64>>);

/// What a table computation returns: rows by label, in any order. A row
/// the computation does not return is "not computed"; a label the
/// published table does not have is an error ([`compare`]).
#[derive(Debug, Clone, Default)]
pub struct Computed {
    /// The computed rows; `None` where a number is not computed.
    pub rows: Vec<LabelledRow>,
    /// Free-text findings shown under the table (spreads, alternatives, …).
    pub notes: Vec<String>,
    /// The study behind the table, for the report's charts (only tables
    /// whose charts need more than the table: `mls-aligned`).
    pub study: Option<serde_json::Value>,
}

impl Computed {
    /// Nothing computed: the table is too costly for `--quick`; the report
    /// shows it as not computed, never as regressed.
    pub fn skipped_in_quick_mode() -> Self {
        Self {
            rows: Vec::new(),
            notes: vec!["not computed with --quick".into()],
            study: None,
        }
    }

    /// A row of numbers that were all computed.
    pub fn row(label: impl Into<String>, values: impl IntoIterator<Item = f64>) -> LabelledRow {
        (label.into(), values.into_iter().map(Some).collect())
    }
}

/// A registered table: published numbers, setup, tolerance and computation.
pub struct TableSpec {
    /// Table id.
    pub id: &'static str,
    /// The published JSON text (compiled in from golden/published).
    pub published_json: &'static str,
    /// The setup in one paragraph, as computed here.
    pub setup: &'static str,
    /// Computes the table.
    pub compute: fn(&RunOptions) -> Result<Computed>,
}

/// Published, computed, deviation and status of one table (the `table` JSON
/// schema of DESIGN.md).
#[derive(Debug, Clone, Serialize)]
pub struct TableReport {
    /// Table id.
    pub id: String,
    /// Title.
    pub title: String,
    /// Seed file.
    pub seed: String,
    /// Table and page.
    pub source: Source,
    /// Setup paragraph.
    pub setup: String,
    /// Unit of the values.
    pub unit: String,
    /// Row labels.
    pub row_labels: Vec<String>,
    /// Column labels.
    pub col_labels: Vec<String>,
    /// Published values.
    pub published: Vec<Vec<Option<f64>>>,
    /// Computed values.
    pub computed: Vec<Vec<Option<f64>>>,
    /// (computed − published)/|published|, or the difference where published is 0.
    pub deviation: Vec<Vec<Option<f64>>>,
    /// Status per entry.
    pub status: Vec<Vec<Status>>,
    /// Whether each computed value, rounded to the published value's
    /// printed significant digits, equals it; `None` where nothing is
    /// compared or the kind has no digits to match (bounds, timings,
    /// machine-precision noise; [`digits_apply`]).
    pub to_digits: Vec<Vec<Option<bool>>>,
    /// Tolerance per entry.
    pub tolerance: Vec<Vec<Tolerance>>,
    /// Findings.
    pub notes: Vec<String>,
    /// The study behind the table, when its charts need it (`mls-aligned`).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub study: Option<serde_json::Value>,
}

impl TableReport {
    /// (reproduced, published) counts.
    pub fn counts(&self) -> (usize, usize) {
        let mut rep = 0;
        let mut total = 0;
        for (prow, srow) in self.published.iter().zip(&self.status) {
            for (p, s) in prow.iter().zip(srow) {
                if p.is_some() {
                    total += 1;
                    if *s == Status::Reproduced {
                        rep += 1;
                    }
                }
            }
        }
        (rep, total)
    }

    /// (reproduced to their printed digits, published numbers the digits
    /// status applies to).
    pub fn digit_counts(&self) -> (usize, usize) {
        let cells = self.to_digits.iter().flatten().flatten();
        let applicable = self
            .to_digits
            .iter()
            .zip(&self.published)
            .flat_map(|(d, p)| d.iter().zip(p))
            .filter(|(d, p)| p.is_some() && d.is_some())
            .count();
        (cells.filter(|&&b| b).count(), applicable)
    }

    /// Every cell that is published or computed, in row-major order: the
    /// one walk over a table that the text rendering here and the report's
    /// markdown share, so that both show the same cells and status words.
    pub fn entries(&self) -> impl Iterator<Item = Entry<'_>> + '_ {
        self.row_labels
            .iter()
            .enumerate()
            .flat_map(move |(i, row)| {
                self.col_labels
                    .iter()
                    .enumerate()
                    .filter(move |&(j, _)| {
                        self.published[i][j].is_some() || self.computed[i][j].is_some()
                    })
                    .map(move |(j, column)| Entry {
                        row,
                        column,
                        published: self.published[i][j],
                        computed: self.computed[i][j],
                        deviation: self.deviation[i][j],
                        status: self.status[i][j],
                        to_digits: self
                            .to_digits
                            .get(i)
                            .and_then(|r| r.get(j))
                            .copied()
                            .flatten(),
                    })
            })
    }

    /// Human-readable rendering: one line per published or computed number.
    pub fn render_text(&self) -> String {
        let mut s = format!(
            "{} — {}\nsource: {} {}, p. {} (seed {})\nsetup: {}\nunit: {}\n\n",
            self.id,
            self.title,
            self.source.document,
            self.source.table,
            self.source.page,
            self.seed,
            self.setup,
            self.unit
        );
        // Columns as wide as their longest label, at least 12.
        let cw = self
            .col_labels
            .iter()
            .map(|c| c.chars().count())
            .fold(12, usize::max);
        s.push_str(&format!(
            "{:<24} {:<cw$} {:>14} {:>14} {:>11}  {:<12} {}\n",
            "row", "column", "published", "computed", "deviation", "status", "to digits"
        ));
        let fmt = |x: Option<f64>| x.map_or("—".to_string(), |x| format!("{x:.6e}"));
        for e in self.entries() {
            let dev = e
                .deviation
                .map_or("—".to_string(), |d| format!("{:+.3}%", 100.0 * d));
            s.push_str(&format!(
                "{:<24} {:<cw$} {:>14} {:>14} {:>11}  {:<12} {}\n",
                e.row,
                e.column,
                fmt(e.published),
                fmt(e.computed),
                dev,
                e.status_word(),
                e.digits_word()
            ));
        }
        let (rep, total) = self.counts();
        let (dig, applicable) = self.digit_counts();
        s.push_str(&format!(
            "\n{rep} of {total} published numbers reproduced; {dig} of {applicable} to their printed digits\n"
        ));
        for n in &self.notes {
            s.push_str(&format!("note: {n}\n"));
        }
        s
    }
}

/// One cell of a [`TableReport`], as [`TableReport::entries`] yields it.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Entry<'a> {
    /// Row label.
    pub row: &'a str,
    /// Column label.
    pub column: &'a str,
    /// The published value, if any.
    pub published: Option<f64>,
    /// The computed value, if any.
    pub computed: Option<f64>,
    /// (computed − published)/|published|, where both exist.
    pub deviation: Option<f64>,
    /// The status.
    pub status: Status,
    /// Reproduced to the printed digits (`None`: does not apply).
    pub to_digits: Option<bool>,
}

impl Entry<'_> {
    /// "reproduced", "deviates", "not computed", or "extra" for a computed
    /// value the publication does not print.
    pub fn status_word(&self) -> &'static str {
        match (self.published, self.status) {
            (None, _) => "extra",
            (_, Status::Reproduced) => "reproduced",
            (_, Status::Deviates) => "deviates",
            (_, Status::NotComputed) => "not computed",
        }
    }

    /// "yes", "no", or "—" where the digits status does not apply.
    pub fn digits_word(&self) -> &'static str {
        match self.to_digits {
            Some(true) => "yes",
            Some(false) => "no",
            None => "—",
        }
    }
}

/// Every registered table, in the order of DESIGN.md.
pub fn registry() -> Vec<TableSpec> {
    let mut all = book::tables();
    all.extend(tls::tables());
    all.extend(thesis::tables());
    all.push(thesis::appendix_a1());
    all.push(facts::table());
    all.push(mls::aligned());
    all
}

/// The ids of all registered tables.
pub fn ids() -> Vec<&'static str> {
    registry().iter().map(|t| t.id).collect()
}

/// Looks up a table by id.
pub fn find(id: &str) -> Result<TableSpec> {
    registry()
        .into_iter()
        .find(|t| t.id == id)
        .ok_or_else(|| Error::UnknownTable(id.to_string()))
}

/// Computes one table and compares it with its published numbers.
pub fn run(spec: &TableSpec, options: &RunOptions) -> Result<TableReport> {
    let published = Published::parse(spec.id, spec.published_json)?;
    let computed = (spec.compute)(options)?;
    compare(spec, &published, computed)
}

/// Runs the given tables in parallel (rayon); `progress` is called after each.
pub fn run_many(
    ids: &[&str],
    options: RunOptions,
    progress: &(dyn Fn(&str, f64) + Sync),
) -> Result<Vec<TableReport>> {
    use rayon::prelude::*;
    let specs: Vec<_> = ids.iter().map(|id| find(id)).collect::<Result<_>>()?;
    // The longest tables start first, so that the others fill the other
    // core while they run; the reports come back in `ids` order.
    let mut order: Vec<usize> = (0..specs.len()).collect();
    order.sort_by_key(|&i| !LONGEST_TABLES.contains(&specs[i].id));
    let mut reports: Vec<(usize, Result<TableReport>)> = order
        .par_iter()
        .map(|&i| {
            let spec = &specs[i];
            let t = std::time::Instant::now();
            let r = run(spec, &options);
            progress(spec.id, t.elapsed().as_secs_f64());
            (i, r)
        })
        .collect();
    reports.sort_by_key(|(i, _)| *i);
    reports.into_iter().map(|(_, r)| r).collect()
}

/// Tables that take most of `hompm reproduce` (mls-aligned: about two
/// minutes of its one longest run), started before the others.
pub const LONGEST_TABLES: [&str; 1] = ["mls-aligned"];

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

/// Places computed rows by their labels: an unknown or repeated label, or
/// a row of the wrong length, is an error; a row not returned stays `None`.
fn rows_by_label(
    id: &str,
    published: &Published,
    rows: Vec<LabelledRow>,
) -> Result<Vec<Vec<Option<f64>>>> {
    let cols = published.col_labels.len();
    let mut grid: Vec<Option<Vec<Option<f64>>>> = vec![None; published.row_labels.len()];
    let fail = |message: String| Error::Published {
        id: id.into(),
        message,
    };
    for (label, values) in rows {
        let r = published
            .row_labels
            .iter()
            .position(|l| *l == label)
            .ok_or_else(|| {
                fail(format!(
                    "the computation returned row '{label}', which the table does not have"
                ))
            })?;
        if values.len() != cols {
            return Err(fail(format!(
                "row '{label}' has {} values for {cols} columns",
                values.len()
            )));
        }
        if grid[r].replace(values).is_some() {
            return Err(fail(format!(
                "the computation returned row '{label}' twice"
            )));
        }
    }
    Ok(grid
        .into_iter()
        .map(|r| r.unwrap_or_else(|| vec![None; cols]))
        .collect())
}

/// Builds the report from published and computed grids.
pub fn compare(spec: &TableSpec, published: &Published, computed: Computed) -> Result<TableReport> {
    let rows = published.row_labels.len();
    let cols = published.col_labels.len();
    let values = rows_by_label(spec.id, published, computed.rows)?;
    let tolerance: Vec<Vec<Tolerance>> = published
        .row_labels
        .iter()
        .map(|r| {
            published
                .col_labels
                .iter()
                .map(|c| published.tolerance.at(r, c))
                .collect()
        })
        .collect();
    let mut deviation = vec![vec![None; cols]; rows];
    let mut status = vec![vec![Status::NotComputed; cols]; rows];
    let mut to_digits = vec![vec![None; cols]; rows];
    for r in 0..rows {
        for c in 0..cols {
            if let (Some(p), Some(v)) = (published.values[r][c], values[r][c]) {
                let kind = effective_tolerance(tolerance[r][c], p);
                deviation[r][c] = Some(if p != 0.0 { (v - p) / p.abs() } else { v - p });
                status[r][c] = if kind.accepts(p, v) {
                    Status::Reproduced
                } else {
                    Status::Deviates
                };
                if let (true, Some(d)) = (digits_apply(kind), published.digits[r][c]) {
                    to_digits[r][c] = Some(equal_to_digits(p, v, d));
                }
            }
        }
    }
    Ok(TableReport {
        id: spec.id.into(),
        title: published.title.clone(),
        seed: published.seed.clone(),
        source: published.source.clone(),
        setup: spec.setup.into(),
        unit: published.unit.clone(),
        row_labels: published.row_labels.clone(),
        col_labels: published.col_labels.clone(),
        published: published.values.clone(),
        computed: values,
        deviation,
        status,
        to_digits,
        tolerance,
        notes: computed.notes,
        study: computed.study,
    })
}
