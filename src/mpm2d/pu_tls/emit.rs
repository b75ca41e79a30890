//! # The lists of PU-TLS: φ_gp of a cell's four Gauss points
//!
//! The last stage of [`super::PuTlsShapes`]'s evaluation (module doc of
//! [`super`]): with the per-particle coefficients [c_pe, B_pe] of every
//! patch at hand, φ_gp = Σ_e N_e(x_g)[c_pe + B_pe·ψ̂_e(x_g)] for the four
//! Gauss points g of a cell and every particle of the 5×5 cells around it,
//! the sum over the patches e that hold both, in the order (b, then a) of
//! e = (a, b). Each particle's four sums are kept in registers while its
//! patches are visited and written once into the lists, which grow within
//! the capacity reserved by [`super::PuTlsShapes::new`].
//!
//! Items: `PuTlsShapes::emit_cell` (private to `mpm2d::pu_tls`).

use super::{fitted_functions, local, PuTlsShapes};
use crate::mpm2d::reconstruction::GaussGrid;

/// The four Gauss points of a cell in
/// [`crate::mpm2d::reconstruction::storage_order`].
const QUAD: [(usize, usize); 4] = [(0, 0), (1, 0), (0, 1), (1, 1)];

impl PuTlsShapes {
    /// φ_gp of the four Gauss points of cell (cx, cy) over the particles of
    /// the 5×5 cells around it, appended to the lists; `K` = 1 + the most
    /// fitted functions. Each particle's four φ_gp are summed in registers
    /// over the patches that hold both it and the cell, in the order
    /// (b, then a) of the patches, and written once.
    pub(super) fn emit_cell<const K: usize>(&mut self, gauss: &GaussGrid, cx: usize, cy: usize) {
        let (n, h) = (self.cells, gauss.cell_size);
        let (x0, x1) = (cx.saturating_sub(2), (cx + 2).min(n - 1));
        let (y0, y1) = (cy.saturating_sub(2), (cy + 2).min(n - 1));
        // N_e(x_g)·(1, ψ₂(x_g), …) of patch e = (cx + i, cy + j) at slot
        // i + 3j, per function r and Gauss point q.
        let mut factors = [[[0.0; 4]; K]; 9];
        for j in 0..3 {
            for i in 0..3 {
                let (a, b) = (cx + i, cy + j);
                for (q, (qi, qj)) in QUAD.into_iter().enumerate() {
                    let (gx, gy) = (2 * cx + qi, 2 * cy + qj);
                    let value = self.gauss_values[gx][i] * self.gauss_values[gy][j];
                    let psi = fitted_functions(
                        local(gauss.abscissae[gx] / h, a),
                        local(gauss.abscissae[gy] / h, b),
                        &self.axis[a],
                        &self.axis[b],
                    );
                    let f = &mut factors[i + 3 * j];
                    f[0][q] = value;
                    for r in 1..K {
                        f[r][q] = value * psi[r - 1];
                    }
                }
            }
        }
        // The cells of a row of the block hold consecutive slots.
        let start = &self.bin_start;
        let row = |by: usize| start[x0 + n * by]..start[x1 + 1 + n * by];
        let total: usize = (y0..=y1).map(|by| row(by).len()).sum();
        let shapes = &mut self.shapes;
        // `phi` is as long as the longest lists have been, overwritten from
        // the start at every evaluation; the lists are its first
        // `particle.len()` entries. It grows (zeros, within the capacity of
        // `new`: never reallocated) only past that length.
        let first = shapes.particle.len();
        if shapes.phi.len() < first + 4 * total {
            shapes.phi.resize(first + 4 * total, 0.0);
        }
        // The four lists of the cell's points, one after the other.
        let (out0, rest) = shapes.phi[first..first + 4 * total].split_at_mut(total);
        let (out1, rest) = rest.split_at_mut(total);
        let (out2, out3) = rest.split_at_mut(total);
        let mut index = 0;
        for by in y0..=y1 {
            // The patches b = cy + j that hold cell row by: by ≤ b ≤ by + 2.
            let js = by.max(cy) - cy..by.min(cy) + 3 - cy;
            for bx in x0..=x1 {
                let is = bx.max(cx) - cx..bx.min(cx) + 3 - cx;
                // The patches that hold both: (index among the particle's
                // nine, N_e ψ̂ at the cell's points), in the order (b, a).
                let mut pairs = [(0, &factors[0]); 9];
                let mut held = 0;
                for j in js.clone() {
                    for i in is.clone() {
                        pairs[held] = ((cx + i - bx) + 3 * (cy + j - by), &factors[i + 3 * j]);
                        held += 1;
                    }
                }
                let pairs = &pairs[..held];
                let slots = start[bx + n * by]..start[bx + n * by + 1];
                let count = slots.len();
                let outs = [
                    &mut out0[index..][..count],
                    &mut out1[index..][..count],
                    &mut out2[index..][..count],
                    &mut out3[index..][..count],
                ];
                blend_patches::<K>(&self.coefficients[slots], pairs, outs);
                index += count;
            }
        }
        let ng = 2 * n;
        for (qi, qj) in QUAD {
            let g = (2 * cx + qi) + ng * (2 * cy + qj);
            shapes.start[g] = shapes.particle.len();
            for by in y0..=y1 {
                shapes
                    .particle
                    .extend_from_slice(&self.bin_particles[row(by)]);
            }
            shapes.end[g] = shapes.particle.len();
        }
    }
}

/// The body of [`blend_patches`], inlined into its baseline and AVX2 copies.
#[inline(always)]
fn blend_patches_kernel<const K: usize>(
    coefficients: &[[[f64; super::FITTED + 1]; 9]],
    pairs: &[(usize, &[[f64; 4]; K])],
    outs: [&mut [f64]; 4],
) {
    let [out0, out1, out2, out3] = outs;
    for (index, cf) in coefficients.iter().enumerate() {
        let mut phi = [0.0; 4];
        for &(e, f) in pairs {
            let c = &cf[e];
            // Σ_r c_r f_r from r = 0, as the sum was.
            let mut dot = f[0].map(|x| c[0] * x);
            for r in 1..K {
                for q in 0..4 {
                    dot[q] += c[r] * f[r][q];
                }
            }
            for q in 0..4 {
                phi[q] += dot[q];
            }
        }
        [out0[index], out1[index], out2[index], out3[index]] = phi;
    }
}

crate::dispatch::avx2_when_available! {
    /// φ_gp at the cell's four Gauss points for a run of particles (their
    /// coefficients `coefficients`, one per slot) into `outs[q]`: Σ over the
    /// `pairs` (patch slot e, N_e ψ̂_e at the points) of Σ_r c_r f_r, from
    /// r = 0, in the order of `pairs`. AVX2 where the processor has it
    /// ([`crate::dispatch`]): the four points are the four lanes of one
    /// register.
    #[inline(never)]
    fn blend_patches<const K: usize>(
        coefficients: &[[[f64; super::FITTED + 1]; 9]],
        pairs: &[(usize, &[[f64; 4]; K])],
        outs: [&mut [f64]; 4],
    ) = blend_patches_kernel;
}
