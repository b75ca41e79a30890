//! # The studies of `hompm reproduce`, run once
//!
//! Everything the report charts beyond the tables is computed here and
//! handed to `report` as data: the convergence of the nine Fig. 6 variants
//! (TLS paper), work against precision, the cost per particle-step, solver
//! time beyond book Tables 4.3–4.4, the stability map and the failure cases.
//! `report` renders these results and computes nothing itself.
//!
//! Items: [`ConvergenceLine`], [`ConvergenceOrders`], [`ReportStudies`],
//! [`run_report_studies`].

use super::failures::{self, FailureCases};
use super::tls_paper::{fig6_errors, fig6_variants, fitted_order};
use super::{
    solver_study, speed, stability_map, work_precision, BarErrors, SolverPoint, SpeedPoint,
    StabilityPoint, WorkPoint,
};
use crate::error::Result;
use serde::Serialize;

/// One Fig. 6 variant's errors at 5, 10, 20 and 40 cells.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct ConvergenceLine {
    /// "MPM", "DDMPM + TLS", "BSMPM-p2 + CS", …
    pub method: String,
    /// The errors per resolution.
    pub errors: Vec<BarErrors>,
    /// The fitted orders of the three errors over the resolutions.
    pub orders: ConvergenceOrders,
}

/// Least-squares slopes of log(error) against log(h)
/// ([`super::tls_paper::fitted_order`]), one per error of [`BarErrors`].
#[derive(Debug, Clone, Copy, PartialEq, Serialize)]
pub struct ConvergenceOrders {
    /// Of the RMS displacement error.
    pub displacement: f64,
    /// Of the RMS grid-velocity error.
    pub grid_velocity: f64,
    /// Of the RMS stress error.
    pub stress: f64,
}

impl ConvergenceOrders {
    /// The orders of `errors` over their element sizes.
    pub fn of(errors: &[BarErrors]) -> Self {
        let h: Vec<f64> = errors.iter().map(|e| e.h).collect();
        let order = |f: fn(&BarErrors) -> f64| {
            let y: Vec<f64> = errors.iter().map(f).collect();
            fitted_order(&h, &y)
        };
        Self {
            displacement: order(|e| e.displacement),
            grid_velocity: order(|e| e.grid_velocity),
            stress: order(|e| e.stress),
        }
    }
}

/// Every study of the report, with the sizes it was run at.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct ReportStudies {
    /// TLS paper Fig. 6 variants.
    pub convergence: Vec<ConvergenceLine>,
    /// Resolutions of the work-precision study.
    pub work_precision_resolutions: Vec<usize>,
    /// Error against wall time.
    pub work_precision: Vec<WorkPoint>,
    /// ns per particle-step.
    pub speed: Vec<SpeedPoint>,
    /// CG and p-multigrid wall times.
    pub solvers: Vec<SolverPoint>,
    /// Degrees of the solver study.
    pub solver_degrees: Vec<usize>,
    /// Critical Courant numbers.
    pub stability: Vec<StabilityPoint>,
    /// The failure cases of tests/spec/properties/stability.rs.
    pub failures: FailureCases,
}

fn convergence() -> Result<Vec<ConvergenceLine>> {
    fig6_variants()
        .into_iter()
        .map(|(m, map)| {
            let legend = map.info().legend;
            let suffix = if legend.is_empty() {
                String::new()
            } else {
                format!(" + {legend}")
            };
            let errors = fig6_errors(m, map)?;
            Ok(ConvergenceLine {
                method: format!("{}{suffix}", m.label()),
                orders: ConvergenceOrders::of(&errors),
                errors,
            })
        })
        .collect()
}

fn solvers(quick: bool) -> Result<(Vec<usize>, Vec<SolverPoint>)> {
    let (degrees, spans): (Vec<usize>, Vec<usize>) = if quick {
        (vec![1, 2, 3], vec![8, 16])
    } else {
        ((1..=8).collect(), vec![16, 32, 64, 128, 256])
    };
    let mut points = Vec::new();
    for &p in &degrees {
        let sp: Vec<usize> = spans
            .iter()
            .copied()
            .filter(|&n| p <= 5 || n <= 64)
            .collect();
        points.extend(solver_study(&[p], &sp, 20_000, 20_000)?);
    }
    Ok((degrees, points))
}

/// Runs every study (reduced sizes with `quick`), calling `done(name,
/// seconds)` after each.
pub fn run_report_studies(quick: bool, done: &dyn Fn(&str, f64)) -> Result<ReportStudies> {
    let timed = |name: &str, t: std::time::Instant| done(name, t.elapsed().as_secs_f64());
    let t = std::time::Instant::now();
    let convergence = convergence()?;
    timed("convergence", t);
    let t = std::time::Instant::now();
    let work_precision_resolutions: Vec<usize> = if quick {
        vec![4, 8]
    } else {
        vec![4, 8, 16, 32, 64]
    };
    let work_precision = work_precision(&work_precision_resolutions)?;
    timed("work-precision", t);
    let t = std::time::Instant::now();
    let (solver_degrees, solvers) = solvers(quick)?;
    timed("solvers", t);
    let t = std::time::Instant::now();
    let stability = stability_map(if quick { 8 } else { 16 })?;
    let failures = failures::failure_cases()?;
    timed("stability", t);
    let t = std::time::Instant::now();
    let cells: &[usize] = if quick {
        &[64, 1024]
    } else {
        &[64, 256, 1024, 4096, 16384]
    };
    let speed = speed(cells, if quick { 1 } else { 3 })?;
    timed("speed", t);
    Ok(ReportStudies {
        convergence,
        work_precision_resolutions,
        work_precision,
        speed,
        solvers,
        solver_degrees,
        stability,
        failures,
    })
}
