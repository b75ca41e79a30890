//! # `hompm basis`: B-spline values at points (book Eqs. 4.19–4.23)
//!
//! Items: [`BasisArgs`], [`basis`].

use super::args::count;
use super::limits::Limits;
use super::{json, Output};
use crate::error::Result;
use crate::spline::KnotVector;
use serde::Serialize;

/// Arguments of `hompm basis`.
#[derive(clap::Args, Debug)]
pub struct BasisArgs {
    /// Polynomial degree p.
    #[arg(long, value_parser = count, allow_negative_numbers = true)]
    degree: usize,
    /// Comma-separated knots, non-decreasing.
    #[arg(
        long,
        value_delimiter = ',',
        allow_hyphen_values = true,
        required = true
    )]
    knots: Vec<f64>,
    /// Comma-separated evaluation points inside the domain.
    #[arg(
        long,
        value_delimiter = ',',
        allow_hyphen_values = true,
        required = true
    )]
    at: Vec<f64>,
    /// Also print first derivatives.
    #[arg(long)]
    derivatives: bool,
    /// Print JSON.
    #[arg(long)]
    json: bool,
}

#[derive(Serialize)]
struct BasisJson {
    degree: usize,
    knots: Vec<f64>,
    points: Vec<f64>,
    values: Vec<Vec<f64>>,
    #[serde(skip_serializing_if = "Option::is_none")]
    derivatives: Option<Vec<Vec<f64>>>,
}

/// Every basis function at every point: the output has points × functions
/// numbers (about 24 bytes each as text), and each point costs O(p² + n).
fn check_limits(a: &BasisArgs, limits: &Limits) -> Result<()> {
    let points = a.at.len() as f64;
    let functions = a.knots.len() as f64;
    let per_value = if a.derivatives { 48.0 } else { 24.0 };
    let what = || format!("{} points × {} knots", a.at.len(), a.knots.len());
    limits.check_memory(what, points * functions * per_value, "an output")?;
    let p = a.degree as f64;
    limits.check_time(what, points * (p * p + functions) * 1e-8)
}

fn all_finite(v: Vec<f64>, x: f64) -> Result<Vec<f64>> {
    for (i, &y) in v.iter().enumerate() {
        crate::error::finite_named(y, || format!("basis function {i} at x = {x}"))?;
    }
    Ok(v)
}

/// `hompm basis`: φ_i(x) (and φ_i'(x)) of [`KnotVector`] at each point.
pub fn basis(a: BasisArgs, limits: &Limits) -> Result<Output> {
    // The knot vector is checked first: it is O(knots), and a degree that
    // does not fit the knots is a clearer message than a time estimate.
    let kv = KnotVector::new(a.knots.clone(), a.degree)?;
    check_limits(&a, limits)?;
    let mut values = Vec::with_capacity(a.at.len());
    let mut derivatives = Vec::new();
    for &x in &a.at {
        values.push(all_finite(kv.dense_values(x)?, x)?);
        if a.derivatives {
            derivatives.push(all_finite(kv.dense_derivatives(x)?, x)?);
        }
    }
    let doc = BasisJson {
        degree: a.degree,
        knots: a.knots,
        points: a.at,
        values,
        derivatives: a.derivatives.then_some(derivatives),
    };
    if a.json {
        return Ok(Output::text(json::strict(&doc)?));
    }
    let (lo, hi) = kv.domain();
    let mut s = format!(
        "degree {} on {} knots: {} basis functions, domain [{lo}, {hi}]\n",
        doc.degree,
        doc.knots.len(),
        kv.num_basis(),
    );
    let row = |r: &[f64]| {
        r.iter()
            .map(|v| format!("{v:.12}"))
            .collect::<Vec<_>>()
            .join(", ")
    };
    for (k, x) in doc.points.iter().enumerate() {
        s.push_str(&format!("x = {x}: phi = [{}]\n", row(&doc.values[k])));
        if let Some(d) = &doc.derivatives {
            s.push_str(&format!("        dphi = [{}]\n", row(&d[k])));
        }
    }
    Ok(Output::text(s))
}
