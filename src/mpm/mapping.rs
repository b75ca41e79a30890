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

use super::grid::{Grid, Shape};
use super::particles::Particles;
use crate::error::{Error, Result};
use crate::quadrature::{gauss_on_cells, QuadraturePoint};
use crate::reconstruct::cubic_spline::{CubicSpline, EndCondition};
use crate::reconstruct::taylor::{reconstruct, Assignment, TlsOptions};
use crate::solve::direct::cholesky_solve;
use crate::solve::richardson::richardson;
use crate::sparse::SparseMatrix;
use serde::Serialize;

/// How particle data reaches the grid.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize)]
#[serde(rename_all = "kebab-case")]
pub enum Mapping {
    /// Particles as quadrature points (standard MPM).
    Direct,
    /// Taylor least squares per cell plus Gauss quadrature.
    Tls,
    /// Cubic-spline reconstruction at the half-span Gauss points.
    CubicSpline,
}

impl Mapping {
    /// Parses `direct`, `tls` or `cubic-spline`.
    pub fn parse(name: &str) -> Result<Self> {
        match name {
            "direct" => Ok(Mapping::Direct),
            "tls" => Ok(Mapping::Tls),
            "cubic-spline" => Ok(Mapping::CubicSpline),
            other => Err(Error::InvalidArgument(format!(
                "mapping must be direct, tls or cubic-spline, got '{other}'"
            ))),
        }
    }
}

/// How the consistent system M^C v = p is solved.
#[derive(Debug, Clone, Copy, PartialEq, Serialize)]
#[serde(rename_all = "kebab-case")]
pub enum ConsistentSolver {
    /// Sparse Cholesky (faer).
    Cholesky,
    /// Thesis §7.2: Richardson from P/M^L, stopped at ‖P − M^C v‖/‖P‖ ≤ tol.
    Richardson {
        /// ε.
        tolerance: f64,
    },
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

/// The basis shapes of every particle at the start of the step.
pub fn particle_shapes(grid: &Grid, particles: &Particles) -> Result<Vec<Shape>> {
    particles.x.iter().map(|&x| grid.shape(x)).collect()
}

/// Lumped nodal masses from particles, book Eq. (4.5): m_i = Σ_p m_p φ_i(x_p).
pub fn lumped_mass(n: usize, particles: &Particles, shapes: &[Shape]) -> Vec<f64> {
    let mut m = vec![0.0; n];
    for (s, &mp) in shapes.iter().zip(&particles.mass) {
        for (j, &phi) in s.values.iter().enumerate() {
            m[s.first + j] += mp * phi;
        }
    }
    m
}

/// Σ_p q_p φ_i(x_p) (gravity and traction loads, thesis §3.2).
pub fn scatter(n: usize, weights: &[f64], shapes: &[Shape]) -> Vec<f64> {
    let mut f = vec![0.0; n];
    for (s, &w) in shapes.iter().zip(weights) {
        for (j, &phi) in s.values.iter().enumerate() {
            f[s.first + j] += w * phi;
        }
    }
    f
}

/// The thesis' half-span Gauss points restricted to the continuum
/// Ω_t ≈ [x_1 − V_1/2, x_N + V_N/2] (thesis §7.2, Figs. 7.3–7.4): on each half
/// span, both points are kept if both lie inside; if neither does and the
/// half span misses Ω_t they are deactivated; otherwise the 2-point rule is
/// redefined on the part of the half span inside Ω_t.
pub fn spline_quadrature(grid: &Grid, particles: &Particles) -> Result<Vec<QuadraturePoint>> {
    let (lo_k, hi_k) = extreme_particles(particles);
    let left = particles.x[lo_k] - 0.5 * particles.volume[lo_k];
    let right = particles.x[hi_k] + 0.5 * particles.volume[hi_k];
    let mut out = Vec::new();
    for (a, b) in grid.cells() {
        let m = 0.5 * (a + b);
        for (c, d) in [(a, m), (m, b)] {
            let pair = gauss_on_cells(&[(c, d)], 2)?;
            let inside = pair.iter().filter(|q| q.x >= left && q.x <= right).count();
            if inside == 2 {
                out.extend(pair);
            } else {
                let (c2, d2) = (c.max(left), d.min(right));
                if d2 > c2 {
                    out.extend(gauss_on_cells(&[(c2, d2)], 2)?);
                }
            }
        }
    }
    Ok(out)
}

fn extreme_particles(p: &Particles) -> (usize, usize) {
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
    (lo, hi)
}

/// A not-a-knot cubic spline of particle values over the particle positions.
fn particle_spline(particles: &Particles, values: &[f64]) -> Result<CubicSpline> {
    let mut idx: Vec<usize> = (0..particles.len()).collect();
    idx.sort_by(|&a, &b| particles.x[a].total_cmp(&particles.x[b]));
    let x: Vec<f64> = idx.iter().map(|&k| particles.x[k]).collect();
    let y: Vec<f64> = idx.iter().map(|&k| values[k]).collect();
    CubicSpline::new(&x, &y, EndCondition::NotAKnot)
}

/// Gauss points per cell for TLS: n_b ≤ 2 N_g/N_e (TLS paper §5.5), i.e. two
/// for quadratic TLS, as the paper uses.
pub const TLS_GAUSS_POINTS: usize = 2;

fn tls_options() -> TlsOptions {
    TlsOptions {
        assignment: Assignment::HalfOpen,
        ..TlsOptions::default()
    }
}

/// Cells that hold at least one particle (half-open), for TLS.
fn active_cells(grid: &Grid, particles: &Particles) -> Vec<(f64, f64)> {
    let cells = grid.cells();
    let n = cells.len();
    cells
        .iter()
        .enumerate()
        .filter(|(e, &(a, b))| {
            particles
                .x
                .iter()
                .any(|&x| (a <= x && x < b) || (*e + 1 == n && x == b))
        })
        .map(|(_, c)| *c)
        .collect()
}

/// The internal force vector f_int (book Eq. 4.6 directly, Eq. 4.38 with TLS,
/// thesis §7.2 with splines).
pub fn internal_force(
    grid: &Grid,
    particles: &Particles,
    shapes: &[Shape],
    mapping: Mapping,
) -> Result<Vec<f64>> {
    let n = grid.num_dofs();
    let mut f = vec![0.0; n];
    match mapping {
        Mapping::Direct => {
            for (k, s) in shapes.iter().enumerate() {
                let w = particles.stress[k] * particles.volume[k];
                for (j, &g) in s.gradients.iter().enumerate() {
                    f[s.first + j] += w * g;
                }
            }
        }
        Mapping::Tls => {
            let cells = grid.cells();
            let tls = reconstruct(&cells, &particles.x, &particles.stress, None, tls_options())?;
            for q in gauss_on_cells(&active_cells(grid, particles), TLS_GAUSS_POINTS)? {
                let s = grid.shape(q.x)?;
                let w = q.weight * tls.evaluate(q.x);
                for (j, &g) in s.gradients.iter().enumerate() {
                    f[s.first + j] += w * g;
                }
            }
        }
        Mapping::CubicSpline => {
            let spline = particle_spline(particles, &particles.stress)?;
            for q in spline_quadrature(grid, particles)? {
                let s = grid.shape(q.x)?;
                let w = q.weight * spline.evaluate(q.x);
                for (j, &g) in s.gradients.iter().enumerate() {
                    f[s.first + j] += w * g;
                }
            }
        }
    }
    Ok(f)
}

/// The result of a velocity projection, before boundary conditions.
#[derive(Debug, Clone, PartialEq)]
pub struct Projection {
    /// Nodal velocities v (zero at DOFs without mass).
    pub velocity: Vec<f64>,
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
/// book Eq. (4.10) directly, Eqs. (4.39)–(4.44) with TLS, thesis §7.2 with splines.
pub fn project_velocity(
    grid: &Grid,
    particles: &Particles,
    shapes: &[Shape],
    mapping: Mapping,
    mass: MassMatrix,
) -> Result<Projection> {
    let n = grid.num_dofs();
    let mut p = vec![0.0; n];
    // Row sums and diagonal are accumulated directly (partition of unity:
    // Σ_b φ_b = 1, so the row sum of ρw φ_a φ_b is ρw φ_a); the full matrix is
    // only assembled when the consistent system is solved.
    let consistent = matches!(mass, MassMatrix::Consistent(_));
    let mut triplets: Vec<(usize, usize, f64)> = Vec::new();
    let mut lumped = vec![0.0; n];
    let mut diagonal = vec![0.0; n];
    let mut add = |s: &Shape, rho_w: f64, mom_w: f64, p: &mut Vec<f64>| {
        let sum: f64 = s.values.iter().sum();
        for (a, &fa) in s.values.iter().enumerate() {
            p[s.first + a] += mom_w * fa;
            lumped[s.first + a] += rho_w * fa * sum;
            diagonal[s.first + a] += rho_w * fa * fa;
            if consistent {
                for (b, &fb) in s.values.iter().enumerate() {
                    triplets.push((s.first + a, s.first + b, rho_w * fa * fb));
                }
            }
        }
    };
    match mapping {
        Mapping::Direct => {
            for (k, s) in shapes.iter().enumerate() {
                let m = particles.mass[k];
                add(s, m, m * particles.v[k], &mut p);
            }
        }
        Mapping::Tls => {
            let cells = grid.cells();
            let nc = cells.len();
            let mut cell_mass = vec![0.0; nc];
            let mut cell_momentum = vec![0.0; nc];
            for k in 0..particles.len() {
                let x = particles.x[k];
                if let Some(e) = cells
                    .iter()
                    .enumerate()
                    .position(|(e, &(a, b))| (a <= x && x < b) || (e + 1 == nc && x == b))
                {
                    cell_mass[e] += particles.mass[k];
                    cell_momentum[e] += particles.mass[k] * particles.v[k];
                }
            }
            let rho_v: Vec<f64> = particles
                .density
                .iter()
                .zip(&particles.v)
                .map(|(r, v)| r * v)
                .collect();
            let rho = reconstruct(
                &cells,
                &particles.x,
                &particles.density,
                Some(&cell_mass),
                tls_options(),
            )?;
            let mom = reconstruct(
                &cells,
                &particles.x,
                &rho_v,
                Some(&cell_momentum),
                tls_options(),
            )?;
            for q in gauss_on_cells(&active_cells(grid, particles), TLS_GAUSS_POINTS)? {
                let s = grid.shape(q.x)?;
                add(
                    &s,
                    q.weight * rho.evaluate(q.x),
                    q.weight * mom.evaluate(q.x),
                    &mut p,
                );
            }
        }
        Mapping::CubicSpline => {
            let rho = particle_spline(particles, &particles.density)?;
            let vel = particle_spline(particles, &particles.v)?;
            for q in spline_quadrature(grid, particles)? {
                let s = grid.shape(q.x)?;
                let r = rho.evaluate(q.x);
                add(&s, q.weight * r, q.weight * r * vel.evaluate(q.x), &mut p);
            }
        }
    }
    let full = SparseMatrix::from_triplets(n, n, &triplets)?;
    let grid_mass: f64 = lumped.iter().sum();
    // Active DOFs: those the mapped mass reaches.
    let active: Vec<usize> = (0..n).filter(|&i| diagonal[i] != 0.0).collect();
    let diag: Vec<f64> = active.iter().map(|&i| diagonal[i]).collect();
    let dmax = diag.iter().cloned().fold(0.0, f64::max);
    let dmin = diag.iter().cloned().fold(f64::INFINITY, f64::min);
    let diagonal_ratio = if dmax > 0.0 { dmin / dmax } else { 0.0 };
    let mut v = vec![0.0; n];
    let mut solver_iterations = 0;
    match mass {
        MassMatrix::Lumped => {
            for &i in &active {
                v[i] = p[i] / lumped[i];
            }
        }
        MassMatrix::Consistent(solver) => {
            let sub = full.submatrix(&active, &active);
            let rhs: Vec<f64> = active.iter().map(|&i| p[i]).collect();
            let x = match solver {
                ConsistentSolver::Cholesky => cholesky_solve(&sub, &rhs)?,
                ConsistentSolver::Richardson { tolerance } => {
                    let ml = sub.row_sums();
                    let r = richardson(&sub, &ml, &rhs, tolerance, 100_000)?;
                    solver_iterations = r.iterations;
                    r.solution
                }
            };
            for (k, &i) in active.iter().enumerate() {
                v[i] = x[k];
            }
        }
    }
    let grid_momentum = match mass {
        MassMatrix::Lumped => lumped.iter().zip(&v).map(|(m, v)| m * v).sum(),
        MassMatrix::Consistent(_) => {
            let mut mv = vec![0.0; n];
            full.mul_vec(&v, &mut mv);
            mv.iter().sum()
        }
    };
    Ok(Projection {
        velocity: v,
        grid_mass,
        grid_momentum,
        solver_iterations,
        diagonal_ratio,
    })
}
