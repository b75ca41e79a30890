//! # Solvers for mass-matrix systems
//!
//! Book §4.6–4.7 and thesis §7.2: the consistent mass matrix M^C of high-order
//! B-splines is SPD but ill-conditioned (κ grows about 8× per degree, book
//! Table 4.2), so plain iterative methods slow down with p.
//!
//! - [`spectrum`]: λ_min, λ_max and κ = λ_max/λ_min (book Eqs. 4.54–4.56);
//! - [`cg`]: conjugate gradients with the stopping rule of Eq. (4.53);
//! - [`richardson`]: the thesis' lumped-preconditioned Richardson iteration;
//! - [`pmultigrid`]: p-multigrid V-cycles (book Eqs. 4.59–4.62);
//! - [`direct`]: sparse Cholesky (faer), the reference;
//! - [`gravity_rhs`]: the right-hand side of the book's test problem
//!   (`mass::unit_density_mass_2d`).
//!
//! Items: [`LinearOperator`], [`IterativeResult`], [`norm`], [`dot`],
//! [`gravity_rhs`], [`cg`], [`direct`], [`pmultigrid`], [`richardson`],
//! [`spectrum`].

pub mod cg;
pub mod direct;
pub mod pmultigrid;
pub mod richardson;
pub mod spectrum;

use crate::error::{Error, Result};
use crate::mass::Kronecker2d;
use crate::sparse::SparseMatrix;

/// A square linear operator y = A x.
pub trait LinearOperator {
    /// Dimension n.
    fn size(&self) -> usize;
    /// y = A x.
    fn apply(&self, x: &[f64], y: &mut [f64]);
}

impl LinearOperator for SparseMatrix {
    fn size(&self) -> usize {
        self.rows()
    }
    fn apply(&self, x: &[f64], y: &mut [f64]) {
        self.mul_vec(x, y)
    }
}

impl LinearOperator for Kronecker2d {
    fn size(&self) -> usize {
        self.rows()
    }
    fn apply(&self, x: &[f64], y: &mut [f64]) {
        Kronecker2d::apply(self, x, y)
    }
}

/// The outcome of an iterative solve.
#[derive(Debug, Clone, PartialEq)]
pub struct IterativeResult {
    /// The final iterate.
    pub solution: Vec<f64>,
    /// Iterations (or cycles) performed.
    pub iterations: usize,
    /// Relative residual ‖r_k‖/‖r_0‖ (or ‖b − A x_k‖/‖b‖) after each iteration,
    /// starting with iteration 0.
    pub residuals: Vec<f64>,
}

/// Euclidean norm.
pub fn norm(v: &[f64]) -> f64 {
    v.iter().map(|x| x * x).sum::<f64>().sqrt()
}

/// Euclidean inner product.
pub fn dot(a: &[f64], b: &[f64]) -> f64 {
    a.iter().zip(b).map(|(x, y)| x * y).sum()
}

/// Checks a right-hand side against an operator size.
pub(crate) fn check_rhs(n: usize, b: &[f64], tol: f64) -> Result<()> {
    if b.len() != n {
        return Err(Error::LengthMismatch {
            what: "right-hand side (one entry per unknown)".into(),
            expected: n,
            got: b.len(),
        });
    }
    for (i, v) in b.iter().enumerate() {
        crate::error::finite_named(*v, || format!("right-hand side entry {i}"))?;
    }
    if !(tol.is_finite() && tol >= f64::EPSILON) {
        return Err(Error::InvalidArgument(format!(
            "the relative tolerance must be finite and at least ε = {:e}, which double precision can resolve; got {tol:e}",
            f64::EPSILON
        )));
    }
    Ok(())
}

/// The right-hand side of book Tables 4.3–4.4: f = M·(−9.81·1), so that the
/// exact solution of M a = f is the constant −9.81.
pub fn gravity_rhs(m: &dyn LinearOperator) -> Vec<f64> {
    let ones = vec![-9.81; m.size()];
    let mut f = vec![0.0; m.size()];
    m.apply(&ones, &mut f);
    f
}
