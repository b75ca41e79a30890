//! # Tables of the TLS paper (and the book's TLS example and §4.5)
//!
//! Registrations only; the runs are in `studies::tls_example` and
//! `studies::tls_paper`. Registered ids:
//! - `tls-1` (TLS paper Table 1, §5.3) and `book-tls-example` (book
//!   §4.4.2): the reconstruction example, conservative quadratic TLS and a
//!   not-a-knot cubic spline on a seeded layout, with the spread over 100
//!   layouts in the notes;
//! - `tls-3` and `tls-5` (Tables 3 and 5): mass and momentum conservation of
//!   the vibrating bar without and with grid crossing;
//! - `book-4.5-large` (book §4.5): conservation and the stress-error ratio
//!   against ULFEM for the large-deformation bar;
//! - `tls-fig6` (Fig. 6): convergence orders of nine method/mapping pairs;
//! - `tls-fig9` (Fig. 9): stress-error factors against ULFEM;
//! - `tls-7` and `tls-fig10` (Table 7, Fig. 10): the column compaction;
//! - `tls-8` (Table 8): DDMPM whose node integrals use n subpoints per
//!   particle in the compaction, against DDMPM-TLS, with measured run times.
//!
//! Items: [`tables`].

use super::{Computed, LabelledRow, RunOptions, Study, TableSpec};
use crate::error::Result;
use crate::mpm::grid::Method;
use crate::mpm::mapping::Mapping;
use crate::reconstruct::taylor::CellAverage;
use crate::studies::tls_example::{
    example_reconstructions, relative_integral_error, rms_error, spreads, Spread, EXAMPLE_SEED,
};
use crate::studies::tls_paper::{
    as_paper_ran, by_method, compaction, compaction_with_average, compactions,
    conservation_by_mapping, conservation_errors, fig6_errors, fig6_variants, fitted_order,
    stress_errors_against_ulfem, subpoint_study, subpoint_study_against, BarRun,
    ConservationByMethod, SubpointStudy, TABLE_8_SUBPOINTS, TLS_METHODS,
};
use crate::studies::BarErrors;
use std::collections::HashMap;

/// Spread notes over the layouts of seeds 1..=100.
fn spread_notes() -> Result<Vec<String>> {
    let s = spreads(100)?;
    let fmt = |name: &str, v: Spread| {
        format!(
            "{name} over 100 seeded layouts: min {:.4e}, median {:.4e}, max {:.4e}",
            v.min, v.median, v.max
        )
    };
    Ok(vec![
        fmt("TLS RMS (100 GP)", s.tls_rms_100),
        fmt("TLS RMS (10 GP)", s.tls_rms_10),
        fmt("cubic-spline RMS (100 GP)", s.spline_rms_100),
        fmt("cubic-spline integral error (2 GP)", s.spline_integral_2),
    ])
}

/// The TLS paper's name of a method: MPM, DDMPM, BSMPM (quadratic).
fn paper_name(method: Method) -> String {
    match method {
        Method::Mpm => "MPM".into(),
        Method::Ddmpm { .. } => "DDMPM".into(),
        Method::Bsmpm { degree: 2 } => "BSMPM".into(),
        other => other.label(),
    }
}

/// The TLS paper's row label of a method with a mapping: "DDMPM",
/// "DDMPM + cubic spline", "DDMPM + TLS" (Figs. 6 and 9); a mapping the
/// paper does not name appends its registered name.
fn variant_label(method: Method, mapping: Mapping) -> String {
    let suffix = match mapping {
        Mapping::Direct => String::new(),
        Mapping::CubicSpline => " + cubic spline".into(),
        Mapping::CubicSplineClipped => " + cubic spline (clipped to Ω_t)".into(),
        Mapping::Tls => " + TLS".into(),
        #[allow(unreachable_patterns)]
        other => format!(" + {}", other.name()),
    };
    format!("{}{suffix}", paper_name(method))
}

/// The rows of a conservation table (TLS paper Tables 3, 5, 7): one per
/// mapping ("Cubic-spline", "TLS"), with (Error_M, Error_P) per method in
/// the columns' order MPM, DDMPM, BSMPM.
fn conservation_rows(by_mapping: Vec<(Mapping, ConservationByMethod)>) -> Vec<LabelledRow> {
    by_mapping
        .into_iter()
        .map(|(mapping, errors)| {
            let label = if mapping == Mapping::Tls {
                "TLS"
            } else {
                "Cubic-spline"
            };
            Computed::row(label, errors.into_iter().flat_map(|(_, (m, p))| [m, p]))
        })
        .collect()
}

fn tls_1() -> TableSpec {
    TableSpec {
        id: "tls-1",
        published_json: include_str!("../../golden/published/tls-1.json"),
        setup: "f(x) = sin(x) + 2 on [0, 4π], four elements of width π, 11 data points: 0 and π \
                (π serves elements 1 and 2), three uniform interior points in [2π, 3π], three \
                seeded random interior points in each of [π, 2π] and [3π, 4π] (seed 1; the \
                published layout is unknown). Conservative quadratic TLS with exact element \
                integrals; not-a-knot cubic spline. RMS over 100 Gauss points per element; \
                integral error with 2 Gauss points per element.",
        compute: |options| {
            let r = example_reconstructions(EXAMPLE_SEED)?;
            let tls = |x: f64| r.tls.evaluate(x);
            let cs = |x: f64| r.spline.evaluate(x);
            // Columns: cubic splines, TLS.
            let rows = vec![
                Computed::row(
                    "RMS error for function (100 Gauss points per element)",
                    [rms_error(&cs, 100)?, rms_error(&tls, 100)?],
                ),
                Computed::row(
                    "Relative error for integral (2 Gauss points per element)",
                    [
                        relative_integral_error(&cs, 2)?,
                        relative_integral_error(&tls, 2)?,
                    ],
                ),
            ];
            let notes = if options.quick {
                vec![]
            } else {
                spread_notes()?
            };
            Ok(Computed {
                rows,
                notes,
                ..Default::default()
            })
        },
    }
}

fn book_example() -> TableSpec {
    TableSpec {
        id: "book-tls-example",
        published_json: include_str!("../../golden/published/book-tls-example.json"),
        setup: "The layout and TLS of tls-1 (seed 1). RMS over 10 Gauss points per element; \
                relative integral error with 10 and with 2 Gauss points per element.",
        compute: |options| {
            let r = example_reconstructions(EXAMPLE_SEED)?;
            let tls = |x: f64| r.tls.evaluate(x);
            let rows = vec![
                Computed::row(
                    "RMS error (10 Gauss points per element)",
                    [rms_error(&tls, 10)?],
                ),
                Computed::row(
                    "Relative integral error (10 Gauss points per element)",
                    [relative_integral_error(&tls, 10)?],
                ),
                Computed::row(
                    "Relative integral error (2 Gauss points per element)",
                    [relative_integral_error(&tls, 2)?],
                ),
            ];
            let notes = if options.quick {
                vec![]
            } else {
                spread_notes()?
            };
            Ok(Computed {
                rows,
                notes,
                ..Default::default()
            })
        },
    }
}

/// The registered TLS-example tables.
pub fn tables() -> Vec<TableSpec> {
    vec![
        tls_1(),
        book_example(),
        tls_3(),
        tls_5(),
        book_4_5_large(),
        tls_fig6(),
        tls_fig9(),
        tls_7(),
        tls_fig10(),
        tls_8(),
    ]
}

/// The rows of `tls-8` from a subpoint study: E, E/E_TLS, t/t_TLS.
fn subpoint_rows(study: &SubpointStudy) -> Vec<LabelledRow> {
    study
        .rows
        .iter()
        .map(|r| {
            Computed::row(
                format!("{} subpoints", r.subpoints),
                [
                    r.stress_error,
                    r.stress_error / study.tls_error,
                    r.seconds / study.tls_seconds,
                ],
            )
        })
        .collect()
}

fn tls_8() -> TableSpec {
    TableSpec {
        id: "tls-8",
        published_json: include_str!("../../golden/published/tls-8.json"),
        setup: "The column compaction of tls-fig10 (TLS paper Table 6; 50 elements, 20 PPC, Δt = 1e-4 s, \
                0.5 s). DDMPM with the direct mapping and lumped mass, whose node integrals V_j and \
                ∫φ_j∇φ_i are re-evaluated every step over n subpoints per particle: the midpoints of n \
                equal parts of [x_p − V_p/2, x_p + V_p/2], weight V_p/n each (after Dhakal and Zhang 2016; \
                the seeds do not define the scheme, docs/conventions.md). E_TLS and t_TLS: DDMPM + TLS with \
                exact node integrals. Wall times measured here, the runs one after another on one thread \
                (best of 3 with --full, else one run): a factor-of-2 check only.",
        compute: |o| {
            if o.quick {
                return Ok(Computed::skipped_in_quick_mode());
            }
            let repeats = if o.full { 3 } else { 1 };
            let midpoints = subpoint_study(&TABLE_8_SUBPOINTS, Method::ddmpm_subpoints, repeats)?;
            // The same DDMPM-TLS reference serves both rules (one run, not two).
            let ends = subpoint_study_against(&midpoints, &TABLE_8_SUBPOINTS, Method::ddmpm_end_subpoints, 1)?;
            let particles = compaction(Method::DDMPM_PARTICLES, Mapping::Direct)?;
            let exact = compaction(Method::DDMPM, Mapping::Direct)?;
            let list = |st: &SubpointStudy| {
                st.rows
                    .iter()
                    .map(|r| format!("{} {:.4e}", r.subpoints, r.stress_error))
                    .collect::<Vec<_>>()
                    .join(", ")
            };
            let notes = vec![
                format!(
                    "E_TLS (DDMPM + TLS, exact node integrals) = {:.4e}, t_TLS = {:.3} s",
                    midpoints.tls_error, midpoints.tls_seconds
                ),
                format!(
                    "limits: one point per particle (particle quadrature) E = {:.4e}; exact node integrals E = {:.4e}",
                    particles.stress_error, exact.stress_error
                ),
                format!(
                    "placement sensitivity, n subpoints including both ends of the particle domain: {}",
                    list(&ends)
                ),
            ];
            Ok(Computed {
                rows: subpoint_rows(&midpoints),
                notes,
                study: Some(Study::Subpoints { midpoints, ends }),
            })
        },
    }
}

fn tls_3() -> TableSpec {
    TableSpec {
        id: "tls-3",
        published_json: include_str!("../../golden/published/tls-3.json"),
        setup: "Vibrating bar, TLS paper Table 2 (H = 1 m, ρ = 2000, E = 7e6 Pa, v0 = 0.28), 40 elements \
                (knot spans), 12 PPC, Δt = 1e-7 s, 19 steps (1.9e-6 s). Both mappings reconstruct the \
                stress and the velocity; consistent mass (sparse Cholesky). Error_M = max over steps of \
                |Σ_ij M_ij − Σ m_p|/Σ m_p; Error_P = max over steps of |1ᵀMv − Σ m_p v_p|/|Σ m_p v_p|, \
                with v the projected nodal velocity before the boundary velocities are zeroed. TLS: \
                quadratic, 2 Gauss points per element; cubic spline: not-a-knot, thesis half-span rule.",
        compute: |_| {
            let run = |m, map| conservation_errors(m, map, 40, 12);
            let rows = conservation_rows(conservation_by_mapping(run)?);
            Ok(Computed {
                rows,
                notes: vec![
                    ddmpm_rule_note(),
                    particle_quadrature_conservation_note(run)?,
                    "The cubic-spline momentum 'error' equals the midpoint-rule error of the particle sum Σ m_p v_p \
                     against the exact ∫ρv (1.7849e-6 at t = 0): the spline integral is nearly exact, the particle \
                     sum is not."
                        .into(),
                ], ..Default::default() })
        },
    }
}

fn tls_fig6() -> TableSpec {
    TableSpec {
        id: "tls-fig6",
        published_json: include_str!("../../golden/published/tls-fig6.json"),
        setup: "Vibrating bar, TLS paper Table 2, 5/10/20/40 elements (knot spans), 12 PPC, Δt = 1e-7 s, \
                19 steps (1.9e-6 s). Orders: least-squares slope of log RMS error against log h over the \
                four resolutions. Displacement and stress at the particles against the analytic solution \
                at their initial positions; velocity: the projected grid velocity interpolated to the \
                particles (the definition under which MPM shows order 2, as the paper states; the notes \
                give the particle velocity at t and at t − Δt/2). Reconstructions: consistent mass; \
                direct mapping: lumped mass. Published values are the integer orders the text states.",
        compute: |_| {
            let mut rows = Vec::new();
            let mut notes = Vec::new();
            for (method, mapping) in fig6_variants() {
                let e = fig6_errors(method, mapping)?;
                let h: Vec<f64> = e.iter().map(|r| r.h).collect();
                let order = |f: &dyn Fn(&BarErrors) -> f64| fitted_order(&h, &e.iter().map(f).collect::<Vec<_>>());
                rows.push(Computed::row(
                    variant_label(method, mapping),
                    [order(&|r| r.displacement), order(&|r| r.grid_velocity), order(&|r| r.stress)],
                ));
                notes.push(format!(
                    "{} {:?}: particle velocity at t order {:.2}, at t − Δt/2 {:.2}; errors at 40 cells: u {:.3e}, grid v {:.3e}, σ {:.3e}",
                    method.label(),
                    mapping,
                    order(&|r| r.velocity),
                    order(&|r| r.velocity_half_step),
                    e[3].displacement,
                    e[3].grid_velocity,
                    e[3].stress
                ));
            }
            notes.insert(0, ddmpm_rule_note());
            Ok(Computed { rows, notes, ..Default::default() })
        },
    }
}

const COMPACTION_SETUP: &str = "Column compaction, TLS paper Table 6: H = 50 m, ρ = 1, E = 1e6 Pa, body force ramped \
    linearly from 0 to b_f = −200 over 0.5 s, bottom fixed, large-strain update (Eq. 3); 50 elements (knot spans), \
    20 PPC, Δt = 1e-4 s, 5000 steps. Reference stress: the equilibrium ρ₀ b(t)(H − X), exact for any constitutive \
    law in 1D once inertia is negligible (the seeds do not print Bardenhagen–Kober's solution). Reconstructions \
    with consistent mass, direct mapping with lumped mass.";

fn tls_fig10() -> TableSpec {
    TableSpec {
        id: "tls-fig10",
        published_json: include_str!("../../golden/published/tls-fig10.json"),
        setup: COMPACTION_SETUP,
        compute: compute_fig10,
    }
}

/// DDMPM under the node-integral rule the tables do not use with `map`
/// (docs/conventions.md, "DDMPM node integrals").
fn other_ddmpm(map: Mapping) -> Method {
    if as_paper_ran(Method::DDMPM, map) == Method::DDMPM {
        Method::DDMPM_PARTICLES
    } else {
        Method::DDMPM
    }
}

/// TLS paper Fig. 10: the stress errors of the compaction. The published
/// cells, each method as the paper ran it, and the other DDMPM rule with
/// each mapping (hompm's findings) in a note.
fn compute_fig10(o: &RunOptions) -> Result<Computed> {
    if o.quick {
        return Ok(Computed::skipped_in_quick_mode());
    }
    let maps = [Mapping::Direct, Mapping::CubicSpline, Mapping::Tls];
    let jobs: Vec<(Method, Mapping)> = TLS_METHODS
        .iter()
        .flat_map(|&m| maps.map(|map| (as_paper_ran(m, map), map)))
        .chain(maps.map(|map| (other_ddmpm(map), map)))
        .collect();
    let runs = compactions(&jobs)?;
    let stress_error = |m: Method, map: Mapping| {
        jobs.iter()
            .zip(&runs)
            .find(|(job, _)| **job == (m, map))
            .map(|(_, run)| run.stress_error)
    };
    // Rows: methods; columns: no reconstruction, cubic spline, TLS.
    let rows = TLS_METHODS
        .iter()
        .map(|&m| {
            let row = maps
                .iter()
                .map(|&map| stress_error(as_paper_ran(m, map), map));
            (paper_name(m), row.collect())
        })
        .collect();
    let other: Vec<String> = maps
        .iter()
        .map(|&map| {
            let m = other_ddmpm(map);
            let e = stress_error(m, map).unwrap_or(f64::NAN);
            format!("{} {map:?} {e:.4e}", m.label())
        })
        .collect();
    Ok(Computed {
        rows,
        notes: vec![
            ddmpm_rule_note(),
            format!("DDMPM under the other rule: {}", other.join(", ")),
        ],
        ..Default::default()
    })
}

/// The note every DDMPM entry of the TLS tables carries: which node-integral
/// rule its cells use.
fn ddmpm_rule_note() -> String {
    "DDMPM cells: node integrals V_j and ∫φ_j∇φ_i by particle quadrature with the direct mapping, exact \
     (the Gauss points of the mapping) with TLS and the cubic spline (docs/conventions.md, 'DDMPM node \
     integrals'); the other rule is listed beside it"
        .into()
}

/// The conservation errors (Error_M, Error_P) of DDMPM with particle-
/// quadrature node integrals under both reconstructions, for a note.
fn particle_quadrature_conservation_note(
    run: impl Fn(Method, Mapping) -> Result<(f64, f64)>,
) -> Result<String> {
    let cells = [Mapping::CubicSpline, Mapping::Tls]
        .into_iter()
        .map(|map| {
            run(Method::DDMPM_PARTICLES, map)
                .map(|(m, p)| format!("{map:?} Error_M {m:.4e}, Error_P {p:.4e}"))
        })
        .collect::<Result<Vec<_>>>()?;
    Ok(format!(
        "DDMPM (particle quadrature) under the other rule: {}",
        cells.join("; ")
    ))
}

/// The note of the TLS author's cell average: the TLS rows recomputed,
/// by `run(method, average)`, with the density fit averaging (x − x_c)²
/// from its antiderivative at the absolute cell ends, in both term orders
/// ([`CellAverage`]; `TLS1D.py` of ewob/TLS).
fn tls_author_average_note(
    run: impl Fn(Method, CellAverage) -> Result<(f64, f64)> + Sync,
) -> Result<String> {
    let variants = [
        (CellAverage::AntiderivativeDifference, "F(b) − F(a)"),
        (
            CellAverage::AntiderivativeSixTerms,
            "the six terms of TLS1D.py",
        ),
    ];
    let mut parts = Vec::new();
    for (average, name) in variants {
        let cells: Vec<String> = by_method(|m| run(m, average))?
            .into_iter()
            .map(|(m, (e_m, e_p))| {
                format!("{} Error_M {e_m:.4e}, Error_P {e_p:.4e}", paper_name(m))
            })
            .collect();
        parts.push(format!("{name}: {}", cells.join(", ")));
    }
    Ok(format!(
        "TLS with the TLS author's cell average of (x − x_c)² on the density fit, from \
         F(x) = x³/3 − x_c x² + x_c² x at the absolute cell ends (ewob/TLS TLS1D.py; \
         docs/conventions.md, 'The TLS author's cell average'): {}",
        parts.join("; ")
    ))
}

fn tls_7() -> TableSpec {
    TableSpec {
        id: "tls-7",
        published_json: include_str!("../../golden/published/tls-7.json"),
        setup: COMPACTION_SETUP,
        compute: |o| {
            if o.quick {
                return Ok(Computed::skipped_in_quick_mode());
            }
            let run = |m, map| {
                compaction(m, map).map(|r: crate::studies::tls_paper::CompactionRun| {
                    (r.mass_error, r.momentum_error)
                })
            };
            let rows = conservation_rows(conservation_by_mapping(run)?);
            let clipped = TLS_METHODS
                .iter()
                .map(|&m| {
                    run(m, Mapping::CubicSplineClipped).map(|(e_m, e_p)| {
                        format!("{} Error_M {e_m:.4e}, Error_P {e_p:.4e}", paper_name(m))
                    })
                })
                .collect::<Result<Vec<_>>>()?;
            Ok(Computed {
                rows,
                notes: vec![
                    ddmpm_rule_note(),
                    particle_quadrature_conservation_note(run)?,
                    format!(
                        "cubic spline with every half span clipped to Ω_t (the integrals end at the \
                         free surface): {}",
                        clipped.join("; ")
                    ),
                    tls_author_average_note(|m, average| {
                        compaction_with_average(m, Mapping::Tls, average)
                            .map(|r| (r.mass_error, r.momentum_error))
                    })?,
                ],
                ..Default::default()
            })
        },
    }
}

fn tls_5() -> TableSpec {
    TableSpec {
        id: "tls-5",
        published_json: include_str!("../../golden/published/tls-5.json"),
        setup: "Vibrating bar with grid crossing, TLS paper Table 4 (H = 1 m, ρ = 2000, E = 4e4 Pa, v0 = 0.8), \
                large-strain update, 20 elements (knot spans), 8 PPC, Δt = 1e-4 s, 1000 steps (0.1 s); \
                error measures and mappings as tls-3, consistent mass.",
        compute: |_| {
            let bar = BarRun { params: "tls-table-4", cells: 20, ppc: 8, dt: 1e-4, steps: 1000 };
            let run = |m, map| bar.conservation_errors(m, map, CellAverage::Exact);
            let rows = conservation_rows(conservation_by_mapping(run)?);
            Ok(Computed {
                rows,
                notes: vec![
                    ddmpm_rule_note(),
                    particle_quadrature_conservation_note(run)?,
                    tls_author_average_note(|m, average| bar.conservation_errors(m, Mapping::Tls, average))?,
                ],
                ..Default::default()
            })
        },
    }
}

fn book_4_5_large() -> TableSpec {
    TableSpec {
        id: "book-4.5-large",
        published_json: include_str!("../../golden/published/book-4.5-large.json"),
        setup: "Book §4.5: vibrating bar with the parameters of book Table 4.1 and v0 = 0.8 (E = 7e6 Pa), \
                large-strain update, 20 knot spans, 8 PPC, Δt = 1e-5 s, 0.1 s (10 000 steps); quadratic \
                B-splines, TLS mapping of stress, density and momentum, consistent mass (Cholesky).",
        compute: |o| {
            if o.quick {
                return Ok(Computed::skipped_in_quick_mode());
            }
            let bar = BarRun { params: "book-table-4.1-large", cells: 20, ppc: 8, dt: 1e-5, steps: 10_000 };
            let bsmpm = Method::Bsmpm { degree: 2 };
            let (m, p) = bar.conservation_errors(bsmpm, Mapping::Tls, CellAverage::Exact)?;
            let (m_author, p_author) =
                bar.conservation_errors(bsmpm, Mapping::Tls, CellAverage::AntiderivativeDifference)?;
            let variants = [(Method::Mpm, Mapping::Direct), (Method::Bsmpm { degree: 2 }, Mapping::Tls)];
            let e: HashMap<_, _> =
                stress_errors_against_ulfem("book-table-4.1-large", 119, 20, 8, 1e-5, 10_000, &variants)?.into_iter().collect();
            let (mpm, tls) = (e[&variants[0]], e[&variants[1]]);
            Ok(Computed {
                rows: vec![Computed::row("TLS-BSMPM, consistent mass", [m, p, mpm / tls])],
                notes: vec![
                    format!("relative L2 stress errors against ULFEM with 120 DOFs (the book's reference): MPM {mpm:.4e}, TLS-BSMPM {tls:.4e}"),
                    format!("TLS-BSMPM with the TLS author's cell average of (x − x_c)² on the density fit from F(b) − F(a), F(x) = x³/3 − x_c x² + x_c² x at the absolute cell ends (ewob/TLS TLS1D.py; docs/conventions.md, 'The TLS author's cell average'): Error_M {m_author:.4e}, Error_P {p_author:.4e}"),
                ],
                ..Default::default()
            })
        },
    }
}

fn tls_fig9() -> TableSpec {
    TableSpec {
        id: "tls-fig9",
        published_json: include_str!("../../golden/published/tls-fig9.json"),
        setup: "Vibrating bar with grid crossing, TLS paper Table 4, 20 elements (knot spans), 8 PPC, Δt = 1e-4 s, \
                0.1 s. Reference: updated-Lagrangian FEM (fem::ulfem) with 1000 elements and Δt = 1e-5 s \
                (self-converged to 3e-6). E = relative L2 error of the particle stress against the reference at \
                the particles' initial positions; factor = E_MPM / E_method. Reconstructions with consistent mass.",
        compute: |o| {
            if o.quick {
                return Ok(Computed::skipped_in_quick_mode());
            }
            let b = Method::Bsmpm { degree: 2 };
            let mpm = (Method::Mpm, Mapping::Direct);
            // The published rows, in the order of golden/published/tls-fig9.json.
            let rows = [(b, Mapping::CubicSpline), (b, Mapping::Tls), (Method::DDMPM, Mapping::CubicSpline), (Method::DDMPM, Mapping::Tls)];
            let extra = [
                (Method::DDMPM_PARTICLES, Mapping::Direct),
                (b, Mapping::Direct),
                (Method::DDMPM, Mapping::Direct),
                (Method::DDMPM_PARTICLES, Mapping::CubicSpline),
                (Method::DDMPM_PARTICLES, Mapping::Tls),
            ];
            let variants: Vec<_> = std::iter::once(mpm).chain(rows).chain(extra).collect();
            let e = stress_errors_against_ulfem("tls-table-4", 1000, 20, 8, 1e-4, 1000, &variants)?;
            let mpm_error = e[0].1;
            let notes: Vec<String> = e
                .iter()
                .map(|((m, map), err)| format!("{} {map:?} {err:.4e} (factor {:.2})", m.label(), mpm_error / err))
                .collect();
            let e: HashMap<_, _> = e.into_iter().collect();
            Ok(Computed {
                rows: rows.iter().map(|&(m, map)| Computed::row(variant_label(m, map), [e[&mpm] / e[&(m, map)]])).collect(),
                notes: vec![ddmpm_rule_note(), format!("relative L2 stress errors: {}", notes.join(", "))], ..Default::default() })
        },
    }
}
