//! # The report
//!
//! `hompm reproduce` runs every registered table, compares it with the
//! published numbers and writes, into one directory:
//! - `report.md`: a section per table (published, computed, deviation, status,
//!   setup, seed and page, notes) and the studies with their charts;
//! - `report.json`: every number (schema in [`ReportJson`]);
//! - `reproduction.md`: the status of every published number of the four
//!   seeds, implemented or not (committed as docs/reproduction.md);
//! - `charts/*.svg|png`: convergence, work-precision, solver cost, stability.
//!
//! The module is split the way the data flow: this file holds the schema
//! ([`ReportJson`]) and [`build`], which assembles it and writes the files;
//! `baseline` the regression baseline by label; `markdown` the markdown of
//! report.md and docs/reproduction.md; `figures`, `mls_figures` and `convention_figures` one function per
//! chart over [`charts`]. Their public functions are re-exported here
//! (`report::baseline_of`, `report::table_markdown`, `report::write_charts`
//! and the other chart functions).
//!
//! A new table is a registration in `tables`; a new chart is one function
//! in `figures` that turns a study into a [`charts::Chart`], plus one line
//! in its `write_charts`.
//!
//! Items: [`Unimplemented`], [`unimplemented()`], [`ReportJson`],
//! [`write_file`], [`ReproduceOptions`], [`studies_json`], [`build`],
//! [`causes`], [`charts`] (and re-exported [`convention_charts`], [`mls_charts`]).

mod baseline;
pub mod causes;
pub mod charts;
mod convention_figures;
mod figures;
mod markdown;
mod mls_figures;

pub use baseline::{baseline_of, regressions, Baseline};
pub use convention_figures::convention_charts;
pub use figures::{
    convergence_charts, solver_table_charts, solver_time_chart, speed_chart, stability_chart,
    work_precision_chart, write_charts,
};
pub use markdown::{reproduction_markdown, table_markdown};
pub use mls_figures::mls_charts;

use crate::error::{Error, Result};
use crate::studies::report::ReportStudies;
use crate::tables::TableReport;
use serde::{Deserialize, Serialize};
use std::collections::BTreeMap;
use std::path::Path;

/// A published table that hompm does not compute yet, with its count of
/// published numbers (golden/unimplemented.json).
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct Unimplemented {
    /// Table id.
    pub id: String,
    /// Seed short name and place.
    pub source: String,
    /// Number of published numbers.
    pub count: usize,
    /// Why it is not computed and what it waits for.
    pub waiting_for: String,
}

/// The published tables not computed yet.
pub fn unimplemented() -> Result<Vec<Unimplemented>> {
    serde_json::from_str(include_str!("../../golden/unimplemented.json")).map_err(|e| {
        Error::Published {
            id: "unimplemented".into(),
            message: e.to_string(),
        }
    })
}

/// The machine-readable report.
#[derive(Debug, Clone, Serialize)]
pub struct ReportJson {
    /// Reproduced published numbers over all computed tables.
    pub reproduced: usize,
    /// Published numbers reproduced to their printed digits.
    pub to_digits: usize,
    /// Published numbers the digits status applies to (not bounds,
    /// timings or machine-precision noise).
    pub digits_apply: usize,
    /// Published numbers in the computed tables.
    pub published_in_computed_tables: usize,
    /// Published numbers in all seeds' tables, computed or not.
    pub published_total: usize,
    /// Every computed table (the `table` schema of DESIGN.md).
    pub tables: Vec<TableReport>,
    /// Tables not computed yet.
    pub unimplemented: Vec<Unimplemented>,
    /// Study data behind the charts (keys: convergence, work_precision, solvers, stability).
    pub studies: BTreeMap<String, serde_json::Value>,
}

/// Writes a text file, creating its directory.
pub fn write_file(path: &Path, text: &str) -> Result<()> {
    if let Some(dir) = path.parent() {
        std::fs::create_dir_all(dir).map_err(|e| Error::Io(format!("{}: {e}", dir.display())))?;
    }
    std::fs::write(path, text).map_err(|e| Error::Io(format!("{}: {e}", path.display())))
}

/// Options of a full report run.
#[derive(Debug, Clone)]
pub struct ReproduceOptions {
    /// Output directory.
    pub out: std::path::PathBuf,
    /// Only these table ids (all if empty); studies run only without `only`.
    pub only: Vec<String>,
    /// Reduced sizes.
    pub quick: bool,
}

/// The studies' results as report.json carries them, by name.
pub fn studies_json(studies: &ReportStudies) -> Result<BTreeMap<String, serde_json::Value>> {
    let value = |v: serde_json::Result<serde_json::Value>| v.map_err(|e| Error::Io(e.to_string()));
    let mut out = BTreeMap::new();
    out.insert(
        "convergence".into(),
        value(serde_json::to_value(&studies.convergence))?,
    );
    out.insert(
        "work_precision".into(),
        value(serde_json::to_value(&studies.work_precision))?,
    );
    out.insert(
        "solvers".into(),
        value(serde_json::to_value(&studies.solvers))?,
    );
    out.insert(
        "stability".into(),
        value(serde_json::to_value(&studies.stability))?,
    );
    out.insert(
        "failures".into(),
        value(serde_json::to_value(studies.failures))?,
    );
    out.insert("speed".into(), value(serde_json::to_value(&studies.speed))?);
    Ok(out)
}

/// The full report: tables, studies, charts, markdown and JSON.
pub fn build(
    reports: Vec<TableReport>,
    options: &ReproduceOptions,
    studies: BTreeMap<String, serde_json::Value>,
) -> Result<ReportJson> {
    let unimpl = unimplemented()?;
    let (reproduced, published) = reports
        .iter()
        .map(|r| r.counts())
        .fold((0, 0), |(a, b), (c, d)| (a + c, b + d));
    let (to_digits, digits_apply) = reports
        .iter()
        .map(|r| r.digit_counts())
        .fold((0, 0), |(a, b), (c, d)| (a + c, b + d));
    let total = published + unimpl.iter().map(|u| u.count).sum::<usize>();
    let report = ReportJson {
        reproduced,
        to_digits,
        digits_apply,
        published_in_computed_tables: published,
        published_total: total,
        tables: reports,
        unimplemented: unimpl,
        studies,
    };
    let chart_of = |id: &str| match id {
        "book-4.3" => Some("solver_cg_iterations"),
        "book-4.4" => Some("solver_pmg_cycles"),
        "tls-fig6" => Some("convergence_displacement"),
        "mls-aligned" => Some("mls_convergence_displacement"),
        _ => None,
    };
    let mut md =
        format!(
        "# hompm report\n\n**{} of {} published numbers reproduced**, {} of {} to their printed digits ({} computed tables{}).\n\n",
        report.reproduced,
        report.published_in_computed_tables,
        report.to_digits,
        report.digits_apply,
        report.tables.len(),
        if options.quick { ", quick mode: reduced sizes" } else { "" }
    );
    if options.only.is_empty() {
        md.push_str("## Charts\n\n![work-precision](charts/work_precision.svg)\n![speed](charts/speed.svg)\n\n![convergence of displacement](charts/convergence_displacement.svg)\n![convergence of velocity](charts/convergence_velocity.svg)\n![convergence of stress](charts/convergence_stress.svg)\n\n![CG iterations](charts/solver_cg_iterations.svg)\n![V-cycles](charts/solver_pmg_cycles.svg)\n![solver time](charts/solver_time.svg)\n\n![stability map](charts/stability_map.svg)\n\n![MLS paper: displacement](charts/mls_convergence_displacement.svg)\n![MLS paper: velocity](charts/mls_convergence_velocity.svg)\n![MLS paper: stress](charts/mls_convergence_stress.svg)\n![MLS paper: error against time](charts/mls_error_history.svg)\n![MLS paper: work-precision](charts/mls_work_precision.svg)\n![MLS and TLS: mapping errors](charts/mls_conservation.svg)\n\n![Other codes' conventions: convergence](charts/convention_convergence.svg)\n![Other codes' conventions: work-precision](charts/convention_work_precision.svg)\n![Other codes' conventions: stability](charts/convention_stability.svg)\n\n");
    }
    for r in &report.tables {
        md.push_str(&table_markdown(r, chart_of(&r.id)));
    }
    write_file(&options.out.join("report.md"), &md)?;
    let json = serde_json::to_string_pretty(&report).map_err(|e| Error::Io(e.to_string()))?;
    write_file(&options.out.join("report.json"), &(json + "\n"))?;
    write_file(
        &options.out.join("reproduction.md"),
        &reproduction_markdown(&report, include_str!("../../docs/reproduction-notes.md"))?,
    )?;
    Ok(report)
}
