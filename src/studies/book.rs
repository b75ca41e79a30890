//! # The book's solver counts
//!
//! Book §4.6–4.7: the condition number of the 2D unit-density B-spline mass
//! matrix (Table 4.2, by the Kronecker identity), and how many CG iterations (Table 4.3) and p-multigrid
//! V-cycles (Table 4.4) the 2D unit-density B-spline mass matrix on the unit
//! square needs, with f = M·(−9.81·1), from zero to a relative residual of
//! 1e-8. The tables `book-4.3` and `book-4.4` register these counts; the
//! alternatives of [`pmg_alternatives`] are the experiments of
//! docs/reproduction-notes.md.
//!
//! Items: [`condition_number`], [`cg_iterations`], [`pmg_cycles`], [`pmg_alternatives`].

use crate::error::Result;
use crate::mass::unit_density_mass_2d;
use crate::solve::cg::{conjugate_gradient, CgVariant};
use crate::solve::gravity_rhs;
use crate::solve::pmultigrid::{PMultigrid, PMultigridOptions, Smoother, Transfer};
use crate::solve::spectrum::spectrum_kronecker;

/// κ = λ_max/λ_min (book Eq. 4.56) of the 2D unit-density mass matrix with
/// `spans` spans per direction and degree `degree`, Dirichlet rows removed,
/// from the 1D eigenvalues and κ(M_y ⊗ M_x) = κ(M_x) κ(M_y) (Table 4.2).
pub fn condition_number(spans: usize, degree: usize) -> Result<f64> {
    Ok(spectrum_kronecker(&unit_density_mass_2d(spans, degree, true)?)?.condition_number())
}

/// CG iteration count for one (p, 1/h) entry of Table 4.3 with a given variant
/// and operator form (`assembled`: the sparse 2D matrix; otherwise the
/// Kronecker product is applied as vec(M X Mᵀ)).
pub fn cg_iterations(
    spans: usize,
    degree: usize,
    variant: CgVariant,
    assembled: bool,
) -> Result<usize> {
    let k = unit_density_mass_2d(spans, degree, true)?;
    let out = if assembled {
        let a = k.assemble();
        let f = gravity_rhs(&a);
        conjugate_gradient(&a, &f, 1e-8, 10_000, variant)?
    } else {
        let f = gravity_rhs(&k);
        conjugate_gradient(&k, &f, 1e-8, 10_000, variant)?
    };
    Ok(out.iterations)
}

/// V-cycle count for one entry of Table 4.4 with the given options.
pub fn pmg_cycles(spans: usize, degree: usize, options: PMultigridOptions) -> Result<usize> {
    let mg = PMultigrid::unit_mass(spans, degree, 2, true, options)?;
    let f = gravity_rhs(mg.matrix());
    Ok(mg.solve(&f, 1e-8, 1000)?.iterations)
}

/// The variants of book §4.7's p-multigrid compared in docs/reproduction.md:
/// (name, options). The first reproduces Table 4.4 without any coarse grid.
pub fn pmg_alternatives() -> Vec<(&'static str, PMultigridOptions)> {
    let book = PMultigridOptions::default();
    vec![
        (
            "16 forward Gauss–Seidel sweeps per cycle, no coarse correction",
            PMultigridOptions {
                coarse_correction: false,
                ..book
            },
        ),
        (
            "symmetric Gauss–Seidel smoother",
            PMultigridOptions {
                smoother: Smoother::SymmetricGaussSeidel,
                ..book
            },
        ),
        (
            "damped Jacobi smoother (ω = 2/3)",
            PMultigridOptions {
                smoother: Smoother::DampedJacobi { omega: 2.0 / 3.0 },
                ..book
            },
        ),
        (
            "consistent transfer",
            PMultigridOptions {
                transfer: Transfer::Consistent,
                ..book
            },
        ),
    ]
}
