//! # Mapping particle data to the grid
//!
//! Two quantities are mapped in every MUSL step: the internal force (book
//! Eq. 4.6) and the nodal velocity (book Eq. 4.10). Each can be computed
//!
//! - **directly**, with the particles as quadrature points (book Eqs. 4.6,
//!   4.10; thesis §3.1);
//! - by **Taylor least squares** on every active cell, integrated with Gauss
//!   quadrature (book §4.4.3, Eqs. 4.36–4.44; TLS paper §5.4): the stress
//!   unconstrained, density and momentum density conservative, with the
//!   element mass Σm_p and momentum Σm_p v_p as prescribed integrals
//!   ([`tls`]);
//! - by **cubic splines** through the particle values, evaluated at the
//!   thesis' half-span Gauss points (thesis §7.2), with points outside the
//!   continuum Ω_t ≈ [x_1 − V_1/2, x_N + V_N/2] deactivated and pairs that
//!   straddle its edge redefined (thesis Figs. 7.3–7.4) ([`spline`]);
//! - by the **MLS paper's code's 1D MLS**: a quadratic moving least
//!   squares fit per cell at two Gauss points, which maps the mass, the
//!   momentum and the loads too (MLS paper Eqs. 14, 18–25, as
//!   `MLS_BSMPM_solvertest1.m` of its code does; [`mls`]).
//!
//! The nodal velocity solves M v = p with M lumped (a division) or
//! consistent (a sparse Cholesky, or the thesis' Richardson iteration)
//! ([`projection`]).
//!
//! A mapping is registered once: [`Mapping::ALL`], [`Mapping::info`] (its
//! name, label, legend, `--help` line and cost) and
//! [`Mapping::reconstruction`] (its [`Reconstruction1d`], or none for the
//! direct mapping). The command line, the labels and the estimates read the
//! registry, and so do the step's three calls, [`MappingWorkspace::begin_step`],
//! [`internal_force`] and [`assemble_projection`]: each does the direct
//! mapping itself and hands every other mapping to its reconstruction
//! ([`reconstruction`] says what the 1D and the 2D reconstructions share).
//!
//! Everything a mapping needs between steps lives in a [`MappingWorkspace`],
//! allocated when the simulation starts: each registered reconstruction
//! with its own buffers ([`TlsWorkspace`]: the particles binned by cell and
//! the Gauss points of the cells that hold them; [`SplineWorkspace`]: the
//! half-span points inside Ω_t and the last step's splines), the consistent
//! solve's buffers, and, in its public fields, what the projection
//! computed. The direct mapping with a lumped mass allocates nothing; TLS
//! allocates its cell fits and a consistent mass its sparse matrix and
//! factorisation, the same amount every step (tests/allocations.rs).
//! [`quadrature`] holds what the mappings' quadratures share.
//!
//! ## How to add a 1D mapping
//! 1. Implement [`Reconstruction`] and [`Reconstruction1d`] in a new child
//!    module, `src/mpm/mapping/<name>.rs` (as [`tls`] and [`spline`] do), and
//!    declare it below.
//! 2. Register it here: one variant of [`Mapping`] (and in
//!    [`Mapping::ALL`]), its arm in [`Mapping::info`] and its arm in
//!    [`Mapping::reconstruction`].
//!
//! That is two files; `--mapping <name>`, the labels and the JSON follow
//! from the registration (tests/spec/meta/extensions.rs walks it).
//!
//! Items: [`Mapping`], [`MappingInfo1d`], [`ConsistentSolver`], [`MassMatrix`],
//! [`MappingWorkspace`], [`internal_force`], [`body_force`], [`project_velocity`],
//! [`assemble_projection`]; the modules [`projection`], [`quadrature`],
//! [`reconstruction`], [`spline`], [`tls`], [`mls`], and re-exported from
//! them [`Projection`], [`solve_projection`], [`diagnose_projection`],
//! [`solve_consistent_acceleration`], [`Accumulator`], [`Reconstruction`],
//! [`Reconstruction1d`], [`TlsWorkspace`], [`TLS_GAUSS_POINTS`],
//! [`SplineWorkspace`], [`MlsWorkspace`], [`MlsWeights`].

pub mod mls;
pub mod projection;
pub mod quadrature;
pub mod reconstruction;
pub mod spline;
pub mod tls;

pub use mls::{MlsWeights, MlsWorkspace};
pub use projection::both_finite;
pub use projection::solve_consistent_acceleration;
pub use projection::{diagnose_projection, running_max, running_min, solve_projection, Projection};
pub use quadrature::Accumulator;
pub(crate) use quadrature::{accumulate_lumped_row, accumulate_momentum_and_diagonal_row};
pub use reconstruction::{Reconstruction, Reconstruction1d};
pub use spline::SplineWorkspace;
pub use tls::{TlsWorkspace, TLS_GAUSS_POINTS};

use super::grid::Grid;
use super::particles::Particles;
use crate::basis::{with_width, Stencils};
use crate::error::{Error, Result};
use crate::reconstruct::taylor::CellAverage;
use crate::solve::richardson::ResidualNorm;
use projection::ProjectionSolve;
use quadrature::accumulate_particles;
use serde::Serialize;

/// How particle data reaches the grid.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, Serialize)]
#[serde(rename_all = "kebab-case")]
pub enum Mapping {
    /// Particles as quadrature points (standard MPM).
    Direct,
    /// Taylor least squares per cell plus Gauss quadrature.
    Tls,
    /// Cubic-spline reconstruction at the half-span Gauss points, restricted
    /// to Ω_t by the thesis' rule: a half span whose two Gauss points lie in
    /// Ω_t is kept whole (thesis §7.2, Figs. 7.3–7.4).
    CubicSpline,
    /// The same splines, with every half span that is not inside Ω_t
    /// clipped to it: the integrals then end at the free surface exactly
    /// (issue #11; the rule under which TLS paper Table 7's spline mass
    /// errors appear, docs/conventions.md).
    CubicSplineClipped,
    /// The MLS paper's code's 1D MLS ([`mls`]) with the consistent Gauss
    /// weight h/2 in every integral (the fix of its weights).
    Mls,
    /// The MLS paper's code's 1D MLS with its own weights: the forces at
    /// its 2D Gauss weight h²/4, the consistent mass at ρh/2
    /// (`MLS_BSMPM_solvertest1.m:322-332, 363`).
    MlsCodeWeights,
}

/// What the rest of hompm knows of a 1D mapping: its names and its cost.
/// One [`Mapping::info`] arm per mapping, as 2D's `MappingInfo`.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct MappingInfo1d {
    /// The name in JSON (serde's) and on the command line (`--mapping`).
    pub name: &'static str,
    /// The mapping in a method's label in words: `… with TLS mapping`.
    pub label: &'static str,
    /// The mapping in a chart's legend, after the method: `BSMPM + TLS`
    /// (empty for the direct mapping).
    pub legend: &'static str,
    /// One line for `--help`.
    pub summary: &'static str,
    /// The reconstruction's cost on top of the direct step, in ns per
    /// particle-step (the command line's run-time estimate).
    pub extra_ns_per_particle_step: f64,
    /// Whether the reconstruction maps the grid's mass, momentum and loads
    /// too ([`Reconstruction1d::body_force`]): then another code's step
    /// (`--scheme usl`, …) takes them from it, and a consistent mass is
    /// the mass of its acceleration (docs/conventions.md, "The MLS
    /// paper's code's 1D MLS").
    pub maps_loads: bool,
}

impl Mapping {
    /// Every 1D mapping, in the order the command line lists them.
    pub const ALL: [Mapping; 6] = [
        Mapping::Direct,
        Mapping::Tls,
        Mapping::CubicSpline,
        Mapping::CubicSplineClipped,
        Mapping::Mls,
        Mapping::MlsCodeWeights,
    ];

    /// The registration of a mapping's names and cost.
    pub fn info(self) -> MappingInfo1d {
        match self {
            Mapping::Direct => MappingInfo1d {
                name: "direct",
                legend: "",
                label: "direct mapping",
                summary: "particles as quadrature points (book Eqs. 4.5-4.10)",
                extra_ns_per_particle_step: 0.0,
                maps_loads: false,
            },
            Mapping::Tls => MappingInfo1d {
                name: "tls",
                legend: "TLS",
                label: "TLS mapping",
                summary: "Taylor least squares (book §4.4.3, TLS paper §5.4)",
                extra_ns_per_particle_step: 200.0,
                maps_loads: false,
            },
            Mapping::CubicSpline => MappingInfo1d {
                name: "cubic-spline",
                legend: "CS",
                label: "cubic-spline mapping",
                summary: "cubic splines (thesis ch. 7), at the thesis' half-span Gauss points",
                extra_ns_per_particle_step: 200.0,
                maps_loads: false,
            },
            Mapping::CubicSplineClipped => MappingInfo1d {
                name: "cubic-spline-clipped",
                legend: "CS (clipped)",
                label: "clipped cubic-spline mapping",
                summary: "cubic splines with every half span clipped to the continuum Ω_t",
                extra_ns_per_particle_step: 200.0,
                maps_loads: false,
            },
            Mapping::Mls => MappingInfo1d {
                name: "mls",
                legend: "MLS",
                label: "MLS mapping",
                summary: "the MLS paper's code's 1D MLS ([1, x, x²], one cell, 2 Gauss points), every integral at weight h/2",
                extra_ns_per_particle_step: 300.0,
                maps_loads: true,
            },
            Mapping::MlsCodeWeights => MappingInfo1d {
                name: "mls-code-weights",
                legend: "MLS (code's weights)",
                label: "MLS mapping with the code's weights",
                summary: "the same MLS with its code's weights: forces at h²/4, consistent mass at ρh/2 (MLS_BSMPM_solvertest1.m:322-332, 363)",
                extra_ns_per_particle_step: 300.0,
                maps_loads: true,
            },
        }
    }

    /// The registration of the reconstructions (book §4.4.3, thesis §7):
    /// the [`Reconstruction1d`] of this mapping, with its buffers for
    /// `grid` and `particles` particles, or `None` for the direct mapping
    /// (book Eqs. 4.6, 4.10).
    pub fn reconstruction(
        self,
        grid: &Grid,
        particles: usize,
    ) -> Result<Option<Box<dyn Reconstruction1d>>> {
        Ok(match self {
            Mapping::Direct => None,
            Mapping::Tls => Some(Box::new(TlsWorkspace::new(grid, particles)?)),
            Mapping::CubicSpline => Some(Box::new(SplineWorkspace::new(particles, false)?)),
            Mapping::CubicSplineClipped => Some(Box::new(SplineWorkspace::new(particles, true)?)),
            Mapping::Mls => Some(Box::new(MlsWorkspace::new(
                grid,
                particles,
                MlsWeights::Consistent,
            )?)),
            Mapping::MlsCodeWeights => Some(Box::new(MlsWorkspace::new(
                grid,
                particles,
                MlsWeights::Code,
            )?)),
        })
    }

    /// The mapping's name in JSON and on the command line.
    pub fn name(self) -> &'static str {
        self.info().name
    }

    /// Whether another code's step (docs/conventions.md, "Conventions of
    /// other codes") can run with these mappings and this mass: the direct
    /// mapping with a lumped mass, or one mapping that maps the loads too
    /// ([`MappingInfo1d::maps_loads`]) for both the force and the velocity.
    pub fn takes_other_conventions(force: Mapping, velocity: Mapping, mass: MassMatrix) -> bool {
        let direct = force == Mapping::Direct && velocity == Mapping::Direct;
        (direct && mass == MassMatrix::Lumped) || (force == velocity && force.info().maps_loads)
    }

    /// The mapping of a name, if one is registered under it.
    pub fn from_name(name: &str) -> Option<Mapping> {
        Mapping::ALL.into_iter().find(|m| m.name() == name)
    }
}

/// How the consistent system M^C v = p is solved.
#[derive(Debug, Clone, Copy, PartialEq, Serialize)]
#[serde(rename_all = "kebab-case")]
pub enum ConsistentSolver {
    /// Sparse Cholesky (faer).
    Cholesky,
    /// Thesis §7.2: Richardson from P/M^L, stopped at ‖P − M^C v‖/‖P‖ ≤ tol
    /// (or, with [`ResidualNorm::Solution`], at ‖P − M^C v‖/‖v‖ < tol).
    Richardson {
        /// ε.
        tolerance: f64,
        /// What the residual is divided by.
        residual: ResidualNorm,
    },
}

impl ConsistentSolver {
    /// The thesis' Richardson iteration with hompm's stopping rule,
    /// ‖P − M^C v‖/‖P‖ ≤ `tolerance` (thesis §7.2).
    pub fn richardson(tolerance: f64) -> Self {
        ConsistentSolver::Richardson {
            tolerance,
            residual: ResidualNorm::Rhs,
        }
    }
}

/// Which mass matrix the velocity projection uses.
#[derive(Debug, Clone, Copy, PartialEq, Serialize)]
#[serde(rename_all = "kebab-case")]
pub enum MassMatrix {
    /// Row-sum (= variational) lumped mass.
    Lumped,
    /// Consistent mass with the given solver.
    Consistent(ConsistentSolver),
}

/// The buffers of the mappings, allocated once per simulation and reused in
/// every step (book Eqs. 4.6, 4.10, 4.38–4.44; thesis §7.2): each
/// registered reconstruction, the consistent solve's buffers, and what the
/// projection computed.
#[derive(Debug)]
pub struct MappingWorkspace {
    /// Every registered mapping that has a reconstruction, with it, in the
    /// order of [`Mapping::ALL`].
    reconstructions: Vec<(Mapping, Box<dyn Reconstruction1d>)>,
    solve: ProjectionSolve,
    /// Nodal momentum p of the projection.
    pub momentum: Vec<f64>,
    /// Row sums of the projection's mass matrix (its lumped mass).
    pub lumped: Vec<f64>,
    /// Diagonal of the projection's mass matrix.
    pub diagonal: Vec<f64>,
    /// Nodal velocities v solved by the projection.
    pub velocity: Vec<f64>,
    /// Iterations of the last consistent solve (0 for a lumped mass or a
    /// Cholesky solve).
    pub solver_iterations: usize,
    /// The relative residual at which the last iterative solve stopped, by
    /// its own rule (0 for a lumped mass or a Cholesky solve).
    pub solver_residual: f64,
}

/// The reconstruction registered for `mapping` among `reconstructions`;
/// `None` for the direct mapping.
fn reconstruction_of(
    reconstructions: &mut [(Mapping, Box<dyn Reconstruction1d>)],
    mapping: Mapping,
) -> Option<&mut dyn Reconstruction1d> {
    reconstructions
        .iter_mut()
        .find(|(m, _)| *m == mapping)
        .map(|(_, r)| r.as_mut() as &mut dyn Reconstruction1d)
}

impl MappingWorkspace {
    /// Buffers for `grid` and `particles` particles: those of every
    /// registered reconstruction ([`Mapping::reconstruction`]).
    pub fn new(grid: &Grid, particles: usize) -> Result<Self> {
        let n = grid.num_dofs();
        let mut reconstructions = Vec::new();
        for m in Mapping::ALL {
            if let Some(r) = m.reconstruction(grid, particles)? {
                reconstructions.push((m, r));
            }
        }
        Ok(Self {
            reconstructions,
            solve: ProjectionSolve::new(n),
            momentum: vec![0.0; n],
            lumped: vec![0.0; n],
            diagonal: vec![0.0; n],
            velocity: vec![0.0; n],
            solver_iterations: 0,
            solver_residual: 0.0,
        })
    }

    /// Prepares what the `mappings` of this step need from the particles at
    /// x^t, with the exact cell average in a TLS density fit: see
    /// [`MappingWorkspace::begin_step_with`] (book Eq. 4.38, thesis §7.2).
    pub fn begin_step(
        &mut self,
        grid: &Grid,
        particles: &Particles,
        mappings: &[Mapping],
    ) -> Result<()> {
        self.begin_step_with(grid, particles, mappings, CellAverage::Exact)
    }

    /// Prepares what the `mappings` of this step need from the particles at
    /// x^t: each one's reconstruction makes its quadrature points and the
    /// basis at them ([`Reconstruction1d::begin_step`]: for TLS the Gauss
    /// points of the cells that hold particles, book Eq. 4.38; for the
    /// cubic splines the half-span rule restricted to Ω_t, thesis §7.2).
    /// `tls_density_average` is how the TLS fit of the density averages
    /// (x − x_c)² in ψ_3 ([`CellAverage`]; the fits of ρv and σ always use
    /// the exact average). Call once per step, before [`internal_force`]
    /// and [`project_velocity`].
    pub fn begin_step_with(
        &mut self,
        grid: &Grid,
        particles: &Particles,
        mappings: &[Mapping],
        tls_density_average: CellAverage,
    ) -> Result<()> {
        for (m, r) in &mut self.reconstructions {
            if mappings.contains(m) {
                r.begin_step(grid, particles, tls_density_average)?;
            }
        }
        Ok(())
    }

    /// The reconstruction of `mapping` and what it reports of its last
    /// step ([`Reconstruction`]); `None` for the direct mapping (book
    /// §4.4.3, thesis §7).
    pub fn reconstruction(&self, mapping: Mapping) -> Option<&dyn Reconstruction1d> {
        self.reconstructions
            .iter()
            .find(|(m, _)| *m == mapping)
            .map(|(_, r)| r.as_ref() as &dyn Reconstruction1d)
    }
}

/// The internal force vector f_int added into `force` (book Eq. 4.6
/// directly, Eq. 4.38 with TLS, thesis §7.2 with splines):
/// f_i = Σ σ_p V_p ∇φ_i(x_p), or ∫ σ̃ ∇φ_i dΩ by the quadrature of the
/// mapping's reconstruction ([`Reconstruction1d::internal_force`]).
pub fn internal_force(
    grid: &Grid,
    particles: &Particles,
    stencils: &Stencils,
    mapping: Mapping,
    ws: &mut MappingWorkspace,
    force: &mut [f64],
) -> Result<()> {
    check_nodal(grid, force)?;
    match reconstruction_of(&mut ws.reconstructions, mapping) {
        None => {
            stencils.scatter_gradients(|k| particles.stress[k] * particles.volume[k], force);
        }
        Some(r) => r.internal_force(particles, force)?,
    }
    Ok(())
}

/// The body force f_ext,i = ∫ (ρb)~ φ_i dΩ by the reconstruction of
/// `mapping` (MLS paper Eqs. 20, 24; [`Reconstruction1d::body_force`]),
/// with b_p = `body(k)`, added into `force`. The direct mapping and a
/// reconstruction that does not map the loads refuse.
pub fn body_force(
    grid: &Grid,
    particles: &Particles,
    mapping: Mapping,
    body: &dyn Fn(usize) -> f64,
    ws: &mut MappingWorkspace,
    force: &mut [f64],
) -> Result<()> {
    check_nodal(grid, force)?;
    match reconstruction_of(&mut ws.reconstructions, mapping) {
        None => Err(Error::Usage(
            "the direct mapping maps the loads in the step itself".into(),
        )),
        Some(r) => r.body_force(particles, body, force),
    }
}

fn check_nodal(grid: &Grid, v: &[f64]) -> Result<()> {
    if v.len() != grid.num_dofs() {
        return Err(Error::InvalidArgument(format!(
            "a nodal vector has {} entries for {} DOFs",
            v.len(),
            grid.num_dofs()
        )));
    }
    Ok(())
}

/// Projects the particle velocities (already updated to t + Δt) onto the grid:
/// book Eq. (4.10) directly, Eqs. (4.39)–(4.44) with TLS, thesis §7.2 with
/// splines. Three steps: assemble M and p, solve M v = p, diagnose.
pub fn project_velocity(
    grid: &Grid,
    particles: &Particles,
    stencils: &Stencils,
    mapping: Mapping,
    mass: MassMatrix,
    ws: &mut MappingWorkspace,
) -> Result<Projection> {
    let consistent = matches!(mass, MassMatrix::Consistent(_));
    assemble_projection(grid, particles, stencils, mapping, consistent, ws)?;
    let matrix = if consistent {
        Some(ws.solve.band.to_sparse()?)
    } else {
        None
    };
    let solver_iterations = solve_projection(matrix.as_ref(), mass, ws)?;
    Ok(diagnose_projection(matrix.as_ref(), solver_iterations, ws))
}

/// Assembles the momentum p_i = ∫ ρv φ_i and the mass matrix
/// M_ij = ∫ ρ φ_i φ_j of the projection by the mapping's quadrature:
/// the particles for the direct mapping (book Eq. 4.10), conservative TLS
/// of ρ and ρv at the cells' Gauss points (Eqs. 4.39–4.44), or cubic
/// splines of ρ and v at the half-span points (thesis §7.2), each added by
/// the mapping's reconstruction ([`Reconstruction1d::accumulate_projection`]).
pub fn assemble_projection(
    grid: &Grid,
    particles: &Particles,
    stencils: &Stencils,
    mapping: Mapping,
    consistent: bool,
    ws: &mut MappingWorkspace,
) -> Result<()> {
    let n = grid.num_dofs();
    for v in [&mut ws.momentum, &mut ws.lumped, &mut ws.diagonal] {
        v.clear();
        v.resize(n, 0.0);
    }
    if consistent {
        ws.solve.band.reset(n, stencils.width() - 1);
    }
    let mut acc = Accumulator {
        momentum: &mut ws.momentum,
        lumped: &mut ws.lumped,
        diagonal: &mut ws.diagonal,
        band: &mut ws.solve.band,
        consistent,
    };
    match reconstruction_of(&mut ws.reconstructions, mapping) {
        None => with_width!(
            stencils.width(),
            accumulate_particles::<W>(&mut acc, stencils, particles)
        ),
        Some(r) => r.accumulate_projection(particles, &mut acc)?,
    }
    Ok(())
}
