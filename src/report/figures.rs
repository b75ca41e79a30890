//! # The report's charts, one function per chart
//!
//! Each function turns the results of a study (or of a table run) into one
//! or more [`super::charts::Chart`]s and writes them as SVG and PNG:
//! convergence (TLS paper Fig. 6), work-precision, speed, the solver counts
//! of book Tables 4.3–4.4 and their wall time, the stability map, and the
//! MLS paper's charts (Figs. 2–4 and beyond, in `mls_figures`).
//! [`write_charts`] calls every one of them. A new chart is one function here plus one line in
//! [`write_charts`].
//!
//! Items: [`convergence_charts`], [`work_precision_chart`], [`speed_chart`],
//! [`solver_table_charts`], [`solver_time_chart`], [`stability_chart`],
//! [`write_charts`].

use super::charts::{self, Chart, Series, Style};
use crate::error::Result;
use crate::studies::failures::FailureCases;
use crate::studies::report::{ConvergenceLine, ConvergenceOrders, ReportStudies};
use crate::studies::tls_paper;
use crate::studies::{BarErrors, SolverPoint, SpeedPoint, StabilityPoint, WorkPoint};
use crate::tables::TableReport;
use std::path::Path;

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
            "Failure cases (tests/spec/properties/stability.rs): grid crossing — MPM column with 80 DOFs: {} crossings, {:.0}x the error of 50 DOFs (thesis §5.1.3);",
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
    super::mls_figures::mls_charts(dir, reports)?;
    super::convention_figures::convention_charts(dir, reports)
}
