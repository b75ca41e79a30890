//! # The charts of the convergence study (issue #38)
//!
//! From the study that `mls-convergence-study` returns (the MLS paper's
//! aligned vibration, Eqs. 38–43, under each combination of conventions of
//! `studies::mls_convergence::combinations`):
//! - **convergence**: the RMS displacement error (Eq. 43) at the study's
//!   end time against the cell size h, one line per combination;
//! - **work-precision**: the same error against the cost of a step, ns per
//!   particle-step, one line per combination through its grids (8 → 64
//!   cells);
//! - **stability**: the largest Δt that reaches the stability scan's end
//!   time on its grid (16 cells), one point per combination, with the
//!   smallest Δt that stopped and the cause in the footnotes.
//!
//! A run that stopped has no point; the footnotes name it.
//!
//! Items: [`convention_charts`].

use super::charts::{self, Chart, Series, Style};
use crate::error::Result;
use crate::studies::mls_convergence::{ConventionRun, ConventionStudy};
use crate::tables::{Study, TableReport};
use std::path::Path;

/// The three charts of `mls-convergence-study` (convergence,
/// work-precision, stability), from the study the table returned. Nothing
/// if the table was not run (or ran with `--quick`).
pub fn convention_charts(dir: &Path, reports: &[TableReport]) -> Result<()> {
    let Some(Study::MlsConvergence(study)) = reports
        .iter()
        .find(|r| r.id == "mls-convergence-study")
        .and_then(|r| r.study.as_ref())
    else {
        return Ok(());
    };
    let stopped = stopped_runs(study);
    convention_convergence_chart(dir, study, &stopped)?;
    convention_work_precision_chart(dir, study, &stopped)?;
    convention_stability_chart(dir, study)
}

/// The runs of combination `c` that reached the end, as points.
fn points(
    study: &ConventionStudy,
    c: usize,
    xy: impl Fn(&ConventionRun, f64) -> (f64, f64),
) -> Vec<(f64, f64)> {
    study
        .runs
        .iter()
        .filter(|r| r.combination == c)
        .filter_map(|r| r.end.map(|e| xy(r, e.displacement)))
        .collect()
}

/// One line per combination, from `xy`.
fn series(study: &ConventionStudy, xy: impl Fn(&ConventionRun, f64) -> (f64, f64)) -> Vec<Series> {
    study
        .combinations
        .iter()
        .enumerate()
        .map(|(c, comb)| Series {
            label: comb.label.to_string(),
            points: points(study, c, &xy),
            style: Style::Line,
            color: c,
        })
        .collect()
}

/// "label at N cells stopped at t = … (cause)" for every run without an
/// end record.
fn stopped_runs(study: &ConventionStudy) -> Vec<String> {
    study
        .runs
        .iter()
        .filter(|r| r.end.is_none())
        .map(|r| {
            let label = study.combinations[r.combination].label;
            match &r.stop {
                Some(s) => format!(
                    "{label}, {} cells: stopped at t = {:.4} s ({})",
                    r.cells,
                    s.time,
                    short_cause(&s.cause)
                ),
                None => format!("{label}, {} cells: no end record", r.cells),
            }
        })
        .collect()
}

/// The first clause of a stop's message, without the numbers that follow
/// it in brackets (the table's notes have the whole message).
fn short_cause(cause: &str) -> &str {
    let end = cause.find(" (").unwrap_or(cause.len()).min(90);
    let end = (0..=end)
        .rev()
        .find(|&k| cause.is_char_boundary(k))
        .unwrap_or(0);
    &cause[..end]
}

/// The x range of `series` widened to the right, so that the legend (drawn
/// in the upper right) does not cover a point.
fn room_for_the_legend(series: &[Series]) -> Option<(f64, f64)> {
    let xs = series.iter().flat_map(|s| s.points.iter().map(|p| p.0));
    let (lo, hi) = xs.fold((f64::INFINITY, 0.0f64), |(lo, hi), x| {
        (lo.min(x), hi.max(x))
    });
    (lo.is_finite() && hi > 0.0).then_some((0.8 * lo, 8.0 * hi))
}

/// The end time's words for titles: T = 0.2 s or one period.
fn end_label(study: &ConventionStudy) -> String {
    format!("t = {} s", study.options.end_time())
}

/// RMS u at the end time against h, per combination.
fn convention_convergence_chart(
    dir: &Path,
    study: &ConventionStudy,
    stopped: &[String],
) -> Result<()> {
    let length = 1.0;
    let lines = series(study, |r, e| (length / r.cells as f64, e));
    let x_range = room_for_the_legend(&lines);
    charts::write(
        dir,
        "convention_convergence",
        &Chart {
            title: format!(
                "Aligned vibration, BSMPM under other codes' conventions: u error at {}",
                end_label(study)
            ),
            x_label: "cell size h [m]".into(),
            y_label: format!("RMS displacement error at {} [m]", end_label(study)),
            log_x: true,
            log_y: true,
            series: lines,
            hlines: vec![],
            footnotes: stopped.to_vec(),
            x_categories: vec![],
            x_range,
            y_range: None,
        },
    )
}

/// RMS u at the end time against ns per particle-step, per combination.
fn convention_work_precision_chart(
    dir: &Path,
    study: &ConventionStudy,
    stopped: &[String],
) -> Result<()> {
    let mut footnotes = vec![
        "Cost: wall-clock ns per particle-step of each run, measured while the study's runs share two cores (rough, not a benchmark)."
            .to_string(),
    ];
    footnotes.extend(stopped.iter().cloned());
    let lines = series(study, |r, e| (r.ns_per_particle_step(), e));
    let x_range = room_for_the_legend(&lines);
    charts::write(
        dir,
        "convention_work_precision",
        &Chart {
            title: format!(
                "Aligned vibration: accuracy against cost of a step, {}",
                end_label(study)
            ),
            x_label: "ns per particle-step".into(),
            y_label: format!("RMS displacement error at {} [m]", end_label(study)),
            log_x: true,
            log_y: true,
            series: lines,
            hlines: vec![],
            footnotes,
            x_categories: vec![],
            x_range,
            y_range: None,
        },
    )
}

/// The largest stable Δt of each combination, as categories.
fn convention_stability_chart(dir: &Path, study: &ConventionStudy) -> Result<()> {
    let Some(options) = study.options.stability else {
        return Ok(());
    };
    let mut series = Vec::new();
    let mut footnotes = Vec::new();
    for (k, limit) in study.stability.iter().enumerate() {
        let label = study.combinations[limit.combination].label;
        if let Some(dt) = limit.largest_stable {
            series.push(Series {
                label: label.to_string(),
                points: vec![((k + 1) as f64, dt)],
                style: Style::Points,
                color: limit.combination,
            });
        }
        let unstable = match (&limit.smallest_unstable, &limit.stop) {
            (Some(dt), Some(stop)) => format!(
                "{}stops at Δt = {dt:.3e} s (step {}: {})",
                if limit.largest_stable.is_none() {
                    "no Δt tried reaches the end; "
                } else {
                    ""
                },
                stop.step,
                short_cause(&stop.cause)
            ),
            _ => format!("no stop up to Δt = {:.1e} s", options.largest_dt),
        };
        footnotes.push(format!("{}. {label}: {unstable}", k + 1));
    }
    charts::write(
        dir,
        "convention_stability",
        &Chart {
            title: format!(
                "Largest stable Δt on {} cells to t = {} s",
                options.cells, options.end_time
            ),
            x_label: "combination (numbered as in the footnotes)".into(),
            y_label: "largest Δt reaching the end [s]".into(),
            log_x: false,
            log_y: true,
            series,
            hlines: vec![],
            footnotes,
            // Empty slots on the right leave room for the legend.
            x_categories: (1..=study.stability.len())
                .map(|k| k.to_string())
                .chain(std::iter::repeat_n(String::new(), 7))
                .collect(),
            x_range: None,
            y_range: None,
        },
    )
}
