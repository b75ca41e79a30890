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

use super::{equal_to_digits, Computed, LabelledRow, Published, RunOptions, TableSpec};
use crate::error::Result;
use crate::mass::{assemble, row_sum_lumping};
use crate::mpm::mapping::{ConsistentSolver, MassMatrix};
use crate::studies::thesis::{
    self, bar_rms, bar_rms_with, OrderInputs, ThesisConventions, ThesisVariant, THESIS_RMS_DIGITS,
};
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

fn rms_grid(variant: ThesisVariant, conventions: ThesisConventions) -> Result<Vec<LabelledRow>> {
    let errors = thesis::rms_grid(variant, &LEVELS, &PPCS, conventions)?;
    Ok(LEVELS
        .iter()
        .zip(errors)
        .map(|(&c, row)| Computed::row(level_label(variant, c), row))
        .collect())
}

/// Orders log2(e(h)/e(h/2)) at 4 PPC, each labelled by its finer level,
/// from the RMS errors rounded as the thesis printed them.
fn order_grid(variant: ThesisVariant, conventions: ThesisConventions) -> Result<Vec<LabelledRow>> {
    order_grid_of(
        variant,
        conventions,
        OrderInputs::AsPrinted(THESIS_RMS_DIGITS),
    )
}

fn order_grid_of(
    variant: ThesisVariant,
    conventions: ThesisConventions,
    inputs: OrderInputs,
) -> Result<Vec<LabelledRow>> {
    let orders = thesis::orders(variant, &LEVELS, 4, conventions, inputs)?;
    Ok(LEVELS[1..]
        .iter()
        .zip(orders)
        .map(|(&c, order)| Computed::row(level_label(variant, c), [order]))
        .collect())
}

/// The note that lists the same table under the text read literally
/// (small strain, ‖P‖), with how many of its values reach the printed
/// digits: the variant the tables' conventions replace.
fn text_literal_note(id: &str, json: &str, rows: &[LabelledRow]) -> Result<String> {
    variant_note(
        "text-literal conventions (small-strain update, book Eq. 4.15; Richardson to ‖P − M^C v‖/‖P‖ ≤ 1e-9)",
        id,
        json,
        rows,
    )
}

/// A note that lists `rows`, computed under another reading named by
/// `heading`, with how many of them reach the printed digits.
fn variant_note(heading: &str, id: &str, json: &str, rows: &[LabelledRow]) -> Result<String> {
    let published = Published::parse(id, json)?;
    let (mut to_digits, mut total) = (0, 0);
    let mut cells = Vec::new();
    for (label, values) in rows {
        let Some(r) = published.row_labels.iter().position(|l| l == label) else {
            continue;
        };
        for (c, v) in values.iter().enumerate() {
            if let (Some(v), Some(p), Some(d)) = (v, published.values[r][c], published.digits[r][c])
            {
                total += 1;
                to_digits += usize::from(equal_to_digits(p, *v, d));
                cells.push(format!("{label} / {}: {v:.5e}", published.col_labels[c]));
            }
        }
    }
    Ok(format!(
        "{heading}: {to_digits} of {total} to the printed digits; {}",
        cells.join("; ")
    ))
}

/// A thesis table under the author's conventions, with its text-literal
/// values in a note.
fn with_text_literal(
    id: &str,
    json: &str,
    grid: fn(ThesisVariant, ThesisConventions) -> Result<Vec<LabelledRow>>,
    variant: ThesisVariant,
    mut notes: Vec<String>,
) -> Result<Computed> {
    let rows = grid(variant, ThesisConventions::AuthorsCode)?;
    let literal = grid(variant, ThesisConventions::TextLiteral)?;
    notes.push(text_literal_note(id, json, &literal)?);
    Ok(Computed {
        rows,
        notes,
        ..Default::default()
    })
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

const T51: &str = include_str!("../../golden/published/thesis-5.1.json");
const T52: &str = include_str!("../../golden/published/thesis-5.2.json");
const T61: &str = include_str!("../../golden/published/thesis-6.1.json");
const T62: &str = include_str!("../../golden/published/thesis-6.2.json");
const T71: &str = include_str!("../../golden/published/thesis-7.1.json");
const T72: &str = include_str!("../../golden/published/thesis-7.2.json");

fn linear_lagrange_rms(_: &RunOptions) -> Result<Computed> {
    with_text_literal(
        "thesis-5.1",
        T51,
        rms_grid,
        ThesisVariant::LinearLagrange,
        vec![],
    )
}

fn bspline_rms(_: &RunOptions) -> Result<Computed> {
    with_text_literal("thesis-6.2", T62, rms_grid, ThesisVariant::BSpline, vec![])
}

/// Thesis Table 7.1, with the finest level re-solved four ways in the notes.
fn spline_based_rms(o: &RunOptions) -> Result<Computed> {
    let mut notes = Vec::new();
    if !o.quick {
        let finest = |mass| {
            bar_rms_with(
                ThesisVariant::SplineBased,
                64,
                4,
                Some(mass),
                ThesisConventions::AuthorsCode,
            )
        };
        let direct = finest(MassMatrix::Consistent(ConsistentSolver::Cholesky))?;
        let tight = finest(MassMatrix::Consistent(ConsistentSolver::richardson(1e-13)))?;
        let loose = finest(MassMatrix::Consistent(ConsistentSolver::richardson(1e-6)))?;
        let lumped = finest(MassMatrix::Lumped)?;
        notes.push(format!(
                        "finest level (64 spans, 4 PPC) against the velocity solve: Richardson 1e-9 (table) {:.4e}; \
                         Richardson 1e-13 {tight:.4e}; Cholesky {direct:.4e}; Richardson 1e-6 {loose:.4e}; lumped mass {lumped:.4e}",
                        bar_rms(ThesisVariant::SplineBased, 64, 4)?
                    ));
    }
    with_text_literal(
        "thesis-7.1",
        T71,
        rms_grid,
        ThesisVariant::SplineBased,
        notes,
    )
}

/// An order table: from the RMS errors as printed, with the orders of the
/// unrounded errors and of the text-literal conventions in notes.
fn order_table(id: &str, json: &str, variant: ThesisVariant) -> Result<Computed> {
    let unrounded = order_grid_of(
        variant,
        ThesisConventions::AuthorsCode,
        OrderInputs::Unrounded,
    )?;
    let note = variant_note(
        "orders of the unrounded RMS errors (the author's conventions)",
        id,
        json,
        &unrounded,
    )?;
    with_text_literal(id, json, order_grid, variant, vec![note])
}

fn linear_lagrange_orders(_: &RunOptions) -> Result<Computed> {
    order_table("thesis-5.2", T52, ThesisVariant::LinearLagrange)
}

fn bspline_orders(_: &RunOptions) -> Result<Computed> {
    order_table("thesis-6.1", T61, ThesisVariant::BSpline)
}

fn spline_based_orders(_: &RunOptions) -> Result<Computed> {
    order_table("thesis-7.2", T72, ThesisVariant::SplineBased)
}

/// Thesis Tables 5.1, 5.2, 6.1, 6.2, 7.1, 7.2.
pub fn tables() -> Vec<TableSpec> {
    vec![
        registered("thesis-5.1", T51,
            "Linear Lagrange MPM (P1), direct mapping, lumped mass. Vibrating bar, thesis Table 4.1 (L = 25 m, ρ = 1, E = 100, v0 = 0.1), both ends fixed; n_p = cells·PPC particles at the centres of equal sub-intervals, V_p = L/n_p, v_p = v0 sin(πx_p/L); Euler–Cromer MUSL with Δt = 1e-5 s, 1999 steps; RMS of u_p against the analytic (linear) displacement at the initial positions, t = 1999·Δt. Conventions of the thesis author's code (MPM_1D_B_spline.m, 2016; public as roeltielen24/BSpline_MPM_1D; run under Octave by scripts/author_code_check.sh): its driver's default flag.deformation = 1, the large-strain update σ ← σ + (E − σ)Δε (book Eq. 4.16), and, with a consistent mass, Richardson iterated while ‖P − M^C v‖/‖v‖ ≥ 1e-9; the text-literal values are in the note.", linear_lagrange_rms),
        registered("thesis-5.2", T52,
            "Orders log2(e(h)/e(h/2)) of the RMS errors from the 4-PPC column of thesis-5.1, rounded to the five significant digits the thesis prints them with before the ratio is taken (the printed values of thesis Table 6.2 give all four printed orders of Table 6.1; docs/conventions.md, \"Orders from printed RMS values\"); the orders of the unrounded errors are in a note.", linear_lagrange_orders),
        registered("thesis-6.1", T61,
            "Orders log2(e(h)/e(h/2)) of the RMS errors from the 4-PPC column of thesis-6.2, rounded to the five significant digits the thesis prints them with before the ratio is taken (the printed values of thesis Table 6.2 give all four printed orders of Table 6.1; docs/conventions.md, \"Orders from printed RMS values\"); the orders of the unrounded errors are in a note.", bspline_orders),
        registered("thesis-6.2", T62,
            "Quadratic B-spline MPM on {0,0,0,α,…,L,L,L}, α = L/n_s, direct mapping, lumped mass; setup and conventions as thesis-5.1.", bspline_rms),
        registered("thesis-7.1", T71,
            "Spline-based MPM: quadratic B-splines; internal force, density and velocity from not-a-knot \
             cubic splines through the particle values at 2 Gauss points per half knot span (deactivated or \
             redefined outside [x_1 − V_1/2, x_N + V_N/2]); consistent mass from the reconstructed density \
             with the same rule; M^C v = P solved in full by Richardson from P/M^L while \
             ‖P − M^C v‖/‖v‖ ≥ 1e-9 (the author's code), then boundary velocities zeroed; setup and \
             conventions as thesis-5.1.", spline_based_rms),
        registered("thesis-7.2", T72,
            "Orders log2(e(h)/e(h/2)) of the RMS errors from the 4-PPC column of thesis-7.1, rounded to the five significant digits the thesis prints them with before the ratio is taken (the printed values of thesis Table 6.2 give all four printed orders of Table 6.1; docs/conventions.md, \"Orders from printed RMS values\"); the orders of the unrounded errors are in a note.", spline_based_orders),
    ]
}
