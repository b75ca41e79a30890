//! # The batch fill of the basis at the particles
//!
//! [`Grid::fill_stencils`](super::Grid::fill_stencils)'s hot paths: φ_i(x_p) and
//! ∇φ_i(x_p) (book Eqs. 4.5–4.6 with B-splines, thesis §6.1, or Lagrange
//! elements, thesis §5.1) at every particle, with the stencil width known
//! at compile time, the same numbers bit for bit as one point at a time
//! (`Grid::evaluate`).

use super::{Grid, GridBasis};
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

impl Grid {
    /// Whether [`Grid::fixed_width_evaluator`] serves this grid: a
    /// B-spline or Lagrange grid without DDMPM's dual domain, whose stencil
    /// width is one of the compile-time widths 2, 3, 4.
    pub(crate) fn fills_fixed_width(&self) -> bool {
        self.dual.is_none()
            && matches!(self.stencil_width(), 2..=4)
            && matches!(self.basis, GridBasis::BSpline(_) | GridBasis::Lagrange(_))
    }

    /// The evaluation of [`Grid::fill_stencils`] at one point, for a loop
    /// that does more with each particle's basis than store it (the fused
    /// 1D step, `mpm::musl`, adds its mass and forces to the nodes while the
    /// basis is in registers): the same numbers bit for bit. `None` unless
    /// `W` is this grid's width and [`Grid::fills_fixed_width`].
    pub(crate) fn fixed_width_evaluator<const W: usize>(
        &self,
    ) -> Option<FixedWidthEvaluator<'_, W>> {
        if W == 0 || W != self.stencil_width() || !self.fills_fixed_width() {
            return None;
        }
        match &self.basis {
            GridBasis::BSpline(kv) => Some(FixedWidthEvaluator::BSpline(kv)),
            GridBasis::Lagrange(basis) => Some(FixedWidthEvaluator::Lagrange(basis)),
            GridBasis::Natural(_) => None,
        }
    }
}

/// φ_i(x) and ∇φ_i(x) at one point into rows of width `W`
/// ([`Grid::fixed_width_evaluator`]).
#[derive(Debug, Clone, Copy)]
pub(crate) enum FixedWidthEvaluator<'a, const W: usize> {
    /// [`KnotVector::values_and_gradients_fixed`].
    BSpline(&'a KnotVector),
    /// [`LagrangeBasis::evaluate_fixed`].
    Lagrange(&'a LagrangeBasis),
}

/// A particle loop over the basis of a fixed width `W`
/// ([`FixedWidthEvaluator::run`]): `run` is compiled once per basis, with
/// `evaluate` the basis' own function, so the loop takes no branch on the
/// kind of basis per particle.
pub(crate) trait FixedWidthLoop<const W: usize> {
    /// What the loop returns.
    type Output;
    /// The loop, given φ_i(x), ∇φ_i(x) at one point into its rows (the
    /// return value is the first function's index).
    fn run(
        self,
        evaluate: impl Fn(f64, &mut [f64; W], &mut [f64; W]) -> Result<usize>,
    ) -> Self::Output;
}

impl<const W: usize> FixedWidthEvaluator<'_, W> {
    /// Runs `particle_loop` with this grid's basis: the branch on its kind
    /// is taken once, outside the loop (the same numbers at every point
    /// as [`Grid::fill_stencils`]).
    #[inline(always)]
    pub(crate) fn run<L: FixedWidthLoop<W>>(self, particle_loop: L) -> L::Output {
        match self {
            Self::BSpline(kv) => {
                particle_loop.run(|x, v, g| kv.values_and_gradients_fixed::<W>(x, v, g))
            }
            // The width was checked with the grid's (fixed_width_evaluator);
            // the basis by value, so that its fields stay in registers.
            Self::Lagrange(basis) => {
                let basis = basis.clone();
                particle_loop.run(move |x, v, g| basis.evaluate_of_width::<W>(x, v, g))
            }
        }
    }
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
