//! # Moving least squares shape functions
//!
//! MLS paper Eqs. (6)–(17). At an evaluation point x, the coefficients a(x)
//! minimise the weighted error J(x) = Σ_p w(x − x_p)[pᵀ(x_p) a − u_p]²
//! (Eq. 7; the paper's pᵀ(x) inside the sum is read as pᵀ(x_p), as Eq. (10)
//! shows), which gives A(x) a = B(x) U with A = Σ_p w p(x_p) p(x_p)ᵀ
//! (Eq. 10) and B = [w_1 p(x_1) … w_N p(x_N)] (Eq. 11). The shape functions
//! are Φ(x)ᵀ = pᵀ(x) A⁻¹(x) B(x) (Eqs. 13–14), so u_h(x) = Σ_p φ_p(x) u_p.
//!
//! Basis: linear, p = [1, x] in 1D and [1, x, y] in 2D (Eq. 15). Weight: the
//! quadratic spline w(r) of Eq. (17) with r = |x − x_p|/(2l), l the cell size,
//! and the tensor product w(r_x) w(r_y) in 2D (Eq. 16). Its support is
//! |x − x_p| < 3l. A singular A (too few points in the support, or all on a
//! line in 2D) is `Error::SingularMoments`, which names the point, the number
//! of points in the support and κ(A).
//!
//! Items: [`quadratic_spline_weight`], [`MLS_MAX_CONDITION`],
//! [`shape_functions_1d`], [`shape_functions_2d`], [`reconstruct_1d`].

use super::least_squares::condition_number_of;
use crate::error::{finite, Error, Result};
use nalgebra::allocator::Allocator;
use nalgebra::{Const, DefaultAllocator, Dim, DimDiff, DimSub, OMatrix, OVector, U1};

/// The quadratic-spline weight of MLS paper Eq. (17) at distance r (in
/// units of the support scale): 3/4 − r² for |r| ≤ ½, ½(3/2 − |r|)² for
/// ½ < |r| ≤ 3/2, 0 beyond. Written with a select instead of branches, as
/// the 2D engine's neighbour search evaluates it four times per candidate
/// and about half of the candidates lie outside the support; one
/// implementation serves the 1D oracle and the 2D engine.
#[inline]
pub fn quadratic_spline_weight(r: f64) -> f64 {
    let r = r.abs();
    let inner = 0.75 - r * r;
    let t = (1.5 - r).max(0.0);
    let outer = 0.5 * t * t;
    if r <= 0.5 {
        inner
    } else {
        outer
    }
}

/// κ(A) above which the moment matrix counts as singular.
pub const MLS_MAX_CONDITION: f64 = 1e12;

/// Φ_p(x) = pᵀ(x) A⁻¹(x) w_p p(x_p) (MLS paper Eq. 14) for a basis of
/// `dim` functions (2 in 1D, 3 in 2D): A is a fixed-size stack matrix.
fn shape_functions<D>(
    dim: D,
    p_eval: &[f64],
    basis_rows: &[Vec<f64>],
    weights: &[f64],
) -> Result<Vec<f64>>
where
    D: Dim + DimSub<U1>,
    DefaultAllocator: Allocator<D, D> + Allocator<D> + Allocator<DimDiff<D, U1>>,
{
    let nb = dim.value();
    let mut a = OMatrix::<f64, D, D>::zeros_generic(dim, dim);
    let mut active = 0;
    for (row, &w) in basis_rows.iter().zip(weights) {
        if w > 0.0 {
            active += 1;
        }
        for i in 0..nb {
            for j in 0..nb {
                a[(i, j)] += w * row[i] * row[j];
            }
        }
    }
    let kappa = condition_number_of(a.clone());
    if kappa.is_nan() || kappa > MLS_MAX_CONDITION {
        return Err(Error::SingularMoments {
            point: p_eval[1..].to_vec(),
            points_in_support: active,
            condition_number: kappa,
            limit: MLS_MAX_CONDITION,
        });
    }
    let chol = a
        .cholesky()
        .ok_or_else(|| Error::Singular("MLS moment matrix A is not positive definite".into()))?;
    // Φ_p = pᵀ(x) A⁻¹ w_p p(x_p) = (A⁻¹ p(x))ᵀ w_p p(x_p)  (A symmetric).
    let z = chol.solve(&OVector::<f64, D>::from_column_slice_generic(
        dim, U1, p_eval,
    ));
    Ok(basis_rows
        .iter()
        .zip(weights)
        .map(|(row, &w)| w * row.iter().zip(z.iter()).map(|(r, q)| r * q).sum::<f64>())
        .collect())
}

/// 1D MLS shape functions φ_p(x) for data points `points`, linear basis
/// [1, x], weight w(|x − x_p|/(2l)). MLS paper Eq. (14).
pub fn shape_functions_1d(x: f64, points: &[f64], cell_size: f64) -> Result<Vec<f64>> {
    finite("evaluation point", x)?;
    check_cell_size(cell_size)?;
    let rows: Vec<Vec<f64>> = points
        .iter()
        .map(|&xp| finite("data point", xp).map(|xp| vec![1.0, xp]))
        .collect::<Result<_>>()?;
    let weights: Vec<f64> = points
        .iter()
        .map(|&xp| quadratic_spline_weight((x - xp) / (2.0 * cell_size)))
        .collect();
    shape_functions(Const::<2>, &[1.0, x], &rows, &weights)
}

/// 2D MLS shape functions with basis [1, x, y] (Eq. 15) and the tensor weight
/// w(r_x) w(r_y) of Eq. (16) on cells of size l_x × l_y.
pub fn shape_functions_2d(
    x: [f64; 2],
    points: &[[f64; 2]],
    cell_size: [f64; 2],
) -> Result<Vec<f64>> {
    finite("evaluation point x", x[0])?;
    finite("evaluation point y", x[1])?;
    check_cell_size(cell_size[0])?;
    check_cell_size(cell_size[1])?;
    let rows: Vec<Vec<f64>> = points.iter().map(|p| vec![1.0, p[0], p[1]]).collect();
    let weights: Vec<f64> = points
        .iter()
        .map(|p| {
            quadratic_spline_weight((x[0] - p[0]) / (2.0 * cell_size[0]))
                * quadratic_spline_weight((x[1] - p[1]) / (2.0 * cell_size[1]))
        })
        .collect();
    shape_functions(Const::<3>, &[1.0, x[0], x[1]], &rows, &weights)
}

fn check_cell_size(l: f64) -> Result<()> {
    if l.is_nan() || l <= 0.0 || l.is_infinite() {
        return Err(Error::InvalidArgument(format!(
            "MLS cell size must be positive and finite, got {l}"
        )));
    }
    Ok(())
}

/// u_h(x) = Σ_p φ_p(x) u_p in 1D (MLS paper Eq. 13).
pub fn reconstruct_1d(x: f64, points: &[f64], values: &[f64], cell_size: f64) -> Result<f64> {
    if points.len() != values.len() {
        return Err(Error::LengthMismatch {
            what: "values (one per point)".into(),
            expected: points.len(),
            got: values.len(),
        });
    }
    let phi = shape_functions_1d(x, points, cell_size)?;
    Ok(phi.iter().zip(values).map(|(p, u)| p * u).sum())
}
