//! # Tables of the book chapter
//!
//! Book §4.6–4.7, Tables 4.2–4.4: the 2D tensor-product B-spline mass matrix
//! (ρ = 1) on the unit square with n = 1/h spans per direction, open uniform
//! knots with C^{p−1} continuity and homogeneous Dirichlet conditions (first
//! and last function of each direction removed: (n + p − 2)² DOFs).
//!
//! - `book-4.2`: κ = λ_max/λ_min by the Kronecker identity κ(M_y⊗M_x) = κ(M_x)κ(M_y).
//! - `book-4.3`: CG iterations for f = M·(−9.81·1) from zero until
//!   ‖r_k‖/‖r_0‖ < 1e-8 (recursive residual, assembled sparse 2D matrix).
//! - `book-4.4`: p-multigrid V-cycles (forward Gauss–Seidel, ν₁ = ν₂ = 8,
//!   lumped transfer, CG to 1e-4 on p = 1) until ‖f − Ma‖/‖f‖ < 1e-8.
//!
//! The runs are [`crate::studies::book`]'s.
//!
//! Items: [`tables`].

use super::{Computed, LabelledRow, TableSpec};
use crate::error::Result;
use crate::solve::cg::CgVariant;
use crate::solve::pmultigrid::PMultigridOptions;
use crate::studies::book::{cg_iterations, condition_number, pmg_alternatives, pmg_cycles};

/// f(p, 1/h) for p = 1 … `degrees` (rows, labelled "p = …" as the book's
/// tables) and the given 1/h (columns, in the published order).
fn grid(
    degrees: usize,
    cols: &[usize],
    mut f: impl FnMut(usize, usize) -> Result<f64>,
) -> Result<Vec<LabelledRow>> {
    (1..=degrees)
        .map(|p| {
            let row = cols
                .iter()
                .map(|&n| f(p, n).map(Some))
                .collect::<Result<_>>()?;
            Ok((format!("p = {p}"), row))
        })
        .collect()
}

fn table_4_2() -> TableSpec {
    TableSpec {
        id: "book-4.2",
        published_json: include_str!("../../golden/published/book-4.2.json"),
        setup: "2D tensor-product B-spline mass matrix, ρ = 1, unit square, 1/h spans per \
                direction, open uniform knots (C^{p−1}), exact Gauss quadrature (p+1 points), \
                homogeneous Dirichlet (first and last function per direction removed). \
                κ = λ_max/λ_min (Eq. 4.56) from faer's 1D eigenvalues and κ(M⊗M) = κ(M)².",
        compute: |_| {
            let rows = grid(5, &[8, 16, 32, 64], |p, n| condition_number(n, p))?;
            Ok(Computed {
                rows,
                notes: vec![],
                ..Default::default()
            })
        },
    }
}

fn table_4_3() -> TableSpec {
    TableSpec {
        id: "book-4.3",
        published_json: include_str!("../../golden/published/book-4.3.json"),
        setup: "Same matrix as book-4.2. f = M·(−9.81·1) (exact solution constant). Plain CG \
                from zero with the recursive residual (Hestenes–Stiefel), stopped when \
                ‖r_k‖/‖r_0‖ < 1e-8 (Eq. 4.53), on the assembled sparse 2D matrix. Integer \
                counts must match exactly; the note gives the spread over CG variants that are \
                equal in exact arithmetic.",
        compute: |_| {
            use rayon::prelude::*;
            let cols = [16, 32, 64, 128];
            // Every (p, 1/h) with its six counts, in parallel; the first
            // (recursive, assembled) is the table's cell.
            let variants = [
                CgVariant::Recursive,
                CgVariant::TrueResidual,
                CgVariant::PolakRibiere,
            ];
            let cells: Vec<(usize, usize)> = (1..=5).flat_map(|p| cols.map(|n| (p, n))).collect();
            let counts: Vec<Vec<usize>> = cells
                .par_iter()
                .map(|&(p, n)| {
                    variants
                        .iter()
                        .flat_map(|&v| [true, false].map(|assembled| (v, assembled)))
                        .map(|(v, assembled)| cg_iterations(n, p, v, assembled))
                        .collect::<Result<_>>()
                })
                .collect::<Result<_>>()?;
            let at = |p: usize, n: usize| {
                cells
                    .iter()
                    .position(|&c| c == (p, n))
                    .map(|k| &counts[k])
                    .ok_or_else(|| {
                        crate::error::Error::InvalidArgument(format!(
                            "no CG run for p = {p}, 1/h = {n}"
                        ))
                    })
            };
            let rows = grid(5, &cols, |p, n| Ok(at(p, n)?[0] as f64))?;
            let mut notes = Vec::new();
            for p in 1..=5 {
                let mut parts = Vec::new();
                for &n in &cols {
                    let counts = at(p, n)?;
                    let lo = counts.iter().min().copied().unwrap_or(0);
                    let hi = counts.iter().max().copied().unwrap_or(0);
                    parts.push(format!("1/h={n}: {lo}–{hi}"));
                }
                notes.push(format!("CG-variant spread, p = {p}: {}", parts.join(", ")));
            }
            Ok(Computed {
                rows,
                notes,
                ..Default::default()
            })
        },
    }
}

fn table_4_4() -> TableSpec {
    TableSpec {
        id: "book-4.4",
        published_json: include_str!("../../golden/published/book-4.4.json"),
        setup: "Same matrix and f as book-4.3. p-multigrid V-cycles from zero: levels p, p−1, …, 1 \
                on the same spans with C^{q−1} continuity and rediscretised mass matrices; \
                forward Gauss–Seidel with ν₁ = ν₂ = 8; lumped transfer M_L⁻¹P, P_ij = ∫φ_i^q φ_j^{q−1}; \
                CG to 1e-4 on p = 1; stop at ‖f − Ma‖/‖f‖ < 1e-8.",
        compute: |options| {
            use rayon::prelude::*;
            let cols = [8, 16, 32, 64];
            // The book's options, then (unless quick) the alternatives of
            // the notes; every (options, p, 1/h) in parallel, each a count
            // or the error that stopped it.
            let mut options_list = vec![PMultigridOptions::default()];
            if !options.quick {
                options_list.extend(pmg_alternatives().into_iter().map(|(_, o)| o));
            }
            let cells: Vec<(usize, usize, usize)> = (0..options_list.len())
                .flat_map(|o| (1..=5).flat_map(move |p| cols.map(|n| (o, p, n))))
                .collect();
            let cycles: Vec<Result<usize>> = cells
                .par_iter()
                .map(|&(o, p, n)| pmg_cycles(n, p, options_list[o]))
                .collect();
            let at = |o: usize, p: usize, n: usize| {
                cells
                    .iter()
                    .position(|&c| c == (o, p, n))
                    .map(|k| &cycles[k])
                    .ok_or_else(|| {
                        crate::error::Error::InvalidArgument(format!(
                            "no p-multigrid run for p = {p}, 1/h = {n}"
                        ))
                    })
            };
            let rows = grid(5, &cols, |p, n| match at(0, p, n)? {
                Ok(c) => Ok(*c as f64),
                Err(e) => Err(e.clone()),
            })?;
            let mut notes = Vec::new();
            for (k, (name, _)) in pmg_alternatives().into_iter().enumerate() {
                if k + 1 >= options_list.len() {
                    break;
                }
                // A variant that does not converge is "n/c".
                let g = grid(5, &cols, |p, n| {
                    Ok(at(k + 1, p, n)?.as_ref().map_or(f64::NAN, |&c| c as f64))
                })?;
                let text: Vec<String> = g
                    .iter()
                    .map(|(_, r)| {
                        r.iter()
                            .map(|v| match v {
                                None => "-".into(),
                                Some(v) if v.is_nan() => "n/c".into(),
                                Some(v) => format!("{v}"),
                            })
                            .collect::<Vec<String>>()
                            .join(" ")
                    })
                    .collect();
                notes.push(format!("{name}: {}", text.join(" | ")));
            }
            Ok(Computed { rows, notes, ..Default::default() })
        },
    }
}

/// The book's registered tables.
pub fn tables() -> Vec<TableSpec> {
    vec![table_4_2(), table_4_3(), table_4_4()]
}
