//! # Least squares approximation
//!
//! Book Eqs. (4.26)–(4.29), TLS paper Eqs. (10)–(11): with basis functions
//! ψ_1 … ψ_{n_b} and data (x_p, f_p), the coefficients solve the normal
//! equations D α = B F with D = Σ_p ψ(x_p) ψ(x_p)ᵀ, B = [ψ(x_1) … ψ(x_N)],
//! F = [f_1 … f_N]ᵀ. The condition number κ(D) is reported because it detects
//! data layouts that make the fit meaningless (TLS paper §5.3).

use crate::error::{finite, Error, Result};
use nalgebra::{DMatrix, DVector};

/// A least-squares fit: coefficients α and κ(D).
#[derive(Debug, Clone, PartialEq)]
pub struct LeastSquaresFit {
    /// α = D⁻¹ B F (book Eq. 4.26).
    pub coefficients: Vec<f64>,
    /// κ₂(D) = λ_max/λ_min of the symmetric matrix D (∞ if singular).
    pub condition_number: f64,
}

/// Condition numbers above this are treated as singular.
pub const SINGULAR_CONDITION: f64 = 1e12;

/// The normal matrix D of book Eq. (4.27) for the rows ψ(x_p).
pub fn normal_matrix(rows: &[Vec<f64>], nb: usize) -> DMatrix<f64> {
    let mut d = DMatrix::zeros(nb, nb);
    for r in rows {
        for i in 0..nb {
            for j in 0..nb {
                d[(i, j)] += r[i] * r[j];
            }
        }
    }
    d
}

/// κ₂ of a symmetric positive semi-definite matrix (∞ if λ_min ≤ 0).
pub fn symmetric_condition_number(d: &DMatrix<f64>) -> f64 {
    if d.nrows() == 0 {
        return 1.0;
    }
    let ev = d.clone().symmetric_eigenvalues();
    let max = ev.iter().cloned().fold(f64::NEG_INFINITY, f64::max);
    let min = ev.iter().cloned().fold(f64::INFINITY, f64::min);
    if min <= 0.0 || max <= 0.0 {
        f64::INFINITY
    } else {
        max / min
    }
}

/// Solves the normal equations for the basis rows ψ(x_p) (one `Vec` per data
/// point, each of length `nb`) and the data values. Errors: mismatched
/// lengths, non-finite data, or κ(D) > [`SINGULAR_CONDITION`]
/// (`Error::Singular`, with κ in the message).
pub fn fit(rows: &[Vec<f64>], values: &[f64], nb: usize) -> Result<LeastSquaresFit> {
    if rows.len() != values.len() {
        return Err(Error::InvalidArgument(format!(
            "{} basis rows but {} data values",
            rows.len(),
            values.len()
        )));
    }
    for (k, v) in values.iter().enumerate() {
        finite(&format!("data value {k}"), *v)?;
    }
    if nb == 0 {
        return Ok(LeastSquaresFit {
            coefficients: vec![],
            condition_number: 1.0,
        });
    }
    let d = normal_matrix(rows, nb);
    let kappa = symmetric_condition_number(&d);
    if kappa.is_nan() || kappa > SINGULAR_CONDITION {
        return Err(Error::Singular(format!(
            "least-squares matrix D has condition number {kappa:e} ({} data points for {nb} basis functions)",
            rows.len()
        )));
    }
    let mut bf = DVector::zeros(nb);
    for (r, v) in rows.iter().zip(values) {
        for i in 0..nb {
            bf[i] += r[i] * v;
        }
    }
    let chol = d
        .cholesky()
        .ok_or_else(|| Error::Singular("least-squares matrix D is not positive definite".into()))?;
    let alpha = chol.solve(&bf);
    Ok(LeastSquaresFit {
        coefficients: alpha.iter().copied().collect(),
        condition_number: kappa,
    })
}
