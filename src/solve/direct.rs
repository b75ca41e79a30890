//! # Sparse Cholesky
//!
//! The direct solver the thesis (§7.2) compares Richardson against: M^C is SPD,
//! so a sparse Cholesky factorisation (faer) solves M^C v = P exactly up to
//! rounding.
//!
//! Items: [`cholesky_solve`].

use crate::error::{Error, Result};
use crate::sparse::SparseMatrix;
use faer::linalg::solvers::Solve;

/// Solves A x = b by sparse Cholesky. `Error::Singular` if A is not SPD.
pub fn cholesky_solve(a: &SparseMatrix, b: &[f64]) -> Result<Vec<f64>> {
    super::check_rhs(a.rows(), b, 1.0)?;
    let m = a.to_faer()?;
    let llt = m
        .sp_cholesky(faer::Side::Lower)
        .map_err(|e| {
            Error::Singular(format!(
                "Cholesky failed ({e:?}): the matrix is not SPD, or its condition number exceeds what double precision resolves"
            ))
        })?;
    let rhs = faer::Mat::<f64>::from_fn(b.len(), 1, |i, _| b[i]);
    let x = llt.solve(&rhs);
    let out: Vec<f64> = (0..b.len()).map(|i| x[(i, 0)]).collect();
    if out.iter().any(|v| !v.is_finite()) {
        return Err(Error::Singular(
            "Cholesky produced a non-finite solution".into(),
        ));
    }
    Ok(out)
}
