//! # Where methods fail: the failure cases of the seeds, as numbers
//!
//! Each function runs one failure the seeds describe and returns what a
//! reader needs to see it; tests/spec/properties/stability.rs asserts on these results and
//! the report's stability chart prints them, so the two never drift apart.
//!
//! - [`column_grid_crossing`]: linear MPM loses its accuracy when particles
//!   cross element boundaries (thesis §5.1.3, Table 4.3); quadratic
//!   B-splines on the same spans do not (thesis §6.2.3);
//! - [`quadratic_lagrange_negative_masses`]: P2 end-node functions are
//!   negative inside the element, so lumped masses can be (thesis §5.2);
//! - [`near_zero_consistent_masses`]: a consistent mass meets near-zero
//!   entries at the moving top of the large-deformation column (thesis
//!   §7.2.4).
//!
//! Items: [`ColumnRun`], [`GridCrossing`], [`column_grid_crossing`],
//! [`NegativeMasses`], [`quadratic_lagrange_negative_masses`],
//! [`NearZeroMasses`], [`near_zero_consistent_masses`], [`FailureCases`],
//! [`failure_cases`].

use crate::error::{Error, Result};
use crate::mpm::diagnostics::rms_error;
use crate::mpm::grid::Method;
use crate::mpm::mapping::{ConsistentSolver, Mapping, MassMatrix};
use crate::scenes::{column, vibrating_bar, Discretisation};
use serde::Serialize;

/// RMS displacement error and grid crossings of one column run.
#[derive(Debug, Clone, Copy, PartialEq, Serialize)]
pub struct ColumnRun {
    /// RMS error of u_p against the series solution (thesis Eq. 4.2).
    pub error: f64,
    /// Grid crossings counted by the step.
    pub crossings: usize,
}

/// The column of thesis Table 4.3 with 50 and 80 DOFs (P1) and with
/// quadratic B-splines on the 80-DOF spans.
#[derive(Debug, Clone, Copy, PartialEq, Serialize)]
pub struct GridCrossing {
    /// P1, 49 elements (50 DOFs).
    pub linear_50: ColumnRun,
    /// P1, 79 elements (80 DOFs).
    pub linear_80: ColumnRun,
    /// Quadratic B-splines, 79 spans.
    pub bspline_80: ColumnRun,
}

fn column_run(method: Method, cells: usize) -> Result<ColumnRun> {
    let p = column::parameters("thesis-table-4.3")?;
    let mut sim = p.simulation(&Discretisation::direct(method, cells, 2))?;
    sim.run(1e-4, 5000)?;
    let exact: Vec<f64> = sim
        .particles
        .x0
        .iter()
        .map(|&y| p.displacement(y, sim.time, 200))
        .collect();
    Ok(ColumnRun {
        error: rms_error(&sim.particles.displacement, &exact)?,
        crossings: sim.diagnostics.grid_crossings,
    })
}

/// Thesis §5.1.3: the column under self-weight (Table 4.3, 2 PPC,
/// Δt = 1e-4 s, t = 0.5 s).
pub fn column_grid_crossing() -> Result<GridCrossing> {
    Ok(GridCrossing {
        linear_50: column_run(Method::Mpm, 49)?,
        linear_80: column_run(Method::Mpm, 79)?,
        bspline_80: column_run(Method::Bsmpm { degree: 2 }, 79)?,
    })
}

/// P2 on the vibrating bar (thesis Table 4.1, 4 elements, Δt = 1e-5 s,
/// t = 0.5 s) with one particle per element, against two particles per
/// element and against P1 with one.
#[derive(Debug, Clone, Copy, PartialEq, Serialize)]
pub struct NegativeMasses {
    /// Steps with a negative active lumped mass, P2 with 1 PPC.
    pub negative_mass_steps: usize,
    /// Steps run.
    pub steps: usize,
    /// The most negative lumped mass.
    pub min_lumped_mass: f64,
    /// RMS displacement error, P2 with 1 PPC.
    pub error_one_ppc: f64,
    /// Steps with a negative mass, P2 with 2 PPC.
    pub negative_mass_steps_two_ppc: usize,
    /// RMS displacement error, P2 with 2 PPC.
    pub error_two_ppc: f64,
    /// RMS displacement error, P1 with 1 PPC.
    pub error_linear_one_ppc: f64,
}

fn bar_run(method: Method, ppc: usize, steps: usize) -> Result<(f64, usize, f64)> {
    let p = vibrating_bar::parameters("thesis-table-4.1")?;
    let mut sim = p.simulation(&Discretisation::direct(method, 4, ppc))?;
    sim.run(1e-5, steps)?;
    let exact: Vec<f64> = sim
        .particles
        .x0
        .iter()
        .map(|&x| p.displacement(x, sim.time))
        .collect();
    let d = &sim.diagnostics;
    Ok((
        rms_error(&sim.particles.displacement, &exact)?,
        d.negative_mass_steps,
        d.min_lumped_mass,
    ))
}

/// Thesis §5.2: negative P2 lumped masses and what they cost.
pub fn quadratic_lagrange_negative_masses() -> Result<NegativeMasses> {
    let steps = 50_000;
    let (error_one_ppc, negative_mass_steps, min_lumped_mass) = bar_run(Method::MpmP2, 1, steps)?;
    let (error_two_ppc, negative_mass_steps_two_ppc, _) = bar_run(Method::MpmP2, 2, steps)?;
    let (error_linear_one_ppc, _, _) = bar_run(Method::Mpm, 1, steps)?;
    Ok(NegativeMasses {
        negative_mass_steps,
        steps,
        min_lumped_mass,
        error_one_ppc,
        negative_mass_steps_two_ppc,
        error_two_ppc,
        error_linear_one_ppc,
    })
}

/// The large-deformation column (thesis Table 4.4, quadratic B-splines, 64
/// spans, 4 PPC, Δt = 1e-4 s, t = 0.5 s) with a consistent mass in the
/// velocity projection.
#[derive(Debug, Clone, Copy, PartialEq, Serialize)]
pub struct NearZeroMasses {
    /// Cubic-spline mapping: min over steps of min M_ii / max M_ii.
    pub min_mass_diagonal_ratio: f64,
    /// Cubic-spline mapping: the largest projected nodal velocity.
    pub max_nodal_velocity: f64,
    /// Cubic-spline mapping: the largest particle velocity.
    pub max_particle_velocity: f64,
    /// Direct mapping: the step at which the run blew up (`None` if it did not).
    pub direct_blow_up_step: Option<usize>,
    /// Direct mapping: the particle that showed it.
    pub direct_blow_up_particle: Option<usize>,
    /// Lumped projection (the thesis' choice): the largest nodal velocity
    /// over the largest particle velocity.
    pub lumped_velocity_ratio: f64,
}

/// Thesis §7.2.4: near-zero consistent masses at the moving top.
pub fn near_zero_consistent_masses() -> Result<NearZeroMasses> {
    let p = column::parameters("thesis-table-4.4")?;
    let b = Method::Bsmpm { degree: 2 };
    let consistent = MassMatrix::Consistent(ConsistentSolver::Cholesky);
    let mut spline = p.simulation(&Discretisation::new(
        b,
        Mapping::CubicSpline,
        consistent,
        64,
        4,
    ))?;
    spline.run(1e-4, 5000)?;
    let mut direct = p.simulation(&Discretisation::new(b, Mapping::Direct, consistent, 64, 4))?;
    let (step, particle) = match direct.run(1e-4, 5000) {
        Ok(()) => (None, None),
        Err(Error::NonPhysicalParticle { step, particle, .. }) => (Some(step), Some(particle)),
        Err(e) => return Err(e),
    };
    let mut lumped = p.simulation(&Discretisation::new(
        b,
        Mapping::Direct,
        MassMatrix::Lumped,
        64,
        4,
    ))?;
    lumped.run(1e-4, 5000)?;
    let (d, l) = (&spline.diagnostics, &lumped.diagnostics);
    Ok(NearZeroMasses {
        min_mass_diagonal_ratio: d.min_mass_diagonal_ratio,
        max_nodal_velocity: d.max_nodal_velocity,
        max_particle_velocity: d.max_particle_velocity,
        direct_blow_up_step: step,
        direct_blow_up_particle: particle,
        lumped_velocity_ratio: l.max_nodal_velocity / l.max_particle_velocity,
    })
}

/// All three failure cases.
#[derive(Debug, Clone, Copy, PartialEq, Serialize)]
pub struct FailureCases {
    /// Thesis §5.1.3.
    pub grid_crossing: GridCrossing,
    /// Thesis §5.2.
    pub negative_masses: NegativeMasses,
    /// Thesis §7.2.4.
    pub near_zero_masses: NearZeroMasses,
}

/// Runs all three failure cases.
pub fn failure_cases() -> Result<FailureCases> {
    Ok(FailureCases {
        grid_crossing: column_grid_crossing()?,
        negative_masses: quadratic_lagrange_negative_masses()?,
        near_zero_masses: near_zero_consistent_masses()?,
    })
}
