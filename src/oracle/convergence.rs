//! # Observed orders of another code against hompm's
//!
//! `hompm check --convergence FILE…` reads the other code's particles at
//! several resolutions, computes its RMS errors against the exact
//! solution (MLS paper Eq. 43, as [`check`](super::check)), runs hompm on
//! the same resolutions, and fits the observed order of each field:
//!
//! - [`fit_order`]: the least-squares slope p of log e = a + p log h over
//!   all resolutions (h = L / cells), with its standard error as the
//!   spread, and the order of each consecutive pair, log(e₁/e₂)/log(h₁/h₂);
//! - the verdict per field: *reference does not converge* when hompm's own
//!   fitted order, or its order over the last pair, is below
//!   [`REFERENCE_ORDER_FLOOR`] (its errors do not fall on these grids, so
//!   no order of the other code can be judged against it); else *not yet
//!   asymptotic* when the pairwise orders of the other code differ by
//!   more than 0.3 between the last two pairs; else the order *holds*
//!   when the other code's fitted order is at least hompm's minus 0.3, and
//!   *falls short* otherwise. The thresholds are choices
//!   (docs/conventions.md, "hompm check"). Only *holds* in every field is
//!   a success (exit 0).
//!
//! The resolutions must differ: a repeated one is refused, not fitted.
//!
//! Items: [`OrderFit`], [`fit_order`], [`FieldConvergence`],
//! [`ConvergenceReport`], [`convergence`], [`REFERENCE_ORDER_FLOOR`],
//! [`HOLDS`].

use super::check::{check, CheckOptions};
use super::input::Input;
use super::setup::Setup;
use super::state::State;
use crate::error::{Error, Result};
use serde::Serialize;
use std::collections::BTreeMap;

/// hompm's order below which the reference is taken not to converge on
/// the grids given (module docs).
pub const REFERENCE_ORDER_FLOOR: f64 = 0.5;

/// The one field verdict that is a success.
pub const HOLDS: &str = "holds";

/// A fitted order.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct OrderFit {
    /// Least-squares slope of log e against log h.
    pub order: f64,
    /// Its standard error (0 for two resolutions).
    pub spread: f64,
    /// The order of each consecutive pair of resolutions.
    pub pairwise: Vec<f64>,
}

/// Fits the order of errors `e` at cell sizes `h` (at least two, all
/// positive).
pub fn fit_order(h: &[f64], e: &[f64]) -> Result<OrderFit> {
    if h.len() != e.len() || h.len() < 2 {
        return Err(Error::InvalidArgument(
            "an order needs errors at two or more resolutions".into(),
        ));
    }
    if let Some(bad) = h.iter().chain(e).find(|v| !(v.is_finite() && **v > 0.0)) {
        return Err(Error::InvalidArgument(format!(
            "an order needs positive, finite cell sizes and errors, got {bad}"
        )));
    }
    let x: Vec<f64> = h.iter().map(|v| v.ln()).collect();
    let y: Vec<f64> = e.iter().map(|v| v.ln()).collect();
    let n = x.len() as f64;
    let (mx, my) = (x.iter().sum::<f64>() / n, y.iter().sum::<f64>() / n);
    let sxx: f64 = x.iter().map(|a| (a - mx).powi(2)).sum();
    if sxx == 0.0 {
        return Err(Error::InvalidArgument(
            "an order needs at least two different resolutions".into(),
        ));
    }
    let sxy: f64 = x.iter().zip(&y).map(|(a, b)| (a - mx) * (b - my)).sum();
    let order = sxy / sxx;
    let intercept = my - order * mx;
    let spread = if x.len() > 2 {
        let ss: f64 = x
            .iter()
            .zip(&y)
            .map(|(a, b)| (b - intercept - order * a).powi(2))
            .sum();
        (ss / (n - 2.0) / sxx).sqrt()
    } else {
        0.0
    };
    let pairwise: Vec<f64> = x
        .windows(2)
        .zip(y.windows(2))
        .map(|(a, b)| (b[0] - b[1]) / (a[0] - a[1]))
        .collect();
    if !(order.is_finite() && spread.is_finite() && pairwise.iter().all(|p| p.is_finite())) {
        return Err(Error::InvalidArgument(
            "an order needs different resolutions: a pair of them is the same".into(),
        ));
    }
    Ok(OrderFit {
        order,
        spread,
        pairwise,
    })
}

/// One field's errors and orders.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct FieldConvergence {
    /// RMS errors against the exact solution per resolution: yours, hompm.
    pub rms_exact: Vec<[f64; 2]>,
    /// The other code's order.
    pub yours: OrderFit,
    /// hompm's order for the same method and scene.
    pub hompm: OrderFit,
    /// `holds`, `falls short` or `not yet asymptotic`.
    pub verdict: String,
}

/// The report of `hompm check --convergence`.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct ConvergenceReport {
    /// Cells per resolution, coarsest first.
    pub cells: Vec<usize>,
    /// Per field with an exact solution.
    pub fields: BTreeMap<String, FieldConvergence>,
    /// One line per field.
    pub verdict: String,
}

/// The verdict of one field (module docs).
fn field_verdict(yours: &OrderFit, hompm: &OrderFit) -> &'static str {
    let p = &yours.pairwise;
    let reference_last = hompm.pairwise.last().copied().unwrap_or(hompm.order);
    if hompm.order < REFERENCE_ORDER_FLOOR || reference_last < REFERENCE_ORDER_FLOOR {
        "reference does not converge"
    } else if p.len() >= 2 && (p[p.len() - 1] - p[p.len() - 2]).abs() > 0.3 {
        "not yet asymptotic"
    } else if yours.order >= hompm.order - 0.3 {
        HOLDS
    } else {
        "falls short"
    }
}

/// Runs the check of each (setup, state, input) resolution and fits the
/// orders. `runs` must be sorted coarsest first.
pub fn convergence(
    runs: &[(Setup, State, Input, usize, f64)],
    o: &CheckOptions,
) -> Result<ConvergenceReport> {
    if let Some(w) = runs.windows(2).find(|w| w[0].3 >= w[1].3) {
        return Err(Error::Input(format!(
            "the resolutions must be different and ordered coarsest first; {} cells follows {}",
            w[1].3, w[0].3
        )));
    }
    if runs.len() < 2 {
        return Err(Error::Input(
            "an order needs files at two or more resolutions".into(),
        ));
    }
    let mut per_field: BTreeMap<String, Vec<[f64; 2]>> = BTreeMap::new();
    let mut h = Vec::new();
    let mut cells = Vec::new();
    for (setup, state, input, n, length) in runs {
        let report = check(setup, state, input, None, o)?;
        h.push(length / *n as f64);
        cells.push(*n);
        for (name, f) in &report.fields {
            if let Some(p) = f.rms_exact {
                per_field
                    .entry(name.clone())
                    .or_default()
                    .push([p.yours, p.hompm]);
            }
        }
    }
    let mut fields = BTreeMap::new();
    let mut lines = Vec::new();
    for (name, errors) in per_field {
        if errors.len() != h.len() {
            continue;
        }
        let yours: Vec<f64> = errors.iter().map(|e| e[0]).collect();
        let ours: Vec<f64> = errors.iter().map(|e| e[1]).collect();
        let (Ok(yf), Ok(hf)) = (fit_order(&h, &yours), fit_order(&h, &ours)) else {
            lines.push(format!("{name}: no order (an error is zero or not finite)"));
            continue;
        };
        let verdict = field_verdict(&yf, &hf);
        lines.push(format!(
            "{name}: your order {:.2} ± {:.2} (pairs {}), hompm's {:.2} (pairs {}): {verdict}",
            yf.order,
            yf.spread,
            yf.pairwise
                .iter()
                .map(|p| format!("{p:.2}"))
                .collect::<Vec<_>>()
                .join(", "),
            hf.order,
            hf.pairwise
                .iter()
                .map(|p| format!("{p:.2}"))
                .collect::<Vec<_>>()
                .join(", ")
        ));
        fields.insert(
            name,
            FieldConvergence {
                rms_exact: errors,
                yours: yf,
                hompm: hf,
                verdict: verdict.into(),
            },
        );
    }
    if fields.is_empty() {
        return Err(Error::Input(
            "no field with an exact solution was given at every resolution".into(),
        ));
    }
    Ok(ConvergenceReport {
        cells,
        fields,
        verdict: lines.join("\n"),
    })
}
