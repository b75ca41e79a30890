//! # Tables of the thesis
//!
//! `thesis-a1`: Appendix A.1–A.2, the assembly of three 2×2 element mass
//! matrices into a 4×4 global matrix and its row-sum lumping.
//!
//! `thesis-5.1` … `thesis-7.2`: the RMS errors and orders of the vibrating
//! bar for linear Lagrange, B-spline and spline-based MPM, run by
//! [`crate::studies::thesis`].
//!
//! Items: [`appendix_a1`], [`tables`].

use super::{Computed, LabelledRow, RunOptions, TableSpec};
use crate::error::Result;
use crate::mass::{assemble, row_sum_lumping};
use crate::mpm::mapping::{ConsistentSolver, MassMatrix};
use crate::studies::thesis::{self, bar_rms, bar_rms_with, ThesisVariant};
use faer::mat;

/// Thesis Appendix A.1 (M = Σ T_eᵀ M_e T_e) and A.2 (M^L_ii = Σ_j M_ij).
pub fn appendix_a1() -> TableSpec {
    TableSpec {
        id: "thesis-a1",
        published_json: include_str!("../../golden/published/thesis-a1.json"),
        setup: "Three linear elements with the element matrices M_1 = [5 4; 2 7], \
                M_2 = [1 2; 2 3], M_3 = [7 3; 5 2] of thesis A.1 (deliberately \
                non-symmetric), element e on global DOFs (e, e+1), assembled by \
                M = Σ T_eᵀ M_e T_e and lumped by row sums.",
        compute: compute_a1,
    }
}

fn compute_a1(_: &RunOptions) -> Result<Computed> {
    let elements = [
        mat![[5.0, 4.0], [2.0, 7.0]],
        mat![[1.0, 2.0], [2.0, 3.0]],
        mat![[7.0, 3.0], [5.0, 2.0]],
    ];
    let connectivity = vec![vec![0, 1], vec![1, 2], vec![2, 3]];
    let m = assemble(&elements, &connectivity, 4)?;
    let mut rows: Vec<_> = (0..m.nrows())
        .map(|i| {
            Computed::row(
                format!("M row {}", i + 1),
                (0..m.ncols()).map(|j| m[(i, j)]),
            )
        })
        .collect();
    rows.push(Computed::row("lumped diagonal", row_sum_lumping(&m)));
    Ok(Computed {
        rows,
        notes: vec![],
        ..Default::default()
    })
}

const LEVELS: [usize; 5] = [4, 8, 16, 32, 64];
const PPCS: [usize; 3] = [4, 6, 8];

/// The row label of a resolution: "16 elements" for Lagrange MPM, "16 knot
/// spans" for the spline variants (the thesis' own words).
fn level_label(variant: ThesisVariant, cells: usize) -> String {
    match variant {
        ThesisVariant::LinearLagrange => format!("{cells} elements"),
        _ => format!("{cells} knot spans"),
    }
}

fn rms_grid(variant: ThesisVariant) -> Result<Vec<LabelledRow>> {
    let errors = thesis::rms_grid(variant, &LEVELS, &PPCS)?;
    Ok(LEVELS
        .iter()
        .zip(errors)
        .map(|(&c, row)| Computed::row(level_label(variant, c), row))
        .collect())
}

/// Orders log2(e(h)/e(h/2)) at 4 PPC, each labelled by its finer level.
fn order_grid(variant: ThesisVariant) -> Result<Vec<LabelledRow>> {
    let orders = thesis::orders(variant, &LEVELS, 4)?;
    Ok(LEVELS[1..]
        .iter()
        .zip(orders)
        .map(|(&c, order)| Computed::row(level_label(variant, c), [order]))
        .collect())
}

/// A registered thesis table; each names its own computation, so a new id
/// can never fall into another's.
fn registered(
    id: &'static str,
    json: &'static str,
    setup: &'static str,
    compute: fn(&RunOptions) -> Result<Computed>,
) -> TableSpec {
    TableSpec {
        id,
        published_json: json,
        setup,
        compute,
    }
}

fn linear_lagrange_rms(_: &RunOptions) -> Result<Computed> {
    Ok(Computed {
        rows: rms_grid(ThesisVariant::LinearLagrange)?,
        notes: vec![],
        ..Default::default()
    })
}

fn bspline_rms(_: &RunOptions) -> Result<Computed> {
    Ok(Computed {
        rows: rms_grid(ThesisVariant::BSpline)?,
        notes: vec![],
        ..Default::default()
    })
}

/// Thesis Table 7.1, with the finest level re-solved four ways in the notes.
fn spline_based_rms(o: &RunOptions) -> Result<Computed> {
    let mut notes = Vec::new();
    if !o.quick {
        let direct = bar_rms_with(
            ThesisVariant::SplineBased,
            64,
            4,
            Some(MassMatrix::Consistent(ConsistentSolver::Cholesky)),
        )?;
        let tight = bar_rms_with(
            ThesisVariant::SplineBased,
            64,
            4,
            Some(MassMatrix::Consistent(ConsistentSolver::richardson(1e-13))),
        )?;
        let loose = bar_rms_with(
            ThesisVariant::SplineBased,
            64,
            4,
            Some(MassMatrix::Consistent(ConsistentSolver::richardson(1e-6))),
        )?;
        let lumped = bar_rms_with(ThesisVariant::SplineBased, 64, 4, Some(MassMatrix::Lumped))?;
        notes.push(format!(
                        "finest level (64 spans, 4 PPC) against the velocity solve: Richardson 1e-9 (table) {:.4e}; \
                         Richardson 1e-13 {tight:.4e}; Cholesky {direct:.4e}; Richardson 1e-6 {loose:.4e}; lumped mass {lumped:.4e}",
                        bar_rms(ThesisVariant::SplineBased, 64, 4)?
                    ));
    }
    Ok(Computed {
        rows: rms_grid(ThesisVariant::SplineBased)?,
        notes,
        ..Default::default()
    })
}

fn linear_lagrange_orders(_: &RunOptions) -> Result<Computed> {
    Ok(Computed {
        rows: order_grid(ThesisVariant::LinearLagrange)?,
        notes: vec![],
        ..Default::default()
    })
}

fn bspline_orders(_: &RunOptions) -> Result<Computed> {
    Ok(Computed {
        rows: order_grid(ThesisVariant::BSpline)?,
        notes: vec![],
        ..Default::default()
    })
}

fn spline_based_orders(_: &RunOptions) -> Result<Computed> {
    Ok(Computed {
        rows: order_grid(ThesisVariant::SplineBased)?,
        notes: vec![],
        ..Default::default()
    })
}

/// Thesis Tables 5.1, 5.2, 6.1, 6.2, 7.1, 7.2.
pub fn tables() -> Vec<TableSpec> {
    vec![
        registered("thesis-5.1", include_str!("../../golden/published/thesis-5.1.json"),
            "Linear Lagrange MPM (P1), direct mapping, lumped mass. Vibrating bar, thesis Table 4.1 (L = 25 m, ρ = 1, E = 100, v0 = 0.1), small-strain update, both ends fixed; n_p = cells·PPC particles at the centres of equal sub-intervals, V_p = L/n_p, v_p = v0 sin(πx_p/L); Euler–Cromer MUSL with Δt = 1e-5 s, 1999 steps; RMS of u_p against the analytic displacement at the initial positions, t = 1999·Δt.", linear_lagrange_rms),
        registered("thesis-5.2", include_str!("../../golden/published/thesis-5.2.json"),
            "Orders log2(e(h)/e(h/2)) from the 4-PPC column of thesis-5.1.", linear_lagrange_orders),
        registered("thesis-6.1", include_str!("../../golden/published/thesis-6.1.json"),
            "Orders log2(e(h)/e(h/2)) from the 4-PPC column of thesis-6.2.", bspline_orders),
        registered("thesis-6.2", include_str!("../../golden/published/thesis-6.2.json"),
            "Quadratic B-spline MPM on {0,0,0,α,…,L,L,L}, α = L/n_s, direct mapping, lumped mass; setup as thesis-5.1.", bspline_rms),
        registered("thesis-7.1", include_str!("../../golden/published/thesis-7.1.json"),
            "Spline-based MPM: quadratic B-splines; internal force, density and velocity from not-a-knot \
             cubic splines through the particle values at 2 Gauss points per half knot span (deactivated or \
             redefined outside [x_1 − V_1/2, x_N + V_N/2]); consistent mass from the reconstructed density \
             with the same rule; M^C v = P solved in full by Richardson from P/M^L to ‖P − M^C v‖/‖P‖ ≤ 1e-9, \
             then boundary velocities zeroed; setup as thesis-5.1.", spline_based_rms),
        registered("thesis-7.2", include_str!("../../golden/published/thesis-7.2.json"),
            "Orders log2(e(h)/e(h/2)) from the 4-PPC column of thesis-7.1.", spline_based_orders),
    ]
}
