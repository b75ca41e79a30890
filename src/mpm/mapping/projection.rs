//! # The velocity projection's solve and its diagnostics
//!
//! Book Eq. (4.10) and thesis Eqs. (3.3)–(3.4): the nodal velocity solves
//! M v = p on the active DOFs (those the mapped mass reaches, M_ii ≠ 0),
//! with M lumped (a division) or consistent (book Eq. 4.44: a sparse
//! Cholesky, or the thesis' Richardson iteration, §7.2). The projection
//! then reports the grid's mass Σ_ij M_ij, its momentum 1ᵀ M v and the
//! diagonal ratio of M (TLS paper Tables 3, 5, 7; thesis §7.2.4). The
//! solve's buffers (the band assembly of M, the active DOFs, the
//! right-hand side) live in `ProjectionSolve`, inside the
//! `MappingWorkspace`, whose public fields hold what the projection
//! computed.
//!
//! Another code's step through a reconstruction that maps the loads
//! solves its acceleration with the same consistent matrix,
//! M a = f_ext − f_int ([`solve_consistent_acceleration`]).
//!
//! Items: [`Projection`], [`solve_projection`], [`diagnose_projection`],
//! [`solve_consistent_acceleration`], [`running_max`], [`running_min`],
//! [`both_finite`].

use super::{ConsistentSolver, MappingWorkspace, MassMatrix};
use crate::error::Result;
use crate::solve::direct::cholesky_solve;
use crate::solve::richardson::richardson_with;
use crate::sparse::{BandAssembly, SparseMatrix};

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

/// The buffers of the consistent solve, allocated once per simulation:
/// the band assembly of M, the active DOFs and the right-hand side (or
/// M v, in the diagnostics) on them.
#[derive(Debug, Clone, Default)]
pub(super) struct ProjectionSolve {
    pub(super) band: BandAssembly,
    active: Vec<usize>,
    rhs: Vec<f64>,
}

impl ProjectionSolve {
    /// Buffers for `dofs` DOFs.
    pub(super) fn new(dofs: usize) -> Self {
        Self {
            band: BandAssembly::default(),
            active: Vec::with_capacity(dofs),
            rhs: Vec::with_capacity(dofs),
        }
    }
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
    if ws.momentum.len() < n || ws.lumped.len() < n {
        return Err(crate::error::Error::InvalidArgument(format!(
            "the projection has {n} DOFs but {} momenta and {} lumped masses",
            ws.momentum.len(),
            ws.lumped.len()
        )));
    }
    ws.velocity.clear();
    let mut iterations = 0;
    ws.solver_residual = 0.0;
    match (mass, consistent) {
        (MassMatrix::Consistent(solver), Some(full)) => {
            ws.velocity.resize(n, 0.0);
            ws.solve.active.clear();
            ws.solve
                .active
                .extend((0..n).filter(|&i| ws.diagonal[i] != 0.0));
            let sub = full.submatrix(&ws.solve.active, &ws.solve.active);
            ws.solve.rhs.clear();
            ws.solve
                .rhs
                .extend(ws.solve.active.iter().map(|&i| ws.momentum[i]));
            let x = match solver {
                ConsistentSolver::Cholesky => cholesky_solve(&sub, &ws.solve.rhs)?,
                ConsistentSolver::Richardson {
                    tolerance,
                    residual,
                } => {
                    let ml = sub.row_sums();
                    let r =
                        richardson_with(&sub, &ml, &ws.solve.rhs, tolerance, residual, 100_000)?;
                    iterations = r.iterations;
                    ws.solver_residual = r.residuals.last().copied().unwrap_or(0.0);
                    r.solution
                }
            };
            for (k, &i) in ws.solve.active.iter().enumerate() {
                ws.velocity[i] = x[k];
            }
        }
        _ => {
            // v_i = p_i / M^L_i where M_ii ≠ 0, else +0: one pass over the DOFs.
            let (momentum, lumped) = (&ws.momentum[..n], &ws.lumped[..n]);
            let dofs = ws.diagonal.iter().zip(momentum).zip(lumped);
            let velocity = dofs.map(|((&d, &p), &m)| if d != 0.0 { p / m } else { 0.0 });
            ws.velocity.extend(velocity);
        }
    }
    ws.solver_iterations = iterations;
    Ok(iterations)
}

/// Solves M a = `force` on the DOFs the mapped mass reaches (M_ii ≠ 0)
/// that are not `fixed`, with M the consistent matrix the last
/// [`super::assemble_projection`] assembled, by sparse Cholesky; a = 0 on
/// every other DOF. This is the MLS paper's code's `nacc = MASS\nforce`
/// (`MLS_BSMPM_solvertest1.m:367-394`): its boundary rows and columns are
/// set apart with a diagonal entry and their accelerations then zeroed,
/// which leaves the other DOFs' system the submatrix solved here.
pub fn solve_consistent_acceleration(
    ws: &mut MappingWorkspace,
    force: impl Fn(usize) -> f64,
    fixed: &[usize],
    acceleration: &mut [f64],
) -> Result<()> {
    let n = ws.diagonal.len();
    if acceleration.len() != n {
        return Err(crate::error::Error::InvalidArgument(format!(
            "a nodal vector has {} entries for {n} DOFs",
            acceleration.len()
        )));
    }
    let full = ws.solve.band.to_sparse()?;
    ws.solve.active.clear();
    ws.solve
        .active
        .extend((0..n).filter(|&i| ws.diagonal[i] != 0.0 && !fixed.contains(&i)));
    let sub = full.submatrix(&ws.solve.active, &ws.solve.active);
    ws.solve.rhs.clear();
    ws.solve
        .rhs
        .extend(ws.solve.active.iter().map(|&i| force(i)));
    let x = cholesky_solve(&sub, &ws.solve.rhs)?;
    acceleration.fill(0.0);
    for (k, &i) in ws.solve.active.iter().enumerate() {
        acceleration[i] = x[k];
    }
    Ok(())
}

/// The projection's diagnostics (TLS paper Tables 3, 5, 7; thesis §7.2.4):
/// total grid mass Σ_ij M_ij, grid momentum 1ᵀ M v, and the diagonal ratio
/// min M_ii / max M_ii over active DOFs.
pub fn diagnose_projection(
    consistent: Option<&SparseMatrix>,
    solver_iterations: usize,
    ws: &mut MappingWorkspace,
) -> Projection {
    // The active DOFs are those with M_ii ≠ 0 (`solve_projection`); the
    // extremes do not depend on the order, and each sum below runs in DOF
    // order from −0.0 as `Iterator::sum` does, both in one pass.
    let (mut dmax, mut dmin) = (0.0, f64::INFINITY);
    let (mut grid_mass, mut lumped_momentum) = (-0.0, -0.0);
    let rows = ws.lumped.iter().zip(&ws.velocity).zip(&ws.diagonal);
    for ((&m, &v), &d) in rows {
        grid_mass += m;
        lumped_momentum += m * v;
        if d != 0.0 {
            // The running extremes by one comparison each (the same values
            // as f64::max and f64::min: dmax, dmin are never NaN, d ≠ 0).
            dmax = running_max(dmax, d);
            dmin = running_min(dmin, d);
        }
    }
    let diagonal_ratio = if dmax > 0.0 { dmin / dmax } else { 0.0 };
    let grid_momentum = match consistent {
        None => lumped_momentum,
        Some(full) => {
            ws.solve.rhs.clear();
            ws.solve.rhs.resize(ws.velocity.len(), 0.0);
            full.mul_vec(&ws.velocity, &mut ws.solve.rhs);
            ws.solve.rhs.iter().sum()
        }
    };
    Projection {
        grid_mass,
        grid_momentum,
        solver_iterations,
        diagonal_ratio,
    }
}

/// Whether a and b are both finite, by floating-point arithmetic: a − a is
/// +0 for a finite a and NaN for ±∞ and NaN, so the sum of the two
/// differences equals 0 exactly when both are finite. The answer of
/// `a.is_finite() & b.is_finite()` in four instructions instead of ten,
/// for the screen of the fused 1D step's last loop (issue #39).
#[inline(always)]
#[allow(clippy::eq_op)] // x − x is the point: NaN exactly for ±∞ and NaN.
pub fn both_finite(a: f64, b: f64) -> bool {
    (a - a) + (b - b) == 0.0
}

/// The larger of a running maximum and x: `f64::max(largest, x)` for a
/// `largest` that is not NaN and zeros of one sign (a NaN x leaves it), in
/// one comparison. A monitor's running maximum waits on each update, and
/// `f64::max`, with its rule for a NaN `largest`, is a chain of five
/// instructions where this is one (issue #39: the chain bounded the
/// projection's diagnosis and the fused step's loops).
#[inline(always)]
pub fn running_max(largest: f64, x: f64) -> f64 {
    if x > largest {
        x
    } else {
        largest
    }
}

/// The smaller of a running minimum and x: `f64::min(smallest, x)` for a
/// `smallest` that is not NaN and zeros of one sign ([`running_max`]).
#[inline(always)]
pub fn running_min(smallest: f64, x: f64) -> f64 {
    if x < smallest {
        x
    } else {
        smallest
    }
}
