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
//! A new table is a registration in `tables`; a new chart is one function
//! here that turns a study into a [`charts::Chart`].
//!
//! Items: [`Unimplemented`], [`unimplemented()`], [`ReportJson`],
//! [`Baseline`], [`baseline_of`], [`regressions`],
//! [`table_markdown`], [`reproduction_markdown`], [`write_file`],
//! [`ReproduceOptions`], [`convergence_charts`], [`work_precision_chart`],
//! [`speed_chart`], [`solver_table_charts`], [`solver_time_chart`],
//! [`stability_chart`], [`write_charts`], [`mls_charts`], [`studies_json`],
//! [`build`], [`causes`], [`charts`].

pub mod causes;
pub mod charts;

use crate::error::{Error, Result};
use crate::scenes::aligned_vibration::{self, AlignedErrors, AlignedMethod};
use crate::studies::failures::FailureCases;
use crate::studies::mls_paper::{self, AlignedStudy, RunOutcome};
use crate::studies::report::{ConvergenceLine, ConvergenceOrders, ReportStudies};
use crate::studies::tls_paper;
use crate::studies::{BarErrors, SolverPoint, SpeedPoint, StabilityPoint, WorkPoint};
use crate::tables::{Status, TableReport, Tolerance};
use charts::{Chart, Series, Style};
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

/// The cells that reproduced, per table: the regression baseline. Each cell
/// is named by its row and column labels, as the tables couple by label,
/// so a table whose rows are reordered or extended keeps its baseline.
pub type Baseline = BTreeMap<String, Vec<[String; 2]>>;

/// The reproduced cells of a set of reports, except measured wall times
/// ([`Tolerance::Timing`]), which vary from run to run.
pub fn baseline_of(reports: &[TableReport]) -> Baseline {
    reports
        .iter()
        .map(|r| {
            let cells = r
                .status
                .iter()
                .enumerate()
                .flat_map(|(i, row)| {
                    row.iter()
                        .enumerate()
                        .filter(move |(j, s)| {
                            **s == Status::Reproduced && r.tolerance[i][*j] != Tolerance::Timing
                        })
                        .map(move |(j, _)| [r.row_labels[i].clone(), r.col_labels[j].clone()])
                })
                .collect();
            (r.id.clone(), cells)
        })
        .collect()
}

/// Cells marked reproduced in the baseline that no longer reproduce, or
/// whose row or column label the table no longer has.
pub fn regressions(reports: &[TableReport], baseline: &Baseline) -> Vec<String> {
    let mut out = Vec::new();
    for r in reports {
        for [row, col] in baseline.get(&r.id).into_iter().flatten() {
            let i = r.row_labels.iter().position(|l| l == row);
            let j = r.col_labels.iter().position(|l| l == col);
            let status = i.zip(j).and_then(|(i, j)| r.status.get(i)?.get(j));
            if status != Some(&Status::Reproduced) {
                out.push(format!("{} [{row} / {col}]", r.id));
            }
        }
    }
    out
}

fn fmt(v: Option<f64>) -> String {
    v.map_or("—".into(), |v| {
        if v != 0.0 && (v.abs() < 1e-3 || v.abs() >= 1e5) {
            format!("{v:.4e}")
        } else {
            format!("{v:.5}")
        }
    })
}

/// The markdown section of one table.
pub fn table_markdown(r: &TableReport, chart: Option<&str>) -> String {
    let (rep, total) = r.counts();
    let (dig, applicable) = r.digit_counts();
    let mut s = format!(
        "## `{}` — {}\n\n*{} {}, p. {} (seed `{}`)* — **{rep} of {total} reproduced**, {dig} of {applicable} to their printed digits\n\n{}\n\n",
        r.id, r.title, r.source.document, r.source.table, r.source.page, r.seed, r.setup
    );
    s.push_str(
        "| row | column | published | computed | deviation | status | to digits |\n|---|---|---|---|---|---|---|\n",
    );
    for e in r.entries() {
        let dev = e
            .deviation
            .map_or("—".into(), |d| format!("{:+.3} %", 100.0 * d));
        s.push_str(&format!(
            "| {} | {} | {} | {} | {dev} | {} | {} |\n",
            e.row,
            e.column,
            fmt(e.published),
            fmt(e.computed),
            e.status_word(),
            e.digits_word()
        ));
    }
    for n in &r.notes {
        s.push_str(&format!("\n> {n}\n"));
    }
    if let Some(c) = chart {
        s.push_str(&format!("\n![{}](charts/{c}.svg)\n", r.id));
    }
    s.push('\n');
    s
}

/// The generated reproduction status (docs/reproduction.md): a summary, one
/// line per table, every published number with the cause of each deviation
/// ([`causes`]), then the analysis of docs/reproduction-notes.md.
pub fn reproduction_markdown(report: &ReportJson, notes: &str) -> Result<String> {
    let rules = causes::causes()?;
    let mut counts = CauseCounts::default();
    let mut lines = String::new();
    for r in &report.tables {
        for e in r.entries().filter(|e| e.published.is_some()) {
            let dev = e
                .deviation
                .map_or("—".into(), |d| format!("{:+.3} %", 100.0 * d));
            let cause = if e.status == Status::Deviates {
                counts.cause_cell(causes::cause_of(&rules, &r.id, e.row, e.column))
            } else {
                String::new()
            };
            lines.push_str(&format!(
                "| `{}` | {} | {} | {} | {} | {dev} | {} | {} | {cause} |\n",
                r.id,
                e.row,
                e.column,
                fmt(e.published),
                fmt(e.computed),
                e.status_word(),
                e.digits_word()
            ));
        }
    }
    let mut s = String::from("# Reproduction status\n\n");
    s.push_str("*Generated by `hompm reproduce --docs docs/reproduction.md` from report.json; the causes come from golden/deviation-causes.json, the analysis below the tables from docs/reproduction-notes.md.*\n\n");
    s.push_str(&format!(
        "**{} of {} published numbers reproduced** in the {} computed tables, **{} of the {} that have digits to match reproduced to their printed digits** (bounds, timings and machine-precision noise have none); the four seeds publish {} numbers in the tables hompm tracks, {} of which are not computed yet (listed below). Of the {} deviations, **{} have a demonstrated cause** and {} a hypothesis; {} have none recorded.\n\n",
        report.reproduced,
        report.published_in_computed_tables,
        report.tables.len(),
        report.to_digits,
        report.digits_apply,
        report.published_total,
        report.published_total - report.published_in_computed_tables,
        counts.demonstrated + counts.hypotheses + counts.unexplained,
        counts.demonstrated,
        counts.hypotheses,
        counts.unexplained,
    ));
    s.push_str(&table_summary_rows(report));
    s.push_str("\n## Every published number\n\n| table | row | column | published | computed | deviation | status | to digits | cause of the deviation |\n|---|---|---|---|---|---|---|---|---|\n");
    s.push_str(&lines);
    s.push('\n');
    s.push_str(notes);
    Ok(s)
}

/// The deviations of docs/reproduction.md by the kind of their cause.
#[derive(Debug, Default)]
struct CauseCounts {
    demonstrated: usize,
    hypotheses: usize,
    unexplained: usize,
}

impl CauseCounts {
    /// The cause column of one deviation, counted by kind.
    fn cause_cell(&mut self, cause: Option<&causes::DeviationCause>) -> String {
        match cause {
            Some(c) if c.kind == causes::CauseKind::Demonstrated => {
                self.demonstrated += 1;
                format!("**demonstrated**: {} ({})", c.cause, c.evidence)
            }
            Some(c) => {
                self.hypotheses += 1;
                format!("hypothesis: {} ({})", c.cause, c.evidence)
            }
            None => {
                self.unexplained += 1;
                "**no cause recorded**".into()
            }
        }
    }
}

/// One line per table (published, reproduced, deviates, not computed), and
/// one per table not computed yet.
fn table_summary_rows(report: &ReportJson) -> String {
    let mut s = String::from(
        "| table | source | published | reproduced | to digits | deviates | not computed |\n|---|---|---|---|---|---|---|\n",
    );
    for r in &report.tables {
        let (rep, total) = r.counts();
        let (dig, applicable) = r.digit_counts();
        let dev = r
            .entries()
            .filter(|e| e.published.is_some() && e.status == Status::Deviates)
            .count();
        s.push_str(&format!(
            "| `{}` | {} {}, p. {} | {total} | {rep} | {dig} of {applicable} | {dev} | {} |\n",
            r.id,
            r.source.document,
            r.source.table,
            r.source.page,
            total - rep - dev
        ));
    }
    for u in &report.unimplemented {
        s.push_str(&format!(
            "| `{}` | {} | {} | — | — | {} ({}) |\n",
            u.id, u.source, u.count, u.count, u.waiting_for
        ));
    }
    s
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

/// The convergence charts (TLS paper Fig. 6): RMS error against h for the
/// nine method/mapping variants, with the fitted order in the legend.
pub fn convergence_charts(dir: &Path, lines: &[ConvergenceLine]) -> Result<()> {
    type Quantity = (
        &'static str,
        &'static str,
        fn(&BarErrors) -> f64,
        fn(&ConvergenceOrders) -> f64,
    );
    let quantities: [Quantity; 3] = [
        (
            "displacement",
            "RMS displacement error [m]",
            |e| e.displacement,
            |o| o.displacement,
        ),
        (
            "velocity",
            "RMS grid-velocity error [m/s]",
            |e| e.grid_velocity,
            |o| o.grid_velocity,
        ),
        (
            "stress",
            "RMS stress error [Pa]",
            |e| e.stress,
            |o| o.stress,
        ),
    ];
    for (name, ylabel, f, order) in quantities {
        let series = lines
            .iter()
            .enumerate()
            .map(|(k, line)| Series {
                label: format!("{} (order {:.2})", line.method, order(&line.orders)),
                points: line.errors.iter().map(|e| (e.h, f(e))).collect(),
                style: Style::Line,
                color: k,
            })
            .collect();
        charts::write(dir, &format!("convergence_{name}"), &Chart {
            title: format!("Convergence of the {name}, vibrating bar (TLS paper Table 2, 12 PPC)"),
            x_label: "element size h [m]".into(),
            y_label: ylabel.into(),
            log_x: true,
            log_y: true,
            series,
            hlines: vec![],
            footnotes: vec![format!(
                "Δt = {:e} s, {} steps; reconstructions with consistent mass; slopes are least-squares fits over the four resolutions.",
                tls_paper::SMALL_BAR_DT,
                tls_paper::SMALL_BAR_STEPS
            )],
            x_categories: vec![],
            x_range: None,
            y_range: None,
        })?;
    }
    Ok(())
}

/// One line per label, in the order the labels first appear, each with its
/// points in study order.
fn lines_by_label<T>(
    points: &[T],
    label: impl Fn(&T) -> &'static str,
    xy: impl Fn(&T) -> (f64, f64),
) -> Vec<Series> {
    let mut labels: Vec<&str> = Vec::new();
    for p in points {
        if !labels.contains(&label(p)) {
            labels.push(label(p));
        }
    }
    labels
        .iter()
        .enumerate()
        .map(|(k, l)| Series {
            label: l.to_string(),
            points: points.iter().filter(|p| label(p) == *l).map(&xy).collect(),
            style: Style::Line,
            color: k,
        })
        .collect()
}

/// The work-precision chart: RMS displacement error against wall time.
pub fn work_precision_chart(dir: &Path, res: &[usize], points: &[WorkPoint]) -> Result<()> {
    let series = lines_by_label(points, |p| p.label, |p| (p.seconds.max(1e-6), p.error));
    charts::write(dir, "work_precision", &Chart {
        title: "Accuracy against cost: vibrating bar (thesis Table 4.1), 4 PPC, 1999 steps".into(),
        x_label: "wall time of the run [s] (one core)".into(),
        y_label: "RMS displacement error at t = 0.02 s [m]".into(),
        log_x: true,
        log_y: true,
        series,
        hlines: vec![],
        x_categories: vec![],
        x_range: None,
        y_range: None,
        footnotes: vec![format!("One point per resolution ({} knot spans / elements); lower and further left is better.", res.iter().map(|r| r.to_string()).collect::<Vec<_>>().join(", "))],
    })?;
    Ok(())
}

/// The speed chart: ns per particle-step against the number of particles,
/// one line per method (log-log); flat lines mean O(particles) steps.
pub fn speed_chart(dir: &Path, points: &[SpeedPoint]) -> Result<()> {
    let series = lines_by_label(
        points,
        |p| p.label,
        |p| (p.particles as f64, p.ns_per_particle_step),
    );
    charts::write(dir, "speed", &Chart {
        title: "Cost of one MUSL step: vibrating bar (thesis Table 4.1), 8 PPC, one thread".into(),
        x_label: "particles".into(),
        y_label: "wall time per particle-step [ns]".into(),
        log_x: true,
        log_y: true,
        series,
        hlines: vec![],
        x_categories: vec![],
        // Room on the right for the legend.
        x_range: Some((1e2, 1e7)),
        y_range: Some((1e1, 1e3)),
        footnotes: vec![
            "Best of repeated runs of about 65 536 particle-steps each; release build. A flat line is a step that costs O(particles).".into(),
        ],
    })?;
    Ok(())
}

/// Published and computed CG iterations and V-cycles (book Tables 4.3–4.4).
pub fn solver_table_charts(dir: &Path, reports: &[TableReport]) -> Result<()> {
    for (id, stem, ylabel, cols) in [
        (
            "book-4.3",
            "solver_cg_iterations",
            "CG iterations to ‖r‖/‖r₀‖ < 1e-8",
            [16.0, 32.0, 64.0, 128.0],
        ),
        (
            "book-4.4",
            "solver_pmg_cycles",
            "p-multigrid V-cycles to 1e-8",
            [8.0, 16.0, 32.0, 64.0],
        ),
    ] {
        let Some(r) = reports.iter().find(|r| r.id == id) else {
            continue;
        };
        let mut series = Vec::new();
        for p in 0..5 {
            let pts = |grid: &Vec<Vec<Option<f64>>>| {
                cols.iter()
                    .zip(&grid[p])
                    .filter_map(|(x, v)| v.map(|v| (*x, v)))
                    .collect::<Vec<_>>()
            };
            series.push(Series {
                label: format!("p = {} computed", p + 1),
                points: pts(&r.computed),
                style: Style::Line,
                color: p,
            });
            series.push(Series {
                label: format!("p = {} published", p + 1),
                points: pts(&r.published),
                style: Style::Markers,
                color: p,
            });
        }
        charts::write(
            dir,
            stem,
            &Chart {
                title: format!("{} — {}", id, r.title),
                x_label: "1/h (knot spans per direction)".into(),
                y_label: ylabel.into(),
                log_x: true,
                log_y: true,
                series,
                hlines: vec![],
                footnotes: vec!["Lines: computed by hompm; crosses: published in the book.".into()],
                x_categories: vec![],
                x_range: None,
                y_range: None,
            },
        )?;
    }
    Ok(())
}

/// Wall time per solve beyond the tables: CG and p-multigrid against DOFs.
pub fn solver_time_chart(dir: &Path, degrees: &[usize], points: &[SolverPoint]) -> Result<()> {
    let mut series = Vec::new();
    for (k, &p) in degrees
        .iter()
        .enumerate()
        .filter(|(_, &p)| p == 2 || p == 4 || p >= 6 || degrees.len() <= 3)
    {
        let pts = |f: fn(&SolverPoint) -> Option<f64>| {
            points
                .iter()
                .filter(|q| q.degree == p)
                .filter_map(|q| f(q).map(|t| (q.dofs as f64, t.max(1e-6))))
                .collect::<Vec<_>>()
        };
        series.push(Series {
            label: format!("CG, p = {p}"),
            points: pts(|q| q.cg_seconds),
            style: Style::Line,
            color: k,
        });
        series.push(Series {
            label: format!("p-multigrid, p = {p}"),
            points: pts(|q| q.pmg_seconds),
            style: Style::Markers,
            color: k,
        });
    }
    charts::write(dir, "solver_time", &Chart {
        title: "Wall time per solve of M a = f, 2D B-spline mass matrix (book §4.6–4.7)".into(),
        x_label: "degrees of freedom (n + p − 2)²".into(),
        y_label: "wall time per solve [s]".into(),
        log_x: true,
        log_y: true,
        series,
        hlines: vec![],
        x_categories: vec![],
        x_range: None,
        y_range: None,
        footnotes: vec!["Lines: CG from zero to 1e-8; crosses: p-multigrid (book setting, including its set-up). Cholesky times are in report.json.".into()],
    })?;
    Ok(())
}

/// The stability chart's footnotes, written from the computed failure cases.
fn failure_footnotes(f: &FailureCases) -> Vec<String> {
    let g = &f.grid_crossing;
    let n = &f.negative_masses;
    let z = &f.near_zero_masses;
    let blow_up = z
        .direct_blow_up_step
        .map_or("the direct mapping stays bounded".into(), |s| {
            format!("the direct mapping blows up at step {s}")
        });
    vec![
        format!(
            "Failure cases (tests/stability.rs): grid crossing — MPM column with 80 DOFs: {} crossings, {:.0}x the error of 50 DOFs (thesis §5.1.3);",
            g.linear_80.crossings,
            g.linear_80.error / g.linear_50.error
        ),
        format!(
            "negative masses — MPM-P2 with 1 PPC: negative lumped mass in {} of {} steps, {:.0}x the error of 2 PPC (thesis §5.2);",
            n.negative_mass_steps,
            n.steps,
            n.error_one_ppc / n.error_two_ppc
        ),
        format!(
            "near-zero consistent masses — BSMPM column, Table 4.4: nodal velocity {:.0} m/s against {:.2} m/s at the particles, {blow_up} (thesis §7.2.4);",
            z.max_nodal_velocity, z.max_particle_velocity
        ),
        "singular TLS — a cell with 2 ill-placed points: κ(D) = ∞, repaired by a virtual point (TLS paper §5.3).".into(),
    ]
}

/// The stability map: the largest stable Courant number per basis and mass,
/// with the failure cases of `studies::failures` as footnotes.
pub fn stability_chart(dir: &Path, map: &[StabilityPoint], failures: &FailureCases) -> Result<()> {
    let lumped: Vec<(f64, f64)> = map
        .iter()
        .enumerate()
        .map(|(k, s)| (k as f64 + 1.0, s.lumped))
        .collect();
    let consistent: Vec<(f64, f64)> = map
        .iter()
        .enumerate()
        .map(|(k, s)| (k as f64 + 1.0, s.consistent))
        .collect();
    let names: Vec<String> = map.iter().map(|s| s.method.clone()).collect();
    charts::write(
        dir,
        "stability_map",
        &Chart {
            title:
                "Largest stable Courant number cΔt/h of Euler–Cromer MUSL (bar, thesis Table 4.1)"
                    .into(),
            x_label: "basis of the background grid".into(),
            y_label: "critical Courant number C [-]".into(),
            log_x: false,
            log_y: false,
            series: vec![
                Series {
                    label: "lumped acceleration".into(),
                    points: lumped,
                    style: Style::Points,
                    color: 0,
                },
                Series {
                    label: "consistent acceleration".into(),
                    points: consistent,
                    style: Style::Points,
                    color: 3,
                },
            ],
            hlines: vec![(1.0, "CFL estimate C = 1 (thesis Eq. 3.5)".into())],
            x_categories: names,
            x_range: None,
            y_range: None,
            footnotes: failure_footnotes(failures),
        },
    )?;
    Ok(())
}

/// Every chart of the report, from the tables and the studies' results.
pub fn write_charts(dir: &Path, reports: &[TableReport], studies: &ReportStudies) -> Result<()> {
    convergence_charts(dir, &studies.convergence)?;
    work_precision_chart(
        dir,
        &studies.work_precision_resolutions,
        &studies.work_precision,
    )?;
    solver_table_charts(dir, reports)?;
    solver_time_chart(dir, &studies.solver_degrees, &studies.solvers)?;
    stability_chart(dir, &studies.stability, &studies.failures)?;
    speed_chart(dir, &studies.speed)?;
    mls_charts(dir, reports)
}

/// The run of the aligned vibration as (x, y) points, if it reached T.
fn aligned_points(
    runs: &[RunOutcome],
    method: AlignedMethod,
    xy: impl Fn(&RunOutcome, &AlignedErrors) -> (f64, f64),
) -> Vec<(f64, f64)> {
    runs.iter()
        .filter(|o| o.method == method)
        .filter_map(|o| o.run.as_ref().map(|r| xy(o, &r.last)))
        .collect()
}

/// The charts of `mls-aligned` (MLS paper Figs. 2–4 and beyond), from the
/// study the table returned: convergence of u, v and σ, the displacement
/// error against time on the finest grid, error against wall time, and
/// (with `--full`) the PPC study. Nothing if the table was not run.
pub fn mls_charts(dir: &Path, reports: &[TableReport]) -> Result<()> {
    let Some(study) = reports
        .iter()
        .find(|r| r.id == "mls-aligned")
        .and_then(|r| r.study.clone())
    else {
        return Ok(());
    };
    let study: AlignedStudy =
        serde_json::from_value(study).map_err(|e| Error::Io(format!("mls-aligned study: {e}")))?;
    let mut methods = mls_paper::METHODS.to_vec();
    methods.push(AlignedMethod::TotalLagrangian { degree: 2 });
    methods.push(mls_paper::TLS_METHOD);
    let runs: Vec<RunOutcome> = study
        .convergence
        .iter()
        .chain(&study.reference)
        .chain(&study.tls)
        .cloned()
        .collect();
    let stopped: Vec<String> = runs
        .iter()
        .filter(|o| o.run.is_none())
        .map(|o| {
            format!(
                "{} at {} cells stopped (no point)",
                o.method.label(),
                o.cells
            )
        })
        .collect();
    mls_convergence_charts(dir, &study, &methods, &runs, &stopped)?;
    mls_history_chart(dir, &study, &methods, &runs)?;
    mls_work_precision_chart(dir, &methods, &runs)?;
    mls_conservation_chart(dir, &runs)?;
    mls_ppc_chart(dir, &study)
}

/// MLS paper Figs. 2–4: error at T against h for each quantity.
fn mls_convergence_charts(
    dir: &Path,
    study: &AlignedStudy,
    methods: &[AlignedMethod],
    runs: &[RunOutcome],
    stopped: &[String],
) -> Result<()> {
    type Quantity = (&'static str, &'static str, fn(&AlignedErrors) -> f64);
    let quantities: [Quantity; 3] = [
        ("displacement", "RMS displacement error at T [m]", |e| {
            e.displacement
        }),
        ("velocity", "RMS velocity error at T [m/s]", |e| e.velocity),
        ("stress", "RMS Cauchy stress error at T [Pa]", |e| e.stress),
    ];
    let scene = aligned_vibration::parameters(mls_paper::PAPER_PARAMETERS)?;
    let setup = format!(
        "E = {:e} Pa, A = {} m, {} PPC, Δt = {:e} s; TL-FE is hompm's total-Lagrangian reference without grid crossing.",
        scene.young,
        scene.amplitude,
        mls_paper::PAPER_PARTICLES_PER_SIDE.pow(2),
        scene.dt
    );
    for (name, ylabel, f) in quantities {
        let series = methods
            .iter()
            .enumerate()
            .map(|(k, &m)| Series {
                label: m.label(),
                points: aligned_points(runs, m, |o, e| (1.0 / o.cells as f64, f(e))),
                style: Style::Line,
                color: k,
            })
            .collect();
        charts::write(
            dir,
            &format!("mls_convergence_{name}"),
            &Chart {
                title: format!(
                    "Aligned vibration (MLS paper Figs. 2–4): {name} at T = {} s",
                    study.options.steps as f64 * scene.dt
                ),
                x_label: "cell size h [m]".into(),
                y_label: ylabel.into(),
                log_x: true,
                log_y: true,
                series,
                hlines: vec![],
                footnotes: std::iter::once(setup.clone())
                    .chain(stopped.iter().cloned())
                    .collect(),
                x_categories: vec![],
                x_range: None,
                y_range: None,
            },
        )?;
    }
    Ok(())
}

/// The displacement error against time on the finest grid.
fn mls_history_chart(
    dir: &Path,
    study: &AlignedStudy,
    methods: &[AlignedMethod],
    runs: &[RunOutcome],
) -> Result<()> {
    let finest = study.options.sizes.iter().copied().max().unwrap_or(0);
    let history = methods
        .iter()
        .enumerate()
        .filter_map(|(k, &m)| {
            runs.iter()
                .find(|o| o.method == m && o.cells == finest)
                .map(|o| Series {
                    label: match &o.failure {
                        Some(_) => format!("{} (stopped)", m.label()),
                        None => m.label(),
                    },
                    points: o
                        .history
                        .iter()
                        .skip(1)
                        .map(|e| (e.time, e.displacement))
                        .collect(),
                    style: Style::Line,
                    color: k,
                })
        })
        .collect();
    charts::write(
        dir,
        "mls_error_history",
        &Chart {
            title: format!(
                "Aligned vibration: displacement error against time, {finest}×{finest} cells"
            ),
            x_label: "time t [s]".into(),
            y_label: "RMS displacement error [m]".into(),
            log_x: false,
            log_y: true,
            series: history,
            hlines: vec![],
            footnotes: vec![format!(
                "One period of sin(cπt/L) is {} s.",
                mls_paper::EARLY_TIME
            )],
            x_categories: vec![],
            x_range: None,
            y_range: None,
        },
    )
}

/// Accuracy against wall time of every run.
fn mls_work_precision_chart(
    dir: &Path,
    methods: &[AlignedMethod],
    runs: &[RunOutcome],
) -> Result<()> {
    let work = methods
        .iter()
        .enumerate()
        .map(|(k, &m)| Series {
            label: m.label(),
            points: runs
                .iter()
                .filter(|o| o.method == m)
                .filter_map(|o| {
                    o.run
                        .as_ref()
                        .map(|r| (r.seconds.max(1e-6), r.last.displacement))
                })
                .collect(),
            style: Style::Line,
            color: k,
        })
        .collect();
    charts::write(dir, "mls_work_precision", &Chart {
        title: "Aligned vibration: accuracy against cost (8 → finest cells)".into(),
        x_label: "wall time of the run [s] (one core)".into(),
        y_label: "RMS displacement error at T [m]".into(),
        log_x: true,
        log_y: true,
        series: work,
        hlines: vec![],
        footnotes: vec!["Each point is one run of T/Δt steps; wall times from the reproduce run (two runs share the two cores).".into()],
        x_categories: vec![],
        x_range: None,
        y_range: None,
    })
}

/// The largest relative mapping errors of mass (line) and momentum
/// (markers) over each run against h, for the direct mapping, MLS and
/// TLS; a run that stopped contributes its errors up to the stop. Zeros
/// are drawn at 1e-17 (the log axis has no zero).
fn mls_conservation_chart(dir: &Path, runs: &[RunOutcome]) -> Result<()> {
    let methods = [
        mls_paper::METHODS[1],
        mls_paper::METHODS[2],
        mls_paper::TLS_METHOD,
    ];
    let errors = |o: &RunOutcome| {
        o.run
            .as_ref()
            .map(|r| r.conservation)
            .or(o.conservation_until_stop)
    };
    let points =
        |m: AlignedMethod, f: fn(&crate::mpm2d::Conservation2d) -> f64| -> Vec<(f64, f64)> {
            runs.iter()
                .filter(|o| o.method == m)
                .filter_map(|o| errors(o).map(|c| (1.0 / o.cells as f64, f(&c).max(1e-17))))
                .collect()
        };
    let series = methods
        .iter()
        .enumerate()
        .flat_map(|(k, &m)| {
            [
                Series {
                    label: format!("{}: mass", m.label()),
                    points: points(m, |c| c.mass),
                    style: Style::Line,
                    color: k + 1,
                },
                Series {
                    label: format!("{}: momentum", m.label()),
                    points: points(m, |c| c.momentum),
                    style: Style::Markers,
                    color: k + 1,
                },
            ]
        })
        .collect();
    charts::write(
        dir,
        "mls_conservation",
        &Chart {
            title: "Aligned vibration: largest mapping errors of mass and momentum over a run".into(),
            x_label: "cell size h [m]".into(),
            y_label: "relative mapping error".into(),
            log_x: true,
            log_y: true,
            series,
            hlines: vec![],
            footnotes: vec!["Mass: |Σm_i − Σm_p|/Σm_p; momentum: |Σ(mv)_i − Σm_p v_p|/Σm_p|v_p|, the largest over every phase-1 mapping (up to the stop for a run that stopped). The floor of the direct mapping is the rounding of the sums.".into()],
            x_categories: vec![],
            x_range: None,
            y_range: None,
        },
    )
}

/// The PPC chart's series: for each method, the error at
/// [`mls_paper::EARLY_TIME`] (line) and at the end T (markers).
fn ppc_series(study: &AlignedStudy) -> Vec<Series> {
    let early = mls_paper::EARLY_TIME;
    let at_early = |m: AlignedMethod| -> Vec<(f64, f64)> {
        study
            .ppc
            .iter()
            .filter(|o| o.method == m)
            .filter_map(|o| {
                o.history
                    .iter()
                    .find(|e| (e.time - early).abs() < 1e-9)
                    .map(|e| (o.ppc as f64, e.displacement))
            })
            .collect()
    };
    [
        mls_paper::METHODS[1],
        mls_paper::METHODS[2],
        mls_paper::TLS_METHOD,
    ]
    .iter()
    .enumerate()
    .flat_map(|(k, &m)| {
        [
            Series {
                label: format!("{} at t = {early} s", m.label()),
                points: at_early(m),
                style: Style::Line,
                color: k + 1,
            },
            Series {
                label: format!("{} at T", m.label()),
                points: aligned_points(&study.ppc, m, |o, e| (o.ppc as f64, e.displacement)),
                style: Style::Markers,
                color: k + 1,
            },
        ]
    })
    .collect()
}

/// One footnote per run that stopped, with its reason.
fn stopped_runs(runs: &[RunOutcome]) -> Vec<String> {
    runs.iter()
        .filter(|o| o.run.is_none())
        .map(|o| {
            format!(
                "{} with {} PPC stopped: {}",
                o.method.label(),
                o.ppc,
                o.failure.clone().unwrap_or_default()
            )
        })
        .collect()
}

/// Sensitivity to the particles per cell (`--full` only).
fn mls_ppc_chart(dir: &Path, study: &AlignedStudy) -> Result<()> {
    if study.ppc.is_empty() {
        return Ok(());
    }
    charts::write(
        dir,
        "mls_ppc",
        &Chart {
            title: format!(
                "Aligned vibration: sensitivity to particles per cell, {0}×{0} cells",
                study.options.ppc_cells
            ),
            x_label: "particles per cell".into(),
            y_label: "RMS displacement error [m]".into(),
            log_x: false,
            log_y: true,
            series: ppc_series(study),
            hlines: vec![],
            footnotes: stopped_runs(&study.ppc),
            x_categories: vec![],
            x_range: None,
            y_range: None,
        },
    )
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
        md.push_str("## Charts\n\n![work-precision](charts/work_precision.svg)\n![speed](charts/speed.svg)\n\n![convergence of displacement](charts/convergence_displacement.svg)\n![convergence of velocity](charts/convergence_velocity.svg)\n![convergence of stress](charts/convergence_stress.svg)\n\n![CG iterations](charts/solver_cg_iterations.svg)\n![V-cycles](charts/solver_pmg_cycles.svg)\n![solver time](charts/solver_time.svg)\n\n![stability map](charts/stability_map.svg)\n\n![MLS paper: displacement](charts/mls_convergence_displacement.svg)\n![MLS paper: velocity](charts/mls_convergence_velocity.svg)\n![MLS paper: stress](charts/mls_convergence_stress.svg)\n![MLS paper: error against time](charts/mls_error_history.svg)\n![MLS paper: work-precision](charts/mls_work_precision.svg)\n![MLS and TLS: mapping errors](charts/mls_conservation.svg)\n\n");
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
