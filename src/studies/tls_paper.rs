//! # The runs of the TLS paper's tables (and book §4.5)
//!
//! Conservation errors of the vibrating bar (TLS paper Tables 3 and 5,
//! book §4.5), convergence orders (Fig. 6), the column compaction (Table 6;
//! Fig. 10 and Table 7) and stress errors against an updated-Lagrangian FEM
//! reference (Fig. 9, book Fig. 4.7). Results are labelled by method and
//! mapping, never picked by position.
//!
//! Items: [`mass_for`], [`TLS_METHODS`], [`SMALL_BAR_DT`], [`SMALL_BAR_STEPS`], [`conservation_errors`],
//! [`conservation_errors_for`], [`BarRun`], [`by_method`],
//! [`ConservationByMethod`], [`conservation_by_mapping`],
//! [`as_paper_ran`], [`fig6_variants`], [`fitted_order`], [`fig6_errors`], [`CompactionRun`],
//! [`compaction`], [`compactions`], [`compaction_uncached`], [`compaction_with_average`],
//! [`compaction_simulation`], [`compaction_stress_error`], [`compaction_start`], [`COMPACTION_DT`], [`COMPACTION_STEPS`],
//! [`compaction_dynamic_reference`],
//! [`TABLE_8_SUBPOINTS`],
//! [`SubpointRow`], [`SubpointStudy`], [`subpoint_study`], [`subpoint_study_against`],
//! [`stress_errors_against_ulfem`].

use super::{bar_errors, BarErrors};
use crate::error::Result;
use crate::fem::ulfem::{Ulfem, UlfemMaterial};
use crate::mpm::diagnostics::relative_l2_error;
use crate::mpm::grid::Method;
use crate::mpm::mapping::{ConsistentSolver, Mapping, MassMatrix};
use crate::mpm::musl::{GravityRamp, RampTimeLevel, Simulation};
use crate::reconstruct::taylor::CellAverage;
use crate::scenes::{column, vibrating_bar, Discretisation};
use rayon::prelude::*;
use serde::Serialize;
use std::collections::HashMap;
use std::sync::{Mutex, OnceLock};

/// The mass matrix the TLS paper pairs with a mapping: the direct mapping
/// with the lumped mass (standard MPM), a reconstruction with the
/// consistent mass (TLS paper §5.4), solved by sparse Cholesky.
pub fn mass_for(mapping: Mapping) -> MassMatrix {
    if mapping == Mapping::Direct {
        MassMatrix::Lumped
    } else {
        MassMatrix::Consistent(ConsistentSolver::Cholesky)
    }
}

/// The three methods of the TLS paper's tables, in their column order.
pub const TLS_METHODS: [Method; 3] = [Method::Mpm, Method::DDMPM, Method::Bsmpm { degree: 2 }];

/// The method as the TLS paper most likely ran it with `mapping`
/// (docs/conventions.md, "DDMPM node integrals"): DDMPM's node integrals
/// use the quadrature of the force integral, the particles for the direct
/// mapping and the Gauss points (exact for P1) for the TLS and cubic-spline
/// mappings. Other methods are returned unchanged. TLS paper §3.3 and §5.4.
pub fn as_paper_ran(method: Method, mapping: Mapping) -> Method {
    match (method, mapping) {
        (Method::Ddmpm { .. }, Mapping::Direct) => Method::DDMPM_PARTICLES,
        (Method::Ddmpm { .. }, _) => Method::DDMPM,
        (other, _) => other,
    }
}

/// The time step of the small-deformation bar runs (TLS paper Table 2,
/// Tables 3 and Fig. 6): Δt = 1e-7 s.
pub const SMALL_BAR_DT: f64 = 1e-7;
/// Their number of steps: 19 (t = 1.9e-6 s).
pub const SMALL_BAR_STEPS: usize = 19;

/// (max mass error, max momentum error) of the vibrating bar of TLS paper
/// Table 2 over 19 steps of 1e-7 s (t = 1.9e-6 s), consistent mass.
pub fn conservation_errors(
    method: Method,
    mapping: Mapping,
    cells: usize,
    ppc: usize,
) -> Result<(f64, f64)> {
    conservation_errors_for(
        "tls-table-2",
        method,
        mapping,
        cells,
        ppc,
        SMALL_BAR_DT,
        SMALL_BAR_STEPS,
    )
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
    let run = BarRun {
        params,
        cells,
        ppc,
        dt,
        steps,
    };
    run.conservation_errors(method, mapping, CellAverage::Exact)
}

/// A vibrating-bar run of [`conservation_errors_for`]: parameter set,
/// resolution and time stepping.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct BarRun<'a> {
    /// The parameter set ([`vibrating_bar::parameters`]).
    pub params: &'a str,
    /// Elements (knot spans).
    pub cells: usize,
    /// Particles per cell.
    pub ppc: usize,
    /// Δt.
    pub dt: f64,
    /// Steps.
    pub steps: usize,
}

impl BarRun<'_> {
    /// (max mass error, max momentum error) with the TLS density fit's
    /// cell average `average` (docs/conventions.md, "The TLS author's cell
    /// average"), consistent mass (Cholesky).
    pub fn conservation_errors(
        &self,
        method: Method,
        mapping: Mapping,
        average: CellAverage,
    ) -> Result<(f64, f64)> {
        let BarRun {
            params,
            cells,
            ppc,
            dt,
            steps,
        } = *self;
        let p = vibrating_bar::parameters(params)?;
        let mass = MassMatrix::Consistent(ConsistentSolver::Cholesky);
        let mut sim = p.simulation(&Discretisation::new(method, mapping, mass, cells, ppc))?;
        sim.settings.tls_density_average = average;
        sim.run(dt, steps)?;
        Ok((
            sim.diagnostics.max_mass_error,
            sim.diagnostics.max_momentum_error,
        ))
    }
}

/// `run(method)` for each of [`TLS_METHODS`], in parallel, labelled: the
/// columns of one row of TLS paper Tables 3, 5 and 7 (and of the TLS
/// author's cell-average experiment, docs/conventions.md).
pub fn by_method(
    run: impl Fn(Method) -> Result<(f64, f64)> + Sync,
) -> Result<ConservationByMethod> {
    let errors: Vec<(f64, f64)> = TLS_METHODS
        .par_iter()
        .map(|&m| run(m))
        .collect::<Result<_>>()?;
    Ok(TLS_METHODS.into_iter().zip(errors).collect())
}

/// (Error_M, Error_P) of each method under one mapping.
pub type ConservationByMethod = Vec<(Method, (f64, f64))>;

/// `run(method, mapping)` for the cubic-spline and the TLS mapping and each
/// of [`TLS_METHODS`] (TLS paper Tables 3, 5, 7), in parallel, labelled.
pub fn conservation_by_mapping(
    run: impl Fn(Method, Mapping) -> Result<(f64, f64)> + Sync,
) -> Result<Vec<(Mapping, ConservationByMethod)>> {
    [Mapping::CubicSpline, Mapping::Tls]
        .into_iter()
        .map(|mapping| Ok((mapping, by_method(|m| run(m, mapping))?)))
        .collect()
}

/// The nine method/mapping combinations of TLS paper Fig. 6, in table
/// order, each method [`as_paper_ran`] with its mapping.
pub fn fig6_variants() -> Vec<(Method, Mapping)> {
    TLS_METHODS
        .into_iter()
        .flat_map(|m| {
            [Mapping::Direct, Mapping::CubicSpline, Mapping::Tls]
                .map(|map| (as_paper_ran(m, map), map))
        })
        .collect()
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
/// Δt = 1e-7 s, 19 steps), with [`mass_for`] the mapping.
pub fn fig6_errors(method: Method, mapping: Mapping) -> Result<Vec<BarErrors>> {
    [5, 10, 20, 40]
        .par_iter()
        .map(|&cells| {
            let d = Discretisation::new(method, mapping, mass_for(mapping), cells, 12);
            bar_errors("tls-table-2", &d, SMALL_BAR_DT, SMALL_BAR_STEPS)
        })
        .collect()
}

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
/// 0.5 s) with [`mass_for`] the mapping. Three tables and the report share
/// these runs, so they are cached per process by (method, mapping); a timed
/// run of [`subpoint_study`] fills the cache too (the same bits).
pub fn compaction(method: Method, mapping: Mapping) -> Result<CompactionRun> {
    if let Some(r) = compaction_cache()
        .lock()
        .ok()
        .and_then(|c| c.get(&(method, mapping)).copied())
    {
        return Ok(r);
    }
    let run = compaction_uncached(method, mapping)?;
    remember_compaction(method, mapping, run);
    Ok(run)
}

/// The per-process cache of [`compaction`].
fn compaction_cache() -> &'static Mutex<HashMap<(Method, Mapping), CompactionRun>> {
    type Cache = Mutex<HashMap<(Method, Mapping), CompactionRun>>;
    static CACHE: OnceLock<Cache> = OnceLock::new();
    CACHE.get_or_init(|| Mutex::new(HashMap::new()))
}

/// Puts a run of [`compaction_uncached`] into [`compaction`]'s cache.
fn remember_compaction(method: Method, mapping: Mapping, run: CompactionRun) {
    if let Ok(mut c) = compaction_cache().lock() {
        c.insert((method, mapping), run);
    }
}

/// [`compaction`] for every (method, mapping) of `jobs`, spread over the
/// cores; the runs in the order of `jobs`.
pub fn compactions(jobs: &[(Method, Mapping)]) -> Result<Vec<CompactionRun>> {
    jobs.par_iter()
        .map(|&(method, mapping)| compaction(method, mapping))
        .collect()
}

/// One uncached compaction run of TLS paper Table 6 ([`compaction`]).
pub fn compaction_uncached(method: Method, mapping: Mapping) -> Result<CompactionRun> {
    compaction_with_average(method, mapping, CellAverage::Exact)
}

/// [`compaction_uncached`] with the TLS density fit's cell average
/// `average` (docs/conventions.md, "The TLS author's cell average").
pub fn compaction_with_average(
    method: Method,
    mapping: Mapping,
    average: CellAverage,
) -> Result<CompactionRun> {
    let sim = compaction_simulation(method, mapping, average, RampTimeLevel::StepStart)?;
    Ok(CompactionRun {
        stress_error: compaction_stress_error(&sim)?,
        mass_error: sim.diagnostics.max_mass_error,
        momentum_error: sim.diagnostics.max_momentum_error,
        crossings: sim.diagnostics.grid_crossings,
        max_displacement: sim
            .particles
            .displacement
            .iter()
            .fold(0.0, |a: f64, u| a.max(u.abs())),
    })
}

/// TLS paper Fig. 10's error of a compaction run: the relative L2 error of
/// the particle stress against the quasi-static ρ₀b(t)(H − X) at the run's
/// time.
pub fn compaction_stress_error(sim: &Simulation) -> Result<f64> {
    let p = column::parameters("tls-table-6")?;
    let exact: Vec<f64> = sim
        .particles
        .x0
        .iter()
        .map(|&x| p.equilibrium_stress(x, sim.time))
        .collect();
    relative_l2_error(&sim.particles.stress, &exact)
}

/// The compaction of TLS paper Table 6 (50 elements, 20 PPC, Δt = 1e-4 s,
/// 0.5 s, [`mass_for`] the mapping) run to its end, with the TLS density
/// average `average` and the ramp read at `time_level`
/// (docs/conventions.md, "The time level of a ramped body force"): the
/// simulation, for a caller that needs more than [`CompactionRun`].
pub fn compaction_simulation(
    method: Method,
    mapping: Mapping,
    average: CellAverage,
    time_level: RampTimeLevel,
) -> Result<Simulation> {
    let mut sim = compaction_start(method, mapping)?;
    sim.settings.tls_density_average = average;
    if let Some(ramp) = sim.settings.gravity_ramp.as_mut() {
        ramp.time_level = time_level;
    }
    sim.run(COMPACTION_DT, COMPACTION_STEPS)?;
    Ok(sim)
}

/// The compaction's time step, TLS paper §6.2: 1e-4 s.
pub const COMPACTION_DT: f64 = 1e-4;
/// Its number of steps: 5000 (0.5 s).
pub const COMPACTION_STEPS: usize = 5000;

/// The compaction of TLS paper Table 6 before its first step (50 elements,
/// 20 PPC, [`mass_for`] the mapping, the ramp read at the step's start).
pub fn compaction_start(method: Method, mapping: Mapping) -> Result<Simulation> {
    column::parameters("tls-table-6")?.simulation(&Discretisation::new(
        method,
        mapping,
        mass_for(mapping),
        50,
        20,
    ))
}

/// The compaction of TLS paper Table 6 as a converged *dynamic* solution:
/// a ULFEM column of `elements` elements with the same law, the same ramp
/// read at `time_level`, and time step `dt`, run to 0.5 s. The paper
/// compares with the quasi-static ρ₀b(H − X) (Bardenhagen and Kober); the
/// difference between the two is the ramp's own dynamic remainder, which
/// no method should be charged with (docs/reproduction-notes.md, tls-fig10).
pub fn compaction_dynamic_reference(
    elements: usize,
    dt: f64,
    time_level: RampTimeLevel,
) -> Result<Ulfem> {
    let p = column::parameters("tls-table-6")?;
    let material = UlfemMaterial {
        density: p.density,
        young: p.young,
        constitutive: p.constitutive,
        gravity: p.gravity,
        gravity_ramp: p.ramp_time.map(|duration| GravityRamp {
            duration,
            time_level,
        }),
    };
    let mut column = Ulfem::new(p.height, elements, material, |_| 0.0, vec![0])?;
    let steps = (COMPACTION_DT * COMPACTION_STEPS as f64 / dt).round() as usize;
    for _ in 0..steps {
        column.step(dt)?;
    }
    Ok(column)
}

/// The subpoint counts of TLS paper Table 8.
pub const TABLE_8_SUBPOINTS: [usize; 7] = [2, 4, 8, 16, 32, 64, 128];

/// One row of TLS paper Table 8: DDMPM whose node integrals use n subpoints
/// per particle, direct mapping, in the compaction of Table 6.
#[derive(Debug, Clone, Copy, PartialEq, Serialize)]
pub struct SubpointRow {
    /// Subpoints per particle.
    pub subpoints: usize,
    /// Relative L2 stress error at t = 0.5 s.
    pub stress_error: f64,
    /// Wall time of the run, seconds (setup and 5000 steps).
    pub seconds: f64,
}

/// TLS paper Table 8 as measured here: the reference DDMPM-TLS run (exact
/// node integrals, the Gauss points of the TLS mapping) and one
/// [`SubpointRow`] per count of `counts`, for the node-integral rule
/// `rule(n)`. The runs are sequential on one thread, so that their wall
/// times are comparable; each time is the best of `repeats` runs.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct SubpointStudy {
    /// Stress error of DDMPM-TLS.
    pub tls_error: f64,
    /// Wall time of DDMPM-TLS, seconds.
    pub tls_seconds: f64,
    /// One row per subpoint count.
    pub rows: Vec<SubpointRow>,
}

/// Runs [`SubpointStudy`] for `counts` with `method_for(n)` the DDMPM variant.
pub fn subpoint_study(
    counts: &[usize],
    method_for: fn(usize) -> Method,
    repeats: usize,
) -> Result<SubpointStudy> {
    subpoints_against(None, counts, method_for, repeats)
}

/// [`subpoint_study`] for another rule against the DDMPM-TLS reference
/// run of `reference`, which is not run again (the same run: its error
/// has the same bits, its time is that run's).
pub fn subpoint_study_against(
    reference: &SubpointStudy,
    counts: &[usize],
    method_for: fn(usize) -> Method,
    repeats: usize,
) -> Result<SubpointStudy> {
    let tls = (reference.tls_error, reference.tls_seconds);
    subpoints_against(Some(tls), counts, method_for, repeats)
}

/// [`subpoint_study`], with the reference (error, seconds) given or run.
fn subpoints_against(
    reference: Option<(f64, f64)>,
    counts: &[usize],
    method_for: fn(usize) -> Method,
    repeats: usize,
) -> Result<SubpointStudy> {
    let timed = |method: Method, mapping: Mapping| -> Result<(f64, f64)> {
        let mut best = f64::INFINITY;
        let mut error = f64::NAN;
        for _ in 0..repeats.max(1) {
            let start = std::time::Instant::now();
            let run = compaction_uncached(method, mapping)?;
            best = best.min(start.elapsed().as_secs_f64());
            remember_compaction(method, mapping, run);
            error = run.stress_error;
        }
        Ok((error, best))
    };
    let (tls_error, tls_seconds) = match reference {
        Some(r) => r,
        None => timed(Method::DDMPM, Mapping::Tls)?,
    };
    let rows = counts
        .iter()
        .map(|&n| {
            let (stress_error, seconds) = timed(method_for(n), Mapping::Direct)?;
            Ok(SubpointRow {
                subpoints: n,
                stress_error,
                seconds,
            })
        })
        .collect::<Result<_>>()?;
    Ok(SubpointStudy {
        tls_error,
        tls_seconds,
        rows,
    })
}

/// Relative L2 stress errors against a ULFEM reference (`ref_elements`
/// elements, Δt_ref = 1e-5 s) of a bar parameter set after `steps` steps of
/// `dt`, for each (method, mapping), labelled, with [`mass_for`] the
/// mapping. TLS paper §6.1 (Fig. 9), book §4.5 (Fig. 4.7).
pub fn stress_errors_against_ulfem(
    params: &str,
    ref_elements: usize,
    cells: usize,
    ppc: usize,
    dt: f64,
    steps: usize,
    variants: &[(Method, Mapping)],
) -> Result<Vec<((Method, Mapping), f64)>> {
    let p = vibrating_bar::parameters(params)?;
    let material = UlfemMaterial {
        density: p.density,
        young: p.young,
        constitutive: p.constitutive,
        gravity: 0.0,
        gravity_ramp: None,
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
            let mut sim = p.simulation(&Discretisation::new(m, map, mass_for(map), cells, ppc))?;
            sim.run(dt, steps)?;
            let r: Vec<f64> = sim
                .particles
                .x0
                .iter()
                .map(|&x| reference.stress_at(x))
                .collect();
            Ok(((m, map), relative_l2_error(&sim.particles.stress, &r)?))
        })
        .collect()
}
