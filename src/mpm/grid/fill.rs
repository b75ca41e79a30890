//! # The batch fill of the basis at the particles
//!
//! [`Grid::fill_stencils`](super::Grid::fill_stencils)'s hot paths: φ_i(x_p) and
//! ∇φ_i(x_p) (book Eqs. 4.5–4.6 with B-splines, thesis §6.1, or Lagrange
//! elements, thesis §5.1) at every particle, with the stencil width known
//! at compile time, the same numbers bit for bit as one point at a time
//! (`Grid::evaluate`).

use crate::basis::Stencils;
use crate::error::Result;
use crate::lagrange::LagrangeBasis;
use crate::spline::bspline::SpanScratch;
use crate::spline::knots::KnotVector;

/// [`Grid::fill_stencils`] on a B-spline grid of width `W` = p + 1 (0: any
/// width): [`KnotVector::values_and_gradients_fixed`] at every point, the
/// same numbers as [`Grid::evaluate`].
pub(super) fn fill_bspline_stencils<const W: usize>(
    kv: &KnotVector,
    xs: impl Iterator<Item = f64>,
    stencils: &mut Stencils,
    scratch: &mut SpanScratch,
) -> Result<()> {
    if W == 0 {
        return fill_any_width(xs, stencils, |x, v, g| {
            kv.values_and_gradients_into(x, scratch, v, g)
        });
    }
    fill_fixed_width::<W>(xs, stencils, |x, v, g| {
        kv.values_and_gradients_fixed::<W>(x, v, g)
    })
}

/// [`Grid::fill_stencils`] on a Lagrange grid of width `W` = degree + 1 (0:
/// any width): [`LagrangeBasis::evaluate_fixed`] at every point, the same
/// numbers as [`LagrangeBasis::evaluate_into`], which a width the basis
/// does not have falls back to.
pub(super) fn fill_lagrange_stencils<const W: usize>(
    basis: &LagrangeBasis,
    xs: impl Iterator<Item = f64>,
    stencils: &mut Stencils,
) -> Result<()> {
    if W == 0 {
        return fill_any_width(xs, stencils, |x, v, g| basis.evaluate_into(x, v, g));
    }
    fill_fixed_width::<W>(xs, stencils, |x, v, g| {
        match basis.evaluate_fixed::<W>(x, v, g) {
            Some(result) => result,
            None => basis.evaluate_into(x, v, g),
        }
    })
}

/// Point k's stencil by `evaluate(x_k, values, gradients)`, which returns
/// its first function, with the width read at run time.
fn fill_any_width(
    xs: impl Iterator<Item = f64>,
    stencils: &mut Stencils,
    mut evaluate: impl FnMut(f64, &mut [f64], &mut [f64]) -> Result<usize>,
) -> Result<()> {
    for (k, x) in xs.enumerate() {
        let (v, g) = stencils.slots_mut(k);
        stencils.first[k] = evaluate(x, v, g)?;
    }
    Ok(())
}

/// Point k's stencil by `evaluate(x_k, values, gradients)` into rows of
/// the compile-time width `W` (no slicing per point).
#[inline(always)]
fn fill_fixed_width<const W: usize>(
    xs: impl Iterator<Item = f64>,
    stencils: &mut Stencils,
    mut evaluate: impl FnMut(f64, &mut [f64; W], &mut [f64; W]) -> Result<usize>,
) -> Result<()> {
    let Stencils {
        first,
        values,
        gradients,
        ..
    } = stencils;
    let rows = values.as_chunks_mut::<W>().0.iter_mut();
    let rows = rows.zip(gradients.as_chunks_mut::<W>().0.iter_mut());
    for ((x, f), (v, g)) in xs.zip(first.iter_mut()).zip(rows) {
        *f = evaluate(x, v, g)?;
    }
    Ok(())
}
