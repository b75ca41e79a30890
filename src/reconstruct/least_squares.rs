//! # Least squares approximation
//!
//! Book Eqs. (4.26)–(4.29), TLS paper Eqs. (10)–(11): with basis functions
//! ψ_1 … ψ_{n_b} and data (x_p, f_p), the coefficients solve the normal
//! equations D α = B F with D = Σ_p ψ(x_p) ψ(x_p)ᵀ, B = [ψ(x_1) … ψ(x_N)],
//! F = [f_1 … f_N]ᵀ. The condition number κ(D) is reported because it detects
//! data layouts that make the fit meaningless (TLS paper §5.3).
//!
//! The systems are small (one unknown per basis function, at most a few),
//! so they are solved in nalgebra's fixed-size stack matrices, the tool for
//! small dense algebra; faer is the crate's type for everything larger
//! (docs/conventions.md, "Matrix types").
//!
//! Items: [`LeastSquaresFit`], [`SINGULAR_CONDITION`], [`fit`], [`fit_rows`].

use crate::error::{finite_named, Error, Result};
use nalgebra::allocator::Allocator;
use nalgebra::{Const, DefaultAllocator, Dim, DimDiff, DimSub, Dyn, OMatrix, OVector, U1};

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

/// κ₂ = λ_max/λ_min by nalgebra's symmetric eigenvalues, for any storage:
/// a fixed-size and a dynamic matrix give bit for bit the same numbers
/// (the same generic algorithm), so small systems live on the stack.
pub(crate) fn condition_number_of<D>(d: OMatrix<f64, D, D>) -> f64
where
    D: Dim + DimSub<U1>,
    DefaultAllocator: Allocator<D, D> + Allocator<D> + Allocator<DimDiff<D, U1>>,
{
    if d.nrows() == 0 {
        return 1.0;
    }
    let ev = d.symmetric_eigenvalues();
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
        return Err(Error::LengthMismatch {
            what: "data values (one per basis row)".into(),
            expected: rows.len(),
            got: values.len(),
        });
    }
    for (k, v) in values.iter().enumerate() {
        finite_named(*v, || format!("data value {k}"))?;
    }
    fit_rows(
        rows.len(),
        nb,
        |p, out| out.copy_from_slice(&rows[p][..nb]),
        |p| values[p],
        None,
    )
}

/// Book Eqs. (4.26)–(4.29) for data given point by point: `row(p, ψ)` fills
/// ψ(x_p) (length `nb`) and `value(p)` is f_p. D = Σ_p ψψᵀ and BF = Σ_p ψ f_p
/// are accumulated point by point, without a `Vec` per point.
///
/// With `max_condition = Some(κ_max)` (a TLS cell, TLS paper §5.3) fewer
/// than `nb` points, or κ(D) > κ_max, is reported first as
/// `Error::Singular`; then non-finite data; then κ(D) >
/// [`SINGULAR_CONDITION`]. Systems of up to four unknowns are solved in
/// fixed-size (stack) matrices, with the same numbers as dynamic ones.
pub fn fit_rows(
    count: usize,
    nb: usize,
    row: impl Fn(usize, &mut [f64]),
    value: impl Fn(usize) -> f64,
    max_condition: Option<f64>,
) -> Result<LeastSquaresFit> {
    let problem = RowProblem {
        count,
        row,
        value,
        max_condition,
    };
    match nb {
        1 => problem.solve(Const::<1>),
        2 => problem.solve(Const::<2>),
        3 => problem.solve(Const::<3>),
        4 => problem.solve(Const::<4>),
        _ => problem.solve(Dyn(nb)),
    }
}

/// The data of [`fit_rows`].
struct RowProblem<R, V> {
    count: usize,
    row: R,
    value: V,
    max_condition: Option<f64>,
}

impl<R: Fn(usize, &mut [f64]), V: Fn(usize) -> f64> RowProblem<R, V> {
    fn solve<D>(&self, dim: D) -> Result<LeastSquaresFit>
    where
        D: Dim + DimSub<U1>,
        DefaultAllocator: Allocator<D, D> + Allocator<D> + Allocator<DimDiff<D, U1>>,
    {
        let nb = dim.value();
        if self.max_condition.is_some() && self.count < nb {
            return Err(Error::Singular(format!(
                "{} data points cannot determine {nb} Taylor coefficients",
                self.count
            )));
        }
        let (d, bf) = self.normal_equations(dim);
        let kappa = condition_number_of(d.clone());
        if let Some(limit) = self.max_condition {
            if kappa.is_nan() || kappa > limit {
                return Err(Error::Singular(format!(
                    "the least-squares matrix D has condition number {kappa:e} > {limit:e}"
                )));
            }
        }
        for p in 0..self.count {
            let v = (self.value)(p);
            if !v.is_finite() {
                return Err(Error::NonFinite {
                    what: format!("data value {p}"),
                    value: v,
                });
            }
        }
        if nb == 0 {
            return Ok(LeastSquaresFit {
                coefficients: vec![],
                condition_number: 1.0,
            });
        }
        if kappa.is_nan() || kappa > SINGULAR_CONDITION {
            return Err(Error::Singular(format!(
                "least-squares matrix D has condition number {kappa:e} ({} data points for {nb} basis functions)",
                self.count
            )));
        }
        let chol = d.cholesky().ok_or_else(|| {
            Error::Singular("least-squares matrix D is not positive definite".into())
        })?;
        let alpha = chol.solve(&bf);
        Ok(LeastSquaresFit {
            coefficients: alpha.iter().copied().collect(),
            condition_number: kappa,
        })
    }

    /// D = Σ_p ψ(x_p) ψ(x_p)ᵀ and BF = Σ_p ψ(x_p) f_p (book Eq. 4.27), in
    /// one pass over the points (each row ψ(x_p) is evaluated once).
    fn normal_equations<D>(&self, dim: D) -> (OMatrix<f64, D, D>, OVector<f64, D>)
    where
        D: Dim,
        DefaultAllocator: Allocator<D, D> + Allocator<D>,
    {
        let nb = dim.value();
        let mut d = OMatrix::<f64, D, D>::zeros_generic(dim, dim);
        let mut bf = OVector::<f64, D>::zeros_generic(dim, U1);
        let mut psi = OVector::<f64, D>::zeros_generic(dim, U1);
        for p in 0..self.count {
            (self.row)(p, psi.as_mut_slice());
            let v = (self.value)(p);
            for i in 0..nb {
                for j in 0..nb {
                    d[(i, j)] += psi[i] * psi[j];
                }
                bf[i] += psi[i] * v;
            }
        }
        (d, bf)
    }
}
