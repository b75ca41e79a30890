//! # `hompm mass`: the book's mass matrix, its spectrum and its solvers
//!
//! The test problem of book §4.6–4.7 (`mass::unit_density_mass`, in 1D or
//! as `mass::unit_density_mass_2d`), κ by a dense symmetric eigensolve
//! (book Eqs. 4.54–4.56), and a solve of M a = M·(−9.81·1) by CG (4.53),
//! p-multigrid (4.59–4.62), Richardson (thesis §7.2) or Cholesky.
//!
//! Items: [`MassArgs`], [`mass`].

use super::args::{count, name, SolverArg};
use super::limits::Limits;
use super::{json, Output};
use crate::error::{Error, Result};
use crate::mass::{unit_density_mass, Kronecker2d};
use crate::solve::{self, cg, direct, pmultigrid, richardson, spectrum, IterativeResult};
use crate::sparse::SparseMatrix;
use serde::Serialize;

/// Arguments of `hompm mass`.
#[derive(clap::Args, Debug)]
pub struct MassArgs {
    /// Polynomial degree p.
    #[arg(long, value_parser = count, allow_negative_numbers = true)]
    degree: usize,
    /// Number of knot spans per direction.
    #[arg(long, value_parser = count, allow_negative_numbers = true)]
    spans: usize,
    /// Dimension: 1, or 2 for the tensor-product matrix.
    #[arg(long, default_value_t = 1, value_parser = count, allow_negative_numbers = true)]
    dim: usize,
    /// Remove the first and last function per direction.
    #[arg(long)]
    dirichlet: bool,
    /// Compute λ_min, λ_max and κ (a dense eigensolve of the 1D factor).
    #[arg(long)]
    condition: bool,
    /// Solve M a = M·(−9.81·1).
    #[arg(long, value_enum)]
    solve: Option<SolverArg>,
    /// Relative tolerance of the iterative solvers (at least ε = 2.2e-16).
    #[arg(long, default_value_t = 1e-8, allow_negative_numbers = true)]
    tol: f64,
    /// What CG and Richardson divide the residual by: rhs (‖b‖, book
    /// Eq. 4.53 and thesis §7.2) or solution (the iterate, as the thesis
    /// author's code).
    #[arg(long, value_enum)]
    residual: Option<super::setup_args::ResidualArg>,
    /// Print JSON.
    #[arg(long)]
    json: bool,
}

impl MassArgs {
    /// The stopping rule's denominator.
    fn residual_norm(&self) -> crate::solve::richardson::ResidualNorm {
        self.residual.map_or(Default::default(), Into::into)
    }
}

#[derive(Serialize, Default)]
struct MassJson {
    size: usize,
    #[serde(skip_serializing_if = "Option::is_none")]
    lambda_min: Option<f64>,
    #[serde(skip_serializing_if = "Option::is_none")]
    lambda_max: Option<f64>,
    #[serde(skip_serializing_if = "Option::is_none")]
    condition_number: Option<f64>,
    #[serde(skip_serializing_if = "Option::is_none")]
    solver: Option<String>,
    #[serde(skip_serializing_if = "Option::is_none")]
    iterations: Option<usize>,
    #[serde(skip_serializing_if = "Option::is_none")]
    residuals: Option<Vec<f64>>,
}

/// Iterations assumed by the time estimate of an iterative solve (CG and
/// Richardson need hundreds on the book's problems; an estimate, not a cap).
const ASSUMED_ITERATIONS: f64 = 2000.0;
/// Seconds per stored nonzero and iteration of a sparse matrix–vector product.
const SECONDS_PER_NONZERO: f64 = 2e-9;
/// Seconds per n³ of a dense symmetric eigensolve.
const SECONDS_PER_EIGEN_FLOP: f64 = 3e-9;

fn validate(a: &MassArgs) -> Result<()> {
    if a.dim != 1 && a.dim != 2 {
        return Err(Error::InvalidArgument(format!(
            "--dim must be 1 or 2, got {}",
            a.dim
        )));
    }
    if a.spans == 0 {
        return Err(Error::InvalidArgument(
            "--spans must be at least 1, got 0".into(),
        ));
    }
    if a.residual.is_some() && !matches!(a.solve, Some(SolverArg::Cg | SolverArg::Richardson)) {
        return Err(Error::InvalidArgument(
            "--residual applies to --solve cg or richardson".into(),
        ));
    }
    if a.solve == Some(SolverArg::Pmg) && a.degree == 0 {
        return Err(Error::InvalidDegree(
            "--solve pmg needs --degree ≥ 1, got 0".into(),
        ));
    }
    if a.solve.is_some() && !(a.tol.is_finite() && a.tol >= f64::EPSILON && a.tol < 1.0) {
        return Err(Error::InvalidArgument(format!(
            "--tol must lie in [ε = {:e}, 1): a relative residual below ε cannot be reached in double precision; got {:e}",
            f64::EPSILON,
            a.tol
        )));
    }
    Ok(())
}

/// Memory and time from the sizes alone: n = spans + p (− 2) functions per
/// direction, N = n^dim DOFs, (2p + 1)^dim nonzeros per row (40 bytes each
/// while assembling), the 1D assembly's (p + 1)³ triplets per span, a dense
/// n × n matrix for the spectrum, and a
/// Cholesky factor of N × (bandwidth) for the direct solver.
fn check_limits(a: &MassArgs, limits: &Limits) -> Result<()> {
    let p = a.degree as f64;
    let n = a.spans as f64 + p - if a.dirichlet { 2.0 } else { 0.0 };
    let dofs = n.powi(a.dim as i32);
    let nnz = dofs * (2.0 * p + 1.0).powi(a.dim as i32);
    let what = |w: &'static str| {
        move || {
            format!(
                "{w} on {dofs:.0} DOFs (degree {}, {} spans, dim {})",
                a.degree, a.spans, a.dim
            )
        }
    };
    // `mass::consistent_mass` collects (p + 1)² triplets of 24 bytes per
    // Gauss point, p + 1 points per span, and `SparseMatrix::from_triplets`
    // copies them once before summing: twice that at the peak.
    let triplets = 2.0 * a.spans as f64 * (p + 1.0).powi(3) * 24.0;
    limits.check_memory(
        what("the mass matrix"),
        triplets + nnz * 40.0,
        "assembly storage",
    )?;
    if a.condition {
        limits.check_memory(what("--condition"), n * n * 8.0 * 2.0, "a dense matrix")?;
        limits.check_time(what("--condition"), n.powi(3) * SECONDS_PER_EIGEN_FLOP)?;
    }
    match a.solve {
        Some(SolverArg::Direct) => {
            let band = if a.dim == 2 { (p + 1.0) * n } else { p + 1.0 };
            limits.check_memory(
                what("--solve direct"),
                dofs * band * 16.0,
                "a Cholesky factor",
            )?;
            limits.check_time(what("--solve direct"), dofs * band * band * 1e-9)?;
        }
        Some(SolverArg::Pmg) => {
            limits.check_memory(
                what("--solve pmg"),
                p * (triplets + nnz * 40.0 + n * n * 16.0),
                "a p-hierarchy",
            )?;
            limits.check_time(what("--solve pmg"), 100.0 * p * nnz * SECONDS_PER_NONZERO)?;
        }
        Some(_) => limits.check_time(
            what("the iterative solve"),
            ASSUMED_ITERATIONS * nnz * SECONDS_PER_NONZERO,
        )?,
        None => {}
    }
    Ok(())
}

/// `hompm mass`.
pub fn mass(a: MassArgs, limits: &Limits) -> Result<Output> {
    validate(&a)?;
    check_limits(&a, limits)?;
    let m1 = unit_density_mass(a.spans, a.degree, a.dirichlet)?;
    if m1.rows() == 0 {
        return Err(Error::InvalidArgument(format!(
            "{} spans of degree {} leave no degrees of freedom after the Dirichlet conditions",
            a.spans, a.degree
        )));
    }
    let kron = (a.dim == 2).then(|| Kronecker2d::new(m1.clone(), m1.clone()));
    let mut doc = MassJson {
        size: kron.as_ref().map_or(m1.rows(), Kronecker2d::rows),
        ..MassJson::default()
    };
    if a.condition {
        let s = match &kron {
            Some(k) => spectrum::spectrum_kronecker(k)?,
            None => spectrum::spectrum_1d(&m1)?,
        };
        doc.lambda_min = Some(s.lambda_min);
        doc.lambda_max = Some(s.lambda_max);
        doc.condition_number = Some(s.condition_number());
    }
    if let Some(solver) = a.solve {
        let matrix = kron
            .as_ref()
            .map_or_else(|| m1.clone(), Kronecker2d::assemble);
        let result = solve_with(solver, &matrix, &a)?;
        doc.solver = Some(name(&solver));
        doc.iterations = (solver != SolverArg::Direct).then_some(result.iterations);
        doc.residuals = Some(result.residuals);
    }
    if a.json {
        return Ok(Output::text(json::strict(&doc)?));
    }
    Ok(Output::text(render(&doc)))
}

fn solve_with(solver: SolverArg, matrix: &SparseMatrix, a: &MassArgs) -> Result<IterativeResult> {
    let f = solve::gravity_rhs(matrix);
    match solver {
        SolverArg::Cg => cg::conjugate_gradient_observed(
            matrix,
            &f,
            a.tol,
            a.residual_norm(),
            100_000,
            cg::CgVariant::Recursive,
            &mut |_, _| {},
        ),
        SolverArg::Pmg => pmultigrid::PMultigrid::unit_mass(
            a.spans,
            a.degree,
            a.dim,
            a.dirichlet,
            pmultigrid::PMultigridOptions::default(),
        )?
        .solve(&f, a.tol, 10_000),
        SolverArg::Richardson => richardson::richardson_with(
            matrix,
            &matrix.row_sums(),
            &f,
            a.tol,
            a.residual_norm(),
            1_000_000,
        ),
        SolverArg::Direct => {
            let x = direct::cholesky_solve(matrix, &f)?;
            let mut ax = vec![0.0; x.len()];
            matrix.mul_vec(&x, &mut ax);
            let r: Vec<f64> = f.iter().zip(&ax).map(|(a, b)| a - b).collect();
            Ok(IterativeResult {
                residuals: vec![solve::norm(&r) / solve::norm(&f)],
                solution: x,
                iterations: 0,
            })
        }
    }
}

fn render(doc: &MassJson) -> String {
    let mut s = format!("size {}\n", doc.size);
    if let (Some(a), Some(b), Some(c)) = (doc.lambda_min, doc.lambda_max, doc.condition_number) {
        s.push_str(&format!(
            "lambda_min {a:.6e}\nlambda_max {b:.6e}\ncondition number {c:.6e}\n"
        ));
    }
    if let (Some(solver), Some(r)) = (&doc.solver, &doc.residuals) {
        let iterations = doc.iterations.map_or("-".into(), |i| i.to_string());
        let last = r.last().map_or("-".into(), |v| format!("{v:.3e}"));
        s.push_str(&format!(
            "{solver}: {iterations} iterations, final relative residual {last}\n"
        ));
    }
    s
}
