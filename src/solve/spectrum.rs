//! # Eigenvalues and condition numbers
//!
//! Book Eqs. (4.54)–(4.56): for an SPD matrix κ(M) = λ_max/λ_min. In 1D the
//! eigenvalues come from faer's self-adjoint eigen solver on the (small) dense
//! matrix; in 2D the Kronecker identity λ(A⊗B) = {λ_i(A) λ_j(B)} gives
//! λ_min = λ_min(A)λ_min(B), λ_max = λ_max(A)λ_max(B) and κ(A⊗B) = κ(A)κ(B),
//! so no 2D matrix is ever formed.
//!
//! Items: [`Spectrum`], [`symmetric_eigenvalues`], [`spectrum_1d`],
//! [`spectrum_kronecker`].

use crate::error::{Error, Result};
use crate::mass::Kronecker2d;
use crate::sparse::SparseMatrix;

/// Extreme eigenvalues (λ_min, λ_max) and κ = λ_max/λ_min of an SPD matrix.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Spectrum {
    /// Smallest eigenvalue.
    pub lambda_min: f64,
    /// Largest eigenvalue.
    pub lambda_max: f64,
}

impl Spectrum {
    /// κ = λ_max/λ_min, book Eq. (4.56).
    pub fn condition_number(&self) -> f64 {
        self.lambda_max / self.lambda_min
    }
}

/// All eigenvalues of a symmetric matrix, ascending (faer).
pub fn symmetric_eigenvalues(m: &SparseMatrix) -> Result<Vec<f64>> {
    if m.rows() != m.cols() || m.rows() == 0 {
        return Err(Error::InvalidArgument(format!(
            "eigenvalues need a non-empty square matrix, got {}×{}",
            m.rows(),
            m.cols()
        )));
    }
    let n = m.rows();
    let scale = power_of_two_scale(m);
    let dense = faer::Mat::<f64>::from_fn(n, n, |i, j| m.get(i, j) * scale);
    let ev = dense
        .self_adjoint_eigenvalues(faer::Side::Lower)
        .map_err(|e| Error::NotConverged(format!("eigenvalue solver: {e:?}")))?;
    let mut v: Vec<f64> = ev.iter().map(|l| l / scale).collect();
    v.sort_by(|a, b| a.total_cmp(b));
    Ok(v)
}

/// 1, or the power of two that brings the largest entry of `m` to [1, 2)
/// when that entry lies outside [2⁻²⁵⁶, 2²⁵⁶]: faer's eigensolver overflows
/// on entries near f64::MAX (diag(1e308, 1e308) came back as ∞). Scaling by
/// a power of two is exact, so the eigenvalues are those of `m`; matrices of
/// ordinary size are not scaled at all, and their eigenvalues are unchanged.
fn power_of_two_scale(m: &SparseMatrix) -> f64 {
    let largest = (0..m.rows())
        .flat_map(|i| m.row(i).1.iter())
        .fold(0.0f64, |a, v| a.max(v.abs()));
    let (low, high) = (2f64.powi(-256), 2f64.powi(256));
    if largest == 0.0 || (low..=high).contains(&largest) {
        return 1.0;
    }
    2f64.powi(-(largest.log2().floor() as i32))
}

/// λ_min, λ_max of an SPD matrix; `Error::Singular` if λ_min ≤ 0.
pub fn spectrum_1d(m: &SparseMatrix) -> Result<Spectrum> {
    let ev = symmetric_eigenvalues(m)?;
    let s = Spectrum {
        lambda_min: ev[0],
        lambda_max: ev[ev.len() - 1],
    };
    // A symmetric eigensolver resolves eigenvalues only to about
    // n·ε·λ_max: below that, λ_min's sign and size are rounding noise and
    // the honest statement is that κ exceeds what double precision resolves.
    let resolution = ev.len() as f64 * f64::EPSILON * s.lambda_max.abs();
    if !s.lambda_min.is_finite() || !s.lambda_max.is_finite() {
        return Err(Error::Singular(format!(
            "the spectrum [{:e}, {:e}] is not finite",
            s.lambda_min, s.lambda_max
        )));
    }
    if s.lambda_max <= 0.0 {
        return Err(Error::Singular(format!(
            "the matrix is not positive definite: λ_max = {:e}",
            s.lambda_max
        )));
    }
    if s.lambda_min.abs() <= resolution {
        return Err(Error::IllConditioned {
            what: format!("the {}×{} matrix", ev.len(), ev.len()),
            kappa_at_least: s.lambda_max.abs() / resolution,
        });
    }
    if s.lambda_min < 0.0 {
        return Err(Error::Singular(format!(
            "the matrix is not positive definite: λ_min = {:e}",
            s.lambda_min
        )));
    }
    Ok(s)
}

/// λ_min, λ_max of M_y ⊗ M_x from the factors' spectra (no 2D matrix).
pub fn spectrum_kronecker(k: &Kronecker2d) -> Result<Spectrum> {
    let sx = spectrum_1d(&k.x)?;
    let sy = spectrum_1d(&k.y)?;
    Ok(Spectrum {
        lambda_min: sx.lambda_min * sy.lambda_min,
        lambda_max: sx.lambda_max * sy.lambda_max,
    })
}
