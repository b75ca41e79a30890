//! # Tables of the thesis
//!
//! `thesis-a1`: Appendix A.1–A.2, the assembly of three 2×2 element mass
//! matrices into a 4×4 global matrix and its row-sum lumping.

use super::{Computed, RunOptions, TableSpec, Tolerance};
use crate::error::Result;
use crate::mass::{assemble, row_sum_lumping};
use nalgebra::DMatrix;

/// Thesis Appendix A.1 (M = Σ T_eᵀ M_e T_e) and A.2 (M^L_ii = Σ_j M_ij).
pub fn appendix_a1() -> TableSpec {
    TableSpec {
        id: "thesis-a1",
        published_json: include_str!("../../golden/published/thesis-a1.json"),
        setup: "Three linear elements with the element matrices M_1 = [5 4; 2 7], \
                M_2 = [1 2; 2 3], M_3 = [7 3; 5 2] of thesis A.1 (deliberately \
                non-symmetric), element e on global DOFs (e, e+1), assembled by \
                M = Σ T_eᵀ M_e T_e and lumped by row sums.",
        tolerance: |_, _| Tolerance::Exact,
        compute: compute_a1,
    }
}

fn compute_a1(_: &RunOptions) -> Result<Computed> {
    let elements = [
        DMatrix::from_row_slice(2, 2, &[5.0, 4.0, 2.0, 7.0]),
        DMatrix::from_row_slice(2, 2, &[1.0, 2.0, 2.0, 3.0]),
        DMatrix::from_row_slice(2, 2, &[7.0, 3.0, 5.0, 2.0]),
    ];
    let connectivity = vec![vec![0, 1], vec![1, 2], vec![2, 3]];
    let m = assemble(&elements, &connectivity, 4)?;
    let mut values: Vec<Vec<Option<f64>>> = m
        .row_iter()
        .map(|r| r.iter().map(|v| Some(*v)).collect())
        .collect();
    values.push(row_sum_lumping(&m).into_iter().map(Some).collect());
    Ok(Computed {
        values,
        notes: vec![],
    })
}
