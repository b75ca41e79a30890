//! Thesis §7.2, Richardson's iteration with the lumped mass, on a 2×2 system
//! small enough to follow by hand:
//!
//! M^C = [[2, 1], [1, 2]], M^L = row sums = [3, 3], P = [3, 0].
//!
//! v⁰ = P/M^L = [1, 0]; r⁰ = P − M^C v⁰ = [1, −1], ‖r⁰‖/‖P‖ = √2/3;
//! v¹ = v⁰ + r⁰/M^L = [4/3, −1/3]; r¹ = [2/3, −2/3], ‖r¹‖/‖P‖ = 2√2/9.
//! I − (M^L)⁻¹M^C = [[1/3, −1/3], [−1/3, 1/3]] has eigenvalues 0 and 2/3,
//! and r⁰ lies in the eigenvector of 2/3, so every iterate shrinks the
//! residual by exactly ρ = 2/3. The exact solution is [2, −1].

use approx::assert_relative_eq;
use hompm::solve::richardson::{richardson, richardson_contraction};
use hompm::sparse::SparseMatrix;

fn system() -> (SparseMatrix, Vec<f64>, Vec<f64>) {
    let mc =
        SparseMatrix::from_triplets(2, 2, &[(0, 0, 2.0), (0, 1, 1.0), (1, 0, 1.0), (1, 1, 2.0)])
            .unwrap();
    (mc, vec![3.0, 3.0], vec![3.0, 0.0])
}

#[test]
fn the_first_iterate_is_the_momentum_over_the_lumped_mass() {
    // A tolerance the initial residual already meets stops at iteration 0
    // with v⁰ = P/M^L.
    let (mc, ml, p) = system();
    let r = richardson(&mc, &ml, &p, 0.5, 10).unwrap();
    assert_eq!(r.iterations, 0);
    assert_eq!(r.solution, vec![1.0, 0.0]);
    assert_relative_eq!(r.residuals[0], 2f64.sqrt() / 3.0, epsilon = 1e-15);
}

#[test]
fn each_iteration_adds_the_residual_over_the_lumped_mass() {
    // 2√2/9 ≈ 0.314 < 0.35 < √2/3 ≈ 0.471: the rule stops at the first
    // iterate whose relative residual meets the tolerance, v¹ = [4/3, −1/3].
    let (mc, ml, p) = system();
    let r = richardson(&mc, &ml, &p, 0.35, 10).unwrap();
    assert_eq!(r.iterations, 1);
    assert_relative_eq!(r.solution[0], 4.0 / 3.0, epsilon = 1e-15);
    assert_relative_eq!(r.solution[1], -1.0 / 3.0, epsilon = 1e-15);
    assert_relative_eq!(r.residuals[1], 2.0 * 2f64.sqrt() / 9.0, epsilon = 1e-15);
}

#[test]
fn the_stopping_rule_is_the_first_iterate_below_the_tolerance() {
    // Residuals √2/3 · (2/3)^k: the first k with √2/3 · (2/3)^k ≤ 1e-9 is 50
    // (ln(3e-9/√2)/ln(2/3) = 49.25).
    let (mc, ml, p) = system();
    let r = richardson(&mc, &ml, &p, 1e-9, 100).unwrap();
    assert_eq!(r.iterations, 50);
    assert!(r.residuals[50] <= 1e-9 && r.residuals[49] > 1e-9);
    for (k, res) in r.residuals.iter().enumerate() {
        let expected = 2f64.sqrt() / 3.0 * (2.0f64 / 3.0).powi(k as i32);
        assert_relative_eq!(*res, expected, max_relative = 1e-6);
    }
    assert_relative_eq!(r.solution[0], 2.0, epsilon = 1e-8);
    assert_relative_eq!(r.solution[1], -1.0, epsilon = 1e-8);
    assert_relative_eq!(
        richardson_contraction(&mc, &ml).unwrap(),
        2.0 / 3.0,
        epsilon = 1e-14
    );
}

#[test]
fn too_few_iterations_are_an_error_not_a_result() {
    let (mc, ml, p) = system();
    assert!(matches!(
        richardson(&mc, &ml, &p, 1e-9, 49),
        Err(hompm::Error::NotConverged(_))
    ));
}

/// A relative tolerance must be finite and at least ε: a smaller one cannot
/// be reached in double precision, an infinite one stops nothing. Every
/// solver refuses both (solve::check_rhs, docs/conventions.md).
#[test]
fn tolerances_outside_epsilon_to_finite_are_refused() {
    use hompm::solve::cg::{conjugate_gradient, CgVariant};
    let (mc, ml, p) = system();
    for tol in [f64::INFINITY, f64::NAN, 1e-17, 0.0, -1.0] {
        assert!(
            richardson(&mc, &ml, &p, tol, 100).is_err(),
            "Richardson accepted {tol}"
        );
        assert!(
            conjugate_gradient(&mc, &p, tol, 100, CgVariant::Recursive).is_err(),
            "CG accepted {tol}"
        );
    }
    assert!(richardson(&mc, &ml, &p, f64::EPSILON, 10_000).is_ok());
}

/// CG's true-residual variant reports ‖b − A x_k‖/‖b‖ itself at every
/// iterate; the recursive residual drifts from it by rounding on an
/// ill-conditioned system (book §4.6: high-p mass matrices).
#[test]
fn the_true_residual_variant_reports_the_true_residual() {
    use hompm::solve::cg::{conjugate_gradient_observed, CgVariant};
    use hompm::solve::richardson::ResidualNorm;
    use hompm::solve::{norm, LinearOperator};
    let m = hompm::mass::unit_density_mass(16, 6, true).unwrap();
    let b: Vec<f64> = (0..m.rows()).map(|i| ((i * 7 % 11) as f64) - 5.0).collect();
    let drift = |variant: CgVariant| {
        let mut iterates: Vec<Vec<f64>> = Vec::new();
        let r = conjugate_gradient_observed(
            &m,
            &b,
            1e-12,
            ResidualNorm::Rhs,
            400,
            variant,
            &mut |_, x| iterates.push(x.to_vec()),
        )
        .unwrap();
        let mut worst: f64 = 0.0;
        for (x, reported) in iterates.iter().zip(&r.residuals).skip(1) {
            let mut ax = vec![0.0; b.len()];
            m.apply(x, &mut ax);
            let truth = norm(&b.iter().zip(&ax).map(|(p, q)| p - q).collect::<Vec<_>>()) / norm(&b);
            worst = worst.max((reported - truth).abs() / truth);
        }
        worst
    };
    let (true_drift, recursive_drift) =
        (drift(CgVariant::TrueResidual), drift(CgVariant::Recursive));
    assert!(true_drift < 1e-12, "{true_drift:e}");
    assert!(
        recursive_drift > 100.0 * true_drift.max(1e-16),
        "{recursive_drift:e}"
    );
}

/// The three stopping rules at a tolerance an iterate meets exactly: thesis
/// §7.2's Richardson stops at ‖r_k‖/‖P‖ ≤ ε (so at that iterate), book
/// Eq. (4.53)'s CG and book §4.7's p-multigrid at ‖r_k‖/‖r_0‖ < ε (so one
/// iterate later). The tolerance is the residual a first run reported, so
/// the comparison is exact.
#[test]
fn stopping_rules_are_at_most_for_richardson_and_strictly_below_for_cg_and_pmultigrid() {
    use hompm::solve::cg::{conjugate_gradient, CgVariant};
    use hompm::solve::pmultigrid::{PMultigrid, PMultigridOptions};
    let (mc, ml, p) = system();
    let first = richardson(&mc, &ml, &p, 1e-12, 100).unwrap();
    let at_equality = richardson(&mc, &ml, &p, first.residuals[3], 100).unwrap();
    assert_eq!(at_equality.iterations, 3);

    let m = hompm::mass::unit_density_mass(8, 3, true).unwrap();
    let b: Vec<f64> = (0..m.rows()).map(|i| ((i * 7 % 11) as f64) - 5.0).collect();
    let first = conjugate_gradient(&m, &b, 1e-14, 100, CgVariant::Recursive).unwrap();
    assert!(first.iterations > 3);
    let at_equality =
        conjugate_gradient(&m, &b, first.residuals[2], 100, CgVariant::Recursive).unwrap();
    assert_eq!(at_equality.iterations, 3);

    let mg = PMultigrid::unit_mass(8, 3, 1, true, PMultigridOptions::default()).unwrap();
    let first = mg.solve(&b, 1e-14, 100).unwrap();
    assert!(first.iterations > 2);
    let at_equality = mg.solve(&b, first.residuals[1], 100).unwrap();
    assert_eq!(at_equality.iterations, 2);
}

/// Thesis §7.2 divides by the lumped masses: Richardson and its contraction
/// refuse a zero, a negative and a NaN lumped mass, each on its own, as
/// `Error::Singular` (docs/conventions.md).
#[test]
fn richardson_refuses_each_kind_of_non_positive_lumped_mass() {
    use hompm::solve::richardson::richardson_contraction;
    use hompm::Error;
    let (mc, _, p) = system();
    for bad in [0.0, -3.0, f64::NAN] {
        let ml = vec![3.0, bad];
        assert!(
            matches!(richardson(&mc, &ml, &p, 1e-9, 10), Err(Error::Singular(_))),
            "{bad}"
        );
        assert!(
            matches!(richardson_contraction(&mc, &ml), Err(Error::Singular(_))),
            "{bad}"
        );
    }
}

/// Book Eq. (4.56) needs a square, non-empty matrix; and whether λ_min is
/// resolved (n·ε·λ_max, the eigensolver's accuracy) does not depend on the
/// units: diag(1, 1e-17) and 1e10 · diag(1, 1e-17) are both ill-conditioned
/// beyond double precision, with κ ≥ 1/(2ε), and 1e10 · diag(1, 1e-3) is
/// not (κ = 1e3).
#[test]
fn eigenvalues_need_a_square_matrix_and_the_rounding_verdict_is_scale_free() {
    use hompm::solve::spectrum::{spectrum_1d, symmetric_eigenvalues};
    use hompm::Error;
    let diag = |a: f64, b: f64| SparseMatrix::from_triplets(2, 2, &[(0, 0, a), (1, 1, b)]).unwrap();
    let wide = SparseMatrix::from_triplets(2, 3, &[(0, 0, 1.0), (1, 1, 1.0)]).unwrap();
    let tall = SparseMatrix::from_triplets(3, 2, &[(0, 0, 1.0), (1, 1, 1.0)]).unwrap();
    let empty = SparseMatrix::from_triplets(0, 0, &[]).unwrap();
    for m in [&wide, &tall, &empty] {
        assert!(matches!(
            symmetric_eigenvalues(m),
            Err(Error::InvalidArgument(_))
        ));
    }
    for scale in [1.0, 1e10] {
        // κ ≥ λ_max / (n ε λ_max) = 1/(2ε) is all that can be said.
        match spectrum_1d(&diag(scale, scale * 1e-17)) {
            Err(Error::IllConditioned { kappa_at_least, .. }) => {
                assert_relative_eq!(kappa_at_least, 0.5 / f64::EPSILON, max_relative = 1e-12)
            }
            other => panic!("scale {scale}: {other:?}"),
        }
        let s = spectrum_1d(&diag(scale, scale * 1e-3)).unwrap();
        assert_relative_eq!(s.condition_number(), 1e3, max_relative = 1e-12);
    }
}

/// At the ends of the f64 range the spectrum is still the matrix's or an
/// error, never ∞ or NaN in disguise: diag(1e308, 1e308) and
/// diag(1e-300, 1e-300) have κ = 1 (faer alone returned ∞ for the first);
/// [[1e308, 1e308], [1e308, 1e308]] has the eigenvalue 2e308, beyond f64,
/// and the zero matrix has no condition number: both `Error::Singular`.
#[test]
fn spectra_at_the_ends_of_the_double_range_are_exact_or_refused() {
    use hompm::solve::spectrum::spectrum_1d;
    use hompm::Error;
    let sym = |a: f64, b: f64| {
        SparseMatrix::from_triplets(2, 2, &[(0, 0, a), (0, 1, b), (1, 0, b), (1, 1, a)]).unwrap()
    };
    for a in [1e308, 1e-300] {
        let s = spectrum_1d(&sym(a, 0.0)).unwrap();
        assert_eq!((s.lambda_min, s.lambda_max), (a, a));
        assert_eq!(s.condition_number(), 1.0);
    }
    for m in [sym(1e308, 1e308), sym(0.0, 0.0)] {
        assert!(matches!(spectrum_1d(&m), Err(Error::Singular(_))), "{m:?}");
    }
}
