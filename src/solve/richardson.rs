//! # Richardson iteration with the lumped mass matrix
//!
//! Thesis §7.2: M^L v^(n+1) = P + (M^L − M^C) v^(n), starting from
//! M^L v^(0) = P, stopped at the first iterate with ‖P − M^C v‖₂/‖P‖₂ ≤ ε
//! (the thesis uses ε = 1e-9). The error contracts by the spectral radius of
//! I − (M^L)⁻¹ M^C ([`richardson_contraction`]); the iteration converges only
//! while that radius is below one.
//!
//! Items: [`richardson`], [`richardson_contraction`].

use super::{check_rhs, norm, IterativeResult};
use crate::error::{Error, Result};
use crate::sparse::SparseMatrix;

/// Runs the thesis' Richardson iteration. `lumped` is the diagonal of M^L.
/// Iteration 0 is v^(0) = P/M^L. Errors if a lumped entry is not positive
/// (thesis §7.2.4: near-zero masses), if the residual grows to non-finite, or
/// if `max_iter` iterations do not meet the tolerance.
pub fn richardson(
    consistent: &SparseMatrix,
    lumped: &[f64],
    rhs: &[f64],
    tol: f64,
    max_iter: usize,
) -> Result<IterativeResult> {
    let n = consistent.rows();
    check_rhs(n, rhs, tol)?;
    if lumped.len() != n {
        return Err(Error::InvalidArgument(format!(
            "lumped diagonal has length {} but the system has size {n}",
            lumped.len()
        )));
    }
    if let Some((i, m)) = lumped
        .iter()
        .enumerate()
        .find(|(_, m)| m.is_nan() || **m <= 0.0)
    {
        return Err(Error::Singular(format!(
            "lumped mass {i} is {m:e}: Richardson needs positive lumped masses"
        )));
    }
    let pnorm = norm(rhs);
    let mut v: Vec<f64> = rhs.iter().zip(lumped).map(|(p, m)| p / m).collect();
    if pnorm == 0.0 {
        return Ok(IterativeResult {
            solution: v,
            iterations: 0,
            residuals: vec![0.0],
        });
    }
    let mut mv = vec![0.0; n];
    let mut residuals = Vec::new();
    for k in 0..=max_iter {
        consistent.mul_vec(&v, &mut mv);
        let r: Vec<f64> = rhs.iter().zip(&mv).map(|(p, q)| p - q).collect();
        let rel = norm(&r) / pnorm;
        residuals.push(rel);
        if !rel.is_finite() {
            return Err(Error::BlowUp(format!(
                "Richardson residual became {rel} at iteration {k}"
            )));
        }
        if rel <= tol {
            return Ok(IterativeResult {
                solution: v,
                iterations: k,
                residuals,
            });
        }
        // M^L v^(n+1) = P + (M^L − M^C) v^(n)  ⇔  v^(n+1) = v^(n) + (P − M^C v^(n))/M^L.
        for i in 0..n {
            v[i] += r[i] / lumped[i];
        }
    }
    Err(Error::NotConverged(format!(
        "Richardson reached {max_iter} iterations with relative residual {:e} (tolerance {tol:e})",
        residuals.last().copied().unwrap_or(f64::NAN)
    )))
}

/// Spectral radius of I − (M^L)⁻¹ M^C, computed from the symmetric similar
/// matrix I − (M^L)^{-1/2} M^C (M^L)^{-1/2} (faer eigenvalues).
pub fn richardson_contraction(consistent: &SparseMatrix, lumped: &[f64]) -> Result<f64> {
    if let Some((i, m)) = lumped
        .iter()
        .enumerate()
        .find(|(_, m)| m.is_nan() || **m <= 0.0)
    {
        return Err(Error::Singular(format!("lumped mass {i} is {m:e}")));
    }
    let s: Vec<f64> = lumped.iter().map(|m| 1.0 / m.sqrt()).collect();
    let scaled = consistent.scale_rows(&s).transpose().scale_rows(&s);
    let ev = super::spectrum::symmetric_eigenvalues(&scaled)?;
    Ok(ev.iter().map(|l| (1.0 - l).abs()).fold(0.0, f64::max))
}
