//! # The charts of the MLS paper's study
//!
//! From the study that the `mls-aligned` table returns: the error at T
//! against h for u, v and σ (MLS paper Figs. 2–4), the displacement error
//! against time on the finest grid, accuracy against wall time for every
//! 2D method, the mapping errors of mass and momentum (direct, MLS, TLS),
//! and with `--full` the PPC study.
//!
//! Items: [`mls_charts`].

use super::charts::{self, Chart, Series, Style};
use crate::error::Result;
use crate::scenes::aligned_vibration::{self, AlignedErrors, AlignedMethod};
use crate::studies::mls_paper::{self, AlignedStudy, RunOutcome};
use crate::tables::{Study, TableReport};
use std::path::Path;

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
    let Some(Study::MlsAligned(study)) = reports
        .iter()
        .find(|r| r.id == "mls-aligned")
        .and_then(|r| r.study.as_ref())
    else {
        return Ok(());
    };
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
    mls_convergence_charts(dir, study, &methods, &runs, &stopped)?;
    mls_history_chart(dir, study, &methods, &runs)?;
    mls_work_precision_chart(dir, &methods, &runs)?;
    mls_conservation_chart(dir, &runs)?;
    mls_ppc_chart(dir, study)
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
