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
//! them. The transcriptions, their printed digits and the tolerance rules
//! live in `published.rs` (re-exported here); this file registers, runs and
//! compares.
//!
//! Items: [`Source`], [`Published`], [`ToleranceKind`], [`CellTolerance`],
//! [`ToleranceRules`], [`Tolerance`], [`Status`], [`Entry`],
//! [`RunOptions`], [`LabelledRow`], [`Computed`], [`Study`], [`TableSpec`], [`TableReport`],
//! [`registry`], [`ids`], [`find`], [`run`], [`run_many`], [`TABLE_CPU_SECONDS`],
//! [`effective_tolerance`], [`significant_digits`], [`equal_to_digits`],
//! [`digits_apply`], [`compare`], [`book`], [`facts`], [`mls`], [`mls_code`], [`mls_convergence`], [`thesis`],
//! [`tls`].

pub mod book;
pub mod facts;
pub mod mls;
pub mod mls_code;
pub mod mls_convergence;
pub mod thesis;
pub mod tls;

mod published;
pub use published::Published;
pub use published::{digits_apply, effective_tolerance, equal_to_digits, significant_digits};
pub use published::{CellTolerance, Source, Status, Tolerance, ToleranceKind, ToleranceRules};

use crate::error::{Error, Result};
use crate::studies::mls_convergence::ConventionStudy;
use crate::studies::mls_paper::AlignedStudy;
use crate::studies::tls_paper::SubpointStudy;
use serde::Serialize;

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
    /// whose charts need more than the table: `mls-aligned`, `tls-8`).
    pub study: Option<Study>,
}

/// The study behind a table whose charts or report need more than its
/// rows, typed, so that the charts read it without parsing JSON.
/// report.json carries it as before: as a JSON object with sorted keys.
#[derive(Debug, Clone, PartialEq)]
pub enum Study {
    /// `mls-aligned`: the MLS paper's study of the aligned vibration.
    MlsAligned(Box<AlignedStudy>),
    /// `mls-convergence-study`: the aligned vibration under other codes'
    /// conventions (issue #38).
    MlsConvergence(Box<ConventionStudy>),
    /// `tls-8`: the subpoint study, with midpoint and end placements.
    Subpoints {
        /// Subpoints at the midpoints of equal parts of the particle.
        midpoints: SubpointStudy,
        /// Subpoints including both ends of the particle.
        ends: SubpointStudy,
    },
}

impl Serialize for Study {
    fn serialize<S: serde::Serializer>(
        &self,
        serializer: S,
    ) -> std::result::Result<S::Ok, S::Error> {
        use serde::ser::Error as _;
        let json = match self {
            Study::MlsAligned(study) => serde_json::to_value(study),
            Study::MlsConvergence(study) => serde_json::to_value(study),
            Study::Subpoints { midpoints, ends } => serde_json::to_value(midpoints).and_then(|m| {
                Ok(serde_json::json!({ "midpoints": m, "ends": serde_json::to_value(ends)? }))
            }),
        }
        .map_err(S::Error::custom)?;
        json.serialize(serializer)
    }
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
    /// machine-precision noise; [`digits_apply`]). In JSON each entry is
    /// `"yes"`, `"no"` or `"n/a"`, never `null`.
    #[serde(serialize_with = "digits_as_words")]
    pub to_digits: Vec<Vec<Option<bool>>>,
    /// Tolerance per entry.
    pub tolerance: Vec<Vec<Tolerance>>,
    /// Findings.
    pub notes: Vec<String>,
    /// The study behind the table, when its charts need it (`mls-aligned`,
    /// `tls-8`).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub study: Option<Study>,
}

/// `to_digits` in JSON: `"yes"`, `"no"` or `"n/a"` per entry.
fn digits_as_words<S: serde::Serializer>(
    rows: &[Vec<Option<bool>>],
    serializer: S,
) -> std::result::Result<S::Ok, S::Error> {
    let words: Vec<Vec<&str>> = rows
        .iter()
        .map(|row| {
            row.iter()
                .map(|d| match d {
                    Some(true) => "yes",
                    Some(false) => "no",
                    None => "n/a",
                })
                .collect()
        })
        .collect();
    serde::Serialize::serialize(&words, serializer)
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
    all.push(mls_code::table());
    all.push(mls_convergence::table());
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

/// Runs the given tables in parallel; `progress` is called after each.
/// One worker per rayon thread takes the next table of a longest-first
/// list ([`TABLE_CPU_SECONDS`]), so that the long serial tables start early
/// and the short ones fill the cores at the end; the reports come back in
/// `ids` order, so they do not depend on the scheduling.
pub fn run_many(
    ids: &[&str],
    options: RunOptions,
    progress: &(dyn Fn(&str, f64) + Sync),
) -> Result<Vec<TableReport>> {
    use rayon::prelude::*;
    let specs: Vec<_> = ids.iter().map(|id| find(id)).collect::<Result<_>>()?;
    let mut order: Vec<usize> = (0..specs.len()).collect();
    order.sort_by(|&a, &b| cpu_seconds(specs[b].id).total_cmp(&cpu_seconds(specs[a].id)));
    let next = std::sync::atomic::AtomicUsize::new(0);
    let done: std::sync::Mutex<Vec<(usize, Result<TableReport>)>> =
        std::sync::Mutex::new(Vec::new());
    (0..rayon::current_num_threads().max(1))
        .into_par_iter()
        .for_each(|_| loop {
            let k = next.fetch_add(1, std::sync::atomic::Ordering::SeqCst);
            let Some(&i) = order.get(k) else { break };
            let spec = &specs[i];
            let t = std::time::Instant::now();
            let r = run(spec, &options);
            progress(spec.id, t.elapsed().as_secs_f64());
            if let Ok(mut d) = done.lock() {
                d.push((i, r));
            }
        });
    let mut reports = done.into_inner().unwrap_or_default();
    if reports.len() != specs.len() {
        return Err(Error::LengthMismatch {
            what: "table reports (one per table run)".into(),
            expected: specs.len(),
            got: reports.len(),
        });
    }
    reports.sort_by_key(|(i, _)| *i);
    reports.into_iter().map(|(_, r)| r).collect()
}

/// The processor time (user + system, seconds) of the tables that take
/// more than a second, each measured alone (`hompm table ID`, release
/// build, 2 cores, at e1edbc2): the order in which [`run_many`] starts
/// them. A table not listed counts as 0 s.
pub const TABLE_CPU_SECONDS: [(&str, f64); 9] = [
    ("mls-aligned", 138.6),
    ("mls-convergence-study", 78.5),
    ("tls-8", 34.7),
    ("tls-7", 9.7),
    ("book-4.3", 5.4),
    ("tls-fig10", 5.3),
    ("book-4.4", 5.0),
    ("thesis-7.1", 2.2),
    ("book-4.5-large", 1.1),
];

/// A table's entry in [`TABLE_CPU_SECONDS`], or 0.
fn cpu_seconds(id: &str) -> f64 {
    TABLE_CPU_SECONDS
        .iter()
        .find(|(t, _)| *t == id)
        .map_or(0.0, |(_, s)| *s)
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
