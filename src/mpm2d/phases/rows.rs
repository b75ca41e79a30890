//! # The rows of a tensor stencil
//!
//! MLS paper Eqs. (4)–(5) walk the nodes of a particle's tensor stencil
//! row by row (b outer, a inner, N_i = N_a(x) N_b(y)). A loop that adds to
//! or reads from nodal arrays takes each row of an array as one slice
//! ([`TensorStencil::for_each_row`], [`StencilRow::for_each`]): one bounds
//! check per row instead of one per node, the same nodes in the same order
//! as [`TensorStencil::for_each`], which is built on it. The particles'
//! stencils come from fixed-width chunks of the workspace's 1D stencils
//! ([`particle_stencils`]).
//!
//! Items: `StencilRow`, `particle_stencils` (private to the phases).

use super::TensorStencil;
use crate::basis::Stencils;

/// Row b of a tensor stencil: the x-stencil [N_a(x)], [N_a'(x)] and the
/// row's N_b(y), N_b'(y).
#[derive(Clone, Copy)]
pub(super) struct StencilRow<'a> {
    values_x: &'a [f64],
    gradients_x: &'a [f64],
    nb: f64,
    db: f64,
}

impl StencilRow<'_> {
    /// The row's width.
    #[inline(always)]
    pub(super) fn len(&self) -> usize {
        self.values_x.len()
    }

    /// Calls `visit(a, N_i, ∇N_i)` for a = 0, 1, … along the row, with
    /// N_i = N_a N_b and ∇N_i = (N_a' N_b, N_a N_b') (Eqs. 4–5).
    #[inline(always)]
    pub(super) fn for_each(&self, mut visit: impl FnMut(usize, f64, [f64; 2])) {
        let (nb, db) = (self.nb, self.db);
        for (a, (&na, &da)) in self.values_x.iter().zip(self.gradients_x).enumerate() {
            visit(a, na * nb, [da * nb, na * db]);
        }
    }
}

impl<'a> TensorStencil<'a> {
    /// Calls `visit(start, row)` for every row b of the stencil in order,
    /// `start` the row's first node (first_y + b)·n + first_x.
    #[inline(always)]
    pub(super) fn for_each_row(&self, mut visit: impl FnMut(usize, StencilRow<'a>)) {
        for (b, (&nb, &db)) in self.values_y.iter().zip(self.gradients_y).enumerate() {
            let row = StencilRow {
                values_x: self.values_x,
                gradients_x: self.gradients_x,
                nb,
                db,
            };
            visit(self.first + b * self.nodes_per_side, row);
        }
    }
}

/// The tensor stencils of every particle, in particle order, from the
/// workspace's 1D stencils of width `w` (the compile-time `W` of the
/// loops that call it, so that each row has a known length and no slice
/// is checked per particle).
#[inline(always)]
pub(super) fn particle_stencils<'a>(
    sx: &'a Stencils,
    sy: &'a Stencils,
    w: usize,
    n: usize,
) -> impl Iterator<Item = TensorStencil<'a>> + 'a {
    let along_x = sx.values.chunks_exact(w).zip(sx.gradients.chunks_exact(w));
    let along_y = sy.values.chunks_exact(w).zip(sy.gradients.chunks_exact(w));
    let firsts = sx.first.iter().zip(&sy.first);
    along_x
        .zip(along_y)
        .zip(firsts)
        .map(move |(((vx, gx), (vy, gy)), (&fx, &fy))| TensorStencil {
            values_x: vx,
            gradients_x: gx,
            values_y: vy,
            gradients_y: gy,
            first: fy * n + fx,
            nodes_per_side: n,
        })
}
