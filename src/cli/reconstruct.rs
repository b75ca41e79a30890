//! # `hompm reconstruct`: a function from scattered data
//!
//! TLS (book Eqs. 4.26–4.37; conservative: TLS paper §5.3), cubic splines
//! (thesis §7.1) or MLS (MLS paper Eqs. 6–17), evaluated at query points,
//! with the integral over each cell. A query outside the cells is an error
//! for every method; cells whose integrals overflow are refused.
//!
//! Items: [`TaylorAverageArg`], [`ReconstructArgs`], [`reconstruct`].

use super::args::{count, name, ReconstructionArg};
use super::limits::Limits;
use super::{json, Output};
use crate::error::{finite_named, Error, Result};
use crate::quadrature::gauss_on_cells;
use crate::reconstruct::{cubic_spline, mls, taylor};
use serde::Serialize;

/// The `--taylor-average` choices ([`taylor::CellAverage`]).
#[derive(clap::ValueEnum, Clone, Copy, Debug, PartialEq, Eq)]
pub enum TaylorAverageArg {
    /// Δx²/3 (book Eq. 4.30).
    Exact,
    /// [F(b) − F(a)]/(b − a), F(x) = x³/3 − x_c x² + x_c² x at the absolute ends.
    AntiderivativeDifference,
    /// The same antiderivative as six terms, in the order of ewob/TLS TLS1D.py.
    AntiderivativeSixTerms,
}

/// Arguments of `hompm reconstruct`.
#[derive(clap::Args, Debug)]
pub struct ReconstructArgs {
    /// The reconstruction.
    #[arg(long, value_enum)]
    method: ReconstructionArg,
    /// Cell boundaries a,b,c,... (consecutive cells [a,b], [b,c], ...).
    #[arg(
        long,
        value_delimiter = ',',
        allow_hyphen_values = true,
        required = true
    )]
    cells: Vec<f64>,
    /// Data abscissae.
    #[arg(
        long,
        value_delimiter = ',',
        allow_hyphen_values = true,
        required = true
    )]
    points: Vec<f64>,
    /// Data values.
    #[arg(
        long,
        value_delimiter = ',',
        allow_hyphen_values = true,
        required = true
    )]
    values: Vec<f64>,
    /// Integral to conserve in each cell (tls-conservative).
    #[arg(long, value_delimiter = ',', allow_hyphen_values = true)]
    integrals: Option<Vec<f64>>,
    /// Number of Taylor basis functions n_b (1 to 20).
    #[arg(long, default_value_t = 3, value_parser = count, allow_negative_numbers = true)]
    order: usize,
    /// How TLS computes the cell average of (x − x_c)² in ψ_3: exactly, or
    /// from the antiderivative at the absolute cell ends, as a difference of
    /// two values or as the six terms of the TLS author's TLS1D.py
    /// (docs/conventions.md, "The TLS author's cell average").
    #[arg(long, value_enum, default_value_t = TaylorAverageArg::Exact)]
    taylor_average: TaylorAverageArg,
    /// Query points, inside the cells.
    #[arg(
        long,
        value_delimiter = ',',
        allow_hyphen_values = true,
        required = true
    )]
    at: Vec<f64>,
    /// Print JSON.
    #[arg(long)]
    json: bool,
}

#[derive(Serialize)]
struct ReconstructJson {
    method: String,
    values: Vec<f64>,
    cell_integrals: Vec<f64>,
    #[serde(skip_serializing_if = "Option::is_none")]
    condition_numbers: Option<Vec<f64>>,
}

/// Gauss points per sub-interval of the cell integrals: exact for TLS of
/// order ≤ 20 and for cubic pieces.
const GAUSS_POINTS: usize = 10;

/// Checks everything that needs no computation: finite data, increasing
/// cells whose integrals fit in double precision, matching lengths, and
/// queries inside the cells.
fn validate(a: &ReconstructArgs) -> Result<Vec<(f64, f64)>> {
    for (list, name) in [
        (&a.cells, "--cells"),
        (&a.points, "--points"),
        (&a.values, "--values"),
        (&a.at, "--at"),
    ] {
        for (i, &x) in list.iter().enumerate() {
            finite_named(x, || format!("{name} entry {i}"))?;
        }
    }
    if a.cells.len() < 2 {
        return Err(Error::InvalidArgument(
            "--cells needs at least two boundaries".into(),
        ));
    }
    if a.points.len() != a.values.len() {
        return Err(Error::InvalidArgument(format!(
            "--points has {} entries but --values has {}",
            a.points.len(),
            a.values.len()
        )));
    }
    let cells: Vec<(f64, f64)> = a.cells.windows(2).map(|w| (w[0], w[1])).collect();
    let largest = a
        .values
        .iter()
        .chain(a.integrals.iter().flatten())
        .fold(0.0f64, |m, v| m.max(v.abs()));
    for (e, &(lo, hi)) in cells.iter().enumerate() {
        if hi <= lo {
            return Err(Error::InvalidArgument(format!(
                "cell {e} [{lo}, {hi}] is empty: --cells must increase"
            )));
        }
        if !((hi - lo) * largest.max(1.0)).is_finite() {
            return Err(Error::InvalidArgument(format!(
                "cell {e} [{lo:e}, {hi:e}]: its width times the largest value {largest:e} overflows double precision, so its integral cannot be computed"
            )));
        }
    }
    let (lo, hi) = (cells[0].0, cells[cells.len() - 1].1);
    if let Some(&x) = a.at.iter().find(|&&x| x < lo || x > hi) {
        return Err(Error::OutsideDomain { x, a: lo, b: hi });
    }
    Ok(cells)
}

/// Work: MLS costs O(points) per evaluation, the others O(log points).
fn check_limits(a: &ReconstructArgs, limits: &Limits) -> Result<()> {
    let evaluations =
        a.at.len() as f64 + GAUSS_POINTS as f64 * (a.points.len() + a.cells.len()) as f64;
    let per = if a.method == ReconstructionArg::Mls {
        a.points.len() as f64
    } else {
        20.0
    };
    let what = || {
        format!(
            "{} reconstruction of {} points",
            name(&a.method),
            a.points.len()
        )
    };
    limits.check_memory(
        what,
        evaluations * 16.0 + a.points.len() as f64 * 200.0,
        "working storage",
    )?;
    limits.check_time(what, evaluations * per * 2e-8)
}

/// A reconstruction ready to evaluate, with its own exact cell integrals
/// where it has them (TLS, book Eq. 4.37) and κ(D) per cell.
struct Fitted {
    eval: Box<dyn Fn(f64) -> Result<f64>>,
    integrals: Option<Vec<f64>>,
    kappas: Option<Vec<f64>>,
}

fn fit(a: &ReconstructArgs, cells: &[(f64, f64)]) -> Result<Fitted> {
    use ReconstructionArg as R;
    match a.method {
        R::Tls | R::TlsConservative => {
            let ints = match (a.method, &a.integrals) {
                (R::Tls, _) => None,
                (_, Some(i)) => Some(i.as_slice()),
                (_, None) => {
                    return Err(Error::InvalidArgument(
                        "tls-conservative needs --integrals".into(),
                    ))
                }
            };
            let options = taylor::TlsOptions {
                order: a.order,
                average: match a.taylor_average {
                    TaylorAverageArg::Exact => taylor::CellAverage::Exact,
                    TaylorAverageArg::AntiderivativeDifference => {
                        taylor::CellAverage::AntiderivativeDifference
                    }
                    TaylorAverageArg::AntiderivativeSixTerms => {
                        taylor::CellAverage::AntiderivativeSixTerms
                    }
                },
                ..Default::default()
            };
            let r = taylor::reconstruct(cells, &a.points, &a.values, ints, options)?;
            Ok(Fitted {
                integrals: Some(r.cell_integrals()),
                kappas: Some(r.condition_numbers()),
                eval: Box::new(move |x| r.value_at(x)),
            })
        }
        R::CubicSpline | R::CubicSplineNatural => {
            let end = if a.method == R::CubicSpline {
                cubic_spline::EndCondition::NotAKnot
            } else {
                cubic_spline::EndCondition::Natural
            };
            let mut pairs: Vec<(f64, f64)> = a
                .points
                .iter()
                .copied()
                .zip(a.values.iter().copied())
                .collect();
            pairs.sort_by(|p, q| p.0.total_cmp(&q.0));
            let (x, y): (Vec<f64>, Vec<f64>) = pairs.into_iter().unzip();
            let s = cubic_spline::CubicSpline::new(&x, &y, end)?;
            Ok(Fitted {
                eval: Box::new(move |z| Ok(s.evaluate(z))),
                integrals: None,
                kappas: None,
            })
        }
        R::Mls => {
            let (cells, points, values) = (cells.to_vec(), a.points.clone(), a.values.clone());
            let eval = move |z: f64| {
                let e = cells
                    .partition_point(|&(_, hi)| hi < z)
                    .min(cells.len() - 1);
                let (lo, hi) = cells[e];
                mls::reconstruct_1d(z, &points, &values, hi - lo)
            };
            Ok(Fitted {
                eval: Box::new(eval),
                integrals: None,
                kappas: None,
            })
        }
    }
}

/// ∫ over each cell by Gauss quadrature on the sub-intervals between data
/// points (the reconstructions are smooth between them).
fn quadrature_integrals(
    cells: &[(f64, f64)],
    points: &[f64],
    eval: &dyn Fn(f64) -> Result<f64>,
) -> Result<Vec<f64>> {
    let mut sorted = points.to_vec();
    sorted.sort_by(|p, q| p.total_cmp(q));
    let mut out = Vec::with_capacity(cells.len());
    for &(lo, hi) in cells {
        let inside =
            &sorted[sorted.partition_point(|&x| x <= lo)..sorted.partition_point(|&x| x < hi)];
        let mut cuts = Vec::with_capacity(inside.len() + 2);
        cuts.push(lo);
        cuts.extend_from_slice(inside);
        cuts.push(hi);
        cuts.dedup();
        let subs: Vec<(f64, f64)> = cuts.windows(2).map(|w| (w[0], w[1])).collect();
        let mut sum = 0.0;
        for q in gauss_on_cells(&subs, GAUSS_POINTS)? {
            sum += q.weight * eval(q.x)?;
        }
        out.push(sum);
    }
    Ok(out)
}

/// `hompm reconstruct`.
pub fn reconstruct(a: ReconstructArgs, limits: &Limits) -> Result<Output> {
    let cells = validate(&a)?;
    check_limits(&a, limits)?;
    let fitted = fit(&a, &cells)?;
    let values: Vec<f64> =
        a.at.iter()
            .map(|&x| (fitted.eval)(x))
            .collect::<Result<_>>()?;
    let cell_integrals = match fitted.integrals {
        Some(i) => i,
        None => quadrature_integrals(&cells, &a.points, &*fitted.eval)?,
    };
    for (i, v) in values.iter().chain(&cell_integrals).enumerate() {
        finite_named(*v, || format!("reconstructed value or integral {i}"))?;
    }
    let doc = ReconstructJson {
        method: name(&a.method),
        values,
        cell_integrals,
        condition_numbers: fitted.kappas,
    };
    if a.json {
        return Ok(Output::text(json::strict(&doc)?));
    }
    let mut s = format!("{} reconstruction\n", doc.method);
    for (x, v) in a.at.iter().zip(&doc.values) {
        s.push_str(&format!("f({x}) = {v:.12e}\n"));
    }
    for (e, c) in doc.cell_integrals.iter().enumerate() {
        s.push_str(&format!("cell {e}: integral {c:.12e}"));
        if let Some(k) = &doc.condition_numbers {
            s.push_str(&format!(", condition number of D {:.3e}", k[e]));
        }
        s.push('\n');
    }
    Ok(Output::text(s))
}
