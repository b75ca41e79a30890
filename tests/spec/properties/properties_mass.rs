//! Mass matrices, Kronecker operators and solvers: book Eqs. (4.2)–(4.4),
//! (4.53)–(4.57); thesis §3.1, §7.2 and A.1–A.2.

use crate::common;

use common::open_knots;
use hompm::mass::{
    consistent_mass, consistent_mass_constant, lumped_by_row_sum, lumped_variational,
    material_point_lumped_mass, material_point_mass, unit_density_mass, Kronecker2d,
};
use hompm::solve::cg::{conjugate_gradient, conjugate_gradient_observed, CgVariant};
use hompm::solve::direct::cholesky_solve;
use hompm::solve::pmultigrid::{gauss_seidel_sweep, gauss_seidel_sweep_kronecker};
use hompm::solve::richardson::ResidualNorm;
use hompm::solve::richardson::{richardson, richardson_contraction};
use hompm::solve::spectrum::{spectrum_1d, spectrum_kronecker, symmetric_eigenvalues};
use hompm::sparse::SparseMatrix;
use hompm::spline::KnotVector;
use proptest::prelude::*;

fn random_matrix(rows: usize, cols: usize, seed: &[f64]) -> SparseMatrix {
    let mut t = Vec::new();
    for i in 0..rows {
        for j in 0..cols {
            let v = seed[(i * cols + j) % seed.len()] * ((i + 2 * j) as f64).sin();
            if v.abs() > 0.2 {
                t.push((i, j, v));
            }
        }
    }
    SparseMatrix::from_triplets(rows, cols, &t).unwrap()
}

fn random_spd(n: usize, seed: &[f64], shift: f64) -> SparseMatrix {
    let b = random_matrix(n, n, seed).to_dense();
    let mut a = &b * b.transpose();
    for i in 0..n {
        a[(i, i)] += shift;
    }
    let mut t = Vec::new();
    for i in 0..n {
        for j in 0..n {
            t.push((i, j, a[(i, j)]));
        }
    }
    SparseMatrix::from_triplets(n, n, &t).unwrap()
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(256))]

    /// Book Eqs. (4.3) and (4.4): for a partition-of-unity basis, row-sum and
    /// variational lumping agree, and the lumped masses sum to ∫ρ.
    ///
    /// Map rows: book-4.2, book-4.4, tls-§3-3, thesis-§5.1-1, thesis-A-2-unnumbered-2 — the lumped masses of three seeds agree for a basis that sums to one.
    #[test]
    fn row_sum_and_variational_lumping_agree(kv in open_knots(6, 0.02), c0 in 0.5f64..3.0, c1 in -0.2f64..0.2) {
        let (a, b) = kv.domain();
        let rho = move |x: f64| c0 + c1 * (x - a) / (b - a);
        let q = kv.degree() + 2;
        let mc = consistent_mass(&kv, &rho, q).unwrap();
        let row = lumped_by_row_sum(&mc);
        let var = lumped_variational(&kv, &rho, q).unwrap();
        let total = c0 * (b - a) + 0.5 * c1 * (b - a);
        prop_assert_eq!(var.len(), kv.num_basis());
        prop_assert_eq!(row.len(), kv.num_basis());
        for (r, v) in row.iter().zip(&var) {
            prop_assert!((r - v).abs() < 1e-12 * total);
        }
        prop_assert!((row.iter().sum::<f64>() - total).abs() < 1e-12 * total);
        prop_assert!(row.iter().all(|&m| m > 0.0));
    }

    /// Thesis §3.1 / book Eq. (4.5): material-point masses are conserved by the
    /// mapping, Σ_ij M_ij = Σ_i m_i = Σ_p m_p (partition of unity, book Eq. 4.24).
    ///
    /// Map rows: tls-§3-4, tls-7, thesis-§3.1-2, thesis-§3.3-2 — one property, stated in three seeds.
    #[test]
    fn material_point_mass_is_conserved(kv in open_knots(5, 0.02),
                                        pts in proptest::collection::vec((0.0f64..=1.0, 0.1f64..2.0), 1..40)) {
        let (a, b) = kv.domain();
        let x: Vec<f64> = pts.iter().map(|(t, _)| a + t * (b - a)).collect();
        let m: Vec<f64> = pts.iter().map(|(_, m)| *m).collect();
        let total: f64 = m.iter().sum();
        let mc = material_point_mass(&kv, &x, &m).unwrap();
        let lumped = material_point_lumped_mass(&kv, &x, &m).unwrap();
        prop_assert!((mc.row_sums().iter().sum::<f64>() - total).abs() < 1e-12 * total);
        prop_assert!((lumped.iter().sum::<f64>() - total).abs() < 1e-12 * total);
        for (l, r) in lumped.iter().zip(mc.row_sums()) {
            prop_assert!((l - r).abs() < 1e-12 * total);
        }
    }

    /// y = Ax sums each row's products in column order from −0, as one
    /// `Iterator::sum` per row: `mul_vec` interleaves two rows, which must
    /// not change a bit (rows of different lengths, empty rows, an odd
    /// number of rows, a y shorter than A).
    #[test]
    fn csr_product_sums_each_row_in_column_order(rows in 1usize..12, cols in 1usize..12,
                                                 entries in proptest::collection::vec((0usize..12, 0usize..12, -1.0f64..1.0), 0..60),
                                                 x in proptest::collection::vec(-1e3f64..1e3, 12),
                                                 short in 0usize..2) {
        let mut seen = std::collections::BTreeSet::new();
        let t: Vec<_> = entries
            .into_iter()
            .map(|(i, j, v)| (i % rows, j % cols, v))
            .filter(|&(i, j, _)| seen.insert((i, j)))
            .collect();
        let a = SparseMatrix::from_triplets(rows, cols, &t).unwrap();
        let n = rows - short.min(rows - 1);
        let mut y = vec![f64::NAN; n];
        a.mul_vec(&x[..cols], &mut y);
        for (i, yi) in y.iter().enumerate() {
            let (c, v) = a.row(i);
            let expected: f64 = c.iter().zip(v).map(|(&j, &aij)| aij * x[j]).sum();
            prop_assert_eq!(yi.to_bits(), expected.to_bits(), "row {}", i);
        }
    }

    /// The forward Gauss–Seidel sweep on B ⊗ A read from the factors
    /// (p-multigrid's 2D smoother) gives every bit of the sweep on the
    /// assembled product: random sparse factors (rows with gaps in their
    /// columns) and B-spline mass matrices (banded rows, read as one run).
    #[test]
    fn kronecker_sweep_is_the_assembled_sweep(na in 1usize..6, nb in 1usize..6,
                                              seed in proptest::collection::vec(-1.0f64..1.0, 13),
                                              banded in proptest::bool::ANY, spans in 1usize..5, degree in 1usize..4,
                                              f in proptest::collection::vec(-10.0f64..10.0, 64),
                                              x0 in proptest::collection::vec(-10.0f64..10.0, 64),
                                              sweeps in 1usize..3) {
        let (a, b) = if banded {
            let m = unit_density_mass(spans, degree, false).unwrap();
            (m.clone(), m)
        } else {
            (random_matrix(na, na, &seed), random_matrix(nb, nb, &seed[5..]))
        };
        let assembled = SparseMatrix::kron(&b, &a);
        let n = assembled.rows();
        prop_assume!(n <= 64);
        let diag: Vec<f64> = assembled.diagonal().iter().map(|&d| if d == 0.0 { 1.5 } else { d }).collect();
        let (mut x1, mut x2) = (x0[..n].to_vec(), x0[..n].to_vec());
        for _ in 0..sweeps {
            gauss_seidel_sweep(&assembled, &diag, &f[..n], &mut x1, false);
            gauss_seidel_sweep_kronecker(&b, &a, &diag, &f[..n], &mut x2);
        }
        let bits = |v: &[f64]| v.iter().map(|x| x.to_bits()).collect::<Vec<_>>();
        prop_assert_eq!(bits(&x2), bits(&x1));
    }

    /// (A⊗B)x = vec(B X Aᵀ) against the assembled product, rectangular factors.
    #[test]
    fn kronecker_product_matches_assembled(ma in 1usize..7, na in 1usize..7, mb in 1usize..7, nb in 1usize..7,
                                           seed in proptest::collection::vec(-1.0f64..1.0, 13),
                                           v in proptest::collection::vec(-1.0f64..1.0, 49)) {
        let a = random_matrix(ma, na, &seed);
        let b = random_matrix(mb, nb, &seed[3..]);
        let k = Kronecker2d::new(a, b);
        prop_assert_eq!((k.rows(), k.cols()), (ma * mb, na * nb));
        prop_assert_eq!((k.assemble().rows(), k.assemble().cols()), (ma * mb, na * nb));
        let x = &v[..na * nb];
        let mut y1 = vec![0.0; ma * mb];
        let mut y2 = vec![0.0; ma * mb];
        k.apply(x, &mut y1);
        k.assemble().mul_vec(x, &mut y2);
        for (p, q) in y1.iter().zip(&y2) {
            prop_assert!((p - q).abs() < 1e-12);
        }
        // The solvers see the same product through their operator interface.
        if ma * mb == na * nb {
            let mut y3 = vec![0.0; ma * mb];
            hompm::solve::LinearOperator::apply(&k, x, &mut y3);
            prop_assert_eq!(&y3, &y1);
        }
    }

    /// Book Eq. (4.57): after k CG iterations the error in the energy norm is at
    /// most 2((√κ−1)/(√κ+1))^k times the initial one. The bound is a statement
    /// about ‖·‖_A, not the Euclidean norm of the error or the residual (which
    /// CG does not make monotone), so ‖e‖_A = √(eᵀAe) is what is tested.
    #[test]
    fn cg_obeys_the_energy_norm_bound(n in 2usize..25, seed in proptest::collection::vec(-1.0f64..1.0, 17),
                                      shift in 0.01f64..2.0, rhs in proptest::collection::vec(-1.0f64..1.0, 25)) {
        let a = random_spd(n, &seed, shift);
        let b = &rhs[..n];
        prop_assume!(b.iter().any(|v| v.abs() > 1e-3));
        let exact = cholesky_solve(&a, b).unwrap();
        let kappa = spectrum_1d(&a).unwrap().condition_number();
        let rate = (kappa.sqrt() - 1.0) / (kappa.sqrt() + 1.0);
        let energy = |x: &[f64]| {
            let e: Vec<f64> = x.iter().zip(&exact).map(|(u, v)| u - v).collect();
            let mut ae = vec![0.0; n];
            a.mul_vec(&e, &mut ae);
            e.iter().zip(&ae).map(|(u, v)| u * v).sum::<f64>().sqrt()
        };
        let e0 = energy(&vec![0.0; n]);
        let mut worst: f64 = 0.0;
        let result = conjugate_gradient_observed(&a, b, 1e-12, ResidualNorm::Rhs, 4 * n, CgVariant::Recursive, &mut |k, x| {
            let bound = 2.0 * rate.powi(k as i32) * e0;
            worst = worst.max(energy(x) - bound - 1e-9 * e0);
        });
        prop_assert!(worst <= 0.0, "bound violated by {worst}");
        let solution = result.map_err(|e| TestCaseError::fail(format!("CG did not converge: {e}")))?;
        prop_assert!(energy(&solution.solution) <= 1e-6 * e0.max(1e-300), "CG's answer is not the solution");
    }
}

/// κ(A ⊗ B) = κ(A) κ(B), against the eigenvalues of the assembled product.
#[test]
fn kronecker_condition_number_is_the_product() {
    for (p, n) in [(1, 4), (2, 3), (3, 5)] {
        let kv = KnotVector::open_uniform(0.0, 1.0, n, p).unwrap();
        let kw = KnotVector::open_uniform(0.0, 2.0, n + 1, p).unwrap();
        let a = consistent_mass_constant(&kv, 1.0).unwrap();
        let b = consistent_mass_constant(&kw, 1.0).unwrap();
        let k = Kronecker2d::new(a.clone(), b.clone());
        let s = spectrum_kronecker(&k).unwrap();
        let ev = symmetric_eigenvalues(&k.assemble()).unwrap();
        let assembled = ev[ev.len() - 1] / ev[0];
        assert!((s.condition_number() - assembled).abs() < 1e-9 * assembled);
        let ka = spectrum_1d(&a).unwrap().condition_number();
        let kb = spectrum_1d(&b).unwrap().condition_number();
        assert!((s.condition_number() - ka * kb).abs() < 1e-9 * assembled);
    }
}

/// The exact linear (P1) mass matrix: h/6·[2 1; 1 2] per element, times ρ.
#[test]
fn linear_consistent_mass_is_the_textbook_matrix() {
    let kv = KnotVector::open_uniform(0.0, 3.0, 3, 1).unwrap();
    let m = consistent_mass_constant(&kv, 2.0).unwrap();
    let h: f64 = 1.0;
    assert!((m.get(0, 0) - 2.0 * h / 3.0).abs() < 1e-14);
    assert!((m.get(1, 1) - 4.0 * h / 3.0).abs() < 1e-14);
    assert!((m.get(0, 1) - h / 3.0).abs() < 1e-14);
    assert_eq!(m.get(0, 2), 0.0);
}

/// Quadratic B-splines away from the boundary are the cardinal ones:
/// ∫ B² = 11h/20, ∫ B(x) B(x − h) = 13h/60, ∫ B(x) B(x − 2h) = h/120
/// (a row sums to h, the partition of unity), times ρ.
#[test]
fn quadratic_consistent_mass_has_the_cardinal_entries() {
    let kv = KnotVector::open_uniform(0.0, 6.0, 6, 2).unwrap();
    let rho = 2.0;
    let m = consistent_mass_constant(&kv, rho).unwrap();
    let h: f64 = 1.0;
    for (j, expected) in [
        (3, 11.0 / 20.0),
        (4, 13.0 / 60.0),
        (5, 1.0 / 120.0),
        (6, 0.0),
    ] {
        assert!(
            (m.get(3, j) - rho * h * expected).abs() < 1e-14,
            "M(3, {j}) = {}",
            m.get(3, j)
        );
    }
    let row: f64 = (0..kv.num_basis()).map(|j| m.get(3, j)).sum();
    assert!((row - rho * h).abs() < 1e-14);
}

/// Thesis §7.2: Richardson with the lumped matrix converges to the direct
/// solution; its contraction factor ρ(I − M_L⁻¹M_C) grows towards 1 with p.
#[test]
fn richardson_converges_and_slows_down_with_degree() {
    let mut last = 0.0;
    for p in 1..=5 {
        let kv = KnotVector::open_uniform(0.0, 1.0, 16, p).unwrap();
        let mc = consistent_mass_constant(&kv, 1.0).unwrap();
        let ml = lumped_by_row_sum(&mc);
        let rhs: Vec<f64> = (0..kv.num_basis()).map(|i| (i as f64).cos()).collect();
        let rho = richardson_contraction(&mc, &ml).unwrap();
        assert!(rho < 1.0 && rho > last, "p = {p}: ρ = {rho}");
        last = rho;
        let it = richardson(&mc, &ml, &rhs, 1e-9, 100_000).unwrap();
        let direct = cholesky_solve(&mc, &rhs).unwrap();
        let err = it
            .solution
            .iter()
            .zip(&direct)
            .map(|(a, b)| (a - b).abs())
            .fold(0.0, f64::max);
        let scale = direct.iter().map(|v| v.abs()).fold(0.0, f64::max);
        assert!(err < 1e-6 * scale, "p = {p}: {err}");
        if p == 1 {
            assert!((rho - 2.0 / 3.0).abs() < 0.02, "P1: ρ → 2/3, got {rho}");
        }
    }
}

/// Failures are typed: a non-SPD system, a non-positive lumped mass, a wrong size.
#[test]
fn solver_failures_are_errors() {
    let bad = SparseMatrix::from_triplets(2, 2, &[(0, 0, 1.0), (1, 1, -1.0)]).unwrap();
    assert!(conjugate_gradient(&bad, &[0.0, 1.0], 1e-8, 10, CgVariant::Recursive).is_err());
    assert!(cholesky_solve(&bad, &[1.0, 1.0]).is_err());
    assert!(spectrum_1d(&bad).is_err());
    let good = SparseMatrix::diagonal_matrix(&[1.0, 2.0]).unwrap();
    assert!(richardson(&good, &[1.0, 0.0], &[1.0, 1.0], 1e-9, 10).is_err());
    assert!(conjugate_gradient(&good, &[1.0], 1e-8, 10, CgVariant::Recursive).is_err());
    assert!(conjugate_gradient(&good, &[1.0, f64::NAN], 1e-8, 10, CgVariant::Recursive).is_err());
    assert!(conjugate_gradient(&good, &[1.0, 1.0], -1.0, 10, CgVariant::Recursive).is_err());
    let kv = KnotVector::open_uniform(0.0, 1.0, 4, 2).unwrap();
    assert!(material_point_mass(&kv, &[0.5, 1.5], &[1.0, 1.0]).is_err());
    assert!(material_point_mass(&kv, &[0.5], &[1.0, 1.0]).is_err());
    assert_eq!(kv.num_basis(), 6);
}

/// Thesis Appendix A.1: M = Σ_e T_eᵀ M_e T_e adds each element matrix into
/// the rows and columns of its DOFs (two P1 elements sharing DOF 1), and
/// refuses element matrices that do not match their DOF lists or DOFs
/// outside the global matrix. Row-sum lumping of the result (book Eq. 4.3,
/// thesis A.2) gives [3, 6, 3].
#[test]
fn assembly_adds_element_matrices_at_their_dofs_and_checks_its_input() {
    use faer::{mat, Mat};
    use hompm::mass::assemble;
    let me = mat![[2.0, 1.0], [1.0, 2.0]];
    let m = assemble(&[me.clone(), me.clone()], &[vec![0, 1], vec![1, 2]], 3).unwrap();
    let expected = [[2.0, 1.0, 0.0], [1.0, 4.0, 1.0], [0.0, 1.0, 2.0]];
    for (i, row) in expected.iter().enumerate() {
        for (j, v) in row.iter().enumerate() {
            assert_eq!(m[(i, j)], *v, "M({i}, {j})");
        }
    }
    assert_eq!(hompm::mass::row_sum_lumping(&m), vec![3.0, 6.0, 3.0]);
    assert!(assemble(std::slice::from_ref(&me), &[vec![0, 1], vec![1, 2]], 3).is_err());
    assert!(assemble(std::slice::from_ref(&me), &[vec![0, 1, 2]], 3).is_err());
    assert!(assemble(&[Mat::zeros(2, 3)], &[vec![0, 1]], 3).is_err());
    assert!(assemble(std::slice::from_ref(&me), &[vec![2, 3]], 3).is_err());
    assert!(assemble(&[me], &[vec![3, 0]], 3).is_err());
}

/// The Kronecker sweep starts each row's sum from −0, as `Iterator::sum`
/// does: with x = f = −0 and positive entries the products are zeros of
/// both signs as the sweep goes, and a sum started from +0 gives some x_i
/// the other sign of zero than the assembled sweep does.
#[test]
fn kronecker_sweep_sums_from_negative_zero_as_the_assembled_sweep() {
    let m = unit_density_mass(3, 2, false).unwrap();
    let assembled = SparseMatrix::kron(&m, &m);
    let n = assembled.rows();
    let diag = assembled.diagonal();
    let f = vec![-0.0; n];
    let (mut x1, mut x2) = (vec![-0.0; n], vec![-0.0; n]);
    gauss_seidel_sweep(&assembled, &diag, &f, &mut x1, false);
    gauss_seidel_sweep_kronecker(&m, &m, &diag, &f, &mut x2);
    let bits = |v: &[f64]| v.iter().map(|x| x.to_bits()).collect::<Vec<_>>();
    assert_eq!(bits(&x2), bits(&x1));
}
