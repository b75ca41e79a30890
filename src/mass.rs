//! # Mass matrices
//!
//! The consistent mass matrix M^C = ∫ ρ φ φᵀ dΩ (book Eqs. 4.2 and 4.58,
//! thesis §3.1) and its lumped forms: row-sum lumping M_ii = Σ_j M^C_ij
//! (book Eq. 4.3, thesis A.2) and variational lumping m = ∫ ρ φ dΩ (book
//! Eq. 4.4). The assembly from element matrices, M = Σ_e T_eᵀ M_e T_e, is
//! thesis Appendix A.1.

use crate::error::{Error, Result};
use nalgebra::DMatrix;

/// Assembles element matrices into a global matrix, thesis Appendix A.1:
/// M = Σ_e T_eᵀ M_e T_e, where T_e is the Boolean matrix that maps the local
/// DOFs of element e to the global ones listed in `connectivity[e]`.
///
/// This dense form is for small worked examples; production paths use banded
/// or sparse storage.
pub fn assemble(
    element_matrices: &[DMatrix<f64>],
    connectivity: &[Vec<usize>],
    size: usize,
) -> Result<DMatrix<f64>> {
    if element_matrices.len() != connectivity.len() {
        return Err(Error::InvalidArgument(format!(
            "{} element matrices but {} connectivity lists",
            element_matrices.len(),
            connectivity.len()
        )));
    }
    let mut global = DMatrix::zeros(size, size);
    for (e, (me, dofs)) in element_matrices.iter().zip(connectivity).enumerate() {
        if me.nrows() != dofs.len() || me.ncols() != dofs.len() {
            return Err(Error::InvalidArgument(format!(
                "element {e}: matrix is {}×{} but it has {} DOFs",
                me.nrows(),
                me.ncols(),
                dofs.len()
            )));
        }
        for (a, &i) in dofs.iter().enumerate() {
            for (b, &j) in dofs.iter().enumerate() {
                if i >= size || j >= size {
                    return Err(Error::InvalidArgument(format!(
                        "element {e}: DOF {} outside 0..{size}",
                        i.max(j)
                    )));
                }
                global[(i, j)] += me[(a, b)];
            }
        }
    }
    Ok(global)
}

/// Row-sum lumping, book Eq. (4.3) and thesis A.2: M_ii = Σ_j M_ij.
pub fn row_sum_lumping(matrix: &DMatrix<f64>) -> Vec<f64> {
    matrix.row_iter().map(|r| r.sum()).collect()
}
