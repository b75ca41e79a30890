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
//!   element mass Σm_p and momentum Σm_p v_p as prescribed integrals;
//! - by **cubic splines** through the particle values, evaluated at the
//!   thesis' half-span Gauss points (thesis §7.2), with points outside the
//!   continuum Ω_t ≈ [x_1 − V_1/2, x_N + V_N/2] deactivated and pairs that
//!   straddle its edge redefined (thesis Figs. 7.3–7.4).
//!
//! The nodal velocity solves M v = p with M lumped (a division) or
//! consistent (a sparse Cholesky, or the thesis' Richardson iteration).
//!
//! Everything a mapping needs between steps lives in a [`MappingWorkspace`]:
//! the particles binned by cell (one counting-sort pass, so TLS costs
//! O(particles + cells)), the quadrature points and their basis stencils,
//! the previous step's cubic splines (refitted in place), and the nodal
//! accumulators of the projection. The direct mapping with a lumped mass
//! allocates nothing; TLS allocates its cell fits and a consistent mass its
//! sparse matrix and factorisation, the same amount every step
//! (tests/allocations.rs).
//!
//! Longer than 600 lines: the internal force and the velocity projection
//! of the three mappings share one workspace whose private buffers (the
//! binned particles, the quadrature stencils, the spline buffers, the band
//! assembly) both reuse; split, those buffers would have to be public to
//! the crate.
//!
//! A mapping is registered once ([`Mapping::ALL`], [`Mapping::info`]: its
//! name, label, legend, `--help` line and cost); the command line, the
//! labels and the estimates read the registry, and its implementation is
//! one arm in each of [`MappingWorkspace::begin_step`], [`internal_force`]
//! and the projection's accumulation, all in this file.
//!
//! Items: [`Mapping`], [`MappingInfo1d`], [`ConsistentSolver`], [`MassMatrix`],
//! [`TLS_GAUSS_POINTS`], [`MappingWorkspace`], [`internal_force`],
//! [`Projection`], [`project_velocity`], [`assemble_projection`],
//! [`solve_projection`], [`diagnose_projection`].

use super::grid::Grid;
use super::particles::Particles;
use crate::basis::{with_width, Stencils};
use crate::error::{Error, Result};
use crate::quadrature::{half_span_points, GaussLegendre, QuadraturePoint};
use crate::reconstruct::cubic_spline::{CubicSpline, EndCondition};
use crate::reconstruct::taylor::{
    reconstruct_binned, CellAverage, CellBins, TlsOptions, TlsReconstruction, TlsScratch,
};
use crate::solve::direct::cholesky_solve;
use crate::solve::richardson::{richardson_with, ResidualNorm};
use crate::sparse::{BandAssembly, SparseMatrix};
use crate::spline::bspline::SpanScratch;
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
}

impl Mapping {
    /// Every 1D mapping, in the order the command line lists them.
    pub const ALL: [Mapping; 4] = [
        Mapping::Direct,
        Mapping::Tls,
        Mapping::CubicSpline,
        Mapping::CubicSplineClipped,
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
            },
            Mapping::Tls => MappingInfo1d {
                name: "tls",
                legend: "TLS",
                label: "TLS mapping",
                summary: "Taylor least squares (book §4.4.3, TLS paper §5.4)",
                extra_ns_per_particle_step: 200.0,
            },
            Mapping::CubicSpline => MappingInfo1d {
                name: "cubic-spline",
                legend: "CS",
                label: "cubic-spline mapping",
                summary: "cubic splines (thesis ch. 7), at the thesis' half-span Gauss points",
                extra_ns_per_particle_step: 200.0,
            },
            Mapping::CubicSplineClipped => MappingInfo1d {
                name: "cubic-spline-clipped",
                legend: "CS (clipped)",
                label: "clipped cubic-spline mapping",
                summary: "cubic splines with every half span clipped to the continuum Ω_t",
                extra_ns_per_particle_step: 200.0,
            },
        }
    }

    /// The mapping's name in JSON and on the command line.
    pub fn name(self) -> &'static str {
        self.info().name
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

/// Gauss points per cell for TLS: n_b ≤ 2 N_g/N_e (TLS paper §5.5), i.e. two
/// for quadratic TLS, as the paper uses.
pub const TLS_GAUSS_POINTS: usize = 2;

/// Quadrature points with the basis evaluated at them.
#[derive(Debug, Clone, Default)]
struct QuadratureStencils {
    points: Vec<QuadraturePoint>,
    /// The cell of each point (TLS evaluates that cell's fit).
    cell: Vec<usize>,
    stencils: Stencils,
}

impl QuadratureStencils {
    fn clear(&mut self) {
        self.points.clear();
        self.cell.clear();
    }

    fn push(&mut self, q: QuadraturePoint, cell: usize) {
        self.points.push(q);
        self.cell.push(cell);
    }

    fn evaluate(&mut self, grid: &Grid, scratch: &mut SpanScratch) -> Result<()> {
        if self.stencils.width() != grid.stencil_width() {
            self.stencils = grid.stencils(0);
        }
        let xs = &self.points;
        self.stencils.resize(xs.len());
        for (k, q) in xs.iter().enumerate() {
            let (v, g) = self.stencils.slots_mut(k);
            self.stencils.first[k] = grid.evaluate(q.x, scratch, v, g)?;
        }
        Ok(())
    }
}

/// The buffers of the mappings, allocated once per simulation and reused in
/// every step.
#[derive(Debug, Clone)]
pub struct MappingWorkspace {
    cells: Vec<(f64, f64)>,
    rule: GaussLegendre,
    scratch: SpanScratch,
    bins: CellBins,
    tls_scratch: TlsScratch,
    tls_quadrature: QuadratureStencils,
    spline_quadrature: QuadratureStencils,
    /// Particle indices sorted by position (cubic splines).
    order: Vec<usize>,
    sorted: (Vec<f64>, Vec<f64>),
    /// Splines of the last step, whose buffers the next fits reuse.
    spare_splines: [Option<CubicSpline>; 2],
    product: Vec<f64>,
    cell_mass: Vec<f64>,
    cell_momentum: Vec<f64>,
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
    band: BandAssembly,
    active: Vec<usize>,
    rhs: Vec<f64>,
    /// How the TLS fit of the density averages (x − x_c)² in ψ_3
    /// ([`CellAverage`]); the simulation copies it from its settings every
    /// step. The fits of ρv and σ always use the exact average.
    pub tls_density_average: CellAverage,
}

impl MappingWorkspace {
    /// Buffers for `grid` and `particles` particles.
    pub fn new(grid: &Grid, particles: usize) -> Result<Self> {
        let n = grid.num_dofs();
        Ok(Self {
            cells: grid.cells(),
            rule: GaussLegendre::new(2)?,
            scratch: SpanScratch::default(),
            bins: CellBins::default(),
            tls_scratch: TlsScratch::default(),
            tls_quadrature: QuadratureStencils::default(),
            spline_quadrature: QuadratureStencils::default(),
            order: (0..particles).collect(),
            sorted: (Vec::with_capacity(particles), Vec::with_capacity(particles)),
            product: Vec::with_capacity(particles),
            cell_mass: vec![0.0; grid.num_cells()],
            cell_momentum: vec![0.0; grid.num_cells()],
            momentum: vec![0.0; n],
            lumped: vec![0.0; n],
            diagonal: vec![0.0; n],
            velocity: vec![0.0; n],
            solver_iterations: 0,
            solver_residual: 0.0,
            band: BandAssembly::default(),
            spare_splines: [None, None],
            active: Vec::with_capacity(n),
            rhs: Vec::with_capacity(n),
            tls_density_average: CellAverage::Exact,
        })
    }

    /// Prepares what the mappings of this step need from the particles at
    /// x^t: the particles binned by cell and the quadrature stencils of TLS
    /// (Gauss points of the cells that hold particles) and of the cubic
    /// splines (the half-span rule restricted to Ω_t). Call once per step,
    /// before [`internal_force`] and [`project_velocity`].
    pub fn begin_step(
        &mut self,
        grid: &Grid,
        particles: &Particles,
        mappings: &[Mapping],
    ) -> Result<()> {
        if mappings.contains(&Mapping::Tls) {
            self.bin_particles(grid, particles)?;
            self.tls_quadrature_points(grid)?;
        }
        let thesis = mappings.contains(&Mapping::CubicSpline);
        let clipped = mappings.contains(&Mapping::CubicSplineClipped);
        if thesis && clipped {
            return Err(Error::InvalidArgument(
                "the force and velocity mappings use two different cubic-spline quadratures".into(),
            ));
        }
        if thesis || clipped {
            self.spline_quadrature_points(grid, particles, clipped)?;
        }
        Ok(())
    }

    fn bin_particles(&mut self, grid: &Grid, particles: &Particles) -> Result<()> {
        let x = &particles.x;
        self.bins.fill(grid.num_cells(), x.len(), |k| {
            Ok((grid.cell_of(x[k])?, None))
        })
    }

    /// Two Gauss points on every cell that holds a particle (book Eq. 4.38).
    fn tls_quadrature_points(&mut self, grid: &Grid) -> Result<()> {
        let q = &mut self.tls_quadrature;
        q.clear();
        for e in 0..grid.num_cells() {
            if self.bins.count(e) == 0 {
                continue;
            }
            let (a, b) = grid.cell_bounds(e);
            for i in 0..TLS_GAUSS_POINTS {
                q.push(self.rule.point(i, a, b), e);
            }
        }
        q.evaluate(grid, &mut self.scratch)
    }

    /// The thesis' half-span Gauss points (quadrature::half_span_points)
    /// restricted to the continuum Ω_t ≈ [x_1 − V_1/2, x_N + V_N/2] (thesis
    /// §7.2, Figs. 7.3–7.4): on each half span, both points are kept if both
    /// lie inside; otherwise the 2-point rule is redefined on the part of the
    /// half span inside Ω_t, and the half span is dropped if it misses Ω_t.
    /// With `clip_every_half_span`, a half span is kept whole only if it
    /// lies inside Ω_t ([`Mapping::CubicSplineClipped`]).
    fn spline_quadrature_points(
        &mut self,
        grid: &Grid,
        particles: &Particles,
        clip_every_half_span: bool,
    ) -> Result<()> {
        let (left, right) = continuum(particles);
        let q = &mut self.spline_quadrature;
        q.clear();
        for e in 0..grid.num_cells() {
            let (a, b) = grid.cell_bounds(e);
            let m = 0.5 * (a + b);
            for (pair, (c, d)) in half_span_points(&self.rule, a, b)
                .into_iter()
                .zip([(a, m), (m, b)])
            {
                let keep_whole = if clip_every_half_span {
                    c >= left && d <= right
                } else {
                    pair.iter().all(|q| q.x >= left && q.x <= right)
                };
                if keep_whole {
                    pair.into_iter().for_each(|p| q.push(p, e));
                } else {
                    let (c2, d2) = (c.max(left), d.min(right));
                    if d2 > c2 {
                        for i in 0..2 {
                            q.push(self.rule.point(i, c2, d2), e);
                        }
                    }
                }
            }
        }
        q.evaluate(grid, &mut self.scratch)
    }
}

/// The continuum Ω_t ≈ [x_1 − V_1/2, x_N + V_N/2] spanned by the particles
/// (thesis §7.2), from the leftmost and rightmost particle.
fn continuum(p: &Particles) -> (f64, f64) {
    let mut lo = 0;
    let mut hi = 0;
    for k in 0..p.len() {
        if p.x[k] < p.x[lo] {
            lo = k;
        }
        if p.x[k] > p.x[hi] {
            hi = k;
        }
    }
    (p.x[lo] - 0.5 * p.volume[lo], p.x[hi] + 0.5 * p.volume[hi])
}

/// A not-a-knot cubic spline of particle values over the particle positions
/// (thesis §7.1), refitted into the buffers of `spare` when there is one.
/// `order` keeps the sorting permutation between steps: it is already
/// sorted unless particles overtook each other.
fn particle_spline(
    order: &mut Vec<usize>,
    sorted: &mut (Vec<f64>, Vec<f64>),
    spare: &mut Option<CubicSpline>,
    particles: &Particles,
    values: &[f64],
) -> Result<CubicSpline> {
    let x = &particles.x;
    if order.len() != x.len() {
        *order = (0..x.len()).collect();
    }
    order.sort_unstable_by(|&a, &b| x[a].total_cmp(&x[b]));
    sorted.0.clear();
    sorted.1.clear();
    for &k in order.iter() {
        sorted.0.push(x[k]);
        sorted.1.push(values[k]);
    }
    match spare.take() {
        Some(s) => s.refit(&sorted.0, &sorted.1, EndCondition::NotAKnot),
        None => CubicSpline::new(&sorted.0, &sorted.1, EndCondition::NotAKnot),
    }
}

/// TLS of particle `values` over particles binned by cell (book Eqs.
/// 4.33–4.37), conservative when cell integrals are given. The bins are
/// half-open ([`Grid::cell_of`]), so a particle on a cell boundary belongs
/// to the cell on its right; the default options are quadratic TLS with
/// virtual points and a κ limit of 1e10.
fn particle_tls(
    cells: &[(f64, f64)],
    bins: &CellBins,
    particles: &Particles,
    values: &[f64],
    integrals: Option<&[f64]>,
    average: CellAverage,
    scratch: &mut TlsScratch,
) -> Result<TlsReconstruction> {
    let options = TlsOptions {
        average,
        ..TlsOptions::default()
    };
    reconstruct_binned(
        cells,
        bins,
        &particles.x,
        values,
        integrals,
        options,
        scratch,
    )
}

/// The internal force vector f_int added into `force` (book Eq. 4.6
/// directly, Eq. 4.38 with TLS, thesis §7.2 with splines):
/// f_i = Σ σ_p V_p ∇φ_i(x_p), or ∫ σ̃ ∇φ_i dΩ by the mapping's quadrature.
pub fn internal_force(
    grid: &Grid,
    particles: &Particles,
    stencils: &Stencils,
    mapping: Mapping,
    ws: &mut MappingWorkspace,
    force: &mut [f64],
) -> Result<()> {
    check_nodal(grid, force)?;
    match mapping {
        Mapping::Direct => {
            stencils.scatter_gradients(|k| particles.stress[k] * particles.volume[k], force);
        }
        Mapping::Tls => {
            let stress = &particles.stress;
            let tls = particle_tls(
                &ws.cells,
                &ws.bins,
                particles,
                stress,
                None,
                CellAverage::Exact,
                &mut ws.tls_scratch,
            )?;
            let q = &ws.tls_quadrature;
            q.stencils.scatter_gradients(
                |k| q.points[k].weight * cell_value(&tls, q.cell[k], q.points[k].x),
                force,
            );
        }
        Mapping::CubicSpline | Mapping::CubicSplineClipped => {
            let stress = &particles.stress;
            let spare = &mut ws.spare_splines[0];
            let spline = particle_spline(&mut ws.order, &mut ws.sorted, spare, particles, stress)?;
            let q = &ws.spline_quadrature;
            let cursor = std::cell::Cell::new(0);
            q.stencils.scatter_gradients(
                |k| {
                    let mut c = cursor.get();
                    let value = spline.evaluate_from(q.points[k].x, &mut c);
                    cursor.set(c);
                    q.points[k].weight * value
                },
                force,
            );
            ws.spare_splines[0] = Some(spline);
        }
    }
    Ok(())
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

/// The TLS reconstruction in cell e at x (a Gauss point of that cell).
fn cell_value(tls: &TlsReconstruction, e: usize, x: f64) -> f64 {
    tls.cells[e].as_ref().map_or(0.0, |fit| fit.evaluate(x))
}

/// What a velocity projection reports besides the velocities, which it
/// leaves in [`MappingWorkspace::velocity`] (before boundary conditions).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Projection {
    /// Total grid mass Σ_ij M_ij of the matrix used.
    pub grid_mass: f64,
    /// Total grid momentum 1ᵀ M v.
    pub grid_momentum: f64,
    /// Iterations of the consistent solver (0 for lumped or Cholesky).
    pub solver_iterations: usize,
    /// min_i M_ii / max_i M_ii over active DOFs.
    pub diagonal_ratio: f64,
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
        Some(ws.band.to_sparse()?)
    } else {
        None
    };
    let solver_iterations = solve_projection(matrix.as_ref(), mass, ws)?;
    Ok(diagnose_projection(matrix.as_ref(), solver_iterations, ws))
}

/// The nodal accumulators of the projection: p, the row sums and diagonal
/// of M, and M's entries when the consistent system is solved.
struct Accumulator<'a> {
    momentum: &'a mut [f64],
    lumped: &'a mut [f64],
    diagonal: &'a mut [f64],
    band: &'a mut BandAssembly,
    consistent: bool,
}

impl Accumulator<'_> {
    /// Adds one quadrature point (a particle, or a Gauss point) with the
    /// weights ρw (mass) and ρvw (momentum). Partition of unity,
    /// Σ_b φ_b = 1, makes the row sum of ρw φ_a φ_b equal to ρw φ_a.
    fn add(&mut self, s: &Stencils, k: usize, rho_w: f64, mom_w: f64) {
        accumulate::<0>(self, s, k, rho_w, mom_w);
    }
}

/// [`Accumulator::add`] with the stencil width `W` known at compile time
/// (0: read it from the stencils).
fn accumulate<const W: usize>(
    acc: &mut Accumulator,
    s: &Stencils,
    k: usize,
    rho_w: f64,
    mom_w: f64,
) {
    let w = if W == 0 { s.width() } else { W };
    let first = s.first[k];
    let values = &s.values[k * w..k * w + w];
    let sum: f64 = values.iter().sum();
    for (a, &fa) in values.iter().enumerate() {
        acc.momentum[first + a] += mom_w * fa;
        acc.lumped[first + a] += rho_w * fa * sum;
        acc.diagonal[first + a] += rho_w * fa * fa;
        if acc.consistent {
            for (b, &fb) in values.iter().enumerate() {
                acc.band.add(first + a, first + b, rho_w * fa * fb);
            }
        }
    }
}

/// The direct mapping of book Eq. (4.10): every particle is a quadrature
/// point with mass m_p and momentum m_p v_p.
///
/// With a lumped mass and a known width, the sums of the current stencil are
/// held in registers while consecutive particles share it (as in
/// `basis::Stencils::scatter_values`): the same additions in the same order,
/// without a store between them.
fn accumulate_particles<const W: usize>(acc: &mut Accumulator, s: &Stencils, p: &Particles) {
    if W == 0 || acc.consistent || p.is_empty() {
        for k in 0..p.len() {
            let m = p.mass[k];
            accumulate::<W>(acc, s, k, m, m * p.velocity[k]);
        }
        return;
    }
    let load = |v: &[f64], f: usize| -> [f64; W] { v[f..f + W].try_into().expect("W entries") };
    let mut current = s.first[0];
    let mut momentum = load(acc.momentum, current);
    let mut lumped = load(acc.lumped, current);
    let mut diagonal = load(acc.diagonal, current);
    for k in 0..p.len() {
        let f = s.first[k];
        if f != current {
            acc.momentum[current..current + W].copy_from_slice(&momentum);
            acc.lumped[current..current + W].copy_from_slice(&lumped);
            acc.diagonal[current..current + W].copy_from_slice(&diagonal);
            current = f;
            momentum = load(acc.momentum, current);
            lumped = load(acc.lumped, current);
            diagonal = load(acc.diagonal, current);
        }
        let (rho_w, mom_w) = (p.mass[k], p.mass[k] * p.velocity[k]);
        let values = &s.values[k * W..(k + 1) * W];
        let sum: f64 = values.iter().sum();
        for (a, &fa) in values.iter().enumerate() {
            momentum[a] += mom_w * fa;
            lumped[a] += rho_w * fa * sum;
            diagonal[a] += rho_w * fa * fa;
        }
    }
    acc.momentum[current..current + W].copy_from_slice(&momentum);
    acc.lumped[current..current + W].copy_from_slice(&lumped);
    acc.diagonal[current..current + W].copy_from_slice(&diagonal);
}

/// Assembles the momentum p_i = ∫ ρv φ_i and the mass matrix
/// M_ij = ∫ ρ φ_i φ_j of the projection by the mapping's quadrature:
/// the particles for the direct mapping (book Eq. 4.10), conservative TLS
/// of ρ and ρv at the cells' Gauss points (Eqs. 4.39–4.44), or cubic
/// splines of ρ and v at the half-span points (thesis §7.2). It stays one
/// piece (about 70 lines, most of them the workspace's field list): it
/// splits the workspace into the disjoint borrows each mapping needs, which
/// Rust allows only where the workspace is destructured; the three mappings
/// are their own functions.
pub fn assemble_projection(
    grid: &Grid,
    particles: &Particles,
    stencils: &Stencils,
    mapping: Mapping,
    consistent: bool,
    ws: &mut MappingWorkspace,
) -> Result<()> {
    let n = grid.num_dofs();
    let MappingWorkspace {
        cells,
        bins,
        tls_scratch,
        tls_quadrature,
        spline_quadrature,
        order,
        sorted,
        spare_splines,
        product,
        cell_mass,
        cell_momentum,
        momentum,
        lumped,
        diagonal,
        band,
        tls_density_average,
        ..
    } = ws;
    for v in [&mut *momentum, &mut *lumped, &mut *diagonal] {
        v.clear();
        v.resize(n, 0.0);
    }
    if consistent {
        band.reset(n, stencils.width() - 1);
    }
    let mut acc = Accumulator {
        momentum,
        lumped,
        diagonal,
        band,
        consistent,
    };
    match mapping {
        Mapping::Direct => {
            with_width!(
                stencils.width(),
                accumulate_particles::<W>(&mut acc, stencils, particles)
            );
        }
        Mapping::Tls => accumulate_tls(
            &mut acc,
            particles,
            cells,
            bins,
            *tls_density_average,
            TlsBuffers {
                scratch: tls_scratch,
                quadrature: tls_quadrature,
                product,
                cell_mass,
                cell_momentum,
            },
        )?,
        Mapping::CubicSpline | Mapping::CubicSplineClipped => accumulate_spline(
            &mut acc,
            particles,
            order,
            sorted,
            spare_splines,
            spline_quadrature,
        )?,
    }
    Ok(())
}

/// The buffers of the TLS mapping, borrowed from [`MappingWorkspace`].
struct TlsBuffers<'a> {
    scratch: &'a mut TlsScratch,
    quadrature: &'a QuadratureStencils,
    product: &'a mut Vec<f64>,
    cell_mass: &'a mut [f64],
    cell_momentum: &'a mut [f64],
}

/// TLS mapping (book §4.4.3, TLS paper §5.4): conservative TLS fits of ρ
/// and ρv per cell, whose prescribed integrals are the cell mass Σ m_p and
/// momentum Σ m_p v_p, integrated at the Gauss points of every cell.
fn accumulate_tls(
    acc: &mut Accumulator,
    particles: &Particles,
    cells: &[(f64, f64)],
    bins: &CellBins,
    density_average: CellAverage,
    b: TlsBuffers,
) -> Result<()> {
    let TlsBuffers {
        scratch: tls_scratch,
        quadrature,
        product,
        cell_mass,
        cell_momentum,
    } = b;
    cell_mass.fill(0.0);
    cell_momentum.fill(0.0);
    for e in 0..cells.len() {
        for &k in bins.points_of(e) {
            cell_mass[e] += particles.mass[k];
            cell_momentum[e] += particles.mass[k] * particles.velocity[k];
        }
    }
    product.clear();
    product.extend(
        particles
            .density
            .iter()
            .zip(&particles.velocity)
            .map(|(r, v)| r * v),
    );
    let density = &particles.density;
    let rho = particle_tls(
        cells,
        bins,
        particles,
        density,
        Some(cell_mass),
        density_average,
        tls_scratch,
    )?;
    let mom = particle_tls(
        cells,
        bins,
        particles,
        product,
        Some(cell_momentum),
        CellAverage::Exact,
        tls_scratch,
    )?;
    let q = quadrature;
    for k in 0..q.points.len() {
        let (x, w, e) = (q.points[k].x, q.points[k].weight, q.cell[k]);
        acc.add(
            &q.stencils,
            k,
            w * cell_value(&rho, e, x),
            w * cell_value(&mom, e, x),
        );
    }
    Ok(())
}

/// Cubic-spline mapping (thesis §7.1–7.2): not-a-knot splines through the
/// particle density and velocity, integrated at the half-span Gauss points.
fn accumulate_spline(
    acc: &mut Accumulator,
    particles: &Particles,
    order: &mut Vec<usize>,
    sorted: &mut (Vec<f64>, Vec<f64>),
    spare_splines: &mut [Option<CubicSpline>; 2],
    quadrature: &QuadratureStencils,
) -> Result<()> {
    let [spare_rho, spare_vel] = spare_splines;
    let rho = particle_spline(order, sorted, spare_rho, particles, &particles.density)?;
    let vel = particle_spline(order, sorted, spare_vel, particles, &particles.velocity)?;
    let q = quadrature;
    let (mut cursor_rho, mut cursor_vel) = (0, 0);
    for k in 0..q.points.len() {
        let (x, w) = (q.points[k].x, q.points[k].weight);
        let r = rho.evaluate_from(x, &mut cursor_rho);
        let v = vel.evaluate_from(x, &mut cursor_vel);
        acc.add(&q.stencils, k, w * r, w * r * v);
    }
    (*spare_rho, *spare_vel) = (Some(rho), Some(vel));
    Ok(())
}

/// Solves M v = p on the active DOFs (those the mapped mass reaches,
/// M_ii ≠ 0) into [`MappingWorkspace::velocity`]: v_i = p_i / m_i with the
/// lumped mass, or the consistent system by sparse Cholesky or the thesis'
/// Richardson iteration (§7.2). Returns the solver's iterations.
pub fn solve_projection(
    consistent: Option<&SparseMatrix>,
    mass: MassMatrix,
    ws: &mut MappingWorkspace,
) -> Result<usize> {
    let n = ws.diagonal.len();
    ws.active.clear();
    ws.active.extend((0..n).filter(|&i| ws.diagonal[i] != 0.0));
    ws.velocity.clear();
    ws.velocity.resize(n, 0.0);
    let mut iterations = 0;
    ws.solver_residual = 0.0;
    match (mass, consistent) {
        (MassMatrix::Consistent(solver), Some(full)) => {
            let sub = full.submatrix(&ws.active, &ws.active);
            ws.rhs.clear();
            ws.rhs.extend(ws.active.iter().map(|&i| ws.momentum[i]));
            let x = match solver {
                ConsistentSolver::Cholesky => cholesky_solve(&sub, &ws.rhs)?,
                ConsistentSolver::Richardson {
                    tolerance,
                    residual,
                } => {
                    let ml = sub.row_sums();
                    let r = richardson_with(&sub, &ml, &ws.rhs, tolerance, residual, 100_000)?;
                    iterations = r.iterations;
                    ws.solver_residual = r.residuals.last().copied().unwrap_or(0.0);
                    r.solution
                }
            };
            for (k, &i) in ws.active.iter().enumerate() {
                ws.velocity[i] = x[k];
            }
        }
        _ => {
            for &i in &ws.active {
                ws.velocity[i] = ws.momentum[i] / ws.lumped[i];
            }
        }
    }
    ws.solver_iterations = iterations;
    Ok(iterations)
}

/// The projection's diagnostics (TLS paper Tables 3, 5, 7; thesis §7.2.4):
/// total grid mass Σ_ij M_ij, grid momentum 1ᵀ M v, and the diagonal ratio
/// min M_ii / max M_ii over active DOFs.
pub fn diagnose_projection(
    consistent: Option<&SparseMatrix>,
    solver_iterations: usize,
    ws: &mut MappingWorkspace,
) -> Projection {
    let grid_mass: f64 = ws.lumped.iter().sum();
    let (mut dmax, mut dmin) = (0.0, f64::INFINITY);
    for &i in &ws.active {
        dmax = f64::max(dmax, ws.diagonal[i]);
        dmin = f64::min(dmin, ws.diagonal[i]);
    }
    let diagonal_ratio = if dmax > 0.0 { dmin / dmax } else { 0.0 };
    let grid_momentum = match consistent {
        None => ws.lumped.iter().zip(&ws.velocity).map(|(m, v)| m * v).sum(),
        Some(full) => {
            ws.rhs.clear();
            ws.rhs.resize(ws.velocity.len(), 0.0);
            full.mul_vec(&ws.velocity, &mut ws.rhs);
            ws.rhs.iter().sum()
        }
    };
    Projection {
        grid_mass,
        grid_momentum,
        solver_iterations,
        diagonal_ratio,
    }
}
