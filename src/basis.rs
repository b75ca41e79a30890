//! # The common interface of one-dimensional bases
//!
//! hompm has two families of 1D bases: B-splines on a knot vector
//! (book §4.3, thesis §6.1) and Lagrange elements (thesis §5.1–5.2). Both have
//! compact support, so at a point only a few functions are non-zero. A
//! [`LocalBasis`] holds those few values and derivatives together with the
//! index of the first one; the [`Basis1d`] trait lets the mass matrices, the
//! reconstructions and the MPM step work with either family.

use crate::error::Result;

/// The non-zero basis functions (and derivatives) at one point.
///
/// `derivatives[k][j]` is the k-th derivative of basis function `first + j`;
/// `derivatives[0]` holds the values themselves.
#[derive(Debug, Clone, PartialEq)]
pub struct LocalBasis {
    /// Global index of the first non-zero function.
    pub first: usize,
    /// `derivatives[k][j]`: k-th derivative of function `first + j`.
    pub derivatives: Vec<Vec<f64>>,
}

impl LocalBasis {
    /// The values φ_{first+j}(x).
    pub fn values(&self) -> &[f64] {
        &self.derivatives[0]
    }

    /// The first derivatives φ'_{first+j}(x); zeros if they were not asked for.
    pub fn gradients(&self) -> &[f64] {
        self.derivatives.get(1).map(|d| d.as_slice()).unwrap_or(&[])
    }

    /// Scatters derivative order `k` into a dense vector of length `n`.
    pub fn dense(&self, k: usize, n: usize) -> Vec<f64> {
        let mut out = vec![0.0; n];
        if let Some(d) = self.derivatives.get(k) {
            for (j, v) in d.iter().enumerate() {
                out[self.first + j] = *v;
            }
        }
        out
    }
}

/// A one-dimensional basis with compact support on a bounded domain.
pub trait Basis1d {
    /// Number of basis functions (degrees of freedom).
    fn num_basis(&self) -> usize;
    /// Polynomial degree on each cell (so that p+1 Gauss points integrate
    /// φ_i φ_j exactly).
    fn degree(&self) -> usize;
    /// The closed domain [a, b] on which the functions form a partition of unity.
    fn domain(&self) -> (f64, f64);
    /// Values and derivatives up to `order` of the non-zero functions at `x`.
    /// Errors for a non-finite `x` or one outside [`Basis1d::domain`].
    fn local(&self, x: f64, order: usize) -> Result<LocalBasis>;
    /// The points where some basis-function derivative is discontinuous
    /// (element boundaries for P1/P2, knots of multiplicity p for B-splines),
    /// used to count grid crossings.
    fn gradient_breaks(&self) -> Vec<f64>;
    /// The integration cells: maximal intervals on which every function is a
    /// polynomial (elements or non-empty knot spans).
    fn cells(&self) -> Vec<(f64, f64)>;
}
