//! # `hompm reproduce`: every table, the studies, the report
//!
//! Checks its output locations first, then runs the registered tables (with
//! a progress bar on a terminal) and, beside them, the studies, then the
//! charts, writes the report,
//! and fails if a number marked reproduced in golden/reproduced.json no
//! longer reproduces.
//!
//! Items: [`ReproduceArgs`], [`reproduce`].

use super::Output;
use crate::error::{Error, Result};
use crate::report;
use crate::tables::{self, RunOptions};
use std::collections::BTreeMap;
use std::path::{Path, PathBuf};

/// Arguments of `hompm reproduce`.
#[derive(clap::Args, Debug)]
pub struct ReproduceArgs {
    /// Output directory.
    #[arg(long, default_value = "target/hompm-report")]
    out: PathBuf,
    /// Only these table ids (studies and charts are skipped).
    #[arg(long, num_args = 1.., value_delimiter = ',')]
    only: Vec<String>,
    /// Reduced sizes (smoke test).
    #[arg(long, conflicts_with = "full")]
    quick: bool,
    /// The largest sizes and the extra studies (mls-aligned: 64 cells, the
    /// PPC study, E = 1e8 Pa; mls-convergence-study: 8-64 cells to T,
    /// which alone took 53 min on 2 shared cores).
    #[arg(long)]
    full: bool,
    /// Also write the generated reproduction status to this path
    /// (docs/reproduction.md in the repository).
    #[arg(long)]
    docs: Option<PathBuf>,
    /// Write the reproduced cells to the crate's own golden/reproduced.json
    /// (a reviewed change; refused when the source tree is not there).
    #[arg(long)]
    update_baseline: bool,
}

/// The baseline file of the crate this binary was built from.
const BASELINE: &str = concat!(env!("CARGO_MANIFEST_DIR"), "/golden/reproduced.json");

/// The --only ids and every output location are checked before any table
/// is computed: the output directory is created and written to, the --docs
/// directory must exist, and --update-baseline needs the crate's golden/.
fn check_outputs(a: &ReproduceArgs) -> Result<()> {
    for o in &a.only {
        tables::find(o)?;
    }
    let io =
        |what: &str, p: &Path, e: std::io::Error| Error::Io(format!("{what} {}: {e}", p.display()));
    std::fs::create_dir_all(&a.out)
        .map_err(|e| io("cannot create the output directory", &a.out, e))?;
    let probe = a.out.join(".hompm-write-probe");
    std::fs::write(&probe, b"")
        .map_err(|e| io("cannot write in the output directory", &a.out, e))?;
    let _ = std::fs::remove_file(&probe);
    if let Some(docs) = &a.docs {
        let dir = docs
            .parent()
            .filter(|d| !d.as_os_str().is_empty())
            .unwrap_or(Path::new("."));
        if !dir.is_dir() {
            return Err(Error::Io(format!(
                "--docs {}: directory {} does not exist",
                docs.display(),
                dir.display()
            )));
        }
    }
    let golden = Path::new(BASELINE).parent().unwrap_or(Path::new(BASELINE));
    if a.update_baseline && !golden.is_dir() {
        return Err(Error::Io(format!(
            "--update-baseline writes {BASELINE}, but {} is not there (run it from the hompm source tree it was built from)",
            golden.display()
        )));
    }
    Ok(())
}

/// Runs the tables with progress on stderr: a bar on a terminal, one line
/// per table otherwise.
fn run_tables(ids: &[&str], options: RunOptions) -> Result<Vec<tables::TableReport>> {
    use std::io::IsTerminal;
    let terminal = std::io::stderr().is_terminal();
    let bar = indicatif::ProgressBar::new(ids.len() as u64);
    if terminal {
        bar.set_style(
            indicatif::ProgressStyle::with_template("{bar:30} {pos}/{len} tables  {msg}")
                .unwrap_or_else(|_| indicatif::ProgressStyle::default_bar()),
        );
    } else {
        bar.set_draw_target(indicatif::ProgressDrawTarget::hidden());
    }
    let done = std::sync::atomic::AtomicUsize::new(0);
    let progress = |id: &str, secs: f64| {
        let k = done.fetch_add(1, std::sync::atomic::Ordering::SeqCst) + 1;
        if terminal {
            bar.set_message(format!("{id} ({secs:.1} s)"));
            bar.inc(1);
        } else {
            eprintln!("[{k}/{}] {id} ({secs:.1} s)", ids.len());
        }
    };
    let reports = tables::run_many(ids, options, &progress)?;
    bar.finish_and_clear();
    Ok(reports)
}

/// The studies (`studies::report`); they need no table.
fn run_studies(quick: bool) -> Result<crate::studies::report::ReportStudies> {
    let done = |name: &str, seconds: f64| eprintln!("study {name} ({seconds:.1} s)");
    crate::studies::report::run_report_studies(quick, &done)
}

/// The charts of the tables and studies (`report`), which only render.
fn write_charts(
    out: &Path,
    reports: &[tables::TableReport],
    studies: &crate::studies::report::ReportStudies,
) -> Result<BTreeMap<String, serde_json::Value>> {
    report::write_charts(&out.join("charts"), reports, studies)?;
    report::studies_json(studies)
}

/// `hompm reproduce`.
pub fn reproduce(a: ReproduceArgs) -> Result<Output> {
    check_outputs(&a)?;
    let ids: Vec<&str> = tables::ids()
        .into_iter()
        .filter(|id| a.only.is_empty() || a.only.iter().any(|o| o == id))
        .collect();
    let options = RunOptions {
        quick: a.quick,
        full: a.full,
    };
    // The studies need no table: they run beside the tables, so that their
    // one-thread parts (the solver and speed timings) fill the core the
    // tables' last runs leave idle, instead of running after them on one.
    let (reports, studies) = if a.only.is_empty() {
        let (reports, studies) = rayon::join(|| run_tables(&ids, options), || run_studies(a.quick));
        let (reports, studies) = (reports?, studies?);
        let charts = write_charts(&a.out, &reports, &studies)?;
        (reports, charts)
    } else {
        (run_tables(&ids, options)?, BTreeMap::new())
    };
    let options = report::ReproduceOptions {
        out: a.out.clone(),
        only: a.only.clone(),
        quick: a.quick,
    };
    let built = report::build(reports, &options, studies)?;
    if let Some(path) = &a.docs {
        let notes = include_str!("../../docs/reproduction-notes.md");
        report::write_file(path, &report::reproduction_markdown(&built, notes)?)?;
    }
    let baseline: report::Baseline =
        serde_json::from_str(include_str!("../../golden/reproduced.json")).map_err(|e| {
            Error::Published {
                id: "reproduced.json".into(),
                message: e.to_string(),
            }
        })?;
    if a.update_baseline {
        let mut merged = baseline.clone();
        merged.extend(report::baseline_of(&built.tables));
        let text = serde_json::to_string_pretty(&merged).map_err(|e| Error::Io(e.to_string()))?;
        report::write_file(Path::new(BASELINE), &(text + "\n"))?;
    }
    let stdout = summary(&built, &a.out);
    let regressed = report::regressions(&checked_tables(&built.tables, a.quick, a.full), &baseline);
    let failure = (!regressed.is_empty() && !a.update_baseline).then(|| {
        Error::InvalidArgument(format!(
            "{} published numbers marked reproduced no longer reproduce: {}",
            regressed.len(),
            regressed.join("; ")
        ))
    });
    Ok(Output {
        stdout,
        warnings: Vec::new(),
        failure,
    })
}

fn summary(built: &report::ReportJson, out: &Path) -> String {
    let mut s = String::new();
    for r in &built.tables {
        let (rep, total) = r.counts();
        let (dig, applicable) = r.digit_counts();
        s.push_str(&format!(
            "{:<20} {rep:>4} of {total:>4} reproduced, {dig:>4} of {applicable:>4} to their digits\n",
            r.id
        ));
    }
    s.push_str(&format!("report written to {}\n", out.display()));
    s.push_str(&format!(
        "{} of {} published numbers reproduced; {} of {} to their printed digits\n",
        built.reproduced, built.published_in_computed_tables, built.to_digits, built.digits_apply
    ));
    s
}

/// Tables whose setup `--full` changes (mls-aligned: its finest pair is
/// 32/64 cells instead of 16/32; mls-convergence-study: 64 cells and T
/// instead of 16 cells and one period), so the default run's baseline does
/// not apply to them.
const CHANGED_BY_FULL: [&str; 2] = ["mls-aligned", "mls-convergence-study"];

/// With --quick, cells that are not computed are skipped, not regressions;
/// with --full, so are the tables of [`CHANGED_BY_FULL`].
fn checked_tables(
    tables: &[tables::TableReport],
    quick: bool,
    full: bool,
) -> Vec<tables::TableReport> {
    tables
        .iter()
        .cloned()
        .map(|mut r| {
            if full && CHANGED_BY_FULL.contains(&r.id.as_str()) {
                r.status
                    .iter_mut()
                    .flatten()
                    .for_each(|s| *s = tables::Status::Reproduced);
            }
            if quick {
                for (i, row) in r.computed.iter().enumerate() {
                    for (j, v) in row.iter().enumerate() {
                        if v.is_none() {
                            r.status[i][j] = tables::Status::Reproduced;
                        }
                    }
                }
            }
            r
        })
        .collect()
}
