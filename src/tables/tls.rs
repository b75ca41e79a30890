//! # Tables of the TLS paper (and the book's TLS example)
//!
//! `tls-1` (TLS paper Table 1, §5.3) and `book-tls-example` (book §4.4.2):
//! f(x) = sin(x) + 2 on [0, 4π], four elements of width π, eleven data points:
//! 0 and π in the first element (π also serves the second element), three
//! uniformly spaced interior points in [2π, 3π], and random points elsewhere.
//! The published random points are unknown, so hompm fixes a seeded layout
//! that follows this description (three random interior points in [π, 2π]
//! and in [3π, 4π]) and reports the spread over 100 such layouts.
//!
//! TLS: quadratic (n_b = 3), conservative with the exact element integrals
//! ∫ f = 2π ± 2 (book Eq. 4.35). Cubic spline: not-a-knot through the 11
//! points (MATLAB's `spline` default), extended beyond the last point.

use super::{Computed, TableSpec, Tolerance};
use crate::error::Result;
use crate::quadrature::gauss_on_cells;
use crate::reconstruct::cubic_spline::{CubicSpline, EndCondition};
use crate::reconstruct::taylor::{reconstruct, TlsOptions, TlsReconstruction};
use crate::rng::SplitMix64;
use std::f64::consts::PI;

/// The seed of the layout shown in the tables (any fixed seed; not tuned).
pub const EXAMPLE_SEED: u64 = 1;

/// f(x) = sin(x) + 2.
pub fn example_function(x: f64) -> f64 {
    x.sin() + 2.0
}

/// The four elements [kπ, (k+1)π].
pub fn example_cells() -> Vec<(f64, f64)> {
    (0..4)
        .map(|k| (k as f64 * PI, (k + 1) as f64 * PI))
        .collect()
}

/// Exact ∫ f over each element.
pub fn example_integrals() -> Vec<f64> {
    example_cells()
        .iter()
        .map(|&(a, b)| 2.0 * (b - a) + a.cos() - b.cos())
        .collect()
}

/// The eleven data points of a layout following TLS paper §5.3, sorted.
pub fn example_points(seed: u64) -> Vec<f64> {
    let mut rng = SplitMix64::new(seed);
    let mut x = vec![0.0, PI];
    for _ in 0..3 {
        x.push(rng.open_interval(PI, 2.0 * PI));
    }
    for k in 1..=3 {
        x.push(2.0 * PI + k as f64 * PI / 4.0);
    }
    for _ in 0..3 {
        x.push(rng.open_interval(3.0 * PI, 4.0 * PI));
    }
    x.sort_by(|a, b| a.total_cmp(b));
    x
}

/// The TLS and cubic-spline reconstructions of one layout.
pub struct ExampleReconstructions {
    /// Conservative quadratic TLS.
    pub tls: TlsReconstruction,
    /// Not-a-knot cubic spline.
    pub spline: CubicSpline,
}

/// Builds both reconstructions for a layout.
pub fn example_reconstructions(seed: u64) -> Result<ExampleReconstructions> {
    let x = example_points(seed);
    let y: Vec<f64> = x.iter().map(|&v| example_function(v)).collect();
    let tls = reconstruct(
        &example_cells(),
        &x,
        &y,
        Some(&example_integrals()),
        TlsOptions::default(),
    )?;
    let spline = CubicSpline::new(&x, &y, EndCondition::NotAKnot)?;
    Ok(ExampleReconstructions { tls, spline })
}

/// RMS error of `g` against f over `points` Gauss points per element.
pub fn rms_error(g: &dyn Fn(f64) -> f64, points: usize) -> Result<f64> {
    let q = gauss_on_cells(&example_cells(), points)?;
    let sum: f64 = q
        .iter()
        .map(|p| (g(p.x) - example_function(p.x)).powi(2))
        .sum();
    Ok((sum / q.len() as f64).sqrt())
}

/// |∫g − 8π| / 8π with `points` Gauss points per element.
pub fn relative_integral_error(g: &dyn Fn(f64) -> f64, points: usize) -> Result<f64> {
    let q = gauss_on_cells(&example_cells(), points)?;
    let integral: f64 = q.iter().map(|p| p.weight * g(p.x)).sum();
    Ok((integral - 8.0 * PI).abs() / (8.0 * PI))
}

/// (min, median, max) of a sample.
fn spread(mut v: Vec<f64>) -> (f64, f64, f64) {
    v.sort_by(|a, b| a.total_cmp(b));
    (v[0], v[v.len() / 2], v[v.len() - 1])
}

/// Spread notes over seeds 1..=100 for the quantities of both tables.
fn spread_notes() -> Result<Vec<String>> {
    let mut tls100 = Vec::new();
    let mut tls10 = Vec::new();
    let mut cs100 = Vec::new();
    let mut csint = Vec::new();
    for seed in 1..=100 {
        let r = example_reconstructions(seed)?;
        tls100.push(rms_error(&|x| r.tls.evaluate(x), 100)?);
        tls10.push(rms_error(&|x| r.tls.evaluate(x), 10)?);
        cs100.push(rms_error(&|x| r.spline.evaluate(x), 100)?);
        csint.push(relative_integral_error(&|x| r.spline.evaluate(x), 2)?);
    }
    let fmt = |name: &str, v: Vec<f64>| {
        let (lo, med, hi) = spread(v);
        format!("{name} over 100 seeded layouts: min {lo:.4e}, median {med:.4e}, max {hi:.4e}")
    };
    Ok(vec![
        fmt("TLS RMS (100 GP)", tls100),
        fmt("TLS RMS (10 GP)", tls10),
        fmt("cubic-spline RMS (100 GP)", cs100),
        fmt("cubic-spline integral error (2 GP)", csint),
    ])
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
        tolerance: |r, c| {
            if r == 1 && c == 1 {
                Tolerance::MachinePrecision
            } else {
                Tolerance::RMS
            }
        },
        compute: |options| {
            let r = example_reconstructions(EXAMPLE_SEED)?;
            let tls = |x: f64| r.tls.evaluate(x);
            let cs = |x: f64| r.spline.evaluate(x);
            let values = vec![
                vec![Some(rms_error(&cs, 100)?), Some(rms_error(&tls, 100)?)],
                vec![
                    Some(relative_integral_error(&cs, 2)?),
                    Some(relative_integral_error(&tls, 2)?),
                ],
            ];
            let notes = if options.quick {
                vec![]
            } else {
                spread_notes()?
            };
            Ok(Computed { values, notes })
        },
    }
}

fn book_example() -> TableSpec {
    TableSpec {
        id: "book-tls-example",
        published_json: include_str!("../../golden/published/book-tls-example.json"),
        setup: "The layout and TLS of tls-1 (seed 1). RMS over 10 Gauss points per element; \
                relative integral error with 10 and with 2 Gauss points per element.",
        tolerance: |r, _| {
            if r == 0 {
                Tolerance::RMS
            } else {
                Tolerance::MachinePrecision
            }
        },
        compute: |options| {
            let r = example_reconstructions(EXAMPLE_SEED)?;
            let tls = |x: f64| r.tls.evaluate(x);
            let values = vec![
                vec![Some(rms_error(&tls, 10)?)],
                vec![Some(relative_integral_error(&tls, 10)?)],
                vec![Some(relative_integral_error(&tls, 2)?)],
            ];
            let notes = if options.quick {
                vec![]
            } else {
                spread_notes()?
            };
            Ok(Computed { values, notes })
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
    ]
}

use crate::mpm::grid::Method;
use crate::mpm::mapping::{ConsistentSolver, Mapping, MassMatrix};
use crate::scenes::{vibrating_bar, Discretisation};
use rayon::prelude::*;

/// (max mass error, max momentum error) of the vibrating bar of TLS paper
/// Table 2 over 19 steps of 1e-7 s (t = 1.9e-6 s), consistent mass.
pub fn conservation_errors(
    method: Method,
    mapping: Mapping,
    cells: usize,
    ppc: usize,
) -> Result<(f64, f64)> {
    conservation_errors_for("tls-table-2", method, mapping, cells, ppc, 1e-7, 19)
}

/// (max mass error, max momentum error) of a bar parameter set with the
/// given resolution and time stepping, consistent mass (Cholesky).
pub fn conservation_errors_for(
    params: &str,
    method: Method,
    mapping: Mapping,
    cells: usize,
    ppc: usize,
    dt: f64,
    steps: usize,
) -> Result<(f64, f64)> {
    let p = vibrating_bar::parameters(params)?;
    let d = Discretisation {
        method,
        force_mapping: mapping,
        velocity_mapping: mapping,
        mass: MassMatrix::Consistent(ConsistentSolver::Cholesky),
        cells,
        ppc,
    };
    let mut sim = p.simulation(&d)?;
    sim.run(dt, steps)?;
    Ok((
        sim.diagnostics.max_mass_error,
        sim.diagnostics.max_momentum_error,
    ))
}

/// The rows of a conservation table (TLS paper Tables 3, 5, 7): for the
/// cubic-spline and the TLS mapping, (Error_M, Error_P) of MPM, DDMPM and BSMPM.
fn conservation_rows(
    run: impl Fn(Method, Mapping) -> Result<(f64, f64)> + Sync,
) -> Result<Vec<Vec<Option<f64>>>> {
    let methods = [Method::Mpm, Method::Ddmpm, Method::Bsmpm { degree: 2 }];
    let mut rows = Vec::new();
    for mapping in [Mapping::CubicSpline, Mapping::Tls] {
        let errs: Vec<(f64, f64)> = methods
            .par_iter()
            .map(|&m| run(m, mapping))
            .collect::<Result<_>>()?;
        rows.push(errs.iter().flat_map(|&(a, b)| [Some(a), Some(b)]).collect());
    }
    Ok(rows)
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
        tolerance: |r, _| if r == 1 { Tolerance::MachinePrecision } else { Tolerance::RMS },
        compute: |_| {
            let rows = conservation_rows(|m, map| conservation_errors(m, map, 40, 12))?;
            Ok(Computed {
                values: rows,
                notes: vec![
                    "The cubic-spline momentum 'error' equals the midpoint-rule error of the particle sum Σ m_p v_p \
                     against the exact ∫ρv (1.7849e-6 at t = 0): the spline integral is nearly exact, the particle \
                     sum is not."
                        .into(),
                ],
            })
        },
    }
}

use crate::studies::{bar_errors, BarErrors};

/// The nine method/mapping combinations of TLS paper Fig. 6, in table order.
pub fn fig6_variants() -> Vec<(Method, Mapping)> {
    let mut v = Vec::new();
    for m in [Method::Mpm, Method::Ddmpm, Method::Bsmpm { degree: 2 }] {
        for map in [Mapping::Direct, Mapping::CubicSpline, Mapping::Tls] {
            v.push((m, map));
        }
    }
    v
}

/// Least-squares slope of log(error) against log(h): the convergence order.
pub fn fitted_order(h: &[f64], e: &[f64]) -> f64 {
    let n = h.len() as f64;
    let x: Vec<f64> = h.iter().map(|v| v.ln()).collect();
    let y: Vec<f64> = e.iter().map(|v| v.ln()).collect();
    let mx = x.iter().sum::<f64>() / n;
    let my = y.iter().sum::<f64>() / n;
    let sxy: f64 = x.iter().zip(&y).map(|(a, b)| (a - mx) * (b - my)).sum();
    let sxx: f64 = x.iter().map(|a| (a - mx) * (a - mx)).sum();
    sxy / sxx
}

/// Errors of one Fig. 6 variant at 5, 10, 20 and 40 cells (12 PPC,
/// Δt = 1e-7 s, 19 steps); reconstructions use the consistent mass.
pub fn fig6_errors(method: Method, mapping: Mapping) -> Result<Vec<BarErrors>> {
    let mass = if mapping == Mapping::Direct {
        MassMatrix::Lumped
    } else {
        MassMatrix::Consistent(ConsistentSolver::Cholesky)
    };
    [5, 10, 20, 40]
        .par_iter()
        .map(|&cells| {
            let d = Discretisation {
                method,
                force_mapping: mapping,
                velocity_mapping: mapping,
                mass,
                cells,
                ppc: 12,
            };
            bar_errors("tls-table-2", &d, 1e-7, 19)
        })
        .collect()
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
        tolerance: |_, _| Tolerance::STATED_ORDER,
        compute: |_| {
            let mut values = Vec::new();
            let mut notes = Vec::new();
            for (method, mapping) in fig6_variants() {
                let e = fig6_errors(method, mapping)?;
                let h: Vec<f64> = e.iter().map(|r| r.h).collect();
                let order = |f: &dyn Fn(&BarErrors) -> f64| fitted_order(&h, &e.iter().map(f).collect::<Vec<_>>());
                values.push(vec![
                    Some(order(&|r| r.displacement)),
                    Some(order(&|r| r.grid_velocity)),
                    Some(order(&|r| r.stress)),
                ]);
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
            Ok(Computed { values, notes })
        },
    }
}

use crate::mpm::diagnostics::relative_l2_error;
use crate::scenes::column;
use std::collections::HashMap;
use std::sync::{Mutex, OnceLock};

/// Outcome of one column-compaction run (TLS paper §6.2, Table 6).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct CompactionRun {
    /// Relative L2 error of the particle stress against ρ₀b(H − X) at t = 0.5 s.
    pub stress_error: f64,
    /// Maximal relative mass error over steps.
    pub mass_error: f64,
    /// Maximal relative momentum error over steps.
    pub momentum_error: f64,
    /// Grid crossings.
    pub crossings: usize,
    /// Maximal |u_p| at the end.
    pub max_displacement: f64,
}

/// Runs the compaction of TLS paper Table 6 (50 elements, 20 PPC, Δt = 1e-4 s,
/// 0.5 s); reconstructions with consistent mass. Cached per process.
pub fn compaction(method: Method, mapping: Mapping) -> Result<CompactionRun> {
    static CACHE: OnceLock<Mutex<HashMap<String, CompactionRun>>> = OnceLock::new();
    let key = format!("{method:?}/{mapping:?}");
    let cache = CACHE.get_or_init(|| Mutex::new(HashMap::new()));
    if let Some(r) = cache.lock().ok().and_then(|c| c.get(&key).copied()) {
        return Ok(r);
    }
    let p = column::parameters("tls-table-6")?;
    let mass = if mapping == Mapping::Direct {
        MassMatrix::Lumped
    } else {
        MassMatrix::Consistent(ConsistentSolver::Cholesky)
    };
    let d = Discretisation {
        method,
        force_mapping: mapping,
        velocity_mapping: mapping,
        mass,
        cells: 50,
        ppc: 20,
    };
    let mut sim = p.simulation(&d)?;
    sim.run(1e-4, 5000)?;
    let exact: Vec<f64> = sim
        .particles
        .x0
        .iter()
        .map(|&x| p.equilibrium_stress(x, sim.time))
        .collect();
    let run = CompactionRun {
        stress_error: relative_l2_error(&sim.particles.stress, &exact)?,
        mass_error: sim.diagnostics.max_mass_error,
        momentum_error: sim.diagnostics.max_momentum_error,
        crossings: sim.diagnostics.grid_crossings,
        max_displacement: sim.particles.u.iter().fold(0.0, |a: f64, u| a.max(u.abs())),
    };
    if let Ok(mut c) = cache.lock() {
        c.insert(key, run);
    }
    Ok(run)
}

const COMPACTION_SETUP: &str = "Column compaction, TLS paper Table 6: H = 50 m, ρ = 1, E = 1e6 Pa, body force ramped \
    linearly from 0 to b_f = −200 over 0.5 s, bottom fixed, large-strain update (Eq. 3); 50 elements (knot spans), \
    20 PPC, Δt = 1e-4 s, 5000 steps. Reference stress: the equilibrium ρ₀ b(t)(H − X), exact for any constitutive \
    law in 1D once inertia is negligible (the seeds do not print Bardenhagen–Kober's solution). Reconstructions \
    with consistent mass, direct mapping with lumped mass.";

fn compaction_grid(
    f: fn(&CompactionRun) -> [f64; 3],
    rows: &[Mapping],
) -> Result<Vec<Vec<Option<f64>>>> {
    let methods = [Method::Mpm, Method::Ddmpm, Method::Bsmpm { degree: 2 }];
    let jobs: Vec<(Method, Mapping)> = methods
        .iter()
        .flat_map(|&m| rows.iter().map(move |&r| (m, r)))
        .collect();
    let runs: Vec<CompactionRun> = jobs
        .par_iter()
        .map(|&(m, r)| compaction(m, r))
        .collect::<Result<_>>()?;
    Ok(runs
        .iter()
        .map(|r| f(r).iter().map(|v| Some(*v)).collect())
        .collect())
}

fn tls_fig10() -> TableSpec {
    TableSpec {
        id: "tls-fig10",
        published_json: include_str!("../../golden/published/tls-fig10.json"),
        setup: COMPACTION_SETUP,
        tolerance: |_, _| Tolerance::RMS,
        compute: |o| {
            if o.quick {
                return Ok(Computed::skipped_in_quick_mode(3, 3));
            }
            let maps = [Mapping::Direct, Mapping::CubicSpline, Mapping::Tls];
            let flat = compaction_grid(|r| [r.stress_error, 0.0, 0.0], &maps)?;
            let values = flat
                .chunks(3)
                .map(|c| c.iter().map(|v| v[0]).collect())
                .collect();
            Ok(Computed {
                values,
                notes: vec![],
            })
        },
    }
}

fn tls_7() -> TableSpec {
    TableSpec {
        id: "tls-7",
        published_json: include_str!("../../golden/published/tls-7.json"),
        setup: COMPACTION_SETUP,
        tolerance: |r, _| {
            if r == 1 {
                Tolerance::MachinePrecision
            } else {
                Tolerance::RMS
            }
        },
        compute: |o| {
            if o.quick {
                return Ok(Computed::skipped_in_quick_mode(2, 6));
            }
            let values = conservation_rows(|m, map| {
                compaction(m, map).map(|r| (r.mass_error, r.momentum_error))
            })?;
            Ok(Computed {
                values,
                notes: vec![],
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
        tolerance: |r, _| if r == 1 { Tolerance::MachinePrecision } else { Tolerance::RMS },
        compute: |_| {
            let rows = conservation_rows(|m, map| conservation_errors_for("tls-table-4", m, map, 20, 8, 1e-4, 1000))?;
            Ok(Computed { values: rows, notes: vec![] })
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
        tolerance: |_, c| if c == 2 { Tolerance::ERROR_RATIO } else { Tolerance::MachinePrecision },
        compute: |o| {
            if o.quick {
                return Ok(Computed::skipped_in_quick_mode(1, 3));
            }
            let (m, p) = conservation_errors_for("book-table-4.1-large", Method::Bsmpm { degree: 2 }, Mapping::Tls, 20, 8, 1e-5, 10_000)?;
            let variants = [(Method::Mpm, Mapping::Direct), (Method::Bsmpm { degree: 2 }, Mapping::Tls)];
            let e = stress_errors_against_ulfem("book-table-4.1-large", 119, 20, 8, 1e-5, 10_000, &variants)?;
            Ok(Computed {
                values: vec![vec![Some(m), Some(p), Some(e[0] / e[1])]],
                notes: vec![format!("relative L2 stress errors against ULFEM with 120 DOFs (the book's reference): MPM {:.4e}, TLS-BSMPM {:.4e}", e[0], e[1])],
            })
        },
    }
}

use crate::fem::ulfem::{Ulfem, UlfemMaterial};

/// Relative L2 stress errors against a ULFEM reference (`ref_elements`
/// elements, Δt_ref = 1e-5 s) of a bar parameter set after `steps` steps of
/// `dt`, for the given (method, mapping) list; reconstructions with
/// consistent mass. TLS paper §6.1 (Fig. 9), book §4.5 (Fig. 4.7).
pub fn stress_errors_against_ulfem(
    params: &str,
    ref_elements: usize,
    cells: usize,
    ppc: usize,
    dt: f64,
    steps: usize,
    variants: &[(Method, Mapping)],
) -> Result<Vec<f64>> {
    let p = vibrating_bar::parameters(params)?;
    let material = UlfemMaterial {
        density: p.density,
        young: p.young,
        constitutive: p.constitutive,
        gravity: 0.0,
    };
    let mut reference = Ulfem::new(
        p.length,
        ref_elements,
        material,
        |x| p.velocity(x, 0.0),
        vec![0, ref_elements],
    )?;
    let t_end = dt * steps as f64;
    let ref_steps = (t_end / 1e-5).round() as usize;
    for _ in 0..ref_steps {
        reference.step(t_end / ref_steps as f64)?;
    }
    variants
        .par_iter()
        .map(|&(m, map)| {
            let mass = if map == Mapping::Direct {
                MassMatrix::Lumped
            } else {
                MassMatrix::Consistent(ConsistentSolver::Cholesky)
            };
            let mut sim = p.simulation(&Discretisation::new(m, map, mass, cells, ppc))?;
            sim.run(dt, steps)?;
            let r: Vec<f64> = sim
                .particles
                .x0
                .iter()
                .map(|&x| reference.stress_at(x))
                .collect();
            relative_l2_error(&sim.particles.stress, &r)
        })
        .collect()
}

fn tls_fig9() -> TableSpec {
    TableSpec {
        id: "tls-fig9",
        published_json: include_str!("../../golden/published/tls-fig9.json"),
        setup: "Vibrating bar with grid crossing, TLS paper Table 4, 20 elements (knot spans), 8 PPC, Δt = 1e-4 s, \
                0.1 s. Reference: updated-Lagrangian FEM (fem::ulfem) with 1000 elements and Δt = 1e-5 s \
                (self-converged to 3e-6). E = relative L2 error of the particle stress against the reference at \
                the particles' initial positions; factor = E_MPM / E_method. Reconstructions with consistent mass.",
        tolerance: |_, _| Tolerance::ERROR_RATIO,
        compute: |o| {
            if o.quick {
                return Ok(Computed::skipped_in_quick_mode(4, 1));
            }
            let b = Method::Bsmpm { degree: 2 };
            let variants = [
                (Method::Mpm, Mapping::Direct),
                (b, Mapping::CubicSpline),
                (b, Mapping::Tls),
                (Method::Ddmpm, Mapping::CubicSpline),
                (Method::Ddmpm, Mapping::Tls),
                (Method::Ddmpm, Mapping::Direct),
                (b, Mapping::Direct),
            ];
            let e = stress_errors_against_ulfem("tls-table-4", 1000, 20, 8, 1e-4, 1000, &variants)?;
            Ok(Computed {
                values: (1..5).map(|k| vec![Some(e[0] / e[k])]).collect(),
                notes: vec![format!(
                    "relative L2 stress errors: MPM {:.4e}, BSMPM+CS {:.4e}, BSMPM+TLS {:.4e}, DDMPM+CS {:.4e}, DDMPM+TLS {:.4e}, DDMPM {:.4e}, BSMPM {:.4e}",
                    e[0], e[1], e[2], e[3], e[4], e[5], e[6]
                )],
            })
        },
    }
}
